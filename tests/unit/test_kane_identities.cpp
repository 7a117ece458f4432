// Identities Kane's equations must satisfy, at random states (fixed seeds) of five scenes:
//
//   1. M (nu×nu) is symmetric positive definite (Cholesky succeeds, eigenvalues > 0).
//   2. M equals its definition M_kl = Σ_i m_i V_ik·V_il + Ω_ik·I_i Ω_il with the partial
//      velocities V_ik and partial angular velocities Ω_ik obtained here by central finite
//      differences of the mass-center positions and rotation matrices along q̇ = N(q) e_k
//      (N written in the test: u = q̇, quaternions q̇ = ½ q ⊗ (0, ω)). This checks the engine's
//      partial velocities without using them.
//   3. The kinetic energy equals ½ Σ m |ṙ|² + ½ ω·I ω with ṙ, ω the exact time derivatives
//      (dual tangents) of the position stage along q̇ — not the engine's velocity stage.
//   4. Work–energy: along ẏ = f(t, y), dE/dt = P, E = T + V (gravity, joint springs, spring
//      potentials) and P the power of everything non-conservative — joint dampers (−c u²),
//      the damping of spring-dampers (−c L̇²), applied forces (F·v_P) and torques (T·ω),
//      including forces that depend on t, q and u. dE/dt is computed (a) by fourth-order central
//      differences E(y ± h ẏ) and (b) exactly, with E evaluated on Workspace<Dual> with tangent ẏ.
//      P is computed in the test from the scene's forces, written out again in C++, with point
//      velocities from dual tangents of the position stage. Because u̇ = M⁻¹f enters dE/dt
//      through T, this ties the forcing f to the energies and the scene's forces.
#include <gtest/gtest.h>

#include <functional>

#include "../support/kane_test_support.hpp"
#include "math/dual.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/frames.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

// Exact kinematics along a direction in q, from the position stage only: positions, rotation
// matrices and their directional derivatives (dual tangents).
class Kinematics {
 public:
  Kinematics(const ks::Model& m, const std::vector<double>& p) : m_(m), ws_(m) {
    std::vector<ks::Dual> pd(p.begin(), p.end());
    ks::set_parameters(m, ws_, pd.data());
  }
  // Positions at q, derivatives along dq.
  void at(const double* q, const double* dq) {
    std::vector<ks::Dual> qd(m_.nq);
    for (int i = 0; i < m_.nq; ++i) qd[i] = ks::Dual(q[i], dq[i]);
    ks::compute_position(m_, ws_, qd.data());
  }
  Matrix3d R(int b) const {
    return ws_.R[b].unaryExpr([](const ks::Dual& x) { return x.v; });
  }
  Matrix3d Rdot(int b) const {
    return ws_.R[b].unaryExpr([](const ks::Dual& x) { return x.d; });
  }
  Vector3d omega(int b) const { return unskew3(Rdot(b) * R(b).transpose()); }
  Vector3d point(int b, const Vector3d& r) const {
    if (b < 0) return r;
    const ks::Vec3<ks::Dual> c = ks::world_point(m_, ws_, b, ks::Vec3<ks::Dual>::Zero().eval());
    return Vector3d(c[0].v, c[1].v, c[2].v) + R(b) * r;
  }
  Vector3d point_velocity(int b, const Vector3d& r) const {
    if (b < 0) return Vector3d::Zero();
    const ks::Vec3<ks::Dual> c = ks::world_point(m_, ws_, b, ks::Vec3<ks::Dual>::Zero().eval());
    return Vector3d(c[0].d, c[1].d, c[2].d) + Rdot(b) * r;
  }
  // Rate of change of the distance between two points (spring-damper L̇).
  double length_rate(int a, const Vector3d& ra, int b, const Vector3d& rb) const {
    const Vector3d e = (point(b, rb) - point(a, ra)).normalized();
    return e.dot(point_velocity(b, rb) - point_velocity(a, ra));
  }

 private:
  const ks::Model& m_;
  ks::Workspace<ks::Dual> ws_;
};

// Power of the non-conservative forces of a scene, written by hand from its YAML.
using PowerFn = std::function<double(const ks::Model&, const Kinematics&, double t, const double* q,
                                     const double* u)>;

struct SceneCase {
  const char* name;
  const char* yaml;
  PowerFn power;
  double range_q = 1.0, range_u = 1.0;
};

int body(const ks::Model& m, const char* name) {
  return m.find_body(name);
}

