// The embedding re-chooses its independent speeds when its partition degrades (coordinate
// partitioning with re-selection): a turning knife-edge vehicle over several full turns (its one
// dependent speed's coefficient passes through zero twice a turn) against the closed form and
// the multiplier formulation, for BDF, Adams (dense and matrix-free Newton) and DOP853, with
// sensitivities; the parallelogram
// four-bar through its toggle positions; a sample whose constraints lose rank fails naming them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../support/constraint_test_support.hpp"
#include "../support/layers.hpp"
#include "model/yaml_reader.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

// A sled on a horizontal planar joint whose blade (at the mass centre) cannot slip sideways:
// −sin θ ẋ + cos θ ẏ = 0. Started at speed v along x turning at ω, it runs round the circle
// x = (v/ω) sin ωt, y = (v/ω)(1 − cos ωt), θ = ωt, at constant speed and energy.
constexpr double kV = 1.5, kW = 2.0;
constexpr const char* kKnifeEdge = R"yaml(
kanesens: 1
scene:
  name: knife_edge
  gravity: [0, 0, -9.81]
  parameters: {m: 2.0, I: 0.3, v: 1.5, w: 2.0}
  bodies:
    - {name: sled, mass: m, inertia: {xx: 0.2, yy: 0.2, zz: I}}
  joints:
    - {name: base, type: planar, parent: ground, child: sled, axis: [0, 0, 1], q0: [0, 0, 0], u0: [v, 0, w]}
  constraints:
    - {name: blade, type: general, a: {base.u1: "-sin(base.q3)", base.u2: "cos(base.q3)"}}
)yaml";

sim::SolverOptions with_method(Method m, double rtol, double atol) {
  sim::SolverOptions o = tolerances(rtol, atol);
  o.method = m;
  return o;
}

ConstraintOptions formulation(ConstraintOptions::Formulation f, Stab s) {
  ConstraintOptions c = constraint_options(s);
  c.formulation = f;
  return c;
}

TEST(EmbeddingRepartition, KnifeEdgeTurnsSeveralTimesUnderEveryMethod) {
  const ks::Model model = model_from_text(kKnifeEdge);
  const auto times = linspace(0, 10, 101);  // 20 rad: 3.2 turns
  const std::vector<std::string> sens = {"v", "m"};
  // Newton with matrix-free GMRES too (linear_solver krylov): through the restarts, with Adams.
  for (const auto& [method, linear_solver] :
       {std::pair{Method::bdf, LinearSolver::dense}, std::pair{Method::adams, LinearSolver::dense},
        std::pair{Method::dop853, LinearSolver::automatic}, std::pair{Method::bdf, LinearSolver::krylov},
        std::pair{Method::adams, LinearSolver::krylov}}) {
    sim::SolverOptions so = with_method(method, 1e-10, 1e-12);
    so.linear_solver = linear_solver;
    const TrajRun e = run(model, times, formulation(ConstraintOptions::Formulation::embedding, Stab::none), so, sens);
    const TrajRun l = run(model, times,
                          formulation(ConstraintOptions::Formulation::multipliers,
                                      method == Method::adams ? Stab::baumgarte : Stab::projection),
                          so, sens);
    ASSERT_TRUE(e.tr.result.ok()) << e.tr.result.message;
    ASSERT_TRUE(l.tr.result.ok()) << l.tr.result.message;
    double closed = 0, vs_multipliers = 0, energy = 0, sens_closed = 0, residual = 0;
    const double E0 = e.tr.energy[0];
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      const double t = times[static_cast<std::size_t>(k)], c = std::cos(kW * t), s = std::sin(kW * t);
      const double exact[6] = {kV / kW * s, kV / kW * (1 - c), kW * t, kV * c, kV * s, kW};
      // ∂/∂v of the closed form; ∂/∂m = 0 (the motion does not depend on the mass).
      const double dv[6] = {s / kW, (1 - c) / kW, 0, c, s, 0};
      for (int r = 0; r < 6; ++r) {
        closed = std::max(closed, std::abs(e.y(k, r) - exact[r]));
        vs_multipliers = std::max(vs_multipliers, std::abs(e.y(k, r) - l.y(k, r)));
        sens_closed = std::max({sens_closed, std::abs(e.s(k, r, 0) - dv[r]), std::abs(e.s(k, r, 1))});
      }
      energy = std::max(energy, std::abs(e.tr.energy[static_cast<std::size_t>(k)] - E0) / E0);
      residual = std::max(residual, e.tr.velocity_residual[static_cast<std::size_t>(k)]);
    }
    const auto& st = e.tr.result.stats;
    std::printf("measure: knife edge, 3.2 turns, %s/%s: embedding vs closed form %.1e, vs multipliers %.1e, relative "
                "energy drift %.1e, sensitivities vs closed form %.1e, velocity residual %.1e; repartitions %ld, "
                "steps %ld (multipliers %ld), rhs %ld (%ld)\n",
                std::string(to_string(method)).c_str(), std::string(to_string(linear_solver)).c_str(), closed, vs_multipliers, energy, sens_closed, residual,
                st.repartitions, st.steps, l.tr.result.stats.steps, st.rhs_evals, l.tr.result.stats.rhs_evals);
    EXPECT_LT(closed, 1e-7);
    EXPECT_LT(vs_multipliers, 1e-7);
    EXPECT_LT(energy, 1e-7);
    EXPECT_LT(sens_closed, 1e-7);
    EXPECT_LT(residual, 1e-12);
    // The heading crosses the singular positions of each partition 13 times; one re-choice each.
    EXPECT_GE(st.repartitions, 10);
    EXPECT_LE(st.repartitions, 16);
  }
}

