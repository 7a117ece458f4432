// The articulated-body algorithm (dynamics/articulated_body.cpp) against u̇ = M⁻¹ f (the mass
// matrix and forcing that match SymPy's KanesMethod, test_kane_golden): a different algorithm
// (three O(n) sweeps, no M) must give the same accelerations, on every joint type, with every
// kind of force, at random states; a physical pendulum against its closed form; and the
// workspace chooses it only where it applies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>

#include "dynamics/equations.hpp"
#include "math/multi_dual.hpp"
#include "kane_test_support.hpp"
#include "test_scenes.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

struct Case {
  const char* name;
  std::string text;
};

// A chain of n links on ball joints (3 speeds each), hanging from the ground.
// A cart on a spring and damper carrying two poles, pushed and braked: planar, one speed per joint.
const char* kCartPoles = R"yaml(kanesens: 1
scene:
  name: cart_poles
  gravity: [0, -9.81, 0]
  parameters: {k: 20, c: 0.3, F0: 2}
  bodies:
    - {name: cart, mass: 2, inertia: {shape: box, size: [0.4, 0.2, 0.2]}}
    - {name: pole, mass: 0.5, inertia: {shape: rod, length: 1, axis: y}}
    - {name: tip, mass: 0.3, inertia: {shape: rod, length: 0.6, axis: y}}
  joints:
    - {name: slide, type: prismatic, parent: ground, child: cart, axis: [1, 0.2, 0],
       spring: {k: k, rest: 0.1}, damper: {c: c}}
    - {name: hinge, type: revolute, parent: cart, child: pole, axis: [0, 0, 1],
       parent_point: [0.1, 0.05, 0], child_point: [0, -0.5, 0], damper: {c: "c*hinge.u^2"}}
    - {name: elbow, type: revolute, parent: pole, child: tip, axis: [0, 0, 1],
       parent_point: [0, 0.5, 0], child_point: [0, -0.3, 0]}
  forces:
    - {type: force, name: push, body: cart, point: [0, 0.1, 0], vector: ["F0*sin(3*t)", 0, 0],
       frame: world}
    - {type: torque, name: brake, body: pole, vector: [0, 0, "-0.1*hinge.u"], frame: body}
)yaml";

// A branched tree: the torso carries three limbs and one of them two more (the sweep from the
// leaves adds several children's shares to one parent), with inertias diagonal and not at the
// joint points, axes along coordinate axes and not, and a prismatic joint.
const char* kBranched = R"yaml(kanesens: 1
scene:
  name: branched
  gravity: [0, -9.81, 0]
  parameters: {m: 1.2, k: 5}
  bodies:
    - {name: torso, mass: 3, inertia: {xx: 0.2, yy: 0.1, zz: 0.15, xy: 0.01}}
    - {name: left, mass: m, inertia: {shape: rod, length: 0.8, axis: y}}
    - {name: right, mass: 0.9, inertia: {shape: rod, length: 0.7, axis: y}}
    - {name: head, mass: 0.5, inertia: {shape: sphere, radius: 0.1}}
    - {name: hand, mass: 0.2, inertia: {xx: 0.01, yy: 0.02, zz: 0.015, yz: 0.002}}
    - {name: finger, mass: 0.1, inertia: {shape: rod, length: 0.2, axis: x}}
  joints:
    - {name: waist, type: revolute, parent: ground, child: torso, axis: [0, 1, 0], child_point: [0, -0.3, 0]}
    - {name: lshoulder, type: revolute, parent: torso, child: left, axis: [1, 0, 0],
       parent_point: [-0.2, 0.3, 0], child_point: [0, 0.4, 0]}
    - {name: rshoulder, type: revolute, parent: torso, child: right, axis: [0, 0.6, 0.8],
       parent_point: [0.2, 0.3, 0.05], child_point: [0.05, 0.35, 0]}
    - {name: neck, type: prismatic, parent: torso, child: head, axis: [0, 1, 0], parent_point: [0, 0.35, 0],
       spring: {k: k, rest: 0.05}}
    - {name: wrist, type: revolute, parent: right, child: hand, axis: [0, 0, 1],
       parent_point: [0, -0.35, 0], child_point: [0.1, 0.05, 0]}
    - {name: knuckle, type: revolute, parent: right, child: finger, axis: [1, 1, 0],
       parent_point: [0, -0.3, 0.05], child_point: [-0.1, 0, 0]}
)yaml";

