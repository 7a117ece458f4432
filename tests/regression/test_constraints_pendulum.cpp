// Constraint multipliers of pendulums built the constraint way, against closed forms:
//
//  * PinReactionMatchesClosedForm: configs/constrained_pendulum.yaml (rod on a planar joint,
//    `coincident` pin at its top end). With θ, θ̇ from the simulation and θ̈ = −(3g/2L) sin θ
//    (the physical pendulum), the mass-center acceleration is
//        a_c = (L/2)(cos θ θ̈ − sin θ θ̇², sin θ θ̈ + cos θ θ̇²)
//    and the pin force on the rod is R = m a_c − m g (g = (0, −9.81)). λ (force on body_a = rod
//    from ground, world x, y) must equal R at every output; θ must follow the 1-DOF equation
//    (integrated here by RK4, h = 1e-3).
//  * FreeRodPinnedMatchesSphericalJoint: the 3-D version, a cylinder on a free joint pinned by a
//    3-row `coincident`, against the same body on a spherical joint (a hanging symmetric top):
//    quaternion, angular velocity and mass-center position agree.
//  * RedundantPins*: the same pendulum pinned twice (two identical pins, or one pin with
//    components [x, y, z] in a planar scene, whose z row is identically zero). Motion unchanged,
//    constraint rank 2, λ the minimum-norm split (each pin R/2; z component 0).
//  * MultiplierSensitivityMatchesFiniteDifferences: dλ/dp from KaneProblem::multiplier_sensitivity
//    (p = m, L, theta0, base.u0[2]) against fourth-order central differences of λ(t) (see the
//    comment at the test for the norm).
//  * DistanceConstraintIsRodTension: a ball held at distance L from the origin by `distance`:
//    λ = force on body_b along e_ab = −(tension) = −m (g cos φ + L φ̇²).
#include <gtest/gtest.h>

#include <cstdio>

#include "../support/constraint_test_support.hpp"
#include "model/scene/parse_scene.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

constexpr double kG = 9.81;

ks::Model pendulum_model() {
  return ks::build_model(ks::parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/constrained_pendulum.yaml"));
}

// Closed-form pin reaction for state (θ, θ̇) of the physical pendulum.
std::array<double, 2> pin_reaction(double m, double L, double th, double thd) {
  const double thdd = -1.5 * kG / L * std::sin(th);
  const double ax = L / 2 * (std::cos(th) * thdd - std::sin(th) * thd * thd);
  const double ay = L / 2 * (std::sin(th) * thdd + std::cos(th) * thd * thd);
  return {m * ax, m * ay + m * kG};
}

TEST(ConstrainedPendulum, PinReactionMatchesClosedForm) {
  const ks::Model model = pendulum_model();
  ASSERT_EQ(model.nconstraint_rows, 2);
  const auto times = linspace(0, 5, 51);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r = run(model, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
    // RK4 of θ̈ = −(3g/2L) sin θ from θ0 = 0.5 at rest.
    const auto ref = rk4<2>([](const std::array<double, 2>& x) {
      return std::array<double, 2>{x[1], -1.5 * kG * std::sin(x[0])};
    }, {0.5, 0.0}, times, 1e-3);
    double worst_lambda = 0, worst_theta = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const int kk = static_cast<int>(k);
      const auto R = pin_reaction(1.0, 1.0, r.y(kk, 2), r.y(kk, 5));
      const double err = std::hypot(r.lambda(kk, 0) - R[0], r.lambda(kk, 1) - R[1]) / std::hypot(R[0], R[1]);
      worst_lambda = std::max(worst_lambda, err);
      worst_theta = std::max(worst_theta, std::abs(r.y(kk, 2) - ref[k][0]));
    }
    std::printf("pendulum pin, stabilization %d: worst |λ − R|/|R| = %.2e over %zu outputs; max |θ − θ_rk4| = %.2e\n",
                static_cast<int>(stab), worst_lambda, times.size(), worst_theta);
    // λ is an algebraic function of the state: exact (roundoff) on the constraint manifold; the
    // Baumgarte terms add 2α(Au) + β²g to the acceleration constraint, so λ moves with the drift.
    EXPECT_LT(worst_lambda, stab == Stab::baumgarte ? 1e-8 : 1e-12);
    EXPECT_LT(worst_theta, 1e-7);
  }
}

