// The position level of the `rolling` constraint: its normal row is the time derivative of the
// contact height (the wheel's lowest point above the plane, `height` honoured), the consistent
// initial state puts a wheel — and a two-wheeled vehicle's both wheels — on the plane by solving
// height and pitch, keeping the driving coordinates, and projection removes the height drift.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "../support/constraint_test_support.hpp"
#include "../support/layers.hpp"
#include "model/yaml_reader.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

std::string disc(double z, double height, const char* normal = "[0, 0, 1]") {
  char buf[1024];
  std::snprintf(buf, sizeof buf, R"yaml(
kanesens: 1
scene:
  name: disc
  gravity: [0, 0, -9.81]
  parameters: {r: 1.0}
  bodies:
    - {name: disc, mass: 1, inertia: {xx: 0.25, yy: 0.5, zz: 0.25}}
  joints:
    - {name: base, type: free, parent: ground, child: disc, q0: [0, 0, %.17g, 1, 0, 0, 0], u0: [-2, 0, 0, 0, 2, 0]}
  constraints:
    - {name: contact, type: rolling, body: disc, radius: r, axis: [0, 1, 0], normal: %s, height: %.17g}
)yaml",
                z, normal, height);
  return buf;
}

// Contact height of rolling constraint `c` at q (position stage only).
double height_at(const ks::Model& m, ks::Workspace<double>& ws, int c, const std::vector<double>& y) {
  ks::compute_position(m, ws, y.data());
  return ks::rolling_contact_height(m, ws, m.constraints[static_cast<std::size_t>(c)]);
}

TEST(RollingPosition, NormalRowIsTheDerivativeOfTheContactHeight) {
  // Tilted plane at height 0.3, tilted axle, random states: d/dt h(q(t)) by a central difference
  // along q̇ = N(q) u against the normal row's velocity residual n·v_P.
  const ks::Model model = model_from_text(disc(1, 0.3, "[0.2, -0.1, 1]"));
  ks::Workspace<double> ws(model);
  const auto p = model.nominal_parameters();
  ks::set_parameters(model, ws, p.data());
  std::mt19937_64 rng(5);
  double worst = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<double> y = random_state(model, rng, 1.0, 3.0);
    std::vector<double> ydot(static_cast<std::size_t>(model.nstate()));
    ks::evaluate_rhs(model, ws, 0.0, y.data(), ydot.data());
    const double vn = ws.velocity_residual[2], h0 = ws.position_residual[2];
    EXPECT_NEAR(h0, height_at(model, ws, 0, y), 1e-15);
    const double dt = 1e-5;
    std::vector<double> yp = y, ym = y;
    for (int i = 0; i < model.nq; ++i) {
      yp[static_cast<std::size_t>(i)] += dt * ydot[static_cast<std::size_t>(i)];
      ym[static_cast<std::size_t>(i)] -= dt * ydot[static_cast<std::size_t>(i)];
    }
    const double fd = (height_at(model, ws, 0, yp) - height_at(model, ws, 0, ym)) / (2 * dt);
    worst = std::max(worst, std::abs(fd - vn) / std::max(1.0, std::abs(vn)));
  }
  std::printf("measure: rolling normal row vs d/dt of the contact height (30 random states, tilted plane): %.2e\n", worst);
  EXPECT_LT(worst, 1e-8);
}

TEST(RollingPosition, HeightIsHonouredAndCorrected) {
  // A disc of radius 1 on the plane z = 0.5: only a centre height of 1.5 touches it.
  for (double z : {0.5, 1.0, 1.5, 3.0}) {
    const ks::Model model = model_from_text(disc(z, 0.5));
    ConstraintOptions keep;
    keep.correct_initial = false;
    KaneProblem raw(model, {}, keep);
    double pos = 0, vel = 0;
    std::vector<double> y0(static_cast<std::size_t>(model.nstate()));
    raw.initial_state(y0.data());
    raw.constraint_residuals(0, y0.data(), pos, vel);
    EXPECT_NEAR(pos, std::abs(z - 1.5), 1e-15) << z;
    KaneProblem fixed(model, {});
    fixed.initial_state(y0.data());
    fixed.constraint_residuals(0, y0.data(), pos, vel);
    std::printf("disc on z = 0.5, centre at %.1f: residual %.2f, corrected to z = %.15f (residual %.1e, correction %.2f)\n",
                z, std::abs(z - 1.5), y0[2], pos, fixed.initial_position_correction());
    EXPECT_LE(pos, 1e-12);
    EXPECT_NEAR(y0[2], 1.5, 1e-12);
    EXPECT_NEAR(fixed.initial_position_correction(), std::abs(z - 1.5), 1e-12);
  }
}

