// The Jacobian from the residual's derivatives in closed form (dynamics/residual_derivatives.hpp,
// KaneProblem::DerivativeMethod::closed_form) must equal the multi-tangent residual pass and the
// whole right-hand side's passes to round-off, and the central differences of the right-hand
// side to their truncation error: on the 3-D benchmark chains and on a branched tree of every
// joint type it covers (revolute, prismatic, cylindrical, universal, planar with a tilted normal,
// weld) with joint springs and dampers, three trees (one whose root joint translates its anchor),
// an anchor far from the world origin and tilted
// gravity, at random states; with force elements and expressions of t, q and u (their pass on
// dual numbers, dynamics::evaluate_applied_forces) on the 3-D arm and on the same tree with
// loads added. jacobian() must take it there and must not where it does not apply (planar
// scenes, constraints, quaternions) or where ydot is not f(t, y).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "dynamics/residual_derivatives.hpp"
#include "jacobian_checks.hpp"
#include "kane_test_support.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;
using Method = KaneProblem::DerivativeMethod;

// Every joint type the closed form covers, in a branched tree whose anchor is far from the
// world origin, plus a second tree; full inertia tensors, mass centres off the joint axes.
const char* kZoo = R"(kanesens: 1
scene:
  name: zoo
  gravity: [1.5, -9.0, 2.5]
  parameters: {k: 7.0, c: 0.3}
  bodies:
    - {name: base, mass: 2.0, inertia: {xx: 0.05, yy: 0.04, zz: 0.06, xy: 0.004, yz: -0.003, xz: 0.002}}
    - {name: slider, mass: 0.7, inertia: {xx: 0.01, yy: 0.02, zz: 0.015, xy: -0.001, yz: 0.002, xz: 0.0005}}
    - {name: gimbal, mass: 0.4, inertia: {xx: 0.003, yy: 0.004, zz: 0.002, xy: 0.0003, yz: 0.0001, xz: -0.0002}}
    - {name: screw, mass: 0.5, inertia: {shape: cylinder, radius: 0.05, length: 0.4, axis: x}}
    - {name: puck, mass: 0.6, inertia: {xx: 0.004, yy: 0.005, zz: 0.007, xy: 0.0002, yz: -0.0004, xz: 0.0003}}
    - {name: tag, mass: 0.2, inertia: {shape: box, size: [0.1, 0.2, 0.05]}}
    - {name: arm, mass: 1.1, inertia: {shape: rod, length: 0.8, axis: y}}
    - {name: forearm, mass: 0.9, inertia: {xx: 0.02, yy: 0.003, zz: 0.021, xy: 0.001, yz: 0.0, xz: 0.0}}
    - {name: sled, mass: 1.3, inertia: {xx: 0.03, yy: 0.02, zz: 0.04, xy: 0.002, yz: 0.001, xz: -0.001}}
    - {name: pendulum, mass: 0.5, inertia: {shape: rod, length: 0.6, axis: z}}
  joints:
    - {name: yaw, type: revolute, parent: ground, child: base, axis: [0.1, 0.2, 1],
       parent_point: [40, -25, 12], child_point: [0.02, -0.01, -0.1], spring: {k: k, rest: 0.1}, damper: {c: c}}
    - {name: lift, type: prismatic, parent: base, child: slider, axis: [0.3, -0.2, 1],
       parent_point: [0.1, 0.05, 0.2], child_point: [0.03, 0.02, -0.15], spring: {k: k}, damper: {c: c}}
    - {name: wrist, type: universal, parent: slider, child: gimbal, axes: [[1, 0.2, 0], [0.1, 1, 0.3]],
       parent_point: [0, 0.1, 0.2], child_point: [0.05, -0.02, 0.1]}
    - {name: feed, type: cylindrical, parent: gimbal, child: screw, axis: [1, 0.1, -0.2],
       parent_point: [0.1, 0, 0.05], child_point: [-0.2, 0.01, 0.02]}
    - {name: table, type: planar, parent: base, child: puck, axis: [0.2, 0.1, 1],
       parent_point: [-0.2, 0.1, 0.05], child_point: [0.04, -0.03, 0.01]}
    - {name: glue, type: weld, parent: puck, child: tag, parent_point: [0.05, 0.05, 0], child_point: [0, 0.1, 0]}
    - {name: shoulder, type: revolute, parent: ground, child: arm, axis: [1, 0, 0.3],
       parent_point: [-3, 2, 1], child_point: [0, 0.4, 0.01], damper: {c: c}}
    - {name: elbow, type: revolute, parent: arm, child: forearm, axis: [0, 0.2, 1],
       parent_point: [0.01, -0.4, 0], child_point: [0, 0.35, -0.02], spring: {k: k, rest: -0.2}}
    - {name: slide, type: planar, parent: ground, child: sled, axis: [0.1, -0.3, 1],
       parent_point: [5, 1, -2], child_point: [0.1, 0.05, 0.02]}
    - {name: swing, type: revolute, parent: sled, child: pendulum, axis: [0, 1, 0.2],
       parent_point: [0, 0, -0.1], child_point: [0.01, 0, 0.3]}
)";

