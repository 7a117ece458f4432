// Kane's M and f (SymPy KanesMethod convention, M u̇ = f) against textbook closed forms, at
// random states (fixed seed):
//   (a) a rigid body on a spherical joint (fixed point O): Euler's equations about O in body
//       components, I_O ω̇ = −ω × I_O ω + r × m g_B, I_O = I_c + m (|r|² 𝟙 − r rᵀ)
//       (parallel-axis theorem; Goldstein, Classical Mechanics, §5.1/5.6);
//   (b) a free body: Newton for the mass center (world components), Euler about the mass center
//       (body components);
//   (c) a uniform rod pendulum about its end: M = m L²/3, f = −m g (L/2) sin q;
//   (d) a prismatic spring–mass–damper: M = m, f = −k x − c ẋ;
//   (e) the joint conventions of docs/reference/scene.md (rotation and mass-center position of
//       the child for every joint type, written here with Eigen::AngleAxis and quaternions).
// Energies are checked too: T = ½ uᵀ M u from the closed-form M, V from the mass-center height.
#include <gtest/gtest.h>

#include "../support/kane_test_support.hpp"
#include "../support/test_scenes.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/frames.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double kTol = 1e-12;  // relative to the size of the quantity compared

struct Evaluated {
  Eigen::MatrixXd M;
  Eigen::VectorXd f;
  double T = 0, V = 0;
};

Evaluated evaluate(const ks::Model& m, ks::Workspace<double>& ws, const std::vector<double>& y,
                   double t = 0) {
  ks::evaluate_mass_matrix_and_forcing(m, ws, t, y.data(), y.data() + m.nq);
  return {ws.mass_matrix, ws.forcing, ks::kinetic_energy(m, ws),
          ks::potential_energy(m, ws, y.data())};
}

// The worst relative errors of M, f and the energies over the random states; `what` names the
// system in the log and in a failure.
struct WorstErrors {
  double M = 0, f = 0, E = 0;
  void add(double err_M, double err_f, double err_E) {
    M = std::max(M, err_M);
    f = std::max(f, err_f);
    E = std::max(E, err_E);
  }
  void expect_below_tolerance(const char* what) const {
    std::printf("%s: worst rel. error M %.2e, f %.2e, energies %.2e\n", what, M, f, E);
    EXPECT_LT(M, kTol) << what;
    EXPECT_LT(f, kTol) << what;
    EXPECT_LT(E, kTol) << what;
  }
};

// ---- (a) top on a spherical joint -----------------------------------------------------------
constexpr const char* kTop = R"(
kanesens: 1
scene:
  name: top
  gravity: [0.4, -9.81, 1.3]
  parameters: {m: 2.5, l: 0.7}
  bodies:
    - {name: rotor, mass: m, inertia: {xx: 0.31, yy: 0.42, zz: 0.55, xy: 0.021, yz: -0.033, xz: 0.047}}
  joints:
    - {name: top, type: spherical, parent: ground, child: rotor, child_point: [0, 0, "-l"]}
)";

TEST(KaneClosedForms, TopOnSphericalJointIsEulerAboutFixedPoint) {
  const ks::Model m = model_from_text(kTop);
  ASSERT_EQ(m.nq, 4);
  ASSERT_EQ(m.nu, 3);
  ks::Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  ks::set_parameters(m, ws, p.data());

  const double mass = 2.5, l = 0.7;
  const Vector3d g(0.4, -9.81, 1.3);
  Matrix3d Ic;
  Ic << 0.31, 0.021, 0.047, 0.021, 0.42, -0.033, 0.047, -0.033, 0.55;
  const Vector3d r(0, 0, l);  // O → mass center, body components
  const Matrix3d IO = Ic + mass * (r.squaredNorm() * Matrix3d::Identity() - r * r.transpose());

  std::mt19937_64 rng(20240611);
  WorstErrors worst;
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<double> y = random_state(m, rng, 1.0, 3.0);
    const Eigen::Vector4d e(y[0], y[1], y[2], y[3]);
    const Vector3d w(y[4], y[5], y[6]);
    const Matrix3d R = quat_to_matrix(e);
    const Evaluated ev = evaluate(m, ws, y);

    const Vector3d f_ref = -w.cross(IO * w) + r.cross(R.transpose() * (mass * g));
    const double T_ref = 0.5 * w.dot(IO * w);
    const double V_ref = -mass * g.dot(R * r);
    worst.add(max_abs(ev.M - IO) / max_abs(IO), (ev.f - f_ref).cwiseAbs().maxCoeff() / f_ref.cwiseAbs().maxCoeff(),
              std::abs(ev.T - T_ref) / std::abs(T_ref) + std::abs(ev.V - V_ref) / (mass * g.norm() * l));
  }
  worst.expect_below_tolerance("top");
}

// ---- (b) free body ----------------------------------------------------------------------------
constexpr const char* kFree = R"(
kanesens: 1
scene:
  name: free_body
  gravity: [0.2, -9.81, 0.5]
  parameters: {m: 1.7}
  bodies:
    - {name: brick, mass: m, inertia: {xx: 0.5, yy: 0.7, zz: 0.9, xy: -0.04, yz: 0.06, xz: 0.03}}
  joints:
    - {name: float, type: free, parent: ground, child: brick}
)";

