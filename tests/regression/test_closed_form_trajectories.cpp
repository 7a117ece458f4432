// Whole trajectories of Kane scenes integrated by CVODES, against closed-form solutions:
//   (a) damped linear oscillator as a prismatic joint with spring and damper: x(t) and
//       ∂x/∂(x0, v0, m, c, k) against the closed form (tests/support/closed_forms.hpp), with the
//       initial conditions both as parameters (q0: x0) and as initial-condition names
//       (slider.q0, slider.u0); exact and difference-quotient sensitivity RHS, exact and DQ
//       Jacobian;
//   (b) small-angle uniform-rod pendulum: period 2π √(2L/(3g)) (1 + θ0²/16) from zero crossings;
//   (c) torque-free rigid body I = diag(1,2,3), ω0 = (1,0,1) (Landau & Lifshitz, Mechanics,
//       §37): ω(t) = (cn, sn, dn)(t | 1/3) (Boost.Math's Jacobi functions, themselves checked
//       against Euler's equations here), on a free joint and on a spherical joint at the mass
//       center; energy and spatial angular momentum R I ω conserved; the quaternion norm stays 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "../support/closed_forms.hpp"
#include "../support/kane_test_support.hpp"
#include "../support/test_scenes.hpp"
#include "sim/simulate.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

ks::SolverOptions options(double rtol, double atol) {
  ks::SolverOptions o;
  o.rtol = rtol;
  o.atol = atol;
  return o;
}

struct SimRun {
  ks::Trajectory traj;
  std::size_t n = 0, ns = 0;
  double state(std::size_t k, std::size_t r) const { return traj.states[k * n + r]; }
  double sens(std::size_t k, std::size_t r, std::size_t i) const {
    return traj.sensitivities[(k * n + r) * ns + i];
  }
};

SimRun simulate_scene(const ks::Model& m, const std::vector<std::string>& sens_names,
                      const ks::SampleInputs& inputs, const ks::SolverOptions& o,
                      const std::vector<double>& times) {
  std::vector<ks::InputRef> sens;
  for (const auto& s : sens_names) sens.push_back(ks::resolve_input(m, s, "test"));
  ks::KaneProblem problem(m, sens);
  problem.set_sample(inputs);
  ks::Integrator integ(o);
  SimRun run;
  run.n = static_cast<std::size_t>(m.nstate());
  run.ns = sens.size();
  ks::RecordFlags flags;
  flags.sensitivities = !sens.empty();
  ks::simulate(problem, integ, times, flags, run.traj);
  return run;
}

// ---- (a) damped oscillator ----------------------------------------------------------------------
constexpr const char* kOscillator = R"yaml(
kanesens: 1
scene:
  name: damped_oscillator
  gravity: [0, 0, 0]
  parameters: {m: 1.0, c: 0.4, k: 4.0, x0: 1.0, v0: 0.0}
  bodies:
    - {name: block, mass: m, inertia: {shape: point}}
  joints:
    - {name: slider, type: prismatic, parent: ground, child: block, axis: [1, 0, 0],
       q0: x0, u0: v0, spring: {k: k, rest: 0}, damper: {c: c}}
)yaml";

struct OscillatorCase {
  const char* name;
  bool ic_names;  // sensitivities to slider.q0/slider.u0 instead of the parameters x0/v0
  ks::SensitivityRhs sens_rhs;
  ks::JacobianKind jacobian;
};

class DampedOscillator : public ::testing::TestWithParam<OscillatorCase> {};