// Loads for the tree: a spring-damper between two bodies of different trees, one to the ground,
// a body-frame force and a torque that read t, q and u, a joint spring whose stiffness reads t.
const char* kLoads = R"yaml(  forces:
    - {type: spring_damper, body_a: screw, point_a: [0.1, 0.02, 0], body_b: forearm, point_b: [0, -0.3, 0.05],
       k: 12, c: 0.4, rest: 0.3}
    - {type: spring_damper, body_a: tag, point_a: [0.02, 0, 0.01], body_b: ground, point_b: [40, -24, 13],
       k: "k * (1 + 0.1 * sin(t))", c: c, rest: 0.2}
    - {type: force, body: puck, point: [0.01, 0.02, 0], vector: ["0.3 * lift.q", "-0.2 * yaw.u", "sin(t)"], frame: body}
    - {type: torque, body: gimbal, vector: ["-0.05 * wrist.u1", "0.02 * feed.q2 * table.u3", 0.01], frame: world}
    - {type: spring_damper, body_a: pendulum, point_a: [0, 0.02, -0.3], body_b: ground, point_b: [5.5, 0.5, -3],
       k: 9, c: 0.2, rest: 0.4}
    - {type: spring_damper, body_a: sled, point_a: [0.05, 0, 0], body_b: arm, point_b: [0, -0.2, 0], k: 3, c: 0.1}
)yaml";

// A random state: coordinates and speeds spread around zero.
std::vector<double> random_state(int n, std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> d(-spread, spread);
  std::vector<double> y(static_cast<std::size_t>(n));
  for (double& v : y) v = d(rng);
  return y;
}

double max_abs(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s = std::max(s, std::abs(x));
  return s;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s = std::max(s, std::abs(a[i] - b[i]));
  return s;
}

