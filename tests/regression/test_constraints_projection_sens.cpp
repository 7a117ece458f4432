// Sensitivities of a constrained system under the three stabilizations (none, Baumgarte,
// CVODES projection) against finite differences of whole trajectories, and the tangent-space
// residual of the sensitivities, G s_q + ∂g/∂p and d(Au)/dε, which is 0 for exact ones.
//
// CVODES 6.4 projects y only (docs/solve.md): the integrated sensitivities of a projected run
// are not those of the projected trajectory. simulate() therefore projects the *recorded*
// sensitivities at each output (ConstraintOptions::project_sensitivities, default on). This file
// measures raw and output-projected sensitivities and pins the accuracy of each
// (docs/explanation/constraints.md has the table).
//
// Scene: the pendulum of test_constraints_pendulum.cpp (planar free rod + pin, m = 1.3,
// L = 0.8, θ0 = 0.5, θ̇0 = 0.7), 5 s (≈ 3 periods), 26 outputs. Sensitivities to m (the motion does
// not depend on m, so the exact sensitivity is 0: reported as an absolute value), L, theta0 and
// base.u0[2]. FD: fourth-order central stencil, h = 3e-4 max(|p|, 1), runs at rtol 1e-13 with the
// same stabilization. Error, per sensitivity: max over t and states of
// |s − fd| / max(peak_r, 1e-3 peak), peak_r = max_t |fd_r| (as test_sensitivities_fd.cpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "../support/constraint_test_support.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {


const std::vector<std::string> kNames = {"m", "L", "theta0", "base.u0[2]"};

struct Measured {
  std::vector<double> err;       // per sensitivity (m: absolute)
  double tangent_pos = 0, tangent_vel = 0;  // max over outputs and sensitivities
  long steps = 0;
};

std::vector<double> fd_states(const ks::Model& model, ks::ConstraintOptions copt, const std::vector<double>& times,
                              const std::string& name, double v) {
  const double h = 3e-4 * std::max(std::abs(v), 1.0);
  std::vector<double> fd;
  for (const auto& [shift, weight] : std::vector<std::pair<double, double>>{{2, -1}, {1, 8}, {-1, -8}, {-2, 1}}) {
    const TrajRun p = run(model, times, copt, tolerances(1e-13, 1e-14), {}, {{name, v + shift * h}});
    EXPECT_TRUE(p.tr.result.ok()) << p.tr.result.message;
    if (fd.empty()) fd.assign(p.tr.states.size(), 0.0);
    for (std::size_t j = 0; j < fd.size(); ++j) fd[j] += weight * p.tr.states[j] / (12 * h);
  }
  return fd;
}

// FD of each sensitivity for each stabilization, computed once.
const std::vector<double>& fd_cache(const ks::Model& model, Stab stab, std::size_t i, const std::vector<double>& times,
                                    double v) {
  static std::map<std::pair<int, std::size_t>, std::vector<double>> cache;
  auto key = std::make_pair(static_cast<int>(stab), i);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, fd_states(model, constraint_options(stab), times, kNames[i], v)).first;
  return it->second;
}

Measured measure(const ks::Model& model, Stab stab, double rtol, bool project_sens,
                 ks::sim::SensitivityMethod corrector = ks::sim::SensitivityMethod::automatic) {
  const auto times = linspace(0, 5, 26);
  ks::ConstraintOptions copt = constraint_options(stab);
  copt.project_sensitivities = project_sens;
  ks::sim::SolverOptions sopt = tolerances(rtol, rtol * 1e-2);
  sopt.sensitivity_method = corrector;
  const TrajRun r = run(model, times, copt, sopt, kNames);
  EXPECT_TRUE(r.tr.result.ok()) << r.tr.result.message;
  Measured out;
  out.steps = r.tr.result.stats.steps;
  std::vector<ks::InputRef> refs;
  for (const auto& nm : kNames) refs.push_back(ks::resolve_input(model, nm, "test"));
  ks::KaneProblem problem(model, refs, copt);
  const int n = r.n, T = static_cast<int>(times.size());
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    const double v = refs[i].kind == ks::InputRef::Kind::parameter ? model.nominal_parameters()[refs[i].index]
                                                                    : r.y(0, refs[i].index);
    const std::vector<double>& fd = fd_cache(model, stab, i, times, v);
    std::vector<double> peak(static_cast<std::size_t>(n), 0.0);
    for (int k = 0; k < T; ++k)
      for (int s = 0; s < n; ++s)
        peak[static_cast<std::size_t>(s)] = std::max(peak[static_cast<std::size_t>(s)], std::abs(fd[static_cast<std::size_t>(k * n + s)]));
    const double peak_all = *std::max_element(peak.begin(), peak.end());
    double e = 0;
    for (int k = 0; k < T; ++k)
      for (int s = 0; s < n; ++s) {
        const double d = std::abs(r.s(k, s, static_cast<int>(i)) - fd[static_cast<std::size_t>(k * n + s)]);
        e = std::max(e, i == 0 ? d : d / std::max(peak[static_cast<std::size_t>(s)], 1e-3 * peak_all));
      }
    out.err.push_back(e);
    for (int k = 0; k < T; ++k) {
      std::vector<double> sv(static_cast<std::size_t>(n)), y(static_cast<std::size_t>(n));
      for (int s = 0; s < n; ++s) {
        sv[static_cast<std::size_t>(s)] = r.s(k, s, static_cast<int>(i));
        y[static_cast<std::size_t>(s)] = r.y(k, s);
      }
      double p, vel;
      problem.sensitivity_constraint_residuals(times[static_cast<std::size_t>(k)], y.data(), static_cast<int>(i),
                                               sv.data(), p, vel);
      out.tangent_pos = std::max(out.tangent_pos, p);
      out.tangent_vel = std::max(out.tangent_vel, vel);
    }
  }
  return out;
}