TEST_P(DampedOscillator, StateAndSensitivitiesMatchClosedForm) {
  const OscillatorCase& c = GetParam();
  const ks::Model m = model_from_text(kOscillator);
  const std::vector<double> times{0.0, 0.5, 1.0, 2.0, 5.0, 10.0};
  std::vector<OscillatorSolution> ref;  // x, ∂x/∂(x0, v0, m, c, k) at times[1..]
  for (std::size_t r = 1; r < times.size(); ++r)
    ref.push_back(damped_oscillator(times[r], 1.0, 0.0, 1.0, 0.4, 4.0));
  const std::vector<std::string> sens =
      c.ic_names ? std::vector<std::string>{"slider.q0", "slider.u0", "m", "c", "k"}
                 : std::vector<std::string>{"x0", "v0", "m", "c", "k"};
  // CVODES's DQ sensitivity RHS perturbs y by about the error tolerance: its round-off grows as
  // eps/rtol, so it runs at rtol 1e-8 (see tests/unit/test_integrator.cpp); exact at 1e-10.
  const bool dq = c.sens_rhs == ks::SensitivityRhs::dq;
  ks::SolverOptions o = dq ? options(1e-8, 1e-10) : options(1e-10, 1e-12);
  o.sens_rhs = c.sens_rhs;
  o.jacobian = c.jacobian;
  const SimRun run = simulate_scene(m, sens, ks::SampleInputs(m), o, times);
  ASSERT_TRUE(run.traj.result.ok()) << run.traj.result.message;

  // Initial state and sensitivities are exact.
  EXPECT_EQ(run.state(0, 0), 1.0);
  EXPECT_EQ(run.state(0, 1), 0.0);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(run.sens(0, 0, i), i == 0 ? 1.0 : 0.0);
    EXPECT_EQ(run.sens(0, 1, i), i == 1 ? 1.0 : 0.0);
  }
  double worst = 0;
  for (std::size_t r = 0; r < ref.size(); ++r) {
    for (std::size_t j = 0; j < 6; ++j) {
      const double got = j == 0 ? run.state(r + 1, 0) : run.sens(r + 1, 0, j - 1);
      const double want = j == 0 ? ref[r].x : ref[r].dx[j - 1];
      worst = std::max(worst, std::abs(got - want) / std::abs(want));
    }
  }
  const auto& st = run.traj.result.stats;
  std::printf(
      "[ measure  ] oscillator %-22s rtol %.0e: worst rel. error %.2e (x and 5 sensitivities, "
      "5 times); steps %ld, rhs %ld, sens rhs %ld, rhs for sens %ld, jac %ld\n",
      c.name, o.rtol, worst, st.steps, st.rhs_evals, st.sens_rhs_evals, st.rhs_evals_for_sens,
      st.jac_evals);
  // Measured: exact ≤ 1.0e-8 at rtol 1e-10; DQ ≤ 5e-7 at rtol 1e-8 (the same integrator on a
  // hand-written oscillator gives 7e-9 and 5e-7, tests/unit/test_integrator.cpp).
  EXPECT_LT(worst, dq ? 3e-6 : 1e-7);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, DampedOscillator,
    ::testing::Values(OscillatorCase{"params/exact/exactJ", false, ks::SensitivityRhs::exact,
                                     ks::JacobianKind::exact},
                      OscillatorCase{"ic_names/exact/exactJ", true,
                                     ks::SensitivityRhs::exact,
                                     ks::JacobianKind::exact},
                      OscillatorCase{"params/exact/dqJ", false, ks::SensitivityRhs::exact,
                                     ks::JacobianKind::dq},
                      OscillatorCase{"params/dq/exactJ", false, ks::SensitivityRhs::dq,
                                     ks::JacobianKind::exact},
                      OscillatorCase{"ic_names/dq/dqJ", true, ks::SensitivityRhs::dq,
                                     ks::JacobianKind::dq}),
    [](const ::testing::TestParamInfo<OscillatorCase>& i) {
      std::string s = i.param.name;
      for (char& ch : s)
        if (ch == '/') ch = '_';
      return s;
    });

