// `kanesens bench rhs SCENE [--repeat N] [--json]`: how long one evaluation of Kane's equations
// takes at a random fixed state (seeded, so runs are comparable):
//   rhs       evaluate_rhs on double: M, f, Cholesky solve, q̇ (what CVODES calls; long
//             unconstrained 3-D chains: the articulated-body recursion instead of M)
//   mf        evaluate_mass_matrix_and_forcing on double: M and f alone
//   jacobian_dual  the exact Jacobian ∂ẏ/∂y column by column: nq + nu evaluate_rhs on Dual
//   jacobian       the exact Jacobian as the solvers get it (KaneProblem::jacobian): in closed
//                  form where it applies, else columns in blocks of up to 16, one
//                  multi-tangent pass per block
//   jacobian_residual   where the default took the closed form (dynamics/residual_derivatives.hpp):
//                  the same with KaneProblem::DerivativeMethod::residual (multi-tangent passes
//                  of the residual)
//   jacobian_whole_rhs  the same with KaneProblem::DerivativeMethod::whole_rhs (multi-tangent
//                  passes of the whole right-hand side); `jacobian_method` says which the
//                  default took
//   jacobian_times one product J v as matrix-free Newton gets it (KaneProblem::jacobian_times):
//                  one Dual pass
// On a scene with constraints, `rhs` includes the multipliers (A M⁻¹ Aᵀ λ = b − A M⁻¹ f) at the
// random state, which violates the constraints. Such a scene adds the right-hand sides CVODES
// integrates at the scene's consistent initial state (the embedding needs a state that the
// independent speeds parameterise), which is where peers are compared (Simbody's
// realize(Acceleration), MuJoCo's mj_forward with an equality constraint):
//   rhs_multipliers  KaneProblem::rhs, multipliers formulation
//   jacobian_times_multipliers  KaneProblem::jacobian_times there, multipliers formulation
//   rhs_embedding    KaneProblem::rhs, embedding: reconstruct u, Cᵀ M C u̇_i = Cᵀ(f − M d)
#include <algorithm>
#include <cmath>
#include <chrono>
#include <iostream>
#include <random>

#include "math/dual.hpp"
#include "commands.hpp"
#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "util/json_writer.hpp"