std::vector<Case> cases() {
  return {{"chain_tilted_8", test_scenes::chain_scene(8, 0.1)},
          {"chain_tilted_long", test_scenes::chain_scene(dynamics::kArticulatedBodyMinSpeeds + 3, 0.1)},
          {"ball_chain", test_scenes::ball_chain(5)},
          {"chain_planar_8", test_scenes::chain_scene(8)},
          {"cart_double_pole_planar", kCartPoles},
          {"spherical", test_scenes::kSphericalScene},
          {"free_universal_cylindrical", test_scenes::kFreeScene},
          {"forces_prismatic_planar", test_scenes::kForcesScene},
          {"branched_tree", kBranched}};
}

TEST(ArticulatedBody, AcceleratesAsTheMassMatrixSolve) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(c.name);
    Model m = model_from_text(c.text);
    // A planar scene with a multi-speed (planar) joint is checked on the 3-D recursion.
    for (const Joint& J : m.joints) m.force_general_3d = m.force_general_3d || (m.evaluate_planar() && J.nu > 1);
    Workspace<double> crba(m), aba(m);
    dynamics::set_articulated_body(m, crba, false);
    dynamics::set_articulated_body(m, aba, true);
    ASSERT_TRUE(aba.articulated_body);
    ASSERT_TRUE(dynamics::uses_articulated_body(m, aba));
    const std::vector<double> p = m.nominal_parameters();
    set_parameters(m, crba, p.data());
    set_parameters(m, aba, p.data());
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(-1, 1);
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<double> y(m.nstate()), f1(m.nstate()), f2(m.nstate());
      for (double& v : y) v = uni(rng);
      const double t = 0.1 * trial;
      ASSERT_TRUE(evaluate_rhs(m, crba, t, y.data(), f1.data()));
      ASSERT_TRUE(evaluate_rhs(m, aba, t, y.data(), f2.data()));
      double scale = 1;
      for (int i = m.nq; i < m.nstate(); ++i) scale = std::max(scale, std::abs(f1[i]));
      // Both solves are backward stable, so they may differ by a few ε κ(M) |u̇| (κ reaches 1e6 on
      // the long tilted chain).
      const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(crba.mass_matrix).eigenvalues();
      const double kappa = ev.maxCoeff() / ev.minCoeff();
      const double tol = std::max(1e-11, 4 * std::numeric_limits<double>::epsilon() * kappa);
      for (int i = 0; i < m.nstate(); ++i) EXPECT_NEAR(f2[i], f1[i], tol * scale) << m.state_names[i] << " trial " << trial;
    }
  }
}

// On dual and multi-tangent scalars (planar chains of one-speed joints): the recursion's
// tangents equal those of M⁻¹ f through the same scalar, at random states and tangents, with
// parameter tangents (mass, length, spring) among them.
void set_tangent(Dual& x, int, double d) { x.d = d; }
void set_tangent(math::MultiDual<8>& x, int i, double d) { x.set_d(i, d); }
double tangent_at(const Dual& x, int) { return x.d; }
double tangent_at(const math::MultiDual<8>& x, int i) { return x.d(i); }

