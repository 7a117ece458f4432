// Where a mechanism stands must not change its dynamics. Each scene is built at its original
// placement and again with the whole scene moved (every ground point, the free joints'
// positions and the rolling planes shifted by an offset o) or turned (every vector and inertia
// tensor of the scene, the gravity included, rotated by one rotation R0; frames are parallel at
// q = 0, so a body-frame vector turns with the rest). At the same state (mapped alike), u̇, λ,
// the energies (the potential up to its constant −M g·o) and the exact derivatives of u̇ with
// respect to every parameter (and, for moves, every state) must be unchanged:
//   ≤ 1e-12 relative for a move of 100 m and for a rotation, ≤ 1e-10 for 1 000 km.
// Relative = max |change| / max |value| over the vector compared. World-fixed points are placed
// exactly (on_grid), so what changes is the evaluation alone. Scenes: a 3-D arm
// (configs/arm_3d.yaml's mechanism), a free body with a tether and a torque, a spatial closed
// loop with a coincident constraint, the planar four-bar (planar evaluation) and a two-wheeled
// vehicle (rear frame on a free joint, steered fork, two rolling wheels).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "dynamics/equations.hpp"
#include "kane_test_support.hpp"
#include "math/dual.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector4d;
using V3 = std::array<std::string, 3>;

struct Placement {
  Vector3d o = Vector3d::Zero();
  Matrix3d R = Matrix3d::Identity();
  bool grid = false;  // world-fixed points on a grid (on_grid)
};

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// R·v for a vector of expressions (directions, body-frame points).
V3 place(const Placement& p, const V3& v) {
  V3 r;
  for (int i = 0; i < 3; ++i) {
    std::string s;
    for (int j = 0; j < 3; ++j) {
      if (p.R(i, j) == 0 || v[j] == "0") continue;
      if (!s.empty()) s += " + ";
      s += p.R(i, j) == 1 ? "(" + v[j] + ")" : num(p.R(i, j)) + "*(" + v[j] + ")";
    }
    r[i] = s.empty() ? "0" : s;
  }
  return r;
}
std::string yaml(const V3& v) { return "[\"" + v[0] + "\", \"" + v[1] + "\", \"" + v[2] + "\"]"; }
std::string dir(const Placement& p, const V3& v) { return yaml(place(p, v)); }

// A point fixed in the world: R·v + o. With `grid`, R·v is first rounded to a grid of 2^-30 m,
// so that adding o (integer components below 2^21) is exact: two placements that differ by o
// then hold the same point to the last bit relative to the scene, and the test sees the
// evaluation, not how the inputs round at 1 000 km (a coordinate there is stored to 1.2e-10 m).
// The moves below use points already on the grid (dyadic numbers, R = 1).
Vector3d on_grid(const Placement& p, const Vector3d& v) {
  Vector3d w = p.R * v;
  if (p.grid)
    for (int i = 0; i < 3; ++i) w[i] = std::ldexp(std::round(std::ldexp(w[i], 30)), -30);
  return w + p.o;
}
std::string ground(const Placement& p, const Vector3d& v) {
  const Vector3d w = on_grid(p, v);
  return "[" + num(w[0]) + ", " + num(w[1]) + ", " + num(w[2]) + "]";
}

// Inertia {xx, yy, zz, xy, yz, xz} (expressions) turned by R: R I Rᵀ.
std::string inertia(const Placement& p, const std::array<std::string, 6>& e) {
  const std::string* I[3][3] = {{&e[0], &e[3], &e[5]}, {&e[3], &e[1], &e[4]}, {&e[5], &e[4], &e[2]}};
  auto entry = [&](int i, int j) {
    std::string s;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double c = p.R(i, a) * p.R(j, b);
        if (c == 0 || *I[a][b] == "0") continue;
        if (!s.empty()) s += " + ";
        s += c == 1 ? "(" + *I[a][b] + ")" : num(c) + "*(" + *I[a][b] + ")";
      }
    return "\"" + (s.empty() ? std::string("0") : s) + "\"";
  };
  return "{xx: " + entry(0, 0) + ", yy: " + entry(1, 1) + ", zz: " + entry(2, 2) + ", xy: " + entry(0, 1) +
         ", yz: " + entry(1, 2) + ", xz: " + entry(0, 2) + "}";
}