// A cylinder (length L along its y axis, radius 0.05) hanging from its top end.
std::string top_scene(bool free, const Eigen::Vector4d& q0, const Eigen::Vector3d& w0) {
  const Eigen::Matrix3d R = quat_to_matrix(q0);
  const Eigen::Vector3d c = -R * Eigen::Vector3d(0, 0.5, 0);  // mass center (L = 1)
  const Eigen::Vector3d v = (R * w0).cross(c);
  char buf[2048];
  const char* head = R"yaml(
kanesens: 1
scene:
  name: hanging_cylinder
  gravity: [0, -9.81, 0]
  bodies:
    - {name: rod, mass: 1.0, inertia: {shape: cylinder, radius: 0.05, length: 1.0, axis: y}}
  joints:
)yaml";
  if (free) {
    std::snprintf(buf, sizeof buf,
                  "%s    - {name: base, type: free, parent: ground, child: rod,\n"
                  "       q0: [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g], u0: [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g]}\n"
                  "  constraints:\n"
                  "    - {name: pin, type: coincident, body_a: rod, point_a: [0, 0.5, 0], body_b: ground, point_b: [0, 0, 0]}\n",
                  head, c[0], c[1], c[2], q0[0], q0[1], q0[2], q0[3], v[0], v[1], v[2], w0[0], w0[1], w0[2]);
  } else {
    std::snprintf(buf, sizeof buf,
                  "%s    - {name: base, type: spherical, parent: ground, child: rod, child_point: [0, 0.5, 0],\n"
                  "       q0: [%.17g, %.17g, %.17g, %.17g], u0: [%.17g, %.17g, %.17g]}\n",
                  head, q0[0], q0[1], q0[2], q0[3], w0[0], w0[1], w0[2]);
  }
  return buf;
}

TEST(ConstrainedPendulum, FreeRodPinnedMatchesSphericalJoint) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 0.3, 0.2).normalized();
  const double angle = 0.6;
  const Eigen::Vector4d q0(std::cos(angle / 2), std::sin(angle / 2) * axis[0], std::sin(angle / 2) * axis[1],
                           std::sin(angle / 2) * axis[2]);
  const Eigen::Vector3d w0(0.5, 6.0, -0.3);
  const ks::Model mf = model_from_text(top_scene(true, q0, w0));
  const ks::Model ms = model_from_text(top_scene(false, q0, w0));
  ASSERT_EQ(mf.nconstraint_rows, 3);
  const auto times = linspace(0, 5, 26);
  const TrajRun rs = run(ms, times, {}, tolerances(1e-11, 1e-13));
  double worst_q = 0, worst_w = 0, worst_x = 0;
  for (Stab stab : {Stab::projection, Stab::baumgarte}) {
    const TrajRun rf = run(mf, times, constraint_options(stab), tolerances(1e-11, 1e-13));
    ASSERT_TRUE(rf.tr.result.ok() && rs.tr.result.ok()) << rf.tr.result.message << rs.tr.result.message;
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      // free: x y z qw qx qy qz | vx vy vz wx wy wz;  spherical: qw qx qy qz | wx wy wz
      Eigen::Vector4d qs, qf;
      for (int c = 0; c < 4; ++c) {
        qs[c] = rs.y(k, c);
        qf[c] = rf.y(k, 3 + c);
      }
      const double sign = qs.dot(qf) < 0 ? -1 : 1;
      worst_q = std::max(worst_q, (qf - sign * qs).cwiseAbs().maxCoeff());
      for (int c = 0; c < 3; ++c) worst_w = std::max(worst_w, std::abs(rf.y(k, 10 + c) - rs.y(k, 4 + c)) / w0.norm());
      const Eigen::Vector3d cs = -quat_to_matrix(qs.normalized()) * Eigen::Vector3d(0, 0.5, 0);
      for (int c = 0; c < 3; ++c) worst_x = std::max(worst_x, std::abs(rf.y(k, c) - cs[c]));
    }
    std::printf("free rod + 3-row pin vs spherical joint (stabilization %d): max |Δquat| %.2e, max |Δω|/|ω0| %.2e, "
                "max |Δx_c| %.2e\n", static_cast<int>(stab), worst_q, worst_w, worst_x);
  }
  EXPECT_LT(worst_q, 1e-7);
  EXPECT_LT(worst_w, 1e-7);
  EXPECT_LT(worst_x, 1e-7);
}