TEST(EmbeddingRepartition, RunsAgainFromTheInitialPartition) {
  // The same problem integrated twice (an ensemble's next sample does this): the second run
  // starts from the t0 partition again and repeats the first bit for bit.
  const ks::Model model = model_from_text(kKnifeEdge);
  KaneProblem problem(model, {}, formulation(ConstraintOptions::Formulation::embedding, Stab::none));
  problem.set_sample(SampleInputs(model));
  for (Method method : {Method::bdf, Method::dop853}) {
    sim::Integrator integ(with_method(method, 1e-9, 1e-11));
    RecordFlags flags;
    Trajectory a, b;
    const auto times = linspace(0, 5, 11);
    simulate(problem, integ, times, flags, a);
    simulate(problem, integ, times, flags, b);
    ASSERT_TRUE(a.result.ok() && b.result.ok());
    EXPECT_GT(a.result.stats.repartitions, 0);
    EXPECT_EQ(a.states, b.states);
    EXPECT_EQ(a.result.stats.repartitions, b.result.stats.repartitions);
  }
}

TEST(EmbeddingRepartition, ParallelogramFourBarThroughItsToggles) {
  // Crank at 12 rad/s: about three turns in 3 s through the collinear positions, where A loses
  // rank for an instant (tests/python/test_stability_toggle.py has the multipliers' side). The
  // embedding needs the projection there (bdf, dop853): without it (adams) the drift lets the
  // linkage take the anti-parallelogram branch (docs/explanation/constraints.md).
  const ks::Model model = build_model(parse_scene_text(
      model::read_text_file(std::string(KANESENS_SOURCE_DIR) + "/configs/parallelogram_four_bar.yaml"), "p.yaml"));
  const auto times = linspace(0, 3, 301);
  const TrajRun l = run(model, times, formulation(ConstraintOptions::Formulation::multipliers, Stab::projection),
                        with_method(Method::bdf, 1e-9, 1e-11), {}, {{"w1", 12}});
  ASSERT_TRUE(l.tr.result.ok()) << l.tr.result.message;
  for (Method method : {Method::bdf, Method::dop853}) {
    const TrajRun e = run(model, times, formulation(ConstraintOptions::Formulation::embedding, Stab::projection),
                          with_method(method, 1e-9, 1e-11), {}, {{"w1", 12}});
    ASSERT_TRUE(e.tr.result.ok()) << to_string(method) << ": " << e.tr.result.message;
    double crank = 0, shape = 0, lo = 0, hi = 0, energy = 0;
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      crank = std::max(crank, std::abs(e.y(k, 0) - l.y(k, 0)));
      shape = std::max(shape, std::abs(e.y(k, 2) - e.y(k, 0)));  // rocker angle = crank angle
      lo = std::min(lo, e.y(k, 0));
      hi = std::max(hi, e.y(k, 0));
      energy = std::max(energy, std::abs(e.tr.energy[static_cast<std::size_t>(k)] - e.tr.energy[0]));
    }
    energy /= std::abs(e.tr.energy[0]);
    std::printf("measure: parallelogram four-bar through its toggles, %s: crank turned %.1f rad, embedding vs "
                "multipliers (bdf) %.1e, parallelogram shape %.1e, relative energy drift %.1e, repartitions %ld, "
                "steps %ld (multipliers, bdf: %ld)\n",
                std::string(to_string(method)).c_str(), hi - lo, crank, shape, energy, e.tr.result.stats.repartitions,
                e.tr.result.stats.steps, l.tr.result.stats.steps);
    EXPECT_GT(hi - lo, 6 * M_PI);
    EXPECT_LT(crank, 1e-4);
    EXPECT_LT(shape, 1e-7);
    EXPECT_LT(energy, 1e-5);
  }
}

TEST(EmbeddingRepartition, RankLossFailsTheSampleNamingTheRows) {
  // Two rows on a planar body, ẋ = 0 and ẋ + max(0, 1 − t) ẏ = 0: from t = 1 on they are the
  // same row, and no two speeds can be solved from them.
  const ks::Model model = model_from_text(R"yaml(
kanesens: 1
scene:
  name: rank_loss
  gravity: [0, 0, -9.81]
  bodies:
    - {name: b, mass: 1, inertia: {xx: 0.2, yy: 0.2, zz: 0.3}}
  joints:
    - {name: base, type: planar, parent: ground, child: b, axis: [0, 0, 1], u0: [0, 0, 1]}
  constraints:
    - {name: stop_x, type: general, a: {base.u1: 1}}
    - {name: fading, type: general, a: {base.u1: 1, base.u2: "max(0, 1 - t)"}}
)yaml");
  for (Method method : {Method::bdf, Method::dop853}) {
    const TrajRun e = run(model, linspace(0, 2, 5), formulation(ConstraintOptions::Formulation::embedding, Stab::none),
                          with_method(method, 1e-8, 1e-10));
    std::printf("rank loss, %s: status %d, message: %s\n", std::string(to_string(method)).c_str(), e.tr.result.status,
                e.tr.result.message.c_str());
    EXPECT_LT(e.tr.result.status, 0);
    EXPECT_NE(e.tr.result.message.find("constraint rows stop_x, fading"), std::string::npos) << e.tr.result.message;
    EXPECT_NE(e.tr.result.message.find("lost rank"), std::string::npos);
    EXPECT_NEAR(e.tr.result.t_fail, 1.0, 1e-3);
    // The multipliers formulation takes the redundant rows in its stride (minimum-norm λ).
    const TrajRun l = run(model, linspace(0, 2, 5), constraint_options(Stab::projection), with_method(method, 1e-8, 1e-10));
    EXPECT_TRUE(l.tr.result.ok()) << l.tr.result.message;
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