// SymPy's rolling disc in steady turning (tests/regression/test_constraints_rolling.cpp has the
// frame mapping): lean q2, spin q̇3, yaw rate from u̇1 = 0.
struct Steady {
  std::vector<double> q0, u0;
  double yaw_rate;
};
Steady steady_turning(double q2, double q3d) {
  const double g = 9.81, a = 0.5 * std::sin(2 * q2), b = 1.2 * std::cos(q2) * q3d, c = 0.8 * g * std::sin(q2);
  const double q1d = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const double u2 = q3d + q1d * std::sin(q2), u3 = q1d * std::cos(q2);
  return {{0, -std::sin(q2), std::cos(q2), std::cos((M_PI + q2) / 2), std::sin((M_PI + q2) / 2), 0, 0},
          {-u2, 0, 0, 0, u2, u3},
          q1d};
}

TEST(RollingPosition, DiscStartedOffItsPlaneIsPutOnItAndTurnsSteadily) {
  // The steady-turning state of test_constraints_rolling with the centre 0.2 too high and
  // 0.05 off sideways, and the translational velocity forgotten: the consistent initial state
  // lowers the centre (height only: the lean, heading and spin are kept) and gives the centre the
  // velocity of rolling; the disc then turns steadily at the closed-form yaw rate.
  const Steady s = steady_turning(0.3, 4);
  const ks::Model model = model_from_text(disc(1, 0));
  std::vector<std::pair<std::string, double>> set;
  const std::vector<double> q0 = {0.05, -std::sin(0.3), std::cos(0.3) + 0.2, s.q0[3], s.q0[4], 0, 0};
  for (int i = 0; i < 7; ++i) set.emplace_back("base.q0[" + std::to_string(i) + "]", q0[static_cast<std::size_t>(i)]);
  for (int i = 3; i < 6; ++i) set.emplace_back("base.u0[" + std::to_string(i) + "]", s.u0[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 3; ++i) set.emplace_back("base.u0[" + std::to_string(i) + "]", 0.0);
  const auto times = linspace(0, 5, 51);
  const TrajRun r = run(model, times, constraint_options(Stab::projection), tolerances(1e-10, 1e-12), {}, set);
  ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
  EXPECT_LE(r.tr.position_residual[0], 1e-12);
  EXPECT_NEAR(r.y(0, 2), std::cos(0.3), 1e-12);  // lowered by 0.2
  EXPECT_NEAR(r.y(0, 0), 0.05, 1e-15);           // x, y kept
  EXPECT_NEAR(r.y(0, 7), s.u0[0], 1e-12);        // rolling velocity given to the centre
  double worst_lean = 0, worst_yaw = 0, worst_h = 0;
  for (int k = 0; k < static_cast<int>(times.size()); ++k) {
    const Eigen::Vector4d q(r.y(k, 3), r.y(k, 4), r.y(k, 5), r.y(k, 6));
    const Eigen::Matrix3d R = quat_to_matrix(q.normalized());
    worst_lean = std::max(worst_lean, std::abs(std::asin(-(R * Eigen::Vector3d(0, 1, 0))[2]) - 0.3));
    // SymPy's yaw rate q̇1 = u3 / cos q2 = ω·B.z / cos q2, B.y the axle, B.x = unit(W.z × B.y).
    const Eigen::Vector3d w = R * Eigen::Vector3d(r.y(k, 10), r.y(k, 11), r.y(k, 12));
    const Eigen::Vector3d By = R * Eigen::Vector3d(0, 1, 0), Bx = Eigen::Vector3d(0, 0, 1).cross(By).normalized();
    worst_yaw = std::max(worst_yaw, std::abs(w.dot(Bx.cross(By)) / std::cos(0.3) - s.yaw_rate));
    worst_h = std::max(worst_h, r.tr.position_residual[static_cast<std::size_t>(k)]);
  }
  std::printf("measure: disc started 0.2 above its plane: height residual at t0 %.1e, over 5 s max |lean − 0.3| "
              "%.2e, max |yaw rate − closed form %.6f| %.2e, max height residual %.1e\n",
              r.tr.position_residual[0], worst_lean, s.yaw_rate, worst_yaw, worst_h);
  EXPECT_LT(worst_lean, 1e-6);
  EXPECT_LT(worst_yaw, 1e-6);
  EXPECT_LT(worst_h, 1e-12);
}

ks::Model two_wheeler() {
  return build_model(parse_scene_text(
      model::read_text_file(std::string(KANESENS_SOURCE_DIR) + "/configs/two_wheeler.yaml"), "two_wheeler.yaml"));
}

// Lean (roll about the heading) of the rear frame, R = Rz(ψ) Rx(φ) Ry(θ): R(2,1) = sin φ.
double lean_of(const double* q) {
  return std::asin(quat_to_matrix(Eigen::Vector4d(q[3], q[4], q[5], q[6]).normalized())(2, 1));
}

TEST(RollingPosition, TwoWheelerWithSampledSteerStartsOnTheGround) {
  const ks::Model model = two_wheeler();
  const int steer_q = model.joints[2].q_offset, steer_u = model.nq + model.joints[2].u_offset;
  const int rear_u = model.nq + model.joints[1].u_offset;
  double worst_h = 0, worst_v = 0, worst_kept = 0, worst_float = 0;
  for (double steer : {-0.6, -0.2, 0.1, 0.45})
    for (double lean : {0.0, -0.1, 0.2})
      for (bool as_parameter : {true, false}) {
        KaneProblem problem(model, {});
        SampleInputs in(model);
        in.set(resolve_input(model, "lean0", "test"), lean);
        if (as_parameter) in.set(resolve_input(model, "steer0", "test"), steer);
        else in.set(resolve_input(model, "steer.q0", "test"), steer);
        problem.set_sample(in);
        std::vector<double> y(static_cast<std::size_t>(model.nstate()));
        problem.initial_state(y.data());
        double pos = 0, vel = 0;
        problem.constraint_residuals(0, y.data(), pos, vel);
        worst_h = std::max(worst_h, pos);
        worst_v = std::max(worst_v, vel);
        worst_float = std::max(worst_float, problem.initial_position_correction());
        // Kept: steer, lean, heading (yaw ψ = 0; R(0,1) = −sin ψ cos φ), the rear wheel's spin
        // and the steer rate.
        const Eigen::Matrix3d R = quat_to_matrix(Eigen::Vector4d(y[3], y[4], y[5], y[6]));
        worst_kept = std::max({worst_kept, std::abs(y[static_cast<std::size_t>(steer_q)] - steer),
                               std::abs(lean_of(y.data()) - lean), std::abs(R(0, 1)),
                               std::abs(y[static_cast<std::size_t>(rear_u)] - 4.0 / 0.3),
                               std::abs(y[static_cast<std::size_t>(steer_u)])});
      }
  std::printf("measure: two-wheeler, steer in [-0.6, 0.45], lean in [-0.1, 0.2] (24 samples): largest correction %.2e m, "
              "contact heights after %.1e, velocity residual %.1e, driving values moved %.1e\n",
              worst_float, worst_h, worst_v, worst_kept);
  EXPECT_GT(worst_float, 1e-3);  // the rough initial state did have a wheel off the ground
  EXPECT_LE(worst_h, 1e-12);
  EXPECT_LE(worst_v, 1e-12);
  EXPECT_LE(worst_kept, 1e-12);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