const char* stab_name(Stab s) {
  return s == Stab::none ? "none" : s == Stab::baumgarte ? "baumgarte" : "projection";
}

TEST(ConstraintSensitivities, StabilizationsAgainstFiniteDifferences) {
  const ks::Model model = model_from_text(kSpinningPinnedPendulum);
  std::printf("| rtol | stabilization | recorded s | steps | dy/dm (abs) | dy/dL | dy/dtheta0 | dy/du0 | max|G s+g_p| | max|d(Au)/de| |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  struct Row {
    double rtol;
    Stab stab;
    bool proj;
    double limit;  // on the L, theta0, u0 errors
  };
  // Limits pinned from the measured values (docs/explanation/constraints.md), with 3-5x margin.
  const std::vector<Row> rows = {
      {1e-8, Stab::none, false, 2e-5},         {1e-8, Stab::baumgarte, false, 1e-6},
      {1e-8, Stab::projection, false, 2e-5},   {1e-8, Stab::projection, true, 1.5e-6},
      {1e-10, Stab::none, false, 2e-7},        {1e-10, Stab::baumgarte, false, 3e-8},
      {1e-10, Stab::projection, false, 1e-6},  {1e-10, Stab::projection, true, 1e-6},
  };
  std::map<double, Measured> raw;
  for (const Row& row : rows) {
    const Measured m = measure(model, row.stab, row.rtol, row.proj);
    if (row.stab == Stab::projection && !row.proj) raw[row.rtol] = m;
    std::printf("| %.0e | %s | %s | %ld | %.1e | %.1e | %.1e | %.1e | %.1e | %.1e |\n", row.rtol, stab_name(row.stab),
                row.stab != Stab::projection ? "as integrated" : row.proj ? "projected at outputs" : "raw (CVODES)",
                m.steps, m.err[0], m.err[1], m.err[2], m.err[3], m.tangent_pos, m.tangent_vel);
    for (std::size_t i = 1; i < m.err.size(); ++i)
      EXPECT_LT(m.err[i], row.limit) << kNames[i] << " " << stab_name(row.stab) << " rtol " << row.rtol;
    // ∂y/∂m is exactly 0 (the motion does not depend on m): the figure is the FD noise, the
    // same at both tolerances, and it moves with the last bits of the RHS (3.7e-8 and 2.5e-7
    // measured for two roundings of the same equations; 7e-9 with a 4x larger step).
    EXPECT_LT(m.err[0], 1e-6);
    if (row.stab == Stab::projection && !row.proj) {
      // Pins the CVODES behaviour: the integrated sensitivities are off the tangent space.
      EXPECT_GT(std::max(m.tangent_pos, m.tangent_vel), 1e-9);
    }
    if (row.stab == Stab::projection && row.proj) {
      EXPECT_LT(m.tangent_pos, 1e-12);
      EXPECT_LT(m.tangent_vel, 1e-11);
      const Measured& r = raw.at(row.rtol);
      const double worst_raw = std::max({r.err[1], r.err[2], r.err[3]});
      const double worst = std::max({m.err[1], m.err[2], m.err[3]});
      // Projecting removes the error normal to the constraints, not the tangential one, so in
      // the max norm it is much better at rtol 1e-8 (about 10x: 3.9e-6 -> 3.7e-7) and about
      // equal at 1e-10, where the tangential error dominates (1.1e-7 vs 1.1e-7; 1.9e-7 vs
      // 1.8e-7 after a round-off-level change of the projection): never worse than 25 % plus
      // the finite differences' own noise (~1e-8, see err[0]).
      EXPECT_LE(worst, 1.25 * worst_raw + 1e-8);
    }
  }
}