// ---- scenes -----------------------------------------------------------------------------------

constexpr const char* kPlanarChain = R"yaml(
kanesens: 1
scene:
  name: planar_chain
  gravity: [0, -9.81, 0]
  parameters: {m: 1.0, L: 0.8, k1: 3.0, c1: 0.2, k2: 2.0, c2: 0.15, ks: 20.0, cs: 0.7}
  bodies:
    - {name: l1, mass: m, inertia: {shape: rod, length: L, axis: y}}
    - {name: l2, mass: "1.3*m", inertia: {shape: rod, length: L, axis: y}}
    - {name: l3, mass: "0.7*m", inertia: {shape: box, size: [0.1, L, 0.05]}}
  joints:
    - {name: j1, type: revolute, parent: ground, child: l1, axis: [0, 0, 1],
       child_point: [0, "L/2", 0], spring: {k: k1, rest: 0.2}, damper: {c: c1}}
    - {name: j2, type: revolute, parent: l1, child: l2, axis: [0, 0, 1], parent_point: [0, "-L/2", 0],
       child_point: [0, "L/2", 0], spring: {k: k2, rest: -0.1}, damper: {c: c2}}
    - {name: j3, type: revolute, parent: l2, child: l3, axis: [0, 0, 1], parent_point: [0, "-L/2", 0],
       child_point: [0, "L/2", 0], damper: {c: c1}}
  forces:
    - {type: spring_damper, name: tether, body_a: l3, point_a: [0, "-L/2", 0], body_b: ground,
       point_b: [1.0, -2.0, 0], k: ks, c: cs, rest: 0.5}
)yaml";

double planar_chain_power(const ks::Model& m, const Kinematics& kin, double, const double*,
                          const double* u) {
  const double c1 = 0.2, c2 = 0.15, cs = 0.7, L = 0.8;
  const double Ld = kin.length_rate(body(m, "l3"), {0, -L / 2, 0}, -1, {1.0, -2.0, 0});
  return -c1 * u[0] * u[0] - c2 * u[1] * u[1] - c1 * u[2] * u[2] - cs * Ld * Ld;
}

constexpr const char* kArm3d = R"yaml(
kanesens: 1
scene:
  name: arm3d
  gravity: [0, 0, -9.81]
  parameters: {m1: 2.0, m2: 1.5, m3: 1.0, m4: 0.8, m5: 0.5, Ixy: 0.01, c: 0.3, k: 4.0}
  bodies:
    - {name: base, mass: m1, inertia: {xx: 0.20, yy: 0.25, zz: 0.30, xy: Ixy, yz: -0.02, xz: 0.015}}
    - {name: upper, mass: m2, inertia: {xx: 0.12, yy: 0.10, zz: 0.05, xy: -0.01, yz: 0.008, xz: 0.02}}
    - {name: slide, mass: m3, inertia: {xx: 0.05, yy: 0.06, zz: 0.04, xy: 0.004, yz: 0.003, xz: -0.005}}
    - {name: wrist, mass: m4, inertia: {xx: 0.03, yy: 0.025, zz: 0.02, xy: 0.002, yz: -0.001, xz: 0.003}}
    - {name: hand, mass: m5, inertia: {xx: 0.01, yy: 0.012, zz: 0.015, xy: -0.001, yz: 0.002, xz: 0.001}}
  joints:
    - {name: yaw, type: revolute, parent: ground, child: base, axis: [0, 0, 1],
       parent_point: [0.1, 0, 0.2], child_point: [0.05, 0, -0.1], damper: {c: c}}
    - {name: shoulder, type: universal, parent: base, child: upper, axes: [[1, 0, 0], [0, 1, 0.2]],
       parent_point: [0, 0, 0.15], child_point: [0.02, 0, -0.3]}
    - {name: extend, type: prismatic, parent: upper, child: slide, axis: [0.1, 0, 1],
       parent_point: [0, 0.01, 0.3], child_point: [0, 0, -0.1], spring: {k: k, rest: 0.05}, damper: {c: c}}
    - {name: twist, type: cylindrical, parent: slide, child: wrist, axis: [0, 1, 1],
       parent_point: [0, 0, 0.1], child_point: [0.03, -0.02, 0.0]}
    - {name: palm, type: planar, parent: wrist, child: hand, axis: [1, 0.2, 0.3],
       parent_point: [0.05, 0, 0], child_point: [0, 0.04, 0.02]}
)yaml";

