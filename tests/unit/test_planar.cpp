// Planar scenes (Model::planar) are evaluated with 3-component spatial vectors; the general 3-D
// evaluation (forced with Model::force_general_3d) must give the same M, f, u̇, energies and
// Dual tangents to round-off, at random states.
#include <gtest/gtest.h>

#include <random>

#include "math/dual.hpp"
#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "test_scenes.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

// Planar, but with everything the criterion allows that a plain chain lacks: a −z axis, points
// and mass centers off the plane, gravity and forces with z components, inertia products with z,
// a weld, a planar joint with normal −z, state-dependent forces.
const char* kAwkwardPlanar = R"yaml(kanesens: 1
scene:
  name: awkward_planar
  gravity: [0.3, -9.81, 2.0]
  parameters: {k: 5, c: 0.2}
  bodies:
    - {name: a, mass: 1.3, inertia: {xx: 0.2, yy: 0.1, zz: 0.25, xz: 0.03, yz: -0.02, xy: 0.01}}
    - {name: b, mass: 0.4, inertia: {shape: box, size: [0.3, 0.1, 0.5]}}
    - {name: w, mass: 0.2, inertia: {shape: sphere, radius: 0.1}}
    - {name: s, mass: 0.6, inertia: {shape: rod, length: 0.7, axis: x}}
    - {name: p, mass: 0.9, inertia: {xx: 0.1, yy: 0.1, zz: 0.05, xz: 0.01}}
  joints:
    - {name: j1, type: revolute, parent: ground, child: a, axis: [0, 0, -2],
       parent_point: [0.1, 0.2, 0.3], child_point: [0, 0.5, -0.2], spring: {k: k, rest: 0.2}}
    - {name: j2, type: prismatic, parent: a, child: b, axis: [1, 1, 0],
       parent_point: [0, -0.5, 0.1], damper: {c: c}}
    - {name: weld, type: weld, parent: b, child: w, parent_point: [0.1, 0, 0.4]}
    - {name: j3, type: revolute, parent: b, child: s, axis: [0, 0, 1],
       parent_point: [0, -0.2, 0], child_point: [0.35, 0, 0.05]}
    - {name: g, type: planar, parent: ground, child: p, axis: [0, 0, -1],
       parent_point: [1, 0, 0.5]}
  forces:
    - {type: spring_damper, name: sd, body_a: s, point_a: [-0.35, 0, 0], body_b: p,
       point_b: [0, 0.1, 0.3], k: k, c: c, rest: 0.3}
    - {type: force, name: f, body: w, point: [0, 0.1, 0], vector: ["sin(t)", 0.5, "j1.u"], frame: body}
    - {type: torque, name: t, body: p, vector: [1, 2, "-0.3*g.u3"], frame: world}
)yaml";

Model build(const std::string& text) { return build_model(parse_scene_text(text, "scene.yaml")); }

template <class S>
struct Eval {
  std::vector<S> ydot;
  MatX<S> M;
  VecX<S> f;
  S T, V;
};

template <class S>
Eval<S> evaluate(const Model& m, const std::vector<S>& y, const S& t) {
  Workspace<S> ws(m);
  const std::vector<double> p0 = m.nominal_parameters();
  const std::vector<S> p(p0.begin(), p0.end());
  set_parameters(m, ws, p.data());
  Eval<S> e;
  e.ydot.resize(y.size());
  EXPECT_TRUE(evaluate_rhs(m, ws, t, y.data(), e.ydot.data()));
  evaluate_mass_matrix_and_forcing(m, ws, t, y.data(), y.data() + m.nq);  // the RHS may not form M, f
  e.M = ws.mass_matrix;
  e.f = ws.forcing;
  e.T = kinetic_energy(m, ws);
  e.V = potential_energy(m, ws, y.data());
  return e;
}

void expect_close(double a, double b, const std::string& what) {
  EXPECT_NEAR(a, b, 1e-12 * std::max(1.0, std::abs(b))) << what;
}

void check_agreement(const std::string& text, int states) {
  Model planar = build(text);
  ASSERT_TRUE(planar.planar) << planar.name;
  Model general = planar;
  general.force_general_3d = true;
  ASSERT_TRUE(planar.evaluate_planar());
  ASSERT_FALSE(general.evaluate_planar());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-2, 2);
  for (int s = 0; s < states; ++s) {
    std::vector<double> y(planar.nstate());
    for (double& v : y) v = uni(rng);
    const double t = uni(rng);
    const auto a = evaluate<double>(planar, y, t), b = evaluate<double>(general, y, t);
    for (int r = 0; r < planar.nu; ++r) {
      for (int c = 0; c < planar.nu; ++c) expect_close(a.M(r, c), b.M(r, c), "M");
      expect_close(a.f[r], b.f[r], "f");
    }
    for (std::size_t i = 0; i < y.size(); ++i) expect_close(a.ydot[i], b.ydot[i], "ydot");
    expect_close(a.T, b.T, "kinetic energy");
    expect_close(a.V, b.V, "potential energy");
    // Dual: one Jacobian column per state; tangents agree too.
    for (std::size_t col = 0; col < y.size(); ++col) {
      std::vector<Dual> yd(y.begin(), y.end());
      yd[col].d = 1;
      const auto ad = evaluate<Dual>(planar, yd, Dual(t)), bd = evaluate<Dual>(general, yd, Dual(t));
      for (std::size_t i = 0; i < y.size(); ++i) {
        expect_close(ad.ydot[i].v, bd.ydot[i].v, "Dual ydot value");
        expect_close(ad.ydot[i].d, bd.ydot[i].d, "Dual ydot tangent, column " + std::to_string(col));
      }
    }
  }
}

}  // namespace

TEST(Planar, Detection) {
  EXPECT_TRUE(build(test_scenes::chain_scene(3)).planar);
  EXPECT_FALSE(build(test_scenes::chain_scene(3, 1e-3)).planar);  // one axis tipped out of plane
  EXPECT_TRUE(build(kAwkwardPlanar).planar);
  EXPECT_TRUE(build(test_scenes::kForcesScene).planar);
  EXPECT_FALSE(build(test_scenes::kSphericalScene).planar);
  EXPECT_FALSE(build(test_scenes::kFreeScene).planar);
  // An axis that depends on a parameter could leave the plane for another parameter value.
  std::string p = test_scenes::chain_scene(2);
  p.replace(p.find("axis: [0, 0, 1]"), 15, "axis: [0, 0, L]");
  EXPECT_FALSE(build(p).planar);
}

TEST(Planar, ChainAgreesWith3D) { check_agreement(test_scenes::chain_scene(7), 5); }
TEST(Planar, ForcesSceneAgreesWith3D) { check_agreement(test_scenes::kForcesScene, 5); }
TEST(Planar, AwkwardSceneAgreesWith3D) { check_agreement(kAwkwardPlanar, 5); }

}  // namespace KANESENS_UNITY_ID