TEST(KaneClosedForms, FreeBodyIsNewtonEuler) {
  const ks::Model m = model_from_text(kFree);
  ASSERT_EQ(m.nq, 7);
  ASSERT_EQ(m.nu, 6);
  ks::Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  ks::set_parameters(m, ws, p.data());
  const double mass = 1.7;
  const Vector3d g(0.2, -9.81, 0.5);
  Matrix3d I;
  I << 0.5, -0.04, 0.03, -0.04, 0.7, 0.06, 0.03, 0.06, 0.9;
  Eigen::MatrixXd M_ref = Eigen::MatrixXd::Zero(6, 6);
  M_ref.topLeftCorner(3, 3) = mass * Matrix3d::Identity();
  M_ref.bottomRightCorner(3, 3) = I;

  std::mt19937_64 rng(7);
  WorstErrors worst;
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<double> y = random_state(m, rng, 2.0, 3.0);
    const Vector3d x(y[0], y[1], y[2]), v(y[7], y[8], y[9]), w(y[10], y[11], y[12]);
    const Evaluated ev = evaluate(m, ws, y);
    Eigen::VectorXd f_ref(6);
    f_ref << mass * g, -w.cross(I * w);
    const double T_ref = 0.5 * mass * v.squaredNorm() + 0.5 * w.dot(I * w);
    const double V_ref = -mass * g.dot(x);
    worst.add(max_abs(ev.M - M_ref) / max_abs(M_ref), (ev.f - f_ref).cwiseAbs().maxCoeff() / f_ref.cwiseAbs().maxCoeff(),
              std::abs(ev.T - T_ref) / T_ref + std::abs(ev.V - V_ref) / (mass * g.norm() * 2));
  }
  worst.expect_below_tolerance("free body");
}

// ---- (c) uniform rod pendulum -----------------------------------------------------------------
const std::string kPendulum = kanesens::test_scenes::rod_pendulum_scene("rod_pendulum", "{m: 1.3, L: 0.9}");

TEST(KaneClosedForms, UniformRodPendulum) {
  const ks::Model m = model_from_text(kPendulum);
  ks::Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  ks::set_parameters(m, ws, p.data());
  const double mass = 1.3, L = 0.9, g = 9.81;
  std::mt19937_64 rng(11);
  WorstErrors worst;
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<double> y = random_state(m, rng, 4.0, 5.0);
    const Evaluated ev = evaluate(m, ws, y);
    const double M_ref = mass * L * L / 3, f_ref = -mass * g * (L / 2) * std::sin(y[0]);
    const double T_ref = 0.5 * M_ref * y[1] * y[1], V_ref = -mass * g * (L / 2) * std::cos(y[0]);
    worst.add(std::abs(ev.M(0, 0) - M_ref) / M_ref, std::abs(ev.f[0] - f_ref) / (mass * g * L / 2),
              std::abs(ev.T - T_ref) / (M_ref * 25) + std::abs(ev.V - V_ref) / (mass * g * L));
  }
  worst.expect_below_tolerance("rod pendulum");
}

// ---- (d) prismatic spring–mass–damper ---------------------------------------------------------
constexpr const char* kSlider = R"(
kanesens: 1
scene:
  name: spring_mass_damper
  gravity: [0, -9.81, 0]   # perpendicular to the slide: does no work
  parameters: {m: 2.0, c: 0.3, k: 5.0}
  bodies:
    - {name: block, mass: m, inertia: {shape: box, size: [0.2, 0.1, 0.1]}}
  joints:
    - {name: slider, type: prismatic, parent: ground, child: block, axis: [1, 0, 0],
       spring: {k: k, rest: 0}, damper: {c: c}}
)";

TEST(KaneClosedForms, PrismaticSpringMassDamper) {
  const ks::Model m = model_from_text(kSlider);
  ks::Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  ks::set_parameters(m, ws, p.data());
  const double mass = 2.0, c = 0.3, k = 5.0;
  std::mt19937_64 rng(13);
  double worst = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<double> y = random_state(m, rng, 2.0, 3.0);
    const Evaluated ev = evaluate(m, ws, y);
    const double f_ref = -k * y[0] - c * y[1];
    worst = std::max({worst, std::abs(ev.M(0, 0) - mass) / mass,
                      std::abs(ev.f[0] - f_ref) / (k * 2 + c * 3),
                      std::abs(ev.T - 0.5 * mass * y[1] * y[1]) / (mass * 9),
                      std::abs(ev.V - 0.5 * k * y[0] * y[0]) / (k * 4)});
  }
  std::printf("spring-mass-damper: worst rel. error %.2e\n", worst);
  EXPECT_LT(worst, kTol);
}

// ---- (e) joint conventions --------------------------------------------------------------------
// One body on one joint to ground, parent_point P, child_point c, at a given q: the child's
// rotation R and its mass center P + d(q) − R c must follow the table of docs/reference/scene.md.
struct ConventionCase {
  const char* name;
  const char* joint;  // the joint's YAML fields after parent/child
  std::vector<double> q;
};