double arm3d_power(const ks::Model&, const Kinematics&, double, const double*, const double* u) {
  // Speeds: yaw.u, shoulder.u1, shoulder.u2, extend.u, twist.u1, twist.u2, palm.u1..u3.
  const double c = 0.3;
  return -c * u[0] * u[0] - c * u[3] * u[3];
}

constexpr const char* kSphericalTop = R"yaml(
kanesens: 1
scene:
  name: spherical_top
  gravity: [0, 0, -9.81]
  parameters: {m: 1.2, l: 0.3, cf: 0.05}
  bodies:
    - {name: rotor, mass: m, inertia: {xx: 0.02, yy: 0.025, zz: 0.035, xy: 0.001, yz: -0.002, xz: 0.0015}}
    - {name: flap, mass: 0.2, inertia: {shape: box, size: [0.1, 0.02, 0.05]}}
  joints:
    - {name: top, type: spherical, parent: ground, child: rotor, child_point: [0, 0, "-l"]}
    - {name: hinge, type: revolute, parent: rotor, child: flap, axis: [1, 0, 0],
       parent_point: [0, 0.05, 0.1], child_point: [0, -0.05, 0], damper: {c: cf}}
)yaml";

double spherical_top_power(const ks::Model&, const Kinematics&, double, const double*,
                           const double* u) {
  return -0.05 * u[3] * u[3];  // speeds: top.wx, wy, wz, hinge.u
}

constexpr const char* kFreeForced = R"yaml(
kanesens: 1
scene:
  name: free_forced
  gravity: [0, -9.81, 0]
  parameters: {m: 1.5, ks: 12.0, cs: 0.4, cb: 0.08}
  bodies:
    - {name: brick, mass: m, inertia: {xx: 0.05, yy: 0.07, zz: 0.09, xy: 0.004, yz: -0.006, xz: 0.003}}
    - {name: bob, mass: 0.3, inertia: {shape: sphere, radius: 0.05}}
  joints:
    - {name: float, type: free, parent: ground, child: brick, parent_point: [0.2, 0, 0],
       child_point: [0.1, 0.05, -0.02]}
    - {name: swing, type: revolute, parent: brick, child: bob, axis: [0, 0, 1],
       parent_point: [0, -0.1, 0], child_point: [0, 0.2, 0], damper: {c: cb}}
  forces:
    - {type: spring_damper, name: tether, body_a: brick, point_a: [0.1, 0.05, 0.1], body_b: ground,
       point_b: [0, 1, 0], k: ks, c: cs, rest: 0.3}
    - {type: force, name: push_w, body: brick, point: [0.05, 0, 0.02],
       vector: ["sin(2*t)", "0.3*float.z", "-0.2*float.vx + 0.1*float.wy"], frame: world}
    - {type: force, name: push_b, body: bob, point: [-0.03, 0.02, 0],
       vector: ["0.5*cos(t)", "float.qx*float.wz", 0.4], frame: body}
    - {type: torque, name: twist_w, body: brick, vector: ["0.1*t", "-0.05*float.wx", "0.2*float.qy"],
       frame: world}
    - {type: torque, name: twist_b, body: bob, vector: [0.03, "0.1*sin(t)*float.y", "-0.02*swing.u"],
       frame: body}
)yaml";

double free_forced_power(const ks::Model& m, const Kinematics& kin, double t, const double* q,
                         const double* u) {
  // q: float.x y z qw qx qy qz, swing.q;  u: float.vx vy vz wx wy wz, swing.u.
  const int brick = body(m, "brick"), bob = body(m, "bob");
  const double cs = 0.4, cb = 0.08;
  double P = -cb * u[6] * u[6];
  const double Ld = kin.length_rate(brick, {0.1, 0.05, 0.1}, -1, {0, 1, 0});
  P += -cs * Ld * Ld;
  const Vector3d F_w(std::sin(2 * t), 0.3 * q[2], -0.2 * u[0] + 0.1 * u[4]);
  P += F_w.dot(kin.point_velocity(brick, {0.05, 0, 0.02}));
  const Vector3d F_b(0.5 * std::cos(t), q[4] * u[5], 0.4);
  P += (kin.R(bob) * F_b).dot(kin.point_velocity(bob, {-0.03, 0.02, 0}));
  const Vector3d T_w(0.1 * t, -0.05 * u[3], 0.2 * q[5]);
  P += T_w.dot(kin.omega(brick));
  const Vector3d T_b(0.03, 0.1 * std::sin(t) * q[1], -0.02 * u[6]);
  P += (kin.R(bob) * T_b).dot(kin.omega(bob));
  return P;
}

