// Forward sensitivities (CVODES, exact sensitivity RHS from dual numbers) against finite
// differences of whole trajectories, for parameter and initial-condition sensitivities of three
// scenes: a double pendulum (m2, L1 — L1 enters a rod shape and two joint points — and initial
// conditions), a 3-D arm (revolute + universal + prismatic; a parameter in an inertia entry and
// one in a joint point) and a spinning top on a spherical joint (the mass-center distance and
// quaternion initial conditions top.q0[i], which are normalised when the initial state is
// formed — the perturbed finite-difference runs are normalised the same way).
//
// Finite differences: the fourth-order central stencil
//     s ≈ [−y(p+2h) + 8 y(p+h) − 8 y(p−h) + y(p−2h)] / (12 h),
// h = 3e-4 × max(|p|, 1) (initial conditions) or 3e-4 × |p| (parameters), each run at
// rtol 1e-13, atol 1e-14. Measured on the arm: truncation scales as h⁴ (7.4e-4 at h = 3e-3,
// 9.3e-6 at 1e-3: the sensitivities reach ~10–100, the motion is strongly nonlinear), and
// integration noise as rtol/h (FD runs at rtol 1e-12 with h = 1e-4 give 4.6e-6, at 1e-13
// 2.9e-7). At h = 3e-4, rtol 1e-13 both are ≲ 1e-7; the sensitivities themselves are
// integrated at rtol 1e-10.
//
// Error measure, for sensitivity i: max over output times t and states r of
//     |s_ri(t) − fd_ri(t)| / max(peak_ri, 1e-3 · peak_i),
// peak_ri = max_t |s_ri(t)| (the pair's own size over the trajectory) and peak_i = max_r peak_ri
// (so a state that a parameter barely moves is judged against a thousandth of the largest
// response, not against its own near-zero size).
//
// Also: the same with matrix-free Newton (linear_solver krylov; staggered and simultaneous
// corrections), and exact vs CVODES difference-quotient sensitivity RHS at rtol 1e-8 — error against the
// same finite differences and cost (rhs evaluations) — printed as a table.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "../support/kane_test_support.hpp"
#include "sim/simulate.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

struct SceneCase {
  const char* name;
  const char* yaml;
  double t_end;
  std::vector<std::string> sensitivities;
};

constexpr const char* kDoublePendulum = R"yaml(
kanesens: 1
scene:
  name: double_pendulum
  gravity: [0, -9.81, 0]
  parameters: {m1: 1.0, L1: 1.0, m2: 1.0, L2: 1.0}
  bodies:
    - {name: rod1, mass: m1, inertia: {shape: rod, length: L1, axis: y}}
    - {name: rod2, mass: m2, inertia: {xx: "m2*L2^2/12", yy: 0, zz: "m2*L2^2/12"}}
  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1],
       parent_point: [0, 0, 0], child_point: [0, "L1/2", 0], q0: 0.5, u0: 0}
    - {name: elbow, type: revolute, parent: rod1, child: rod2, axis: [0, 0, 1],
       parent_point: [0, "-L1/2", 0], child_point: [0, "L2/2", 0], q0: 0.3, u0: 0.2}
)yaml";

constexpr const char* kArm = R"yaml(
kanesens: 1
scene:
  name: arm
  gravity: [0, 0, -9.81]
  parameters: {Iyy2: 0.10, px: 0.05, m2: 1.5}
  bodies:
    - {name: base, mass: 2.0, inertia: {xx: 0.2, yy: 0.25, zz: 0.3, xy: 0.01, yz: -0.02, xz: 0.015}}
    - {name: upper, mass: m2, inertia: {xx: 0.12, yy: Iyy2, zz: 0.05, xy: -0.01, yz: 0.008, xz: 0.02}}
    - {name: slide, mass: 1.0, inertia: {xx: 0.05, yy: 0.06, zz: 0.04, xy: 0.004, yz: 0.003, xz: -0.005}}
  joints:
    - {name: yaw, type: revolute, parent: ground, child: base, axis: [0, 0, 1],
       parent_point: [0, 0, 0.2], child_point: [0.05, 0, -0.1], u0: 0.5, damper: {c: 0.1}}
    - {name: shoulder, type: universal, parent: base, child: upper, axes: [[1, 0, 0], [0, 1, 0.2]],
       parent_point: [px, 0, 0.15], child_point: [0.02, 0, -0.3], q0: [0.3, -0.2], u0: [0.1, 0.4]}
    - {name: extend, type: prismatic, parent: upper, child: slide, axis: [0.1, 0, 1],
       parent_point: [0, 0.01, 0.3], child_point: [0, 0, -0.1], q0: 0.05,
       spring: {k: 40, rest: 0.05}, damper: {c: 0.5}}
)yaml";