Vector4d quat_of(const Matrix3d& R) {  // (w, x, y, z), R proper
  const Eigen::Quaterniond q(R);
  return {q.w(), q.x(), q.y(), q.z()};
}

// A scene: its text at a placement, its state at a placement (from one base state), and how a
// speed-space or multiplier vector turns with the scene (world components of free joints'
// speeds, of coincident and rolling multipliers).
struct Scene {
  std::string name;
  std::function<std::string(const Placement&)> text;
  // Free joints (index of the joint's first coordinate and speed, base translation) and ball
  // joints (translation none): their quaternion and speeds turn with the scene.
  struct Free {
    int q, u;
    Vector3d x;
    bool ball = false;
  };
  std::vector<Free> free;
  std::vector<int> vector_multipliers;  // first row of each 3-row world-vector multiplier
  bool rotate = true;                   // the rotation check applies (not for planar-only scenes)
  // Tolerances are multiplied by it: round-off in u̇ and its derivatives grows with M's condition
  // number, of the order of 10⁴ for a long chain.
  double conditioning = 1;
};

std::vector<double> placed_state(const Scene& s, const Model& m, std::vector<double> y, const Placement& p) {
  const Vector4d q0 = quat_of(p.R);
  const Vector4d q0c(q0[0], -q0[1], -q0[2], -q0[3]);
  for (const Scene::Free& f : s.free) {
    const int lin = f.ball ? 0 : 3;
    if (!f.ball) {
      const Vector3d x = on_grid(p, f.x);
      for (int i = 0; i < 3; ++i) y[f.q + i] = x[i];
    }
    const Vector4d e(y[f.q + lin], y[f.q + lin + 1], y[f.q + lin + 2], y[f.q + lin + 3]);
    const Vector4d e2 = quat_mul(quat_mul(q0, e), q0c);  // R_PC' = R0 R_PC R0ᵀ
    for (int i = 0; i < 4; ++i) y[f.q + lin + i] = e2[i];
    for (int b = 0; b < lin / 3 + 1; ++b) {  // v (parent components) and ω (child components) turn by R0
      double* u = y.data() + m.nq + f.u + 3 * b;
      const Vector3d w = p.R * Vector3d(u[0], u[1], u[2]);
      for (int i = 0; i < 3; ++i) u[i] = w[i];
    }
  }
  return y;
}

// Turns a vector of speeds (nu) or multipliers (m) like the state.
void turn_speeds(const Scene& s, const Placement& p, double* u) {
  for (const Scene::Free& f : s.free)
    for (int b = 0; b < (f.ball ? 1 : 2); ++b) {
      const Vector3d w = p.R * Vector3d(u[f.u + 3 * b], u[f.u + 3 * b + 1], u[f.u + 3 * b + 2]);
      for (int i = 0; i < 3; ++i) u[f.u + 3 * b + i] = w[i];
    }
}
void turn_multipliers(const Scene& s, const Placement& p, double* l) {
  for (int r : s.vector_multipliers) {
    const Vector3d w = p.R * Vector3d(l[r], l[r + 1], l[r + 2]);
    for (int i = 0; i < 3; ++i) l[r + i] = w[i];
  }
}

// ---------------------------------------------------------------- the scenes

