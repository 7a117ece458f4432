// Events located by the integrators (sim/solve/ode_problem.hpp, OdeEvents) under CVODES BDF and
// Adams (CV_NORMAL and step-by-step paths) and DOP853 (its continuous extension):
//   - simple pendulum θ'' = −(g/L) sin θ released from θ0 at rest: the first zero crossing of θ is
//     the quarter period τ = K(sin(θ0/2))·√(L/g) (Boost.Math ellint_1), and its sensitivities
//     dτ/dp = −(∂g/∂y·s)/(∂g/∂y·ẏ) at τ from the integrated sensitivities match the closed
//     forms dτ/dL = τ/(2L), dτ/dθ0 = √(L/g)·K'(k)·cos(θ0/2)/2, K'(k) = E/(k(1−k²)) − K/k;
//   - damped oscillator: the count of zero crossings of x in each direction against the closed
//     form's zeros; an event that never happens (count 0);
//   - a stopping event ends the run at τ with an ok status, later outputs not recorded.
#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sim/solve/integrator.hpp"
#include "kane_test_support.hpp"
#include "layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;  // every layer by name (tests/support/layers.hpp)

namespace {

constexpr double gravity = 9.81;

// y = [θ, θ̇]; sensitivities to L (0) and θ0 (1). `stepwise`: the problem asks for the step
// check (after_step never changes anything), which sends CVODES down its step-by-step path.
class Pendulum : public ks::OdeProblem {
 public:
  Pendulum(double L, double theta0, bool stepwise) : L_(L), theta0_(theta0), stepwise_(stepwise) {}
  int size() const override { return 2; }
  void initial_state(double* y0) const override {
    y0[0] = theta0_;
    y0[1] = 0;
  }
  void rhs(double, const double* y, double* ydot) override {
    ydot[0] = y[1];
    ydot[1] = -gravity / L_ * std::sin(y[0]);
  }
  int num_sensitivities() const override { return 2; }
  void initial_sensitivity(int i, double* s0) const override {
    s0[0] = i == 1 ? 1 : 0;
    s0[1] = 0;
  }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double, const double* y, const double*, int i, const double* s, double* sdot) override {
    sdot[0] = s[1];
    sdot[1] = -gravity / L_ * std::cos(y[0]) * s[0] + (i == 0 ? gravity / (L_ * L_) * std::sin(y[0]) : 0.0);
  }
  bool has_step_check() const override { return stepwise_; }
  bool after_step(double, double*, double* const*) override { return false; }

  double L_, theta0_;
  bool stepwise_;
};

// x'' + 2ζω x' + ω² x = 0, x(0) = 1, x'(0) = 0, underdamped (its zeros: in the test).
class Damped : public ks::OdeProblem {
 public:
  int size() const override { return 2; }
  void initial_state(double* y0) const override {
    y0[0] = 1;
    y0[1] = 0;
  }
  void rhs(double, const double* y, double* ydot) override {
    ydot[0] = y[1];
    ydot[1] = -2 * zeta * omega * y[1] - omega * omega * y[0];
  }
  double zeta = 0.05, omega = 3.0;
};

// g_0 = y[0] (direction d0), g_1 = y[0] − 5 (never reached); records every occurrence and its
// time sensitivities −(s_i[0])/ẏ0 with ẏ0 = y[1].
class Crossings : public ks::OdeEvents {
 public:
  explicit Crossings(int d0, bool stop = false) : d0_(d0), stop_(stop) {}
  int size() const override { return 2; }
  int direction(int i) const override { return i == 0 ? d0_ : 0; }
  void g(double, const double* y, double* gout) override {
    gout[0] = y[0];
    gout[1] = y[0] - 5;
  }
  bool occurred(int i, double t, const double* y, const double* const* s) override {
    if (i != 0) {
      ++never;
      return false;
    }
    times.push_back(t);
    if (s) {
      dtau.push_back({-s[0][0] / y[1], -s[1][0] / y[1]});
    }
    return stop_;
  }
  std::vector<double> times;
  std::vector<std::array<double, 2>> dtau;
  int never = 0;

 private:
  int d0_;
  bool stop_;
};

struct Case {
  const char* name;
  ks::Method method;
  bool stepwise;
};

ks::SolverOptions options(ks::Method method, double rtol) {
  ks::SolverOptions o;
  o.method = method;
  o.rtol = rtol;
  o.atol = rtol * 1e-2;
  o.max_steps = 1000000;
  o.jacobian = ks::JacobianKind::dq;
  return o;
}

class Events : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(Events, PendulumQuarterPeriodAndItsSensitivities) {
  const Case c = GetParam();
  const double L = 1.3, theta0 = 1.2;
  Pendulum p(L, theta0, c.stepwise);
  Crossings ev(-1);
  const std::vector<double> times = ks::output_grid(2.0, 21);
  int recorded = 0;
  const ks::IntegrationResult r = ks::integrate(p, options(c.method, 1e-10), times,
                                                [&](int, double, const double*, const double* const*) { ++recorded; },
                                                nullptr, &ev);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(std::isnan(r.stopped_at));
  EXPECT_EQ(recorded, 21);
  const double k = std::sin(theta0 / 2), K = boost::math::ellint_1(k), E = boost::math::ellint_2(k);
  const double tau = K * std::sqrt(L / gravity);
  const double dK = E / (k * (1 - k * k)) - K / k;
  const double dtau_dL = tau / (2 * L), dtau_dtheta0 = std::sqrt(L / gravity) * dK * std::cos(theta0 / 2) / 2;
  ASSERT_GE(ev.times.size(), 1u);
  // Falling crossings at τ, 5τ, 9τ, ... (rising ones at 3τ, 7τ, ...).
  EXPECT_EQ(ev.times.size(), static_cast<std::size_t>(std::floor((2.0 / tau - 1) / 4)) + 1);
  std::printf("%s: tau %.15f (closed form %.15f), dtau/dL %.10f (%.10f), dtau/dtheta0 %.10f (%.10f)\n", c.name,
              ev.times[0], tau, ev.dtau[0][0], dtau_dL, ev.dtau[0][1], dtau_dtheta0);
  EXPECT_NEAR(ev.times[0], tau, 1e-8);
  EXPECT_NEAR(ev.dtau[0][0], dtau_dL, 1e-7);
  EXPECT_NEAR(ev.dtau[0][1], dtau_dtheta0, 1e-7);
  EXPECT_EQ(ev.never, 0);
}