// Parameter x0 and initial-condition name slider.q0 are the same derivative, and setting the
// initial condition by name overrides the q0 expression.
TEST(DampedOscillatorInputs, InitialConditionNamesAgreeWithParameters) {
  const ks::Model m = model_from_text(kOscillator);
  const std::vector<double> times{0.0, 0.5, 1.0, 2.0};
  const auto o = options(1e-10, 1e-12);
  const SimRun a = simulate_scene(m, {"x0", "v0"}, ks::SampleInputs(m), o, times);
  const SimRun b = simulate_scene(m, {"slider.q0", "slider.u0"}, ks::SampleInputs(m), o, times);
  ASSERT_TRUE(a.traj.result.ok() && b.traj.result.ok());
  for (std::size_t k = 0; k < times.size(); ++k)
    for (std::size_t r = 0; r < 2; ++r) {
      EXPECT_EQ(a.state(k, r), b.state(k, r));
      for (std::size_t i = 0; i < 2; ++i) EXPECT_NEAR(a.sens(k, r, i), b.sens(k, r, i), 1e-12);
    }
  // x0 = 0.3 given as the initial condition (the q0 expression then no longer applies).
  ks::SampleInputs in(m);
  in.set(ks::resolve_input(m, "slider.q0", "test"), 0.3);
  in.set(ks::resolve_input(m, "slider.u0", "test"), -0.7);
  const SimRun c = simulate_scene(m, {}, in, o, {0.0, 1.0});
  ASSERT_TRUE(c.traj.result.ok());
  const double wn = 2, zeta = 0.1, wd = wn * std::sqrt(1 - zeta * zeta), x0 = 0.3, v0 = -0.7;
  const double x1 =
      std::exp(-zeta * wn) * (x0 * std::cos(wd) + (v0 + zeta * wn * x0) / wd * std::sin(wd));
  EXPECT_EQ(c.state(0, 0), 0.3);
  EXPECT_NEAR(c.state(1, 0), x1, 1e-8 * std::abs(x1));
}

// ---- (b) small-angle pendulum period ------------------------------------------------------------
const std::string kPendulum = kanesens::test_scenes::rod_pendulum_scene("rod_pendulum", "{m: 0.7, L: 1.2}", ", q0: 1.0e-3");

// Root of the cubic Hermite interpolant of (q, q̇) on [t0, t1] (q0, q1 of opposite signs).
double hermite_root(double t0, double t1, double q0, double q1, double d0, double d1) {
  const double h = t1 - t0;
  auto p = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * q1 +
           (s3 - s2) * h * d1;
  };
  double a = 0, b = 1;
  for (int it = 0; it < 200 && b - a > 1e-16; ++it) {
    const double mid = 0.5 * (a + b);
    if ((p(mid) > 0) == (q0 > 0))
      a = mid;
    else
      b = mid;
  }
  return t0 + 0.5 * (a + b) * h;
}

TEST(SmallAnglePendulum, PeriodMatchesUniformRodFormula) {
  const ks::Model m = model_from_text(kPendulum);
  const double L = 1.2, g = 9.81, theta0 = 1e-3;
  const double T0 = 2 * M_PI * std::sqrt(2 * L / (3 * g));
  const double T_ref = T0 * (1 + theta0 * theta0 / 16);  // finite-amplitude correction, 6e-8
  const double dt = 0.005;
  std::vector<double> times;
  for (int k = 0; k * dt <= 10 * T0 + 1e-12; ++k) times.push_back(k * dt);
  const SimRun run = simulate_scene(m, {}, ks::SampleInputs(m), options(1e-10, 1e-14), times);
  ASSERT_TRUE(run.traj.result.ok()) << run.traj.result.message;
  std::vector<double> crossings;
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double q0 = run.state(k, 0), q1 = run.state(k + 1, 0);
    if ((q0 > 0) != (q1 > 0))
      crossings.push_back(
          hermite_root(times[k], times[k + 1], q0, q1, run.state(k, 1), run.state(k + 1, 1)));
  }
  ASSERT_GE(crossings.size(), 18u);
  double worst = 0;
  for (std::size_t i = 2; i < crossings.size(); ++i)  // consecutive full periods
    worst = std::max(worst, std::abs(crossings[i] - crossings[i - 2] - T_ref) / T_ref);
  const double mean =
      (crossings.back() - crossings.front()) / (0.5 * static_cast<double>(crossings.size() - 1));
  const double first =
      crossings.front() / (T_ref / 4);  // the first crossing is at a quarter period
  std::printf(
      "[ measure  ] pendulum: T_ref %.12f s; mean period rel. error %.2e, worst single period "
      "%.2e, "
      "first crossing / (T/4) - 1 = %.2e, %zu crossings; without the amplitude correction: %.2e\n",
      T_ref, std::abs(mean - T_ref) / T_ref, worst, first - 1, crossings.size(),
      std::abs(mean - T0) / T0);
  EXPECT_LT(std::abs(mean - T_ref) / T_ref, 1e-8);
  EXPECT_LT(worst, 1e-7);
  EXPECT_LT(std::abs(first - 1), 1e-7);
}