namespace kanesens::cli {

using namespace kanesens::dynamics;
using namespace kanesens::model;
using namespace kanesens::sim;

namespace {
struct BenchOptions {
  std::string scene;
  int repeat = 31;
  double batch_seconds = 2e-3;
  unsigned seed = 1;
  bool json = false;
  bool general_3d = false;  // evaluate a planar scene with the 3-D code (Model::force_general_3d)
  long long profile = 0;  // > 0: exactly this many untimed evaluations of each kind (profilers)
  std::string rhs_algorithm = "auto";  // auto (the workspace's choice), mass_matrix, articulated_body
};

struct Timing {
  std::string name;
  double median_ns = 0, min_ns = 0;
  long long batch = 0;  // evaluations per batch
  int batches = 0;
};

// Times `f` (one evaluation per call): calibrates the batch size, then returns the median and
// minimum per-call time over `repeat` batches.
template <class F>
Timing time_it(const std::string& name, const BenchOptions& o, F&& f) {
  using clock = std::chrono::steady_clock;
  if (o.profile > 0) {
    for (long long i = 0; i < o.profile; ++i) f();
    return Timing{name, 0, 0, o.profile, 0};
  }
  auto run = [&](long long n) {
    const auto t0 = clock::now();
    for (long long i = 0; i < n; ++i) f();
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  long long n = 1;
  run(n);  // warm caches
  while (true) {
    const double s = run(n);
    if (s >= o.batch_seconds || n > (1LL << 40)) break;
    n = s > 0 ? std::max(2 * n, static_cast<long long>(1.2 * n * o.batch_seconds / s)) : 2 * n;
  }
  std::vector<double> per_call;
  for (int r = 0; r < o.repeat; ++r) per_call.push_back(run(n) / static_cast<double>(n) * 1e9);
  std::sort(per_call.begin(), per_call.end());
  Timing t;
  t.name = name;
  t.median_ns = per_call[per_call.size() / 2];
  t.min_ns = per_call.front();
  t.batch = n;
  t.batches = o.repeat;
  return t;
}

int run_bench_rhs(const BenchOptions& o) {
  if (o.repeat < 1) throw InputError({}, "--repeat", "must be at least 1");
  Model m = build_model(parse_scene_file(o.scene));
  m.force_general_3d = o.general_3d;
  const std::vector<double> p = m.nominal_parameters();

  // A random fixed state: q, u uniform in [-1, 1], quaternions normalised.
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> y(m.nstate());
  for (double& v : y) v = uni(rng);
  for (const Joint& J : m.joints)
    if (J.quaternion_offset >= 0) {
      double* e = y.data() + J.quaternion_offset;
      const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      for (int i = 0; i < 4; ++i) e[i] /= n;
    }
  const int n = m.nstate();

  Workspace<double> ws(m);
  if (o.rhs_algorithm != "auto") {
    dynamics::set_articulated_body(m, ws, o.rhs_algorithm == "articulated_body");
    if (o.rhs_algorithm == "articulated_body" && !uses_articulated_body(m, ws))
      throw InputError({}, "--rhs-algorithm",
                       "articulated_body needs a scene without constraints, and on the planar path joints of "
                       "at most one speed each (add --general-3d to evaluate it in 3-D)");
  }
  set_parameters(m, ws, p.data());
  std::vector<double> ydot(n);
  double sink = 0;
  if (!evaluate_rhs(m, ws, 0.0, y.data(), ydot.data()))
    throw InputError({}, "scene", "the mass matrix is not positive definite at the benchmark state");

  Workspace<Dual> wd(m);
  std::vector<Dual> pd(p.begin(), p.end());
  set_parameters(m, wd, pd.data());
  std::vector<Dual> yd(y.begin(), y.end()), yddot(n);
  std::vector<double> jac(static_cast<std::size_t>(n) * n);  // column-major n×n

  std::vector<Timing> timings;
  timings.push_back(time_it("rhs", o, [&] {
    evaluate_rhs(m, ws, 0.0, y.data(), ydot.data());
    sink += ydot[n - 1];
  }));
  timings.push_back(time_it("mass_matrix_and_forcing", o, [&] {
    evaluate_mass_matrix_and_forcing(m, ws, 0.0, y.data(), y.data() + m.nq);
    sink += ws.forcing[m.nu - 1];
  }));
  timings.push_back(time_it("jacobian_dual", o, [&] {
    for (int c = 0; c < n; ++c) {
      yd[c].d = 1.0;
      evaluate_rhs(m, wd, Dual(0.0), yd.data(), yddot.data());
      yd[c].d = 0.0;
      for (int r = 0; r < n; ++r) jac[static_cast<std::size_t>(c) * n + r] = yddot[r].d;
    }
    sink += jac.back();
  }));

  const char* jacobian_method = "";
  {
    KaneProblem problem(m, {});
    problem.set_sample(SampleInputs(m));
    timings.push_back(time_it("jacobian", o, [&] {
      problem.jacobian(0.0, y.data(), ydot.data(), jac.data());
      sink += jac.back();
    }));
    using Method = KaneProblem::DerivativeMethod;
    const Method took = problem.last_jacobian_method();
    jacobian_method = took == Method::closed_form ? "closed_form" : took == Method::residual ? "residual" : "whole_rhs";
    if (took == Method::closed_form) {
      problem.set_jacobian_method(Method::residual);
      timings.push_back(time_it("jacobian_residual", o, [&] {
        problem.jacobian(0.0, y.data(), ydot.data(), jac.data());
        sink += jac.back();
      }));
    }
    problem.set_jacobian_method(KaneProblem::DerivativeMethod::whole_rhs);
    timings.push_back(time_it("jacobian_whole_rhs", o, [&] {
      problem.jacobian(0.0, y.data(), ydot.data(), jac.data());
      sink += jac.back();
    }));
    problem.set_jacobian_method(KaneProblem::DerivativeMethod::residual);
    std::vector<double> v(static_cast<std::size_t>(n)), jv(v.size());
    for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = std::sin(1.0 + i);
    timings.push_back(time_it("jacobian_times", o, [&] {
      problem.jacobian_times(0.0, y.data(), ydot.data(), v.data(), jv.data());
      sink += jv.back();
    }));
  }

  // Constrained right-hand sides at the consistent initial state (nominal parameters).
  std::vector<double> constrained_state;
  if (m.nconstraint_rows > 0) {
    for (const auto formulation :
         {ConstraintOptions::Formulation::multipliers, ConstraintOptions::Formulation::embedding}) {
      ConstraintOptions c;
      c.formulation = formulation;
      KaneProblem problem(m, {}, c);
      problem.set_sample(SampleInputs(m));
      std::vector<double> y0(problem.size()), y0dot(problem.size());
      problem.initial_state(y0.data());
      if (constrained_state.empty()) constrained_state = y0;
      const bool multipliers = formulation == ConstraintOptions::Formulation::multipliers;
      timings.push_back(time_it(multipliers ? "rhs_multipliers" : "rhs_embedding", o, [&] {
        problem.rhs(0.0, y0.data(), y0dot.data());
        sink += y0dot.back();
      }));
      if (multipliers) {
        std::vector<double> v(y0.size()), jv(y0.size());
        for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(1.0 + static_cast<double>(i));
        timings.push_back(time_it("jacobian_times_multipliers", o, [&] {
          problem.jacobian_times(0.0, y0.data(), y0dot.data(), v.data(), jv.data());
          sink += jv.back();
        }));
      }
    }
  }

  if (o.json) {
    JsonWriter j(std::cout);
    j.begin_object();
    j.key("scene").value(m.name);
    j.key("file").value(o.scene);
    j.key("nbody").value(m.nbody());
    j.key("nq").value(m.nq);
    j.key("nu").value(m.nu);
    j.key("planar_scene").value(m.planar);
    j.key("path").value(m.evaluate_planar() ? "planar" : "3d");
    j.key("rhs_algorithm").value(uses_articulated_body(m, ws) ? "articulated_body" : "mass_matrix");
    j.key("seed").value(static_cast<long long>(o.seed));
    j.key("repeat").value(o.repeat);
    j.key("jacobian_method").value(jacobian_method);
    if (!constrained_state.empty()) {
      // The consistent initial state [q; u] of the constrained timings, for peers to use.
      j.key("nconstraint_rows").value(m.nconstraint_rows);
      j.key("constrained_state").begin_array();
      for (double v : constrained_state) j.value(v);
      j.end_array();
    }
    for (const Timing& t : timings) {
      j.key(t.name).begin_object();
      j.key("median_ns").value(t.median_ns);
      j.key("min_ns").value(t.min_ns);
      j.key("evaluations_per_second").value(1e9 / t.median_ns);
      j.key("batch").value(t.batch);
      j.key("batches").value(t.batches);
      j.end_object();
    }
    j.key("checksum").value(sink);  // keeps the work observable; meaningless otherwise
    j.end_object();
    std::cout << "\n";
  } else {
    std::cout << "scene '" << m.name << "': " << m.nbody() << " bodies, nq = " << m.nq << ", nu = " << m.nu
              << ", " << (m.evaluate_planar() ? "planar" : "3-D") << " evaluation (median of " << o.repeat
              << " batches)\n";
    for (const Timing& t : timings) {
      char line[160];
      std::snprintf(line, sizeof line, "  %-24s %12.1f ns  %12.0f evaluations/s\n", t.name.c_str(), t.median_ns,
                    1e9 / t.median_ns);
      std::cout << line;
    }
    if (sink == 1.2345e300) std::cout << "";  // the sink must be read
  }
  return 0;
}
}  // namespace

CLI::App* add_bench(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("bench", "Speed of the right-hand side (JSON with --json); the work-precision benchmark is kanesens-workprecision");
  cmd->require_subcommand(1);
  auto* rhs = cmd->add_subcommand("rhs", "Time the right-hand side, M and f, and the exact (Dual) Jacobian");
  auto o = std::make_shared<BenchOptions>();
  rhs->add_option("scene", o->scene, "Scene YAML file")->required();
  rhs->add_option("--repeat", o->repeat, "Number of timed batches (the median is reported)")->check(integer_in(1, 100000));
  rhs->add_option("--batch-seconds", o->batch_seconds, "Minimum duration of one batch, s")->check(finite_number(0, 3600));
  rhs->add_option("--seed", o->seed, "Seed of the random state");
  rhs->add_flag("--json", o->json, "Print JSON");
  rhs->add_flag("--general-3d", o->general_3d, "Evaluate a planar scene with the general 3-D code");
  rhs->add_option("--profile", o->profile,
                  "Run exactly N untimed evaluations of each kind (for callgrind: instructions / N)")
      ->check(integer_in(0, 1LL << 40));
  rhs->add_option("--rhs-algorithm", o->rhs_algorithm,
                  "How `rhs` finds u̇: auto (articulated_body for unconstrained chains of one-speed joints, "
                  "or evaluated in 3-D with 28 or more speeds, else mass_matrix), mass_matrix (M and its "
                  "factor) or articulated_body")
      ->check(CLI::IsMember({"auto", "mass_matrix", "articulated_body"}));
  rhs->callback([&action, o] { action = [o] { return run_bench_rhs(*o); }; });
  return cmd;
}

}  // namespace kanesens::cli
