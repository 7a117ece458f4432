// Closed loops and couplers against their one-degree-of-freedom reductions, integrated here by a
// fixed-step RK4 (h = 1e-3, error ≪ 1e-9 over these horizons).
//
//  * ParallelogramFourBarMatchesOneDofReduction: crank and rocker identical rods (mass m, length
//    L) pivoted at ground points a distance d apart, coupler rod (mass m_c, length d) pinned to
//    the crank tip, loop closed by a `coincident` constraint between the coupler's far end and the
//    rocker tip. The coupler translates without rotating, its center moving like the crank tip
//    (speed L θ̇), so with θ the crank angle from the downward vertical
//        T = ½ (2 m L²/3 + m_c L²) θ̇²,   V = −(m g L/2 · 2 + m_c g L) cos θ
//    and θ̈ = −g sin θ (m L + m_c L) / (2 m L²/3 + m_c L²).
//  * GearCouplerMatchesOneDofReduction: wheel a (disc, center on its axis) and wheel b (disc whose
//    center is e below its pivot) linked by `coupler` u_a = k u_b (k = −2). With θ = q_b,
//        (I_a k² + I_b + m_b e²) θ̈ = −m_b g e sin θ,
//    and λ (generalized force on joint_a's speed) = I_a q̈_a = I_a k θ̈.
#include <gtest/gtest.h>

#include <cstdio>

#include "../support/constraint_test_support.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

constexpr double kG = 9.81;

constexpr const char* kParallelogram = R"yaml(
kanesens: 1
scene:
  name: parallelogram_four_bar
  gravity: [0, -9.81, 0]
  parameters: {m: 1.0, mc: 0.7, L: 1.0, d: 1.5, th0: 0.6}
  bodies:
    - {name: crank, mass: m, inertia: {shape: rod, length: L, axis: y}}
    - {name: coupler, mass: mc, inertia: {shape: rod, length: d, axis: x}}
    - {name: rocker, mass: m, inertia: {shape: rod, length: L, axis: y}}
  joints:
    - {name: crank_j, type: revolute, parent: ground, child: crank, axis: [0, 0, 1],
       child_point: [0, "L/2", 0], q0: th0}
    - {name: elbow, type: revolute, parent: crank, child: coupler, axis: [0, 0, 1],
       parent_point: [0, "-L/2", 0], child_point: ["-d/2", 0, 0], q0: "-th0"}
    - {name: rocker_j, type: revolute, parent: ground, child: rocker, axis: [0, 0, 1],
       parent_point: [d, 0, 0], child_point: [0, "L/2", 0], q0: th0}
  constraints:
    - {name: loop, type: coincident, body_a: coupler, point_a: ["d/2", 0, 0], body_b: rocker, point_b: [0, "-L/2", 0]}
)yaml";

TEST(ConstraintLoops, ParallelogramFourBarMatchesOneDofReduction) {
  const ks::Model model = model_from_text(kParallelogram);
  ASSERT_EQ(model.nconstraint_rows, 2);
  const double m = 1.0, mc = 0.7, L = 1.0;
  const double k = kG * (m * L + mc * L) / (2 * m * L * L / 3 + mc * L * L);
  const auto times = linspace(0, 8, 81);
  const auto ref = rk4<2>([&](const std::array<double, 2>& x) {
    return std::array<double, 2>{x[1], -k * std::sin(x[0])};
  }, {0.6, 0.0}, times, 1e-3);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r = run(model, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
    double worst = 0, worst_u = 0, worst_shape = 0;
    for (int i = 0; i < static_cast<int>(times.size()); ++i) {
      const auto& x = ref[static_cast<std::size_t>(i)];
      worst = std::max(worst, std::abs(r.y(i, 0) - x[0]));
      worst_u = std::max(worst_u, std::abs(r.y(i, 3) - x[1]));
      // parallelogram shape: elbow = −θ, rocker = θ
      worst_shape = std::max({worst_shape, std::abs(r.y(i, 1) + r.y(i, 0)), std::abs(r.y(i, 2) - r.y(i, 0))});
    }
    std::printf("parallelogram four-bar (stabilization %d): max |θ − θ_rk4| %.2e, max |θ̇ − θ̇_rk4| %.2e, "
                "shape %.2e, steps %ld\n", static_cast<int>(stab), worst, worst_u, worst_shape, r.tr.result.stats.steps);
    EXPECT_LT(worst, 1e-7);
    EXPECT_LT(worst_u, 1e-7);
    EXPECT_LT(worst_shape, 1e-7);
  }
}

constexpr const char* kGears = R"yaml(
kanesens: 1
scene:
  name: geared_wheels
  gravity: [0, -9.81, 0]
  parameters: {ma: 2.0, ra: 0.3, mb: 1.5, rb: 0.5, e: 0.2, k: -2.0}
  bodies:
    - {name: wheel_a, mass: ma, inertia: {shape: cylinder, radius: ra, length: 0.05, axis: z}}
    - {name: wheel_b, mass: mb, inertia: {shape: cylinder, radius: rb, length: 0.05, axis: z}}
  joints:
    - {name: ja, type: revolute, parent: ground, child: wheel_a, axis: [0, 0, 1], q0: -2.0}
    - {name: jb, type: revolute, parent: ground, child: wheel_b, axis: [0, 0, 1],
       parent_point: [0.8, 0, 0], child_point: [0, e, 0], q0: 1.0}
  constraints:
    - {name: mesh, type: coupler, joint_a: ja, joint_b: jb, ratio: k, offset: 0}
)yaml";

TEST(ConstraintLoops, GearCouplerMatchesOneDofReduction) {
  const ks::Model model = model_from_text(kGears);
  ASSERT_EQ(model.nconstraint_rows, 1);
  const double ma = 2.0, ra = 0.3, mb = 1.5, rb = 0.5, e = 0.2, k = -2.0;
  const double Ia = ma * ra * ra / 2, Ib = mb * rb * rb / 2;
  const double J = Ia * k * k + Ib + mb * e * e;
  const auto times = linspace(0, 6, 61);
  const auto ref = rk4<2>([&](const std::array<double, 2>& x) {
    return std::array<double, 2>{x[1], -mb * kG * e * std::sin(x[0]) / J};
  }, {1.0, 0.0}, times, 1e-3);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r = run(model, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
    double worst = 0, worst_a = 0, worst_l = 0, peak_l = 0;
    for (int i = 0; i < static_cast<int>(times.size()); ++i) {
      const auto& x = ref[static_cast<std::size_t>(i)];
      const double th = r.y(i, 1);
      worst = std::max(worst, std::abs(th - x[0]));
      worst_a = std::max(worst_a, std::abs(r.y(i, 0) - k * th));
      const double lam = Ia * k * (-mb * kG * e * std::sin(th) / J);
      worst_l = std::max(worst_l, std::abs(r.lambda(i, 0) - lam));
      peak_l = std::max(peak_l, std::abs(lam));
    }
    std::printf("gear coupler k = -2 (stabilization %d): max |θ_b − θ_rk4| %.2e, max |q_a − k q_b| %.2e, "
                "max |λ − I_a k θ̈| / peak %.2e (peak %.3g N·m)\n",
                static_cast<int>(stab), worst, worst_a, worst_l / peak_l, peak_l);
    EXPECT_LT(worst, 1e-7);
    EXPECT_LT(worst_a, 1e-7);
    EXPECT_LT(worst_l / peak_l, 1e-9);
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