// ---- (c) torque-free rigid body -----------------------------------------------------------------
constexpr const char* kFreeBody = R"yaml(
kanesens: 1
scene:
  name: torque_free_free_joint
  gravity: [0, 0, 0]
  bodies:
    - {name: body, mass: 1.0, inertia: {xx: 1, yy: 2, zz: 3}}
  joints:
    - {name: float, type: free, parent: ground, child: body, q0: [0.1, -0.2, 0.3, 1, 0, 0, 0],
       u0: [0.05, 0.0, -0.02, 1, 0, 1]}
)yaml";

constexpr const char* kSphericalBody = R"yaml(
kanesens: 1
scene:
  name: torque_free_spherical_joint
  gravity: [0, -9.81, 0]    # the joint is at the mass center: gravity exerts no moment
  bodies:
    - {name: body, mass: 1.0, inertia: {xx: 1, yy: 2, zz: 3}}
  joints:
    - {name: ball, type: spherical, parent: ground, child: body,
       q0: [0.9, 0.1, -0.3, 0.2], u0: [1, 0, 1]}
)yaml";

// The reference itself: ω(0) = (1, 0, 1), and Euler's equations I ω̇ = (I ω) × ω with
// I = diag(1, 2, 3), ω̇ by central differences (error ~ d² ≈ 1e-10).
TEST(TorqueFreeClosedForm, SolvesEulersEquations) {
  const Omega w0 = torque_free_omega(0);
  EXPECT_EQ(w0.w1, 1.0);
  EXPECT_EQ(w0.w2, 0.0);
  EXPECT_EQ(w0.w3, 1.0);
  const double d = 1e-5;
  double worst = 0;
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 10.0;
    const Omega w = torque_free_omega(t), a = torque_free_omega(t - d), b = torque_free_omega(t + d);
    const double r1 = 1 * (b.w1 - a.w1) / (2 * d) - (2 - 3) * w.w2 * w.w3;
    const double r2 = 2 * (b.w2 - a.w2) / (2 * d) - (3 - 1) * w.w3 * w.w1;
    const double r3 = 3 * (b.w3 - a.w3) / (2 * d) - (1 - 2) * w.w1 * w.w2;
    worst = std::max({worst, std::abs(r1), std::abs(r2), std::abs(r3)});
  }
  std::printf("[ measure  ] torque-free closed form: Euler's equations residual %.1e\n", worst);
  EXPECT_LT(worst, 1e-8);
}

struct TorqueFreeCase {
  const char* name;
  const char* yaml;
};
class TorqueFreeBody : public ::testing::TestWithParam<TorqueFreeCase> {};