Scene arm() {
  Scene s;
  s.name = "arm_3d";
  s.text = [](const Placement& p) {
    return std::string("kanesens: 1\nscene:\n  name: arm\n  gravity: ") + dir(p, {"0", "0", "-9.81"}) + R"(
  parameters: {m0: 3.0, r0: 0.15, h0: 0.2, m1: 1.5, L1: 0.6, m2: 0.8, L2: 0.5, m3: 0.3, lh: 0.1,
               k_tele: 50.0, rest_tele: 0.05, c_tele: 2.0, c_sh: 0.1, b_wrist: 0.02, tau0: 0.05,
               k_tip: 5.0, c_tip: 0.1}
  bodies:
    - {name: base, mass: m0, inertia: )" +
           inertia(p, {"m0*(3*r0^2 + h0^2)/12", "m0*(3*r0^2 + h0^2)/12", "m0*r0^2/2", "0", "0", "0"}) + R"(}
    - {name: upper, mass: m1, inertia: )" +
           inertia(p, {"m1*L1^2/12", "m1*L1^2/12 + 0.002", "0.004", "0.001", "-0.0015", "0.0008"}) + R"(}
    - {name: forearm, mass: m2, inertia: )" +
           inertia(p, {"m2*L2^2/12", "0.9*m2*L2^2/12", "0.002", "-0.0005", "0.0007", "0.0004"}) + R"(}
    - {name: hand, mass: m3, inertia: )" +
           inertia(p, {"0.0012", "0.0010", "0.0008", "0.0001", "-0.0002", "0.00015"}) + R"(}
  joints:
    - {name: yaw, type: revolute, parent: ground, child: base, axis: )" + dir(p, {"0", "0", "1"}) +
           ", parent_point: " + ground(p, {0, 0, 0}) + ", child_point: " + dir(p, {"0", "0", "-h0/2"}) + R"(}
    - {name: shoulder, type: revolute, parent: base, child: upper, axis: )" + dir(p, {"1", "1", "0"}) +
           ", parent_point: " + dir(p, {"0", "0", "h0/2"}) + ", child_point: " + dir(p, {"0", "0", "-L1/2"}) +
           R"(, damper: {c: c_sh}}
    - {name: telescope, type: prismatic, parent: upper, child: forearm, axis: )" + dir(p, {"0", "0", "1"}) +
           ", parent_point: " + dir(p, {"0", "0", "L1/2"}) + ", child_point: " + dir(p, {"0", "0", "-L2/2"}) +
           R"(, spring: {k: k_tele, rest: rest_tele}, damper: {c: c_tele}}
    - {name: wrist, type: universal, parent: forearm, child: hand, axes: [)" + dir(p, {"1", "0", "0"}) + ", " +
           dir(p, {"0", "1", "0"}) + "], parent_point: " + dir(p, {"0", "0", "L2/2"}) +
           ", child_point: " + dir(p, {"0", "0", "-lh"}) + R"(}
  forces:
    - {type: torque, name: wrist_drag, body: hand, frame: body, vector: )" +
           dir(p, {"-b_wrist*wrist.u1", "-b_wrist*wrist.u2", "tau0*sin(3*t)"}) + R"(}
    - {type: spring_damper, name: tip_tether, body_a: hand, point_a: )" + dir(p, {"0", "0", "lh"}) +
           ", body_b: ground, point_b: " + ground(p, {0.5, 0.5, 2.0}) +
           ", k: k_tip, c: c_tip, rest: 0.5}\n";
  };
  return s;
}

Scene free_body() {
  Scene s;
  s.name = "free_body";
  s.free = {{0, 0, Vector3d(0.25, -0.25, 1.125)}};
  s.text = [](const Placement& p) {
    return std::string("kanesens: 1\nscene:\n  name: free\n  gravity: ") + dir(p, {"0", "0", "-9.81"}) + R"(
  parameters: {m: 2.0, k: 30.0, c: 0.5}
  bodies:
    - {name: body, mass: m, inertia: )" + inertia(p, {"0.3", "0.5", "0.7", "0.02", "-0.03", "0.05"}) + R"(}
  joints:
    - {name: float, type: free, parent: ground, child: body, child_point: )" + dir(p, {"0.1", "0", "-0.2"}) + R"(}
  forces:
    - {type: spring_damper, name: tether, body_a: body, point_a: )" + dir(p, {"0.2", "0.1", "0.3"}) +
           ", body_b: ground, point_b: " + ground(p, {0, 0, 2}) + R"(, k: k, c: c, rest: 0.4}
    - {type: torque, name: spin, body: body, frame: body, vector: )" + dir(p, {"0.1*sin(t)", "0", "0"}) + R"(}
    - {type: torque, name: drag, body: body, frame: body, vector: [-0.2*float.wx, -0.2*float.wy, -0.2*float.wz]}
)";
  };
  return s;
}