// Quaternion joints and a planar joint under moving parents, and a weld.
constexpr const char* kNested = R"yaml(
kanesens: 1
scene:
  name: nested
  gravity: [0.5, -9.81, 0.3]
  parameters: {cc: 0.25}
  bodies:
    - {name: carrier, mass: 3.0, inertia: {xx: 0.3, yy: 0.2, zz: 0.25, xy: 0.02, yz: 0.01, xz: -0.03}}
    - {name: bob, mass: 1.1, inertia: {xx: 0.04, yy: 0.05, zz: 0.06, xy: -0.003, yz: 0.002, xz: 0.004}}
    - {name: drone, mass: 0.6, inertia: {xx: 0.02, yy: 0.03, zz: 0.035, xy: 0.001, yz: -0.002, xz: 0.0015}}
    - {name: sled, mass: 0.9, inertia: {shape: box, size: [0.3, 0.2, 0.1]}}
    - {name: lump, mass: 0.4, inertia: {xx: 0.01, yy: 0.012, zz: 0.014, xy: 0.001}}
  joints:
    - {name: turn, type: revolute, parent: ground, child: carrier, axis: [0, 1, 0.3],
       parent_point: [0.1, 0.2, 0], child_point: [0.3, 0, 0.1], damper: {c: cc}}
    - {name: ball, type: spherical, parent: carrier, child: bob, parent_point: [0.2, -0.1, 0.3],
       child_point: [0.05, 0.25, -0.04]}
    - {name: hover, type: free, parent: bob, child: drone, parent_point: [0, -0.1, 0.05],
       child_point: [0.02, 0.03, -0.01]}
    - {name: skate, type: planar, parent: carrier, child: sled, axis: [1, 0, 0],
       parent_point: [-0.2, 0, 0.1], child_point: [0.05, 0.02, 0]}
    - {name: glue, type: weld, parent: sled, child: lump, parent_point: [0.1, 0.1, 0],
       child_point: [0, -0.05, 0.02]}
  forces:
    - {type: force, name: thrust, body: drone, point: [0.01, 0, 0.02],
       vector: ["0.2*hover.qz", "2 + 0.3*cos(3*t)", "-0.1*hover.wy"], frame: body}
)yaml";

double nested_power(const ks::Model& m, const Kinematics& kin, double t, const double* q,
                    const double* u) {
  // q: turn.q, ball.qw..qz (1-4), hover.x y z qw qx qy qz (5-11), skate.q1..q3 (12-14);
  // u: turn.u, ball.wx..wz (1-3), hover.vx..wz (4-9), skate.u1..u3 (10-12).
  const int drone = body(m, "drone");
  const Vector3d F_b(0.2 * q[11], 2 + 0.3 * std::cos(3 * t), -0.1 * u[8]);
  return -0.25 * u[0] * u[0] + (kin.R(drone) * F_b).dot(kin.point_velocity(drone, {0.01, 0, 0.02}));
}

const std::vector<SceneCase>& scenes() {
  static const std::vector<SceneCase> s = {
      {"planar_chain", kPlanarChain, planar_chain_power, 1.5, 2.0},
      {"arm3d", kArm3d, arm3d_power, 1.0, 2.0},
      {"spherical_top", kSphericalTop, spherical_top_power, 1.0, 4.0},
      {"free_forced", kFreeForced, free_forced_power, 1.0, 2.0},
      {"nested", kNested, nested_power, 1.0, 2.0},
  };
  return s;
}

class KaneIdentities : public ::testing::TestWithParam<SceneCase> {};

