// The `rolling` constraint (a disc of radius r on a plane, no slip) against SymPy's rolling disc
// (sympy/physics/mechanics/tests/test_linearize.py, test_linearize_rolling_disc_kane) and the
// closed form for rolling down an incline, and the constraint bias −(Ȧu) of every constraint kind
// against a finite difference.
//
// Mapping of SymPy's rolling disc to our frames. SymPy: N.z down, gravity +g N.z,
// A = rot(q1 about N.z), B = rot(q2 about A.x), C = rot(q3 about B.y), disc axis B.y, contact
// P = CO + r B.z. Ours: world W with z up, gravity −g W.z. Take N.x = W.x, N.y = −W.y,
// N.z = −W.z (a rotation by π about x: T = diag(1, −1, −1)), and the disc's body frame = C. Then
// the free joint's rotation (body → world) is R = Rx(π) Rz(q1) Rx(q2) Ry(q3); at q1 = q3 = 0 it
// is Rx(π + q2): quaternion (cos((π+q2)/2), sin((π+q2)/2), 0, 0). In W, B.x = (1, 0, 0),
// B.y = (0, −cos q2, −sin q2), B.z = (0, sin q2, −cos q2), so the center is CO = P − r B.z =
// (0, −r sin q2, r cos q2) with P at the origin, and the lean is read back as
// sin q2 = −(R e_y)·W.z. Speeds: ω = u1 B.x + u2 B.y + u3 B.z with u1 = q̇2 = 0,
// u2 = q̇3 + q̇1 sin q2, u3 = q̇1 cos q2; in body (C = B at q3 = 0) components ω = (0, u2, u3).
// Rolling: v_CO = ω × (CO − P) = −r ω × B.z = −r u2 B.x + r u1 B.y = (−r u2, 0, 0).
// Steady turning (u̇1 = 0): ½ sin(2q2) q̇1² + (6/5) cos q2 q̇3 q̇1 + 4 g sin q2 /(5r) = 0; for
// q2 = 0.3, q̇3 = 4, r = m = 1, g = 9.81 the roots are q̇1 = −0.52257787531129441459 and
// −15.719966261444493993 (an independent SymPy KanesMethod model keeps q2 constant to 8e-16
// over 5 s).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "../support/constraint_test_support.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

constexpr double kG = 9.81;

std::string disc_scene(const std::vector<double>& q0, const std::vector<double>& u0, const char* normal,
                       double height = 0) {
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"yaml(
kanesens: 1
scene:
  name: rolling_disc
  gravity: [0, 0, -9.81]
  parameters: {m: 1.0, r: 1.0}
  bodies:
    - {name: disc, mass: m, inertia: {xx: "m*r^2/4", yy: "m*r^2/2", zz: "m*r^2/4"}}
  joints:
    - {name: base, type: free, parent: ground, child: disc,
       q0: [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g, %.17g], u0: [%.17g, %.17g, %.17g, %.17g, %.17g, %.17g]}
  constraints:
    - {name: contact, type: rolling, body: disc, radius: r, axis: [0, 1, 0], normal: %s, height: %.17g}
)yaml",
                q0[0], q0[1], q0[2], q0[3], q0[4], q0[5], q0[6], u0[0], u0[1], u0[2], u0[3], u0[4], u0[5], normal, height);
  return buf;
}

// Steady turning: (q0, u0) of the free joint for lean q2 and spin rate q̇3, yaw rate from
// SymPy's u̇1.
struct Steady {
  std::vector<double> q0, u0;
  double yaw_rate;
};
Steady steady_turning(double q2, double q3d, bool slow_root, double r = 1.0) {
  const double a = 0.5 * std::sin(2 * q2), b = 1.2 * std::cos(q2) * q3d, c = 0.8 * kG * std::sin(q2) / r;
  const double disc = std::sqrt(b * b - 4 * a * c);
  const double q1d = slow_root ? (-b + disc) / (2 * a) : (-b - disc) / (2 * a);
  const double u2 = q3d + q1d * std::sin(q2), u3 = q1d * std::cos(q2);
  Steady s;
  s.yaw_rate = q1d;
  s.q0 = {0, -r * std::sin(q2), r * std::cos(q2), std::cos((M_PI + q2) / 2), std::sin((M_PI + q2) / 2), 0, 0};
  s.u0 = {-r * u2, 0, 0, 0, u2, u3};
  return s;
}