// A spatial chain long enough that the right-hand side on double takes the articulated-body
// recursion (dynamics::kArticulatedBodyMinSpeeds); the sensitivities still go through M.
Scene long_chain() {
  Scene s;
  s.name = "long_chain";
  s.conditioning = 30;  // cond(M) ≈ 6·10⁴ for a 30-link spatial chain of rods
  s.text = [](const Placement& p) {
    const int n = dynamics::kArticulatedBodyMinSpeeds + 2;
    // Appended piece by piece (GCC 12 warns falsely on chains of string operator+).
    std::string t = "kanesens: 1\nscene:\n  name: long_chain\n  gravity: ";
    t += dir(p, {"0", "-9.81", "0"});
    t += "\n  parameters: {m: 0.7, L: 0.4}\n  bodies:\n";
    const std::string body_inertia = inertia(p, {"m*L^2/12", "0.002", "m*L^2/12 + 0.001", "0.0003", "-0.0002", "0.0001"});
    for (int i = 0; i < n; ++i) {
      t += "    - {name: b";
      t += std::to_string(i);
      t += ", mass: m, inertia: ";
      t += body_inertia;
      t += "}\n";
    }
    t += "  joints:\n";
    const V3 axes[3] = {{"0", "0", "1"}, {"1", "0", "0"}, {"0.6", "0", "0.8"}};
    for (int i = 0; i < n; ++i) {
      t += "    - {name: j";
      t += std::to_string(i);
      t += ", type: revolute, parent: ";
      if (i > 0) {
        t += "b";
        t += std::to_string(i - 1);
      } else {
        t += "ground";
      }
      t += ", child: b";
      t += std::to_string(i);
      t += ", axis: ";
      t += dir(p, axes[i % 3]);
      t += ", parent_point: ";
      t += i > 0 ? dir(p, {"0", "-L/2", "0"}) : ground(p, {0, 0, 0});
      t += ", child_point: ";
      t += dir(p, {"0", "L/2", "0"});
      t += "}\n";
    }
    return t;
  };
  return s;
}

// Crank (revolute about z), coupler on a ball joint at the crank's tip, rocker (revolute about
// a tilted axis at a second ground pivot); the coupler's tip on the rocker's tip (3 rows).
Scene spatial_loop() {
  Scene s;
  s.name = "spatial_loop";
  s.free = {{1, 1, Vector3d::Zero(), true}};
  s.vector_multipliers = {0};
  s.text = [](const Placement& p) {
    return std::string("kanesens: 1\nscene:\n  name: loop\n  gravity: ") + dir(p, {"0", "-9.81", "0"}) + R"(
  parameters: {r: 0.2, c: 0.7, b: 0.5, m1: 1.0, m2: 2.0, m3: 1.5}
  bodies:
    - {name: crank, mass: m1, inertia: )" + inertia(p, {"1e-4", "m1*r^2/12", "m1*r^2/12", "0", "0", "0"}) + R"(}
    - {name: coupler, mass: m2, inertia: )" + inertia(p, {"1e-3", "m2*c^2/12", "m2*c^2/12", "0", "0", "0"}) + R"(}
    - {name: rocker, mass: m3, inertia: )" + inertia(p, {"1e-4", "m3*b^2/12", "m3*b^2/12", "0", "0", "0"}) + R"(}
  joints:
    - {name: crank, type: revolute, parent: ground, child: crank, axis: )" + dir(p, {"0", "0", "1"}) +
           ", parent_point: " + ground(p, {0, 0, 0}) + ", child_point: " + dir(p, {"-r/2", "0", "0"}) + R"(}
    - {name: ball, type: spherical, parent: crank, child: coupler, parent_point: )" + dir(p, {"r/2", "0", "0"}) +
           ", child_point: " + dir(p, {"-c/2", "0", "0"}) + R"(}
    - {name: rocker, type: revolute, parent: ground, child: rocker, axis: )" + dir(p, {"0.3", "0.2", "1"}) +
           ", parent_point: " + ground(p, {0.625, 0.125, 0.0625}) + ", child_point: " + dir(p, {"-b/2", "0", "0"}) + R"(}
  constraints:
    - {name: loop, type: coincident, body_a: coupler, point_a: )" + dir(p, {"c/2", "0", "0"}) +
           ", body_b: rocker, point_b: " + dir(p, {"b/2", "0", "0"}) + "}\n";
  };
  return s;
}