// ---- 1 and 2: M is SPD and equals its definition from finite-differenced partial velocities --
TEST_P(KaneIdentities, MassMatrixIsSpdAndMatchesPartialVelocityDefinition) {
  const SceneCase& sc = GetParam();
  const ks::Model m = model_from_text(sc.yaml);
  const std::vector<double> p = m.nominal_parameters();
  ks::Workspace<double> ws(m), ws_h(m);
  ks::set_parameters(m, ws, p.data());
  ks::set_parameters(m, ws_h, p.data());
  std::mt19937_64 rng(1234);
  const double h = 1e-6;
  double worst_sym = 0, worst_def = 0, min_eig = 1e300;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> y = random_state(m, rng, sc.range_q, sc.range_u);
    const double* q = y.data();
    ks::evaluate_mass_matrix_and_forcing(m, ws, 0.0, q, q + m.nq);
    const Eigen::MatrixXd M = ws.mass_matrix;
    const double scale = max_abs(M);
    worst_sym = std::max(worst_sym, max_abs(M - M.transpose()) / scale);
    Eigen::LLT<Eigen::MatrixXd> llt(M);
    EXPECT_EQ(llt.info(), Eigen::Success) << sc.name << " trial " << trial;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
    min_eig = std::min(min_eig, eig.eigenvalues().minCoeff() / eig.eigenvalues().maxCoeff());

    // Partial velocities by central differences along q̇ = N(q) e_k.
    const int nb = m.nbody();
    std::vector<std::vector<Vector3d>> V(nb, std::vector<Vector3d>(m.nu)),
        W(nb, std::vector<Vector3d>(m.nu));
    std::vector<Matrix3d> R0(nb);
    std::vector<Matrix3d> I_world(nb);
    ks::compute_position(m, ws_h, q);
    for (int b = 0; b < nb; ++b) {
      R0[b] = ws_h.R[b];
      I_world[b] = R0[b] * ws_h.inertia_body[b] * R0[b].transpose();
    }
    for (int k = 0; k < m.nu; ++k) {
      std::vector<double> ek(m.nu, 0.0);
      ek[k] = 1;
      const std::vector<double> dq = qdot_of(m, q, ek.data());
      std::vector<double> qp(q, q + m.nq), qm(q, q + m.nq);
      for (int i = 0; i < m.nq; ++i) {
        qp[i] += h * dq[i];
        qm[i] -= h * dq[i];
      }
      ks::compute_position(m, ws_h, qp.data());
      std::vector<Vector3d> cp(nb);
      for (int b = 0; b < nb; ++b) cp[b] = ks::world_point(m, ws_h, b, Vector3d::Zero().eval());
      std::vector<Matrix3d> Rp(ws_h.R.begin(), ws_h.R.end());
      ks::compute_position(m, ws_h, qm.data());
      for (int b = 0; b < nb; ++b) {
        V[b][k] = (cp[b] - ks::world_point(m, ws_h, b, Vector3d::Zero().eval())) / (2 * h);
        W[b][k] = unskew3((Rp[b] - ws_h.R[b]) / (2 * h) * R0[b].transpose());
      }
    }
    Eigen::MatrixXd M_def = Eigen::MatrixXd::Zero(m.nu, m.nu);
    for (int b = 0; b < nb; ++b)
      for (int k = 0; k < m.nu; ++k)
        for (int l = 0; l < m.nu; ++l)
          M_def(k, l) += ws_h.mass[b] * V[b][k].dot(V[b][l]) + W[b][k].dot(I_world[b] * W[b][l]);
    worst_def = std::max(worst_def, max_abs(M - M_def) / scale);
  }
  std::printf("%-14s M: asymmetry %.1e, min eig/max eig %.2e, |M - M_def|/|M| %.2e (FD h = %g)\n",
              sc.name, worst_sym, min_eig, worst_def, h);
  EXPECT_LE(worst_sym, 1e-15);
  EXPECT_GT(min_eig, 0.0);
  EXPECT_LT(worst_def, 1e-8);  // central differences: O(h²) + O(eps/h) ≈ 1e-10
}