// The rod of configs/constrained_pendulum.yaml, pinned by `constraints` (YAML list items).
std::string pinned_rod_scene(const std::string& name, const std::string& constraints) {
  return R"yaml(
kanesens: 1
scene:
  name: )yaml" + name + R"yaml(
  gravity: [0, -9.81, 0]
  parameters: {m: 1.0, L: 1.0, theta0: 0.5}
  bodies:
    - {name: rod, mass: m, inertia: {shape: rod, length: L, axis: y}}
  joints:
    - {name: base, type: planar, parent: ground, child: rod, axis: [0, 0, 1],
       q0: ["L/2*sin(theta0)", "-L/2*cos(theta0)", theta0]}
  constraints:
)yaml" + constraints;
}

const std::string kTwoPins = pinned_rod_scene("pinned_twice", R"yaml(
    - {name: pin1, type: coincident, body_a: rod, point_a: [0, "L/2", 0], body_b: ground, point_b: [0, 0, 0]}
    - {name: pin2, type: coincident, body_a: rod, point_a: [0, "L/2", 0], body_b: ground, point_b: [0, 0, 0]}
)yaml");

const std::string kXYZPin = pinned_rod_scene("pinned_xyz", R"yaml(
    - {name: pin, type: coincident, body_a: rod, point_a: [0, "L/2", 0], body_b: ground, point_b: [0, 0, 0],
       components: [x, y, z]}
)yaml");

TEST(ConstrainedPendulum, RedundantPinsShareTheReaction) {
  const ks::Model single = pendulum_model();
  const ks::Model twice = model_from_text(kTwoPins);
  ASSERT_EQ(twice.nconstraint_rows, 4);
  const auto times = linspace(0, 5, 51);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r1 = run(single, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    const TrajRun r2 = run(twice, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r1.tr.result.ok() && r2.tr.result.ok()) << r2.tr.result.message;
    double worst_y = 0, worst_split = 0;
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      for (int s = 0; s < 6; ++s) worst_y = std::max(worst_y, std::abs(r1.y(k, s) - r2.y(k, s)));
      const double R = std::hypot(r1.lambda(k, 0), r1.lambda(k, 1));
      for (int c = 0; c < 2; ++c) {
        worst_split = std::max(worst_split, std::abs(r2.lambda(k, c) - r1.lambda(k, c) / 2) / R);
        worst_split = std::max(worst_split, std::abs(r2.lambda(k, 2 + c) - r1.lambda(k, c) / 2) / R);
      }
    }
    std::printf("two identical pins (stabilization %d): max |Δy| %.2e vs one pin; max |λ_pin − R/2|/|R| %.2e\n",
                static_cast<int>(stab), worst_y, worst_split);
    EXPECT_LT(worst_y, 1e-7);
    EXPECT_LT(worst_split, 1e-7);
  }
  // Rank and split at one state, straight from the augmented solve.
  std::vector<double> y = {std::sin(0.5) / 2, -std::cos(0.5) / 2, 0.5, 0, 0, 0};
  y[3] = 0.5 * std::cos(0.5) * 1.3;  // a consistent velocity, θ̇ = 1.3
  y[4] = 0.5 * std::sin(0.5) * 1.3;
  y[5] = 1.3;
  const Evaluation e1 = evaluate_at(single, y), e2 = evaluate_at(twice, y);
  EXPECT_EQ(e1.rank, 2);
  EXPECT_EQ(e2.rank, 2);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(e2.lambda[c], e1.lambda[c] / 2, 1e-12);
    EXPECT_NEAR(e2.lambda[2 + c], e1.lambda[c] / 2, 1e-12);
  }
  for (int s = 0; s < 6; ++s) EXPECT_NEAR(e1.ydot[s], e2.ydot[s], 1e-12);
  const auto R = pin_reaction(1, 1, 0.5, 1.3);
  EXPECT_NEAR(e1.lambda[0], R[0], 1e-12);
  EXPECT_NEAR(e1.lambda[1], R[1], 1e-12);
  std::printf("rank: one pin %d of %d rows, two pins %d of %d rows\n", e1.rank, single.nconstraint_rows, e2.rank,
              twice.nconstraint_rows);
}