// configs/four_bar.yaml's mechanism with numbers: planar, so evaluated by the planar path
// (moves only: a rotation would take it out of the x–y plane).
Scene four_bar() {
  Scene s;
  s.name = "four_bar";
  s.rotate = false;
  s.text = [](const Placement& p) {
    return std::string(R"(kanesens: 1
scene:
  name: four_bar
  gravity: [0, -9.81, 0]
  parameters: {r: 0.2, c: 0.7, b: 0.5, m1: 1.0, m2: 2.0, m3: 1.5}
  bodies:
    - {name: crank, mass: m1, inertia: {shape: rod, length: r, axis: x}}
    - {name: coupler, mass: m2, inertia: {shape: rod, length: c, axis: x}}
    - {name: rocker, mass: m3, inertia: {shape: rod, length: b, axis: x}}
  joints:
    - {name: crank, type: revolute, parent: ground, child: crank, axis: [0, 0, 1], parent_point: )") +
           ground(p, {0, 0, 0}) + R"(, child_point: ["-r/2", 0, 0]}
    - {name: coupler, type: revolute, parent: crank, child: coupler, axis: [0, 0, 1],
       parent_point: ["r/2", 0, 0], child_point: ["-c/2", 0, 0]}
    - {name: rocker, type: revolute, parent: ground, child: rocker, axis: [0, 0, 1], parent_point: )" +
           ground(p, {0.625, 0, 0}) + R"(, child_point: ["-b/2", 0, 0]}
  constraints:
    - {name: loop, type: coincident, body_a: coupler, point_a: ["c/2", 0, 0], body_b: rocker, point_b: ["b/2", 0, 0]}
)";
  };
  return s;
}

// A two-wheeled vehicle: rear frame on a free joint, rear wheel on a revolute about the frame's
// y axis, a fork steering about a raked axis, the front wheel on the fork; both wheels roll on
// the plane through the placement's origin.
Scene vehicle() {
  Scene s;
  s.name = "vehicle";
  s.free = {{0, 0, Vector3d(0.0, 0.0, 0.875)}};
  s.vector_multipliers = {0, 3};
  s.text = [](const Placement& p) {
    const Vector3d n = p.R * Vector3d(0, 0, 1);
    const std::string height = num(n.dot(p.o));
    return std::string("kanesens: 1\nscene:\n  name: vehicle\n  gravity: ") + dir(p, {"0", "0", "-9.81"}) + R"(
  parameters: {mf: 12.0, mw: 2.0, mk: 3.0, rw: 0.35}
  bodies:
    - {name: frame, mass: mf, inertia: )" + inertia(p, {"0.9", "1.6", "1.1", "0", "0", "-0.2"}) + R"(}
    - {name: rear, mass: mw, inertia: )" + inertia(p, {"mw*rw^2/4", "mw*rw^2/2", "mw*rw^2/4", "0", "0", "0"}) + R"(}
    - {name: fork, mass: mk, inertia: )" + inertia(p, {"0.2", "0.25", "0.08", "0", "0", "0.02"}) + R"(}
    - {name: front, mass: mw, inertia: )" + inertia(p, {"mw*rw^2/4", "mw*rw^2/2", "mw*rw^2/4", "0", "0", "0"}) + R"(}
  joints:
    - {name: base, type: free, parent: ground, child: frame}
    - {name: rear_axle, type: revolute, parent: frame, child: rear, axis: )" + dir(p, {"0", "1", "0"}) +
           ", parent_point: " + dir(p, {"-0.5", "0", "-0.55"}) + R"(}
    - {name: steer, type: revolute, parent: frame, child: fork, axis: )" + dir(p, {"0.3", "0", "1"}) +
           ", parent_point: " + dir(p, {"0.45", "0", "0.1"}) + ", child_point: " + dir(p, {"0", "0", "0.3"}) + R"(}
    - {name: front_axle, type: revolute, parent: fork, child: front, axis: )" + dir(p, {"0", "1", "0"}) +
           ", parent_point: " + dir(p, {"0.2", "0", "-0.35"}) + R"(}
  constraints:
    - {name: rear_contact, type: rolling, body: rear, radius: rw, axis: )" + dir(p, {"0", "1", "0"}) +
           ", normal: " + dir(p, {"0", "0", "1"}) + ", height: " + height + R"(}
    - {name: front_contact, type: rolling, body: front, radius: rw, axis: )" + dir(p, {"0", "1", "0"}) +
           ", normal: " + dir(p, {"0", "0", "1"}) + ", height: " + height + "}\n";
  };
  return s;
}