// Both of CVODES's sensitivity correctors, and the stacked system (which projects the state
// block and keeps the sensitivities' errors in its norm), under projection, against the same
// finite differences and bounds. The simultaneous corrector tests the state's and the sensitivities' local errors as
// one norm, which CVODES's projection step recomputes from the projected state error alone; the
// projection callback puts the sensitivities back (sim/solve/cvodes_callbacks.cpp). Without it
// the simultaneous errors were 8.3e-4 (rtol 1e-6) and 2.5e-5 (rtol 1e-8), growing step by step,
// against staggered's 1.4e-5 and 3.8e-7.
TEST(ConstraintSensitivities, ProjectionWithEitherCorrectorAgainstFiniteDifferences) {
  const ks::Model model = model_from_text(kSpinningPinnedPendulum);
  using ks::sim::SensitivityMethod;
  struct Row {
    double rtol;
    double limit;  // on the L, theta0, u0 errors (staggered measures 1.4e-5 and 3.8e-7)
  };
  for (const Row& row : {Row{1e-6, 5e-5}, Row{1e-8, 1.5e-6}})
    for (SensitivityMethod corrector :
         {SensitivityMethod::staggered, SensitivityMethod::simultaneous, SensitivityMethod::stacked}) {
      const Measured m = measure(model, Stab::projection, row.rtol, true, corrector);
      const std::string name(ks::sim::to_string(corrector));
      std::printf("rtol %.0e %-12s steps %ld  dy/dL %.1e  dy/dtheta0 %.1e  dy/du0 %.1e\n", row.rtol, name.c_str(), m.steps,
                  m.err[1], m.err[2], m.err[3]);
      for (std::size_t i = 1; i < m.err.size(); ++i)
        EXPECT_LT(m.err[i], row.limit) << kNames[i] << " " << name << " rtol " << row.rtol;
      EXPECT_LT(m.err[0], 1e-6) << name;
    }
}

// The recorder projects every sensitivity and differentiates λ along every one in multi-tangent
// passes (KaneProblem::project_sensitivities, multiplier_sensitivities); one at a time, single
// tangents (project_sensitivity, multiplier_sensitivity) give the same numbers to round-off, at
// a state off the constraints and along arbitrary directions. Twenty directions (the four inputs
// five times over) take two blocks, of 16 and 4.
TEST(ConstraintSensitivities, AllAtOnceEqualOneAtATime) {
  const ks::Model model = model_from_text(kSpinningPinnedPendulum);
  std::vector<ks::InputRef> refs;
  std::vector<std::string> names;
  for (int copy = 0; copy < 5; ++copy)
    for (const auto& nm : kNames) {
      refs.push_back(ks::resolve_input(model, nm, "test"));
      names.push_back(nm);
    }
  ks::KaneProblem problem(model, refs, constraint_options(Stab::projection));
  const int n = model.nstate(), m = model.nconstraint_rows, ns = static_cast<int>(refs.size());
  std::vector<double> y(static_cast<std::size_t>(n));
  problem.initial_state(y.data());
  for (int r = 0; r < n; ++r) y[static_cast<std::size_t>(r)] += 1e-3 * std::sin(1.0 + r);
  std::vector<std::vector<double>> all(static_cast<std::size_t>(ns)), one;
  std::vector<double*> columns;
  for (int i = 0; i < ns; ++i) {
    for (int r = 0; r < n; ++r) all[static_cast<std::size_t>(i)].push_back(std::cos(0.7 * i + 1.3 * r) * (1 + i));
    columns.push_back(all[static_cast<std::size_t>(i)].data());
  }
  one = all;
  const double t = 0.4;
  std::vector<double> dl_all(static_cast<std::size_t>(m * ns)), dl_one(static_cast<std::size_t>(m));
  problem.multiplier_sensitivities(t, y.data(), columns.data(), dl_all.data());
  for (int i = 0; i < ns; ++i) {
    problem.multiplier_sensitivity(t, y.data(), i, one[static_cast<std::size_t>(i)].data(), dl_one.data());
    for (int r = 0; r < m; ++r)
      EXPECT_NEAR(dl_all[static_cast<std::size_t>(r * ns + i)], dl_one[static_cast<std::size_t>(r)],
                  1e-12 * (1 + std::abs(dl_one[static_cast<std::size_t>(r)])))
          << "dλ" << r << "/d" << names[static_cast<std::size_t>(i)] << " (direction " << i << ")";
  }
  problem.project_sensitivities(t, y.data(), columns.data());
  double moved = 0;
  for (int i = 0; i < ns; ++i) {
    std::vector<double>& s = one[static_cast<std::size_t>(i)];
    const std::vector<double> before = s;
    problem.project_sensitivity(t, y.data(), i, s.data());
    for (int r = 0; r < n; ++r) {
      const std::size_t k = static_cast<std::size_t>(r);
      moved = std::max(moved, std::abs(s[k] - before[k]));
      EXPECT_NEAR(all[static_cast<std::size_t>(i)][k], s[k], 1e-12 * (1 + std::abs(s[k])))
          << "projected s" << r << " of " << names[static_cast<std::size_t>(i)] << " (direction " << i << ")";
    }
  }
  EXPECT_GT(moved, 1e-3);  // the directions were far from the tangent space
}