TEST(ConstrainedPendulum, RedundantZeroRowInPlanarScene) {
  const ks::Model single = pendulum_model();
  const ks::Model xyz = model_from_text(kXYZPin);
  ASSERT_TRUE(xyz.planar);
  ASSERT_EQ(xyz.nconstraint_rows, 3);
  const auto times = linspace(0, 5, 51);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r1 = run(single, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    const TrajRun r3 = run(xyz, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r1.tr.result.ok() && r3.tr.result.ok()) << r3.tr.result.message;
    double worst_y = 0, worst_l = 0, worst_z = 0;
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      for (int s = 0; s < 6; ++s) worst_y = std::max(worst_y, std::abs(r1.y(k, s) - r3.y(k, s)));
      for (int c = 0; c < 2; ++c) worst_l = std::max(worst_l, std::abs(r1.lambda(k, c) - r3.lambda(k, c)));
      worst_z = std::max(worst_z, std::abs(r3.lambda(k, 2)));
    }
    std::printf("pin [x,y,z] in planar scene (stabilization %d): max |Δy| %.2e, max |Δλ_xy| %.2e, max |λ_z| %.2e\n",
                static_cast<int>(stab), worst_y, worst_l, worst_z);
    EXPECT_LT(worst_y, 1e-9);
    EXPECT_LT(worst_l, 1e-8);
    EXPECT_EQ(worst_z, 0.0);
  }
  std::vector<double> y = {std::sin(0.5) / 2, -std::cos(0.5) / 2, 0.5, 0, 0, 0};
  EXPECT_EQ(evaluate_at(xyz, y).rank, 2);
}

// dλ/dp vs finite differences. Norm, per sensitivity i: max over outputs t and rows r of
// |dλ_ri(t) − fd_ri(t)| / max_{t,r} |dλ_ri(t)| — the error relative to the sensitivity's peak
// over the trajectory (λ components cross zero, so a pointwise relative error is meaningless).
// FD: [−λ(p+2h) + 8λ(p+h) − 8λ(p−h) + λ(p−2h)]/(12h), h = 3e-4 max(|p|, 1), runs at rtol 1e-13.

std::vector<double> multiplier_fd_errors(const ks::Model& model, Stab stab, const std::vector<std::string>& names,
                                         const std::vector<double>& times, double rtol, std::vector<double>* peak_out) {
  const TrajRun r = run(model, times, constraint_options(stab), tolerances(rtol, rtol * 1e-2), names);
  EXPECT_TRUE(r.tr.result.ok()) << r.tr.result.message;
  std::vector<double> err;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const ks::InputRef ref = ks::resolve_input(model, names[i], "test");
    double v;
    if (ref.kind == ks::InputRef::Kind::parameter) {
      v = model.nominal_parameters()[ref.index];
    } else {
      v = r.y(0, ref.index);  // the (consistent) initial value
    }
    const double h = 3e-4 * std::max(std::abs(v), 1.0);
    std::vector<double> fd(r.tr.multipliers.size(), 0.0);
    for (const auto& [shift, weight] : std::vector<std::pair<double, double>>{{2, -1}, {1, 8}, {-1, -8}, {-2, 1}}) {
      const TrajRun p = run(model, times, constraint_options(stab), tolerances(1e-13, 1e-14), {}, {{names[i], v + shift * h}});
      EXPECT_TRUE(p.tr.result.ok()) << p.tr.result.message;
      for (std::size_t j = 0; j < fd.size(); ++j) fd[j] += weight * p.tr.multipliers[j] / (12 * h);
    }
    double peak = 0, e = 0;
    for (int k = 0; k < static_cast<int>(times.size()); ++k)
      for (int row = 0; row < r.m; ++row) peak = std::max(peak, std::abs(r.dlambda(k, row, static_cast<int>(i))));
    for (int k = 0; k < static_cast<int>(times.size()); ++k)
      for (int row = 0; row < r.m; ++row)
        e = std::max(e, std::abs(r.dlambda(k, row, static_cast<int>(i)) - fd[static_cast<std::size_t>(k * r.m + row)]) / peak);
    err.push_back(e);
    if (peak_out) peak_out->push_back(peak);
  }
  return err;
}

}  // namespace