// A base state: random, with the free joints' translations from Scene::free and (vehicle) a
// lean and steer of the size a real run has.
std::vector<double> base_state(const Scene& s, const Model& m) {
  std::mt19937_64 rng(7);
  std::vector<double> y = random_state(m, rng, 1.0, 1.0);
  for (const Scene::Free& f : s.free) {
    for (int i = 0; i < 3; ++i) y[f.q + i] = f.x[i];
    for (int i = 0; i < 3; ++i) y[m.nq + f.u + i] *= 3;  // a few m/s
  }
  return y;
}

// ---------------------------------------------------------------- what is compared

struct Result {
  std::vector<double> udot, lambda, dudot;  // dudot: every parameter's, then (moves) every state's
  double T = 0, V = 0, mass = 0;
  Vector3d g;
};

Result evaluate(const Scene& s, const Placement& p, bool state_tangents) {
  const Model m = model_from_text(s.text(p), s.name + ".yaml");
  const std::vector<double> y0 = base_state(s, m);
  const std::vector<double> y = placed_state(s, m, y0, p);
  const std::vector<double> par = m.nominal_parameters();
  Result r;
  Workspace<double> ws(m);
  set_parameters(m, ws, par.data());
  std::vector<double> ydot(m.nstate());
  EXPECT_TRUE(evaluate_rhs(m, ws, 0.3, y.data(), ydot.data())) << s.name;
  r.udot.assign(ydot.begin() + m.nq, ydot.end());
  r.lambda.assign(ws.multipliers.data(), ws.multipliers.data() + m.nconstraint_rows);
  // A rolling contact's multipliers are in its plane's basis (t1, t2, n), whose t1 follows the
  // world x axis: compare the contact forces as world vectors.
  for (const auto& c : m.constraints) {
    if (c.kind != kanesens::model::Constraint::Kind::rolling) continue;
    const Vector3d n = Vector3d(ws.values[c.normal[0]], ws.values[c.normal[1]], ws.values[c.normal[2]]).normalized();
    Vector3d t1, t2;
    kanesens::dynamics::rolling_plane_basis<double>(n, t1, t2);
    double* l = r.lambda.data() + c.row_offset;
    const Vector3d w = l[0] * t1 + l[1] * t2 + l[2] * n;
    for (int i = 0; i < 3; ++i) l[i] = w[i];
  }
  r.T = kinetic_energy(m, ws);
  r.V = potential_energy(m, ws, y.data());
  r.g = ws.gravity;
  for (int b = 0; b < m.nbody(); ++b) r.mass += ws.mass[b];

  Workspace<Dual> wd(m);
  std::vector<Dual> pd(par.begin(), par.end()), yd(y.begin(), y.end()), ydd(m.nstate());
  auto tangent = [&] {
    evaluate_rhs(m, wd, Dual(0.3), yd.data(), ydd.data());
    for (int i = 0; i < m.nu; ++i) r.dudot.push_back(ydd[m.nq + i].d);
  };
  for (int i = 0; i < m.nparam(); ++i) {
    pd[i].d = 1;
    set_parameters(m, wd, pd.data());
    pd[i].d = 0;
    tangent();
  }
  if (state_tangents) {
    set_parameters(m, wd, pd.data());
    for (int i = 0; i < m.nstate(); ++i) {
      yd[i].d = 1;
      tangent();
      yd[i].d = 0;
    }
  }
  // Speeds and multipliers in the original scene's components.
  const Placement back{Vector3d::Zero(), p.R.transpose()};
  turn_speeds(s, back, r.udot.data());
  turn_multipliers(s, back, r.lambda.data());
  for (std::size_t k = 0; k + m.nu <= r.dudot.size(); k += m.nu) turn_speeds(s, back, r.dudot.data() + k);
  return r;
}