TEST(ClosedFormJacobian, MatchesTheDualPassesAndDifferences) {
  const std::vector<std::pair<std::string, Model>> scenes = {
      {"chain8_spatial", model_from_source_file("bench/configs/chain8_spatial.yaml")},
      {"chain10_spatial", model_from_source_file("bench/configs/chain10_spatial.yaml")},
      {"zoo", model_from_text(kZoo)},
      {"arm_3d", model_from_source_file("configs/arm_3d.yaml")},
      {"zoo with loads", model_from_text(std::string(kZoo) + kLoads)},
  };
  // The chains' M is dense; the branched tree's is factored along the tree: both solves are used.
  EXPECT_FALSE(kanesens::dynamics::Workspace<double>(scenes[0].second).tree_factor);
  EXPECT_TRUE(kanesens::dynamics::Workspace<double>(scenes[2].second).tree_factor);
  EXPECT_FALSE(kanesens::dynamics::ResidualDerivatives::needs_applied_pass(scenes[2].second));
  EXPECT_TRUE(kanesens::dynamics::ResidualDerivatives::needs_applied_pass(scenes[3].second));
  EXPECT_TRUE(kanesens::dynamics::ResidualDerivatives::needs_applied_pass(scenes[4].second));
  std::mt19937 rng(29);
  for (const auto& [name, m] : scenes) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(kanesens::dynamics::ResidualDerivatives::applies(m));
    KaneProblem p(m, {});
    p.set_sample(SampleInputs(m));
    const int n = p.size();
    for (int trial = 0; trial < 4; ++trial) {
      const std::vector<double> y = random_state(n, rng, trial == 0 ? 0.0 : 1.2);
      std::vector<double> ydot(static_cast<std::size_t>(n));
      p.rhs(0.3, y.data(), ydot.data());
      std::vector<double> J(static_cast<std::size_t>(n) * n), Jr(J.size()), Jw(J.size());
      p.set_jacobian_method(Method::closed_form);
      p.jacobian(0.3, y.data(), ydot.data(), J.data());
      EXPECT_EQ(p.last_jacobian_method(), Method::closed_form);
      p.set_jacobian_method(Method::residual);
      p.jacobian(0.3, y.data(), ydot.data(), Jr.data());
      EXPECT_EQ(p.last_jacobian_method(), Method::residual);
      p.set_jacobian_method(Method::whole_rhs);
      p.jacobian(0.3, y.data(), ydot.data(), Jw.data());
      const double scale = std::max(1.0, max_abs(Jw));
      const double err_residual = max_diff(J, Jr) / scale, err_whole = max_diff(J, Jw) / scale;
      EXPECT_LT(err_residual, 1e-11) << "closed form vs residual pass, trial " << trial;
      EXPECT_LT(err_whole, 1e-11) << "closed form vs whole right-hand side, trial " << trial;

      const double efd = central_difference_error(p, 0.3, y, J, scale);
      EXPECT_LT(efd, 1e-6) << "closed form vs central differences, trial " << trial;
      std::printf("%s trial %d: closed form vs residual %.2e, vs whole %.2e, vs differences %.2e (n = %d)\n",
                  name.c_str(), trial, err_residual, err_whole, efd, n);
    }
  }
}

TEST(ClosedFormJacobian, IsNotTakenWhereItDoesNotApply) {
  // Planar scene, constraints, quaternions.
  for (const char* scene : {"configs/nlink_chain_4.yaml", "configs/four_bar.yaml", "configs/spinning_top.yaml"}) {
    SCOPED_TRACE(scene);
    const Model m = model_from_source_file(scene);
    EXPECT_FALSE(kanesens::dynamics::ResidualDerivatives::applies(m));
    KaneProblem p(m, {});
    p.set_sample(SampleInputs(m));
    std::vector<double> y(static_cast<std::size_t>(p.size())), ydot(y.size()), J(y.size() * y.size());
    p.initial_state(y.data());
    p.rhs(0.1, y.data(), ydot.data());
    p.jacobian(0.1, y.data(), ydot.data(), J.data());
    EXPECT_NE(p.last_jacobian_method(), Method::closed_form);
  }
}

TEST(ClosedFormJacobian, FallsBackWhenYdotIsNotTheRightHandSide) {
  // Then the residual does not vanish: the result must be a Jacobian at y (the whole
  // right-hand side's, which does not use ydot), not one at other accelerations.
  for (const std::string& text : {std::string(kZoo), std::string(kZoo) + kLoads}) {
  const Model m = model_from_text(text);
  KaneProblem p(m, {});
  p.set_sample(SampleInputs(m));
  std::mt19937 rng(5);
  const int n = p.size();
  const std::vector<double> y = random_state(n, rng, 0.8);
  std::vector<double> ydot(static_cast<std::size_t>(n)), J(static_cast<std::size_t>(n) * n), Jw(J.size());
  p.rhs(0.0, y.data(), ydot.data());
  p.jacobian(0.0, y.data(), ydot.data(), J.data());
  EXPECT_EQ(p.last_jacobian_method(), Method::closed_form);
  std::vector<double> wrong(ydot);
  wrong.back() += 1e-4 * (1 + std::abs(wrong.back()));
  p.jacobian(0.0, y.data(), wrong.data(), Jw.data());
  EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs);
  EXPECT_LT(max_diff(J, Jw) / std::max(1.0, max_abs(J)), 1e-11);
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