// On the 3-D path the recorded dλ/dε come from the stacked right-hand side's residual passes
// (−δλ left in their constraint part); one at a time, the multiplier form's single-tangent
// passes give the same numbers to round-off — rolling disc with Baumgarte terms, twenty
// directions in two blocks, at a state off the constraints.
TEST(ConstraintSensitivities, AllAtOnceMultipliersOnTheThreeDimensionalPath) {
  const ks::Model model =
      ks::build_model(ks::parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/rolling_disc.yaml"));
  const std::vector<std::string> inputs = {"m", "r", "base.u0[0]", "base.q0[4]"};
  std::vector<ks::InputRef> refs;
  for (int copy = 0; copy < 5; ++copy)
    for (const auto& nm : inputs) refs.push_back(ks::resolve_input(model, nm, "test"));
  ks::KaneProblem problem(model, refs, constraint_options(Stab::baumgarte));
  problem.set_sample(ks::SampleInputs(model));
  const int n = model.nstate(), m = model.nconstraint_rows, ns = static_cast<int>(refs.size());
  std::vector<double> y(static_cast<std::size_t>(n));
  problem.initial_state(y.data());
  for (int r = 0; r < n; ++r) y[static_cast<std::size_t>(r)] += 1e-2 * std::sin(1.0 + r);
  std::vector<std::vector<double>> dirs(static_cast<std::size_t>(ns));
  std::vector<const double*> columns;
  for (int i = 0; i < ns; ++i) {
    for (int r = 0; r < n; ++r) dirs[static_cast<std::size_t>(i)].push_back(std::cos(0.7 * i + 1.3 * r) * (1 + i));
    columns.push_back(dirs[static_cast<std::size_t>(i)].data());
  }
  std::vector<double> dl_all(static_cast<std::size_t>(m * ns)), dl_one(static_cast<std::size_t>(m));
  problem.multiplier_sensitivities(0.4, y.data(), columns.data(), dl_all.data());
  double largest = 0;
  for (int i = 0; i < ns; ++i) {
    problem.multiplier_sensitivity(0.4, y.data(), i, dirs[static_cast<std::size_t>(i)].data(), dl_one.data());
    for (int r = 0; r < m; ++r) {
      largest = std::max(largest, std::abs(dl_one[static_cast<std::size_t>(r)]));
      EXPECT_NEAR(dl_all[static_cast<std::size_t>(r * ns + i)], dl_one[static_cast<std::size_t>(r)],
                  1e-12 * (1 + std::abs(dl_one[static_cast<std::size_t>(r)])))
          << "dλ" << r << "/d" << inputs[static_cast<std::size_t>(i % 4)] << " (direction " << i << ")";
    }
  }
  EXPECT_GT(largest, 1.0);  // the directions move λ
  // λ with them (the recorder's call): the residual pass's own λ, the multiplier form's to
  // round-off; the same dλ/dε.
  std::vector<double> lambda(static_cast<std::size_t>(m)), lambda_rhs(lambda.size()), dl_with(dl_all.size());
  problem.multipliers_and_sensitivities(0.4, y.data(), columns.data(), lambda.data(), dl_with.data());
  problem.multipliers(0.4, y.data(), lambda_rhs.data());
  for (int r = 0; r < m; ++r)
    EXPECT_NEAR(lambda[static_cast<std::size_t>(r)], lambda_rhs[static_cast<std::size_t>(r)],
                1e-12 * (1 + std::abs(lambda_rhs[static_cast<std::size_t>(r)])))
        << "λ" << r;
  EXPECT_EQ(dl_with, dl_all);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