double rel_change(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(a[i]));
  }
  return s > 0 ? d / s : d;
}

struct Changes {
  double udot, lambda, energy, sens;
};

// The change from placement `ref` to placement `p` (same R, or ref = 1).
Changes changes(const Scene& s, const Placement& p, const Placement& ref = {}) {
  const bool moved_only = p.R == ref.R;
  const Result a = evaluate(s, ref, moved_only), b = evaluate(s, p, moved_only);
  Changes c{};
  c.udot = rel_change(a.udot, b.udot);
  c.lambda = rel_change(a.lambda, b.lambda);
  c.sens = rel_change(a.dudot, b.dudot);
  // The potential moves by its constant −M g·o (g of the placed scene).
  const double shift = -b.mass * b.g.dot(p.o - ref.o);
  c.energy = std::max(std::abs(b.T - a.T) / std::abs(a.T), std::abs(b.V - shift - a.V) / (std::abs(a.V) + std::abs(shift)));
  return c;
}

Matrix3d turn() {  // a rotation with no special axis
  return (Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()) * Eigen::AngleAxisd(-1.9, Vector3d(-2, 0.5, 1).normalized()))
      .toRotationMatrix();
}

std::vector<Scene> scenes() { return {arm(), free_body(), spatial_loop(), four_bar(), vehicle(), long_chain()}; }

void print(const std::string& scene, const std::string& what, const Changes& c) {
  std::printf("| %s | %s | %.1e | %.1e | %.1e | %.1e |\n", scene.c_str(), what.c_str(), c.udot, c.lambda, c.energy,
              c.sens);
}

// Every change within tol × the scene's conditioning.
void expect_within(const Scene& s, const Changes& c, double tol, const std::string& what) {
  tol *= s.conditioning;
  EXPECT_LE(c.udot, tol) << s.name << " " << what;
  EXPECT_LE(c.lambda, tol) << s.name << " " << what;
  EXPECT_LE(c.energy, tol) << s.name << " " << what;
  EXPECT_LE(c.sens, tol) << s.name << " " << what;
}

class Invariance : public ::testing::TestWithParam<int> {};

TEST_P(Invariance, MovedScene) {
  const Scene s = scenes()[GetParam()];
  const Vector3d dir = Vector3d(0.6, -0.48, 0.64);  // unit, no special direction
  for (const double L : {100.0, 1e4, 1e6}) {
    Placement p;
    p.o = L * dir;
    const Changes c = changes(s, p);
    print(s.name, "moved " + num(L) + " m", c);
    expect_within(s, c, L <= 100 ? 1e-12 : L <= 1e4 ? 1e-11 : 1e-10, "moved " + num(L));
  }
}

TEST_P(Invariance, TurnedScene) {
  const Scene s = scenes()[GetParam()];
  if (!s.rotate) GTEST_SKIP() << "planar scene";
  Placement p;
  p.R = turn();
  const Changes c = changes(s, p);
  print(s.name, "turned", c);
  expect_within(s, c, 1e-12, "turned");
}

// A move of 1 000 km in a turned scene (against the turned scene: the rotation is the test above).
TEST_P(Invariance, TurnedAndMovedFar) {
  const Scene s = scenes()[GetParam()];
  if (!s.rotate) GTEST_SKIP() << "planar scene";
  Placement ref;
  ref.R = turn();
  ref.grid = true;
  Placement p = ref;
  p.o = Vector3d(-310000, 770000, 500000);
  const Changes c = changes(s, p, ref);
  print(s.name, "turned, moved 1e6 m", c);
  expect_within(s, c, 1e-10, "turned, moved 1e6 m");
}

TEST(InvarianceScenes, LongChainTakesTheArticulatedBodyRecursion) {
  const Model m = model_from_text(long_chain().text(Placement{}));
  EXPECT_TRUE(Workspace<double>(m).articulated_body) << "the long_chain cases would not test it";
}

INSTANTIATE_TEST_SUITE_P(Scenes, Invariance, ::testing::Range(0, 6), [](const auto& info) {
  return scenes()[static_cast<std::size_t>(info.param)].name;
});

}  // namespace

}  // namespace KANESENS_UNITY_ID