constexpr const char* kTop = R"yaml(
kanesens: 1
scene:
  name: spinning_top
  gravity: [0, 0, -9.81]
  parameters: {m: 1.0, l: 0.1}
  bodies:
    - {name: rotor, mass: m, inertia: {xx: 0.004, yy: 0.0045, zz: 0.006, xy: 0.0002}}
  joints:
    - {name: top, type: spherical, parent: ground, child: rotor, child_point: [0, 0, "-l"],
       q0: [0.98, 0.15, 0.05, 0.0], u0: [0.2, 0.1, 30]}
)yaml";

const std::vector<SceneCase>& scenes() {
  static const std::vector<SceneCase> s = {
      {"double_pendulum", kDoublePendulum, 3.0, {"m2", "L1", "shoulder.q0", "elbow.u0"}},
      {"arm", kArm, 1.5, {"Iyy2", "px", "shoulder.q0[0]", "shoulder.u0[1]", "extend.u0"}},
      {"spinning_top", kTop, 2.0, {"l", "m", "top.q0[1]", "top.q0[0]", "top.u0[2]"}},
  };
  return s;
}

ks::SolverOptions options(double rtol, double atol) {
  ks::SolverOptions o;
  o.rtol = rtol;
  o.atol = atol;
  return o;
}

std::vector<double> output_times(double t_end) {
  std::vector<double> t;
  for (int k = 0; k <= 20; ++k) t.push_back(t_end * k / 20);
  return t;
}

// The value an input has in the nominal sample: a parameter's value, or the initial condition as
// written in the scene (before quaternion normalisation).
double nominal_input(const ks::Model& m, const ks::InputRef& ref) {
  const std::vector<double> p = m.nominal_parameters();
  if (ref.kind == ks::InputRef::Kind::parameter) return p[ref.index];
  ks::Workspace<double> ws(m);
  ks::set_parameters(m, ws, p.data());
  std::vector<ks::Slot> slots;
  for (const ks::Joint& J : m.joints) slots.insert(slots.end(), J.q0.begin(), J.q0.end());
  for (const ks::Joint& J : m.joints) slots.insert(slots.end(), J.u0.begin(), J.u0.end());
  return ws.values[slots[ref.index]];
}

struct Sensitivities {
  std::vector<double> s;  // T × n × ns, as ks::Trajectory
  ks::SolverStats stats;
  double wall = 0;
};

Sensitivities run_sensitivities(const ks::Model& m, const std::vector<ks::InputRef>& sens,
                                const ks::SolverOptions& o,
                                const std::vector<double>& times) {
  ks::KaneProblem problem(m, sens);
  ks::Integrator integ(o);
  ks::Trajectory tr;
  ks::RecordFlags flags;
  flags.energy = false;
  const auto t0 = std::chrono::steady_clock::now();
  ks::simulate(problem, integ, times, flags, tr);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(tr.result.ok()) << tr.result.message;
  return {tr.sensitivities, tr.result.stats, wall};
}

// Fourth-order central differences of whole trajectories: T × n × ns.
std::vector<double> finite_differences(const ks::Model& m, const std::vector<ks::InputRef>& sens,
                                       const std::vector<double>& times) {
  const std::size_t n = static_cast<std::size_t>(m.nstate()), ns = sens.size(), T = times.size();
  std::vector<double> fd(T * n * ns, 0.0);
  ks::KaneProblem problem(m, {});
  ks::Integrator integ(options(1e-13, 1e-14));
  ks::RecordFlags flags;
  flags.sensitivities = false;
  flags.energy = false;
  ks::Trajectory tr;
  for (std::size_t i = 0; i < ns; ++i) {
    const double v = nominal_input(m, sens[i]);
    const double hr = 3e-4;
    const double h = sens[i].kind == ks::InputRef::Kind::parameter
                         ? hr * std::abs(v)
                         : hr * std::max(std::abs(v), 1.0);
    for (const auto& [shift, weight] :
         std::vector<std::pair<double, double>>{{2, -1}, {1, 8}, {-1, -8}, {-2, 1}}) {
      ks::SampleInputs in(m);
      in.set(sens[i], v + shift * h);
      problem.set_sample(in);
      ks::simulate(problem, integ, times, flags, tr);
      EXPECT_TRUE(tr.result.ok()) << tr.result.message;
      for (std::size_t k = 0; k < T; ++k)
        for (std::size_t r = 0; r < n; ++r)
          fd[(k * n + r) * ns + i] += weight * tr.states[k * n + r] / (12 * h);
    }
  }
  return fd;
}

// Per sensitivity: the error measure of the file comment.
std::vector<double> errors(const std::vector<double>& s, const std::vector<double>& fd,
                           std::size_t T, std::size_t n, std::size_t ns) {
  std::vector<double> err(ns, 0.0);
  for (std::size_t i = 0; i < ns; ++i) {
    std::vector<double> peak(n, 0.0);
    for (std::size_t k = 0; k < T; ++k)
      for (std::size_t r = 0; r < n; ++r)
        peak[r] = std::max(peak[r], std::abs(s[(k * n + r) * ns + i]));
    const double peak_i = *std::max_element(peak.begin(), peak.end());
    for (std::size_t k = 0; k < T; ++k)
      for (std::size_t r = 0; r < n; ++r) {
        const std::size_t at = (k * n + r) * ns + i;
        err[i] = std::max(err[i], std::abs(s[at] - fd[at]) / std::max(peak[r], 1e-3 * peak_i));
      }
  }
  return err;
}