template <class S>
void check_tangents_against_mass_matrix(const Model& m, int directions) {
  Workspace<S> crba(m), aba(m);
  dynamics::set_articulated_body(m, crba, false);
  dynamics::set_articulated_body(m, aba, true);  // a small tree: the constructor may choose M
  ASSERT_TRUE(aba.articulated_body);
  ASSERT_TRUE(dynamics::uses_articulated_body(m, aba));
  ASSERT_FALSE(dynamics::uses_articulated_body(m, crba));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1, 1);
  const std::vector<double> p0 = m.nominal_parameters();
  std::vector<S> p(p0.begin(), p0.end());
  for (int i = 0; i < directions && i < m.nparam(); ++i) set_tangent(p[static_cast<std::size_t>(i)], i, 1.0);
  set_parameters(m, crba, p.data());
  set_parameters(m, aba, p.data());
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<S> y(m.nstate()), f1(m.nstate()), f2(m.nstate());
    for (S& v : y) {
      v = S(uni(rng));
      for (int i = 0; i < directions; ++i) set_tangent(v, i, uni(rng));
    }
    ASSERT_TRUE(evaluate_rhs(m, crba, S(0.2), y.data(), f1.data()));
    ASSERT_TRUE(evaluate_rhs(m, aba, S(0.2), y.data(), f2.data()));
    double scale = 1;
    for (int r = 0; r < m.nstate(); ++r) {
      scale = std::max(scale, std::abs(math::value_of(f1[r])));
      for (int i = 0; i < directions; ++i) scale = std::max(scale, std::abs(tangent_at(f1[r], i)));
    }
    for (int r = 0; r < m.nstate(); ++r) {
      EXPECT_NEAR(math::value_of(f2[r]), math::value_of(f1[r]), 1e-11 * scale) << m.state_names[r];
      for (int i = 0; i < directions; ++i)
        EXPECT_NEAR(tangent_at(f2[r], i), tangent_at(f1[r], i), 1e-11 * scale)
            << m.state_names[r] << " direction " << i << " trial " << trial;
    }
  }
}

TEST(ArticulatedBody, TangentsAsTheMassMatrixSolve) {
  // Both recursions on dual and multi-tangent scalars (with parameter tangents) against forming
  // and factoring M on the same scalar: the planar path, and the 3-D path on a tipped chain, on
  // the cart with poles (prismatic and revolute joints) forced into 3-D and on a branched tree.
  for (const auto& [name, text, planar] : std::vector<std::tuple<std::string, std::string, bool>>{
           {"chain_planar_8", test_scenes::chain_scene(8), true},
           {"cart_double_pole_planar", kCartPoles, true},
           {"chain_tipped_8", test_scenes::chain_scene(8, 0.1), false},
           {"cart_double_pole_3d", kCartPoles, false},
           {"branched_tree", kBranched, false}}) {
    SCOPED_TRACE(name);
    Model m = model_from_text(text);
    m.force_general_3d = !planar;
    ASSERT_EQ(m.evaluate_planar(), planar);
    check_tangents_against_mass_matrix<Dual>(m, 1);
    check_tangents_against_mass_matrix<math::MultiDual<8>>(m, 8);
  }
}

// On double a rotation's step is written two entries at a time (one_rotation_to_parent); the dual
// scalars run the templated step it stands in for. Each entry is formed by the same operations in
// the same order, so from the same inputs (the stages before it, copied from double) the recursion
// gives u̇ on double equal to the dual values bit for bit: on chains (about coordinate axes and
// not) and on trees (several children per parent, bodies without children, prismatic joints left
// to the templated step).
TEST(ArticulatedBody, PairedStepGivesTheTemplatedStepsBits) {
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"chain_3d_8", test_scenes::chain_scene(8)},
           {"chain_tipped_8", test_scenes::chain_scene(8, 0.1)},
           {"cart_double_pole_3d", kCartPoles},
           {"branched_tree", kBranched}}) {
    SCOPED_TRACE(name);
    Model m = model_from_text(text);
    m.force_general_3d = true;
    Workspace<double> paired(m);
    Workspace<Dual> templated(m);
    dynamics::set_articulated_body(m, paired, true);
    dynamics::set_articulated_body(m, templated, true);
    ASSERT_TRUE(dynamics::uses_articulated_body(m, paired));
    ASSERT_TRUE(dynamics::uses_articulated_body(m, templated));
    const std::vector<double> p = m.nominal_parameters();
    set_parameters(m, paired, p.data());
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> uni(-1.5, 1.5);
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<double> y(m.nstate()), f(m.nstate());
      for (double& v : y) v = uni(rng);
      ASSERT_TRUE(evaluate_rhs(m, paired, 0.3, y.data(), f.data()));
      // The recursion's inputs, with tangents: the values must not depend on them.
      auto dual = [&](double v) { return Dual(v, uni(rng)); };
      for (int b = 0; b < m.nbody(); ++b) {
        templated.spatial_inertia[b].m = dual(paired.spatial_inertia[b].m);
        for (int k = 0; k < 3; ++k) templated.spatial_inertia[b].h[k] = dual(paired.spatial_inertia[b].h[k]);
        for (int k = 0; k < 9; ++k) templated.spatial_inertia[b].I.data()[k] = dual(paired.spatial_inertia[b].I.data()[k]);
        for (int k = 0; k < 6; ++k) templated.wrench[b][k] = dual(paired.wrench[b][k]);
      }
      for (std::size_t j = 0; j < m.joints.size(); ++j)
        for (int k = 0; k < 3; ++k) templated.joint_offset[j][k] = dual(paired.joint_offset[j][k]);
      for (int k = 0; k < m.nu; ++k) {
        for (int i = 0; i < 6; ++i) templated.partial[k][i] = dual(paired.partial[k][i]);
        templated.forcing[k] = dual(paired.forcing[k]);
      }
      ASSERT_TRUE(dynamics::articulated_body_accelerations(m, templated));
      for (int k = 0; k < m.nu; ++k)
        EXPECT_EQ(f[m.nq + k], templated.udot[k].v) << m.state_names[m.nq + k] << " trial " << trial;
    }
  }
}