double lean_of(const TrajRun& run, int k) {
  const Eigen::Vector4d q(run.y(k, 3), run.y(k, 4), run.y(k, 5), run.y(k, 6));
  return std::asin(-(quat_to_matrix(q.normalized()) * Eigen::Vector3d(0, 1, 0))[2]);
}

TEST(RollingDisc, SteadyTurningFormulaMatchesReference) {
  EXPECT_NEAR(steady_turning(0.3, 4, true).yaw_rate, -0.52257787531129441459, 1e-14);
  EXPECT_NEAR(steady_turning(0.3, 4, false).yaw_rate, -15.719966261444493993, 1e-12);
}

TEST(RollingDisc, InitialStateRollsAndTurnsSteadily) {
  // At t = 0: the constraint is satisfied (no correction needed) and the lean acceleration is 0.
  for (bool slow : {true, false}) {
    const Steady s = steady_turning(0.3, 4, slow);
    const ks::Model model = model_from_text(disc_scene(s.q0, s.u0, "[0, 0, 1]"));
    ASSERT_EQ(model.nconstraint_rows, 3);
    std::vector<double> y = s.q0;
    y.insert(y.end(), s.u0.begin(), s.u0.end());
    ks::Workspace<double> ws(model);
    const auto p = model.nominal_parameters();
    ks::set_parameters(model, ws, p.data());
    std::vector<double> ydot(13);
    ASSERT_TRUE(ks::evaluate_rhs(model, ws, 0.0, y.data(), ydot.data()));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(ws.velocity_residual[i], 0, 1e-14);
    EXPECT_EQ(ws.constraint_rank, 3);
    // ω̇ in body components: steady turning at q3 = 0 has ω̇_C = (ω_C-fixed rate) ... the lean
    // rate u1 stays 0, so the world-frame angular acceleration has no B.x component.
    const Eigen::Matrix3d R = quat_to_matrix(Eigen::Vector4d(y[3], y[4], y[5], y[6]));
    const Eigen::Vector3d w(y[10], y[11], y[12]), wd(ydot[10], ydot[11], ydot[12]);
    // d/dt(ω·B.x) = ω̇·B.x + ω·Ḃx; B.x rotates with A (rate q̇1 about W.z via N.z = −W.z).
    const Eigen::Vector3d Bx(1, 0, 0), wA(0, 0, -s.yaw_rate);
    const double u1dot = (R * wd).dot(Bx) + (R * w).dot(wA.cross(Bx));
    std::printf("steady turning (%s root, q̇1 = %.6f): u̇1 at t0 = %.2e, contact λ = (%.6f, %.6f, %.6f)\n",
                slow ? "slow" : "fast", s.yaw_rate, u1dot, ws.multipliers[0], ws.multipliers[1], ws.multipliers[2]);
    EXPECT_NEAR(u1dot, 0, 1e-12);
    // Vertical contact force supports the weight; horizontal one is the centripetal force.
    EXPECT_NEAR(ws.multipliers[2], kG, 1e-12);
  }
}

TEST(RollingDisc, SteadyTurningStaysSteady) {
  const auto times = linspace(0, 5, 51);
  for (bool slow : {true, false}) {
    const Steady s = steady_turning(0.3, 4, slow);
    const ks::Model model = model_from_text(disc_scene(s.q0, s.u0, "[0, 0, 1]"));
    for (Stab stab : {Stab::projection, Stab::none}) {
      const TrajRun r = run(model, times, constraint_options(stab), tolerances(1e-10, 1e-12));
      ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
      double worst_lean = 0, worst_h = 0, worst_res = 0, worst_speed = 0;
      for (int k = 0; k < static_cast<int>(times.size()); ++k) {
        worst_lean = std::max(worst_lean, std::abs(lean_of(r, k) - 0.3));
        worst_h = std::max(worst_h, std::abs(r.y(k, 2) - std::cos(0.3)));
        worst_res = std::max(worst_res, r.tr.velocity_residual[static_cast<std::size_t>(k)]);
        const double speed = std::hypot(r.y(k, 7), r.y(k, 8));
        worst_speed = std::max(worst_speed, std::abs(speed - std::abs(s.u0[0])));
      }
      std::printf("rolling disc steady turning (%s root, stabilization %d): max |lean − 0.3| %.2e, "
                  "max |z_c − r cos q2| %.2e, max |v_P| %.2e, max | |v_c| − r|u2| | %.2e, steps %ld\n",
                  slow ? "slow" : "fast", static_cast<int>(stab), worst_lean, worst_h, worst_res, worst_speed,
                  r.tr.result.stats.steps);
      EXPECT_LT(worst_lean, 1e-6);
      EXPECT_LT(worst_h, 1e-6);
      EXPECT_LT(worst_speed, 1e-6);
    }
  }
}