TEST_P(Events, DampedOscillatorCountsItsZeroCrossings) {
  const Case c = GetParam();
  Damped p;
  const double end = 20.0;
  // x = e^{−ζωt}(cos ω_d t + (ζω/ω_d) sin ω_d t): zero where tan(ω_d t) = −ω_d/(ζω), i.e.
  // ω_d t = π − atan(ω_d/(ζω)) + nπ.
  const double wd = p.omega * std::sqrt(1 - p.zeta * p.zeta);
  const double first = (std::numbers::pi - std::atan(wd / (p.zeta * p.omega))) / wd;
  const int zeros = static_cast<int>(std::floor((end - first) / (std::numbers::pi / wd))) + 1;
  for (int d : {0, 1, -1}) {
    Crossings ev(d);
    const ks::IntegrationResult r =
        ks::integrate(p, options(c.method, 1e-9), ks::output_grid(end, 11), [](int, double, const double*, const double* const*) {},
                      nullptr, &ev);
    ASSERT_TRUE(r.ok()) << r.message;
    // x starts at 1 and falls first: falling crossings are the 1st, 3rd, ...
    const int expected = d == 0 ? zeros : d < 0 ? (zeros + 1) / 2 : zeros / 2;
    EXPECT_EQ(static_cast<int>(ev.times.size()), expected) << "direction " << d;
    for (std::size_t j = 0; j < ev.times.size(); ++j) {
      const int n = d == 0 ? static_cast<int>(j) : d < 0 ? 2 * static_cast<int>(j) : 2 * static_cast<int>(j) + 1;
      EXPECT_NEAR(ev.times[j], first + n * std::numbers::pi / wd, 1e-7) << "crossing " << j;
    }
    EXPECT_EQ(ev.never, 0);  // an event that never happens: count 0
  }
}

TEST_P(Events, StopEndsTheRunAtTheEventWithAnOkStatus) {
  const Case c = GetParam();
  Pendulum p(1.0, 0.5, c.stepwise);
  Crossings ev(0, true);
  const std::vector<double> times = ks::output_grid(2.0, 101);
  std::vector<double> recorded;
  const ks::IntegrationResult r = ks::integrate(p, options(c.method, 1e-10), times,
                                                [&](int, double t, const double*, const double* const*) { recorded.push_back(t); },
                                                nullptr, &ev);
  ASSERT_TRUE(r.ok()) << r.message;
  const double tau = boost::math::ellint_1(std::sin(0.25)) * std::sqrt(1.0 / gravity);
  ASSERT_EQ(ev.times.size(), 1u);
  EXPECT_NEAR(r.stopped_at, tau, 1e-8);
  EXPECT_NE(r.message.find("stopped by an event"), std::string::npos) << r.message;
  ASSERT_FALSE(recorded.empty());
  EXPECT_LE(recorded.back(), tau);
  EXPECT_GT(recorded.back(), tau - 0.02 - 1e-12);  // every output before τ, none after
  EXPECT_EQ(r.outputs_recorded, static_cast<int>(recorded.size()));
}

namespace {
// g = t − at: a zero exactly at a given time.
class AtTime : public ks::OdeEvents {
 public:
  explicit AtTime(double at) : at_(at) {}
  int size() const override { return 1; }
  int direction(int) const override { return 0; }
  void g(double t, const double*, double* gout) override { gout[0] = t - at_; }
  bool occurred(int, double t, const double*, const double* const*) override {
    times.push_back(t);
    return false;
  }
  std::vector<double> times;

 private:
  double at_;
};
}  // namespace

// A zero that falls exactly on an output time (or the end) is one event, and every output is
// recorded once.
TEST_P(Events, AnEventExactlyAtAnOutputTimeIsSeenOnce) {
  const Case c = GetParam();
  const std::vector<double> times = ks::output_grid(0.2, 5);  // 0, 0.05, 0.1, 0.15, 0.2
  for (double at : {times[2], times[4]}) {
    Pendulum p(1.0, 0.5, c.stepwise);
    AtTime ev(at);
    std::vector<double> recorded;
    const ks::IntegrationResult r = ks::integrate(p, options(c.method, 1e-10), times,
                                                  [&](int, double t, const double*, const double* const*) { recorded.push_back(t); },
                                                  nullptr, &ev);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(recorded, times);
    ASSERT_EQ(ev.times.size(), 1u) << "event at " << at;
    EXPECT_NEAR(ev.times[0], at, 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, Events,
                         ::testing::Values(Case{"bdf", ks::Method::bdf, false}, Case{"adams", ks::Method::adams, false},
                                           Case{"bdf_stepwise", ks::Method::bdf, true},
                                           Case{"dop853", ks::Method::dop853, false}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace KANESENS_UNITY_ID