TEST_P(TorqueFreeBody, OmegaMatchesJacobiEllipticFunctions) {
  const ks::Model m = model_from_text(GetParam().yaml);
  std::vector<double> times;  // t = 0, 0.1, ..., 20
  for (int k = 0; k <= 200; ++k) times.push_back(k / 10.0);
  const ks::Joint& J = m.joints[0];
  const int qe = J.quaternion_offset,
            uw = m.nq + J.u_offset + (J.type == ks::JointType::free ? 3 : 0);
  const Eigen::Matrix3d I = Eigen::Vector3d(1, 2, 3).asDiagonal();
  // Two tolerances: the errors must shrink with rtol (they are integration errors, not a
  // modelling error). Measured (BDF, atol 1e-14): ω 3.9e-8 at rtol 1e-10 and 6.8e-10 at 1e-12;
  // 2E drift 1.5e-8 / 2.6e-10; H drift 7.6e-9 / 1.1e-10; ||q| − 1| 5.1e-10 / 7.0e-12.
  struct Level {
    double rtol, tol_w, tol_E, tol_H, tol_norm;
  };
  for (const Level& lv :
       {Level{1e-10, 2e-7, 1e-7, 5e-8, 5e-9}, Level{1e-12, 5e-9, 2e-9, 1e-9, 1e-10}}) {
    const SimRun run = simulate_scene(m, {}, ks::SampleInputs(m), options(lv.rtol, 1e-14), times);
    ASSERT_TRUE(run.traj.result.ok()) << run.traj.result.message;
    Eigen::Vector3d H0 = Eigen::Vector3d::Zero();  // set at k = 0
    double worst_w = 0, worst_E = 0, worst_H = 0, worst_Hvec = 0, worst_norm = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const Eigen::Vector3d w(run.state(k, uw), run.state(k, uw + 1), run.state(k, uw + 2));
      const Omega exact = torque_free_omega(times[k]);
      worst_w = std::max({worst_w, std::abs(w[0] - exact.w1), std::abs(w[1] - exact.w2),
                          std::abs(w[2] - exact.w3)});
      Eigen::Vector4d e;
      for (int c = 0; c < 4; ++c) e[c] = run.state(k, qe + c);
      worst_norm = std::max(worst_norm, std::abs(e.norm() - 1));
      const Eigen::Vector3d H = quat_to_matrix(e.normalized()) * I * w;  // spatial, R I ω
      if (k == 0) H0 = H;
      worst_E = std::max(worst_E, std::abs(w.dot(I * w) - 4) / 4);  // 2E = 4
      worst_H = std::max(worst_H, std::abs(H.norm() - std::sqrt(10.0)) / std::sqrt(10.0));
      worst_Hvec = std::max(worst_Hvec, (H - H0).norm() / std::sqrt(10.0));
    }
    const auto& st = run.traj.result.stats;
    std::printf(
        "[ measure  ] torque-free %-28s rtol %.0e, t in [0, 20]: max |w - (cn,sn,dn)| %.2e; "
        "2E rel. drift %.2e; |H| %.2e; |H - H(0)|/|H| %.2e; max ||q| - 1| %.2e; steps %ld\n",
        m.name.c_str(), lv.rtol, worst_w, worst_E, worst_H, worst_Hvec, worst_norm, st.steps);
    // ω is O(1): absolute error = relative error.
    EXPECT_LT(worst_w, lv.tol_w);
    EXPECT_LT(worst_E, lv.tol_E);
    EXPECT_LT(worst_Hvec, lv.tol_H);
    EXPECT_LT(worst_norm, lv.tol_norm);
    if (J.type == ks::JointType::free) {  // the mass center drifts uniformly
      for (std::size_t k = 0; k < times.size(); ++k) {
        EXPECT_NEAR(run.state(k, 0), 0.1 + 0.05 * times[k], 1e-9);
        EXPECT_NEAR(run.state(k, 1), -0.2, 1e-9);
        EXPECT_NEAR(run.state(k, 2), 0.3 - 0.02 * times[k], 1e-9);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Joints, TorqueFreeBody,
                         ::testing::Values(TorqueFreeCase{"free", kFreeBody},
                                           TorqueFreeCase{"spherical", kSphericalBody}),
                         [](const ::testing::TestParamInfo<TorqueFreeCase>& i) {
                           return std::string(i.param.name);
                         });

}  // namespace

}  // namespace KANESENS_UNITY_ID