// ---- 3 and 4: kinetic energy from exact point velocities; dE/dt = P ---------------------------
TEST_P(KaneIdentities, EnergyRateEqualsPowerOfNonConservativeForces) {
  const SceneCase& sc = GetParam();
  const ks::Model m = model_from_text(sc.yaml);
  const std::vector<double> p = m.nominal_parameters();
  ks::Workspace<double> ws(m);
  ks::Workspace<ks::Dual> wsd(m);
  ks::set_parameters(m, ws, p.data());
  {
    std::vector<ks::Dual> pd(p.begin(), p.end());
    ks::set_parameters(m, wsd, pd.data());
  }
  Kinematics kin(m, p);
  auto energy = [&](double t, const std::vector<double>& y) {
    ks::evaluate_state_expressions(m, ws, t, y.data(), y.data() + m.nq);
    ks::compute_position(m, ws, y.data());
    ks::compute_velocity(m, ws, y.data() + m.nq);
    return ks::kinetic_energy(m, ws) + ks::potential_energy(m, ws, y.data());
  };

  std::mt19937_64 rng(98765);
  std::uniform_real_distribution<double> time(0.0, 5.0);
  double worst_fd = 0, worst_dual = 0, worst_T = 0, worst_N = 0, max_P = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> y = random_state(m, rng, sc.range_q, sc.range_u);
    const double t = time(rng);
    const double* q = y.data();
    const double* u = q + m.nq;
    std::vector<double> ydot(m.nstate());
    ASSERT_TRUE(ks::evaluate_rhs(m, ws, t, y.data(), ydot.data()));

    // q̇ = N(q) u: the engine's kinematic equations against the test's.
    const std::vector<double> qd = qdot_of(m, q, u);
    for (int i = 0; i < m.nq; ++i) worst_N = std::max(worst_N, std::abs(ydot[i] - qd[i]));

    // Kinetic energy from exact derivatives of the positions.
    kin.at(q, qd.data());
    double T_ref = 0;
    for (int b = 0; b < m.nbody(); ++b) {
      const Vector3d v = kin.point_velocity(b, Vector3d::Zero()), w = kin.omega(b);
      const Matrix3d R = kin.R(b);
      T_ref += 0.5 * ws.mass[b] * v.squaredNorm() +
               0.5 * w.dot(R * ws.inertia_body[b] * R.transpose() * w);
    }
    const double E0 = energy(t, y);
    const double T = ks::kinetic_energy(m, ws);
    worst_T = std::max(worst_T, std::abs(T - T_ref) / T_ref);
    (void)E0;

    // Power of the non-conservative forces, from the scene written out by hand.
    const double P = sc.power(m, kin, t, q, u);

    // dE/dt (a) fourth-order central differences along ẏ (E has no explicit t: the springs
    // have constant k). The step moves the state by h·|ẏ|∞ = 3e-3 whatever the size of ẏ:
    // truncation O(h⁴) (measured ≤ 1e-10 relative at 3e-3), round-off O(eps |E| / h).
    double ydot_max = 1;
    for (double v : ydot) ydot_max = std::max(ydot_max, std::abs(v));
    const double h = 3e-3 / ydot_max;
    auto shifted = [&](double s) {
      std::vector<double> ys = y;
      for (int i = 0; i < m.nstate(); ++i) ys[i] += s * h * ydot[i];
      return energy(t, ys);
    };
    const double dE_fd = (-shifted(2) + 8 * shifted(1) - 8 * shifted(-1) + shifted(-2)) / (12 * h);

    // (b) exactly: E on duals with tangent ẏ; T and V separately give the scale of the sum.
    std::vector<ks::Dual> yd(m.nstate());
    for (int i = 0; i < m.nstate(); ++i) yd[i] = ks::Dual(y[i], ydot[i]);
    const ks::Dual* qdl = yd.data();
    ks::evaluate_state_expressions(m, wsd, ks::Dual(t, 1.0), qdl, qdl + m.nq);
    ks::compute_position(m, wsd, qdl);
    ks::compute_velocity(m, wsd, qdl + m.nq);
    const double dT = ks::kinetic_energy(m, wsd).d, dV = ks::potential_energy(m, wsd, qdl).d;
    const double dE_dual = dT + dV;

    // Scale: the terms that cancel (the identity is a balance of dT/dt, dV/dt and P).
    const double scale = std::abs(dT) + std::abs(dV) + std::abs(P);
    worst_fd = std::max(worst_fd, std::abs(dE_fd - P) / scale);
    worst_dual = std::max(worst_dual, std::abs(dE_dual - P) / scale);
    max_P = std::max(max_P, std::abs(P) / scale);
  }
  std::printf(
      "%-14s dE/dt = P: rel. error finite diff %.2e, dual %.2e (|P|/scale up to %.2f); "
      "T vs exact point velocities %.2e; q̇ = N(q)u %.1e\n",
      sc.name, worst_fd, worst_dual, max_P, worst_T, worst_N);
  EXPECT_LT(worst_fd, 1e-8);
  EXPECT_LT(worst_dual, 1e-12);
  EXPECT_LT(worst_T, 1e-12);
  EXPECT_LT(worst_N, 1e-14);
}

INSTANTIATE_TEST_SUITE_P(Scenes, KaneIdentities, ::testing::ValuesIn(scenes()),
                         [](const ::testing::TestParamInfo<SceneCase>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace

}  // namespace KANESENS_UNITY_ID