TEST(RollingDisc, PerturbedSteadyTurningDrifts) {
  // The test above would also pass for a disc that does not move at all; a 1 % error in the
  // yaw rate must make the lean oscillate (by 1.5e-3 over 5 s in an independent SymPy model).
  Steady s = steady_turning(0.3, 4, true);
  const double q1d = s.yaw_rate * 1.01, u2 = 4 + q1d * std::sin(0.3), u3 = q1d * std::cos(0.3);
  s.u0 = {-u2, 0, 0, 0, u2, u3};
  const ks::Model model = model_from_text(disc_scene(s.q0, s.u0, "[0, 0, 1]"));
  const auto times = linspace(0, 5, 101);
  const TrajRun r = run(model, times, constraint_options(Stab::projection), tolerances(1e-10, 1e-12));
  ASSERT_TRUE(r.tr.result.ok());
  double worst = 0;
  for (int k = 0; k < static_cast<int>(times.size()); ++k) worst = std::max(worst, std::abs(lean_of(r, k) - 0.3));
  std::printf("rolling disc, yaw rate +1 %%: max |lean − 0.3| = %.2e\n", worst);
  EXPECT_GT(worst, 3e-4);
  EXPECT_LT(worst, 1e-2);
}

TEST(RollingDisc, InclineFrictionIsOneThirdWeightSine) {
  // Upright disc (axis = world y) at rest on a plane with normal n = (sin α, 0, cos α) through the
  // origin: center at r n, downhill d = (cos α, 0, −sin α). Rolling from rest: center acceleration
  // (2/3) g sin α along d, friction on the disc −(1/3) m g sin α along d, normal force m g cos α.
  const double alpha = 0.3;
  const double sa = std::sin(alpha), ca = std::cos(alpha);
  char normal[128];
  std::snprintf(normal, sizeof normal, "[%.17g, 0, %.17g]", sa, ca);
  const ks::Model model = model_from_text(disc_scene({sa, 0, ca, 1, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, normal));
  const auto times = linspace(0, 1.5, 16);
  const TrajRun r = run(model, times, constraint_options(Stab::projection), tolerances(1e-10, 1e-12));
  ASSERT_TRUE(r.tr.result.ok()) << r.tr.result.message;
  const Eigen::Vector3d n(sa, 0, ca), d(ca, 0, -sa), e_y(0, 1, 0);
  double worst_f = 0, worst_n = 0, worst_s = 0, worst_lat = 0;
  for (int k = 0; k < static_cast<int>(times.size()); ++k) {
    // λ is in the plane's basis (t1, t2, n); t1 is world x projected onto the plane.
    Eigen::Vector3d t1, t2;
    ks::rolling_plane_basis<double>(n, t1, t2);
    const Eigen::Vector3d lam = r.lambda(k, 0) * t1 + r.lambda(k, 1) * t2 + r.lambda(k, 2) * n;
    worst_f = std::max(worst_f, std::abs(lam.dot(d) + kG * sa / 3) / (kG * sa / 3));
    worst_n = std::max(worst_n, std::abs(lam.dot(n) - kG * ca) / (kG * ca));
    worst_lat = std::max(worst_lat, std::abs(lam.dot(e_y)));
    const Eigen::Vector3d c(r.y(k, 0), r.y(k, 1), r.y(k, 2));
    const double t = times[static_cast<std::size_t>(k)];
    worst_s = std::max(worst_s, std::abs(c.dot(d) - kG * sa / 3 * t * t));
    worst_s = std::max(worst_s, std::abs(c.dot(n) - 1.0));
  }
  std::printf("disc on incline α = 0.3: friction rel. err %.2e, normal rel. err %.2e, lateral %.1e, "
              "center vs (1/3) g sinα t² %.2e\n", worst_f, worst_n, worst_lat, worst_s);
  EXPECT_LT(worst_f, 1e-9);
  EXPECT_LT(worst_n, 1e-9);
  EXPECT_LT(worst_lat, 1e-9);
  EXPECT_LT(worst_s, 1e-8);
}

// The bias b = −(Ȧu + ȧ0) against a central difference of the velocity residual A(q)u + a0 along
// q̇ = N(q)u at fixed u: d/dt (A u + a0)|_{u fixed} = Ȧu + ȧ0.
double bias_error(const ks::Model& model, const std::vector<double>& y) {
  ks::Workspace<double> ws(model);
  const auto p = model.nominal_parameters();
  ks::set_parameters(model, ws, p.data());
  const int nq = model.nq, n = model.nstate(), m = model.nconstraint_rows;
  std::vector<double> ydot(static_cast<std::size_t>(n));
  ks::evaluate_rhs(model, ws, 0.0, y.data(), ydot.data());
  const std::vector<double> bias(ws.constraint_bias.data(), ws.constraint_bias.data() + m);
  const double h = 1e-5;
  std::vector<double> plus(static_cast<std::size_t>(m)), minus(static_cast<std::size_t>(m));
  for (double sgn : {1.0, -1.0}) {
    std::vector<double> ys = y, dummy(static_cast<std::size_t>(n));
    for (int i = 0; i < nq; ++i) ys[static_cast<std::size_t>(i)] += sgn * h * ydot[static_cast<std::size_t>(i)];
    ks::evaluate_rhs(model, ws, sgn * h, ys.data(), dummy.data());
    for (int r = 0; r < m; ++r) (sgn > 0 ? plus : minus)[static_cast<std::size_t>(r)] = ws.velocity_residual[r];
  }
  double err = 0, scale = 0;
  for (int r = 0; r < m; ++r) {
    const double fd = (plus[static_cast<std::size_t>(r)] - minus[static_cast<std::size_t>(r)]) / (2 * h);
    err = std::max(err, std::abs(fd + bias[static_cast<std::size_t>(r)]));
    scale = std::max(scale, std::abs(bias[static_cast<std::size_t>(r)]));
  }
  return err / std::max(scale, 1.0);
}

TEST(ConstraintBias, MatchesFiniteDifferenceForEveryKind) {
  constexpr const char* kScene = R"yaml(
kanesens: 1
scene:
  name: bias_check
  gravity: [0, 0, -9.81]
  parameters: {r: 0.4}
  bodies:
    - {name: wheel, mass: 1.0, inertia: {xx: 0.05, yy: 0.08, zz: 0.06, xy: 0.01}}
    - {name: arm, mass: 0.5, inertia: {xx: 0.02, yy: 0.01, zz: 0.03}}
    - {name: link, mass: 0.7, inertia: {shape: rod, length: 0.8, axis: x}}
  joints:
    - {name: base, type: free, parent: ground, child: wheel}
    - {name: hinge, type: revolute, parent: wheel, child: arm, axis: [0.2, 1, 0.1], parent_point: [0.1, 0, 0.2],
       child_point: [0, 0, -0.3]}
    - {name: swing, type: universal, parent: ground, child: link, axes: [[1, 0, 0], [0, 1, 0]],
       parent_point: [1, 0.5, 2], child_point: [-0.4, 0, 0]}
  constraints:
    - {name: contact, type: rolling, body: wheel, radius: r, axis: [0.1, 1, -0.2], normal: [0.2, -0.1, 1], height: 0}
    - {name: pin, type: coincident, body_a: arm, point_a: [0.1, 0.2, 0.3], body_b: link, point_b: [0.4, 0, 0.1]}
    - {name: rope, type: distance, body_a: wheel, point_a: [0.3, 0, 0], body_b: link, point_b: [0.4, 0.05, 0], length: 1.5}
)yaml";
  const ks::Model model = model_from_text(kScene);
  std::mt19937_64 rng(7);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> y = random_state(model, rng, 1.0, 2.0);
    worst = std::max(worst, bias_error(model, y));
  }
  std::printf("constraint bias vs central difference of A(q(t))u (rolling + coincident + distance, 20 random "
              "states): worst %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

TEST(ConstraintBias, RollingDiscPlanarAndTilted) {
  std::mt19937_64 rng(11);
  double worst = 0;
  for (const char* normal : {"[0, 0, 1]", "[0.3, 0.2, 1]"}) {
    const ks::Model model = model_from_text(disc_scene({0, 0, 1, 1, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, normal));
    for (int trial = 0; trial < 20; ++trial) worst = std::max(worst, bias_error(model, random_state(model, rng, 1.0, 3.0)));
  }
  std::printf("rolling disc bias vs central difference (40 random states): worst %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

// The rolling rows' tangents in the solvers' multi-tangent passes, on a tilted plane whose
// normal is a function of the parameter r (its norm and basis then carry r's tangent) and on a
// fixed tilted plane (formed on values): the sensitivity right-hand sides J s + ∂f/∂p against
// central differences of the right-hand side in r, in m and along a state direction.
TEST(RollingSensitivities, PlaneNormalOfAParameterAndFixedMatchDifferences) {
  std::mt19937_64 rng(17);
  for (const char* normal : {R"([0.2, "0.3*r", 1])", "[0.2, 0.3, 1]"}) {
    SCOPED_TRACE(normal);
    const ks::Model m = model_from_text(disc_scene({0, 0, 1, 1, 0, 0, 0}, {0, 0, 0, 0, 0, 0}, normal));
    ks::ConstraintOptions co;
    co.formulation = ks::ConstraintOptions::Formulation::multipliers;
    co.stabilization = ks::ConstraintOptions::Stabilization::baumgarte;
    const std::vector<ks::InputRef> refs = {ks::resolve_input(m, "r", "test"), ks::resolve_input(m, "m", "test"),
                                            ks::resolve_input(m, "base.u0[4]", "test")};
    ks::KaneProblem p(m, refs, co);
    const ks::SampleInputs nominal(m);
    p.set_sample(nominal);
    const int n = p.size();
    const std::vector<double> y = random_state(m, rng, 1.0, 2.0);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<std::vector<double>> s(3, std::vector<double>(static_cast<std::size_t>(n), 0.0));
    for (double& v : s[2]) v = u(rng);  // a state direction; the parameters' start at 0
    std::vector<std::vector<double>> sdot(3, std::vector<double>(static_cast<std::size_t>(n)));
    std::vector<double> f(static_cast<std::size_t>(n));
    const double* in[3] = {s[0].data(), s[1].data(), s[2].data()};
    double* out[3] = {sdot[0].data(), sdot[1].data(), sdot[2].data()};
    p.rhs_with_sensitivities(0.1, y.data(), 3, in, f.data(), out);

    const double h = 1e-6;
    std::vector<double> fp(f.size()), fm(f.size());
    auto difference = [&](int i) {
      if (i < 2) {
        const double p0 = nominal.get(m, refs[static_cast<std::size_t>(i)]);
        ks::SampleInputs moved = nominal;
        moved.set(refs[static_cast<std::size_t>(i)], p0 + h);
        p.set_sample(moved);
        p.rhs(0.1, y.data(), fp.data());
        moved.set(refs[static_cast<std::size_t>(i)], p0 - h);
        p.set_sample(moved);
        p.rhs(0.1, y.data(), fm.data());
        p.set_sample(nominal);
      } else {
        std::vector<double> yp(y), ym(y);
        for (int r = 0; r < n; ++r) {
          yp[static_cast<std::size_t>(r)] += h * s[2][static_cast<std::size_t>(r)];
          ym[static_cast<std::size_t>(r)] -= h * s[2][static_cast<std::size_t>(r)];
        }
        p.rhs(0.1, yp.data(), fp.data());
        p.rhs(0.1, ym.data(), fm.data());
      }
    };
    for (int i = 0; i < 3; ++i) {
      difference(i);
      double scale = 1, err = 0;
      for (int r = 0; r < n; ++r) {
        const double fd = (fp[static_cast<std::size_t>(r)] - fm[static_cast<std::size_t>(r)]) / (2 * h);
        scale = std::max(scale, std::abs(fd));
        err = std::max(err, std::abs(sdot[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)] - fd));
      }
      std::printf("normal %s, sensitivity %d: multi-tangent pass vs central difference %.2e (scale %.2e)\n", normal,
                  i, err / scale, scale);
      EXPECT_LT(err / scale, 1e-7) << "sensitivity " << i;
    }
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