TEST(ConstrainedPendulum, MultiplierSensitivityMatchesFiniteDifferences) {
  const ks::Model model = model_from_text(kSpinningPinnedPendulum);
  const std::vector<std::string> names = {"m", "L", "theta0", "base.u0[2]"};
  const auto times = linspace(0, 5, 26);
  for (Stab stab : {Stab::baumgarte, Stab::none, Stab::projection}) {
    std::vector<double> peak;
    const auto err = multiplier_fd_errors(model, stab, names, times, 1e-10, &peak);
    for (std::size_t i = 0; i < names.size(); ++i) {
      std::printf("dλ/d%-10s stabilization %d: max |dλ − fd| / peak = %.2e (peak %.3g)\n", names[i].c_str(),
                  static_cast<int>(stab), err[i], peak[i]);
      EXPECT_LT(err[i], 1e-6) << names[i] << " stabilization " << static_cast<int>(stab);
    }
  }
}

TEST(ConstrainedPendulum, DistanceConstraintIsRodTension) {
  constexpr const char* kScene = R"yaml(
kanesens: 1
scene:
  name: distance_pendulum
  gravity: [0, -9.81, 0]
  parameters: {m: 2.0, L: 1.5, phi0: 0.8}
  bodies:
    - {name: ball, mass: m, inertia: {shape: sphere, radius: 0.1}}
  joints:
    - {name: base, type: planar, parent: ground, child: ball, axis: [0, 0, 1],
       q0: ["L*sin(phi0)", "-L*cos(phi0)", 0.2], u0: [0, 0, 3.0]}
  constraints:
    - {name: rod, type: distance, body_a: ground, point_a: [0, 0, 0], body_b: ball, point_b: [0, 0, 0], length: L}
)yaml";
  const ks::Model model = model_from_text(kScene);
  ASSERT_EQ(model.nconstraint_rows, 1);
  const double m = 2.0, L = 1.5;
  const auto times = linspace(0, 5, 51);
  const auto ref = rk4<2>([&](const std::array<double, 2>& x) {
    return std::array<double, 2>{x[1], -kG / L * std::sin(x[0])};
  }, {0.8, 0.0}, times, 1e-3);
  for (Stab stab : {Stab::projection, Stab::baumgarte, Stab::none}) {
    const TrajRun r = run(model, times, constraint_options(stab), tolerances(1e-10, 1e-12));
    ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
    double worst_l = 0, worst_phi = 0, worst_spin = 0;
    for (int k = 0; k < static_cast<int>(times.size()); ++k) {
      const double x = r.y(k, 0), y = r.y(k, 1), vx = r.y(k, 3), vy = r.y(k, 4);
      const double phi = std::atan2(x, -y), phid = (x * vy - y * vx) / (x * x + y * y);
      const double tension = m * (kG * std::cos(phi) + L * phid * phid);
      worst_l = std::max(worst_l, std::abs(r.lambda(k, 0) + tension) / tension);
      worst_phi = std::max(worst_phi, std::abs(phi - ref[static_cast<std::size_t>(k)][0]));
      worst_spin = std::max(worst_spin, std::abs(r.y(k, 5) - 3.0));  // the ball's spin is untouched
    }
    std::printf("distance pendulum (stabilization %d): worst |λ + T|/T = %.2e, max |φ − φ_rk4| = %.2e, spin drift %.1e\n",
                static_cast<int>(stab), worst_l, worst_phi, worst_spin);
    // Off the manifold (none, Baumgarte: |x| ≠ L by the drift) the closed form in φ, φ̇ is not exact.
    EXPECT_LT(worst_l, stab == Stab::projection ? 1e-10 : 2e-8);
    EXPECT_LT(worst_phi, 1e-7);
    EXPECT_LT(worst_spin, 1e-9);
  }
}

}  // namespace KANESENS_UNITY_ID