class SensitivitiesVsFiniteDifferences : public ::testing::TestWithParam<SceneCase> {};

TEST_P(SensitivitiesVsFiniteDifferences, ExactSensitivityRhsAgreesWithTrajectoryDifferences) {
  const SceneCase& sc = GetParam();
  const ks::Model m = model_from_text(sc.yaml);
  std::vector<ks::InputRef> sens;
  for (const auto& name : sc.sensitivities) sens.push_back(ks::resolve_input(m, name, "test"));
  const std::vector<double> times = output_times(sc.t_end);
  const std::size_t T = times.size(), n = static_cast<std::size_t>(m.nstate()), ns = sens.size();

  const std::vector<double> fd = finite_differences(m, sens, times);

  struct Variant {
    const char* label;
    ks::SensitivityRhs rhs;
    double rtol, atol;
    ks::Method method = ks::Method::bdf;
    ks::LinearSolver linear_solver = ks::LinearSolver::automatic;  // dense for these small scenes
    ks::SensitivityMethod sensitivity_method = ks::SensitivityMethod::staggered;
  };
  // Row 4: the explicit DOP853 (its sensitivities from its own stages, not CVODES); rows 5, 6:
  // matrix-free Newton (GMRES on exact J v) for the state and the sensitivity corrections.
  const std::vector<Variant> variants = {
      {"exact", ks::SensitivityRhs::exact, 1e-10, 1e-12},
      {"exact", ks::SensitivityRhs::exact, 1e-8, 1e-10},
      {"dq", ks::SensitivityRhs::dq, 1e-8, 1e-10},
      {"dop853", ks::SensitivityRhs::exact, 1e-10, 1e-12, ks::Method::dop853},
      {"kry/stg", ks::SensitivityRhs::exact, 1e-10, 1e-12, ks::Method::bdf, ks::LinearSolver::krylov},
      {"kry/sim", ks::SensitivityRhs::exact, 1e-10, 1e-12, ks::Method::bdf, ks::LinearSolver::krylov,
       ks::SensitivityMethod::simultaneous},
  };
  std::printf("\n  %-16s %-5s %-6s  %-9s  %6s %8s %9s %12s %9s\n", sc.name, "rhs", "rtol",
              "max err", "steps", "rhs", "sens rhs", "rhs for sens", "wall s");
  std::vector<std::vector<double>> err_of;
  for (const Variant& v : variants) {
    ks::SolverOptions o = options(v.rtol, v.atol);
    o.sens_rhs = v.rhs;
    o.method = v.method;
    o.linear_solver = v.linear_solver;
    o.sensitivity_method = v.sensitivity_method;
    const Sensitivities r = run_sensitivities(m, sens, o, times);
    const std::vector<double> err = errors(r.s, fd, T, n, ns);
    err_of.push_back(err);
    std::printf("  %-16s %-5s %-6.0e  %-9.2e  %6ld %8ld %9ld %12ld %9.4f\n", "", v.label, v.rtol,
                *std::max_element(err.begin(), err.end()), r.stats.steps, r.stats.rhs_evals,
                r.stats.sens_rhs_evals, r.stats.rhs_evals_for_sens, r.wall);
  }
  std::printf("  per sensitivity (exact, rtol 1e-10):");
  for (std::size_t i = 0; i < ns; ++i)
    std::printf(" %s %.1e%s", sc.sensitivities[i].c_str(), err_of[0][i], i + 1 < ns ? "," : "\n");

  for (std::size_t i = 0; i < ns; ++i) {
    EXPECT_LT(err_of[0][i], 1e-6) << sc.name << ": " << sc.sensitivities[i]
                                  << " (exact, rtol 1e-10)";
    EXPECT_LT(err_of[1][i], 1e-4) << sc.name << ": " << sc.sensitivities[i]
                                  << " (exact, rtol 1e-8)";
    EXPECT_LT(err_of[2][i], 1e-3) << sc.name << ": " << sc.sensitivities[i] << " (dq, rtol 1e-8)";
    EXPECT_LT(err_of[3][i], 1e-6) << sc.name << ": " << sc.sensitivities[i] << " (dop853, rtol 1e-10)";
    EXPECT_LT(err_of[4][i], 1e-6) << sc.name << ": " << sc.sensitivities[i] << " (krylov, staggered)";
    EXPECT_LT(err_of[5][i], 1e-6) << sc.name << ": " << sc.sensitivities[i] << " (krylov, simultaneous)";
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, SensitivitiesVsFiniteDifferences, ::testing::ValuesIn(scenes()),
                         [](const ::testing::TestParamInfo<SceneCase>& i) {
                           return std::string(i.param.name);
                         });

}  // namespace

}  // namespace KANESENS_UNITY_ID