TEST(ArticulatedBody, PhysicalPendulumClosedForm) {
  // A uniform rod hinged at its end: θ̈ = −(3g / 2L) sin θ, by the recursion on the 3-D path.
  const double L = 0.9, g = 9.81;  // and m = 1.3, which θ̈ does not depend on
  Model m = model_from_text(test_scenes::rod_pendulum_scene("rod", "{m: 1.3, L: 0.9}"));
  m.force_general_3d = true;
  Workspace<double> ws(m);
  dynamics::set_articulated_body(m, ws, true);
  ASSERT_TRUE(ws.articulated_body);
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  for (const double theta : {-2.5, -0.4, 0.3, 1.2, 3.0}) {
    const double y[2] = {theta, 0.7};
    double ydot[2];
    ASSERT_TRUE(evaluate_rhs(m, ws, 0.0, y, ydot));
    EXPECT_NEAR(ydot[1], -3 * g / (2 * L) * std::sin(theta), 1e-12 * 3 * g / (2 * L)) << theta;
  }
}

TEST(ArticulatedBody, ChosenForUnconstrainedSpatialChainsOnly) {
  // Chains of one-speed joints take it at any length; chains with multi-speed joints from
  // kArticulatedBodyMinSpeeds speeds on (where it overtakes M and its factor).
  for (const int n : {1, 2, 8, dynamics::kArticulatedBodyMinSpeeds})
    EXPECT_TRUE(Workspace<double>(model_from_text(test_scenes::chain_scene(n, 0.1))).articulated_body) << n;
  const int balls = (dynamics::kArticulatedBodyMinSpeeds + 2) / 3;  // 3 balls·speeds ≥ the threshold
  EXPECT_TRUE(Workspace<double>(model_from_text(test_scenes::ball_chain(balls))).articulated_body);
  EXPECT_FALSE(Workspace<double>(model_from_text(test_scenes::ball_chain(balls - 1))).articulated_body);
  EXPECT_FALSE(Workspace<double>(model_from_text(test_scenes::kSphericalScene)).articulated_body)
      << "4 speeds with a ball joint";
  const Model planar = model_from_text(test_scenes::chain_scene(40));
  ASSERT_TRUE(planar.evaluate_planar());
  EXPECT_TRUE(Workspace<double>(planar).articulated_body) << "the planar path's own recursion";
  EXPECT_TRUE(Workspace<Dual>(model_from_text(test_scenes::chain_scene(8, 0.1))).articulated_body)
      << "the 3-D recursion runs on duals for joints of one speed";
  EXPECT_TRUE(Workspace<math::MultiDual<8>>(model_from_text(test_scenes::chain_scene(8, 0.1))).articulated_body);
  EXPECT_FALSE(Workspace<Dual>(model_from_text(test_scenes::ball_chain(balls))).articulated_body)
      << "several speeds a joint: on double only";
  EXPECT_TRUE(Workspace<Dual>(planar).articulated_body) << "the planar recursion runs on duals";
  EXPECT_TRUE(Workspace<math::MultiDual<8>>(planar).articulated_body);
  const Model closed = model_from_text(test_scenes::n_four_bar(6));
  Workspace<double> ws(closed);
  EXPECT_FALSE(ws.articulated_body);
  dynamics::set_articulated_body(closed, ws, true);
  EXPECT_FALSE(ws.articulated_body) << "the multipliers need M's factor";
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