Matrix3d rot(const Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

TEST(KaneClosedForms, JointKinematicsFollowSceneContract) {
  const Vector3d P(0.3, -0.2, 0.5), c(0.1, 0.4, -0.25);
  const std::vector<ConventionCase> cases = {
      {"revolute", "type: revolute, axis: [1, 2, 2]", {0.7}},
      {"prismatic", "type: prismatic, axis: [0, 3, 4]", {0.35}},
      {"cylindrical", "type: cylindrical, axis: [1, 1, 0]", {-0.6, 0.2}},
      {"universal", "type: universal, axes: [[1, 0, 0], [0, 1, 1]]", {0.5, -0.8}},
      {"universal_zx", "type: universal, axes: [[0, 0, 1], [1, 0, 0]]", {0.5, -0.8}},  // coordinate axes
      {"planar_z", "type: planar, axis: [0, 0, 1]", {0.2, -0.3, 1.1}},
      {"planar_x", "type: planar, axis: [1, 0, 0]", {0.2, -0.3, 1.1}},
      {"planar_tilted", "type: planar, axis: [1, 1, 1]", {0.2, -0.3, 1.1}},
      {"spherical", "type: spherical", {0.5, 0.5, -0.5, 0.5}},
      {"free", "type: free", {0.4, -0.1, 0.2, 0.5, 0.1, 0.7, std::sqrt(1 - 0.25 - 0.01 - 0.49)}},
  };
  for (const ConventionCase& cc : cases) {
    const std::string yaml = std::string(R"yaml(
kanesens: 1
scene:
  name: convention
  bodies:
    - {name: b, mass: 1, inertia: {xx: 1, yy: 1, zz: 1}}
  joints:
    - {name: j, parent: ground, child: b, parent_point: [0.3, -0.2, 0.5], child_point: [0.1, 0.4, -0.25], )yaml") +
                             cc.joint + "}\n";
    const ks::Model m = model_from_text(yaml);
    ASSERT_EQ(m.nq, static_cast<int>(cc.q.size())) << cc.name;
    ks::Workspace<double> ws(m);
    const std::vector<double> p = m.nominal_parameters();
    ks::set_parameters(m, ws, p.data());
    ks::compute_position(m, ws, cc.q.data());
    const std::vector<double>& q = cc.q;
    Matrix3d R = Matrix3d::Identity();
    Vector3d d = Vector3d::Zero();  // joint-point displacement, parent (world) frame
    const std::string n = cc.name;
    if (n == "revolute") R = rot({1, 2, 2}, q[0]);
    if (n == "prismatic") d = q[0] * Vector3d(0, 0.6, 0.8);
    if (n == "cylindrical") {
      R = rot({1, 1, 0}, q[0]);
      d = q[1] * Vector3d(1, 1, 0).normalized();
    }
    if (n.rfind("universal", 0) == 0) {
      // The second axis is carried by the first rotation: the partial angular velocities are a1
      // and rot(a1, q1) a2.
      const Vector3d a1 = n == "universal" ? Vector3d(1, 0, 0) : Vector3d(0, 0, 1);
      const Vector3d a2 = n == "universal" ? Vector3d(0, 1, 1).normalized() : Vector3d(1, 0, 0);
      R = rot(a1, q[0]) * rot(a2, q[1]);
      EXPECT_LT((ws.partial[0].head<3>() - a1).norm(), 1e-15) << n;
      EXPECT_LT((ws.partial[1].head<3>() - rot(a1, q[0]) * a2).norm(), 1e-15) << n;
    }
    if (n.rfind("planar", 0) == 0) {
      // e1 = unit(x − (x·n) n) (y if n ∥ x), e2 = n × e1; translation first, then rot(n, q3).
      const Vector3d nn = n == "planar_z"   ? Vector3d(0, 0, 1)
                          : n == "planar_x" ? Vector3d(1, 0, 0)
                                            : Vector3d(1, 1, 1).normalized();
      const Vector3d x = n == "planar_x" ? Vector3d(0, 1, 0) : Vector3d(1, 0, 0);
      const Vector3d e1 = (x - x.dot(nn) * nn).normalized(), e2 = nn.cross(e1);
      if (n == "planar_z") {
        EXPECT_LT((e1 - Vector3d::UnitX()).norm() + (e2 - Vector3d::UnitY()).norm(), 1e-15);
      }
      d = q[0] * e1 + q[1] * e2;
      R = rot(nn, q[2]);
    }
    if (n == "spherical") R = quat_to_matrix(Eigen::Vector4d(q[0], q[1], q[2], q[3]));
    if (n == "free") {
      d = Vector3d(q[0], q[1], q[2]);
      R = quat_to_matrix(Eigen::Vector4d(q[3], q[4], q[5], q[6]));
    }
    const Vector3d com = P + d - R * c;
    EXPECT_LT(max_abs(ws.R[0] - R), 1e-14) << cc.name;
    EXPECT_LT((ks::world_point(m, ws, 0, Vector3d::Zero().eval()) - com).norm(), 1e-14) << cc.name;
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
