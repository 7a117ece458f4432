// Tests of solve/rk4 (the fixed-step baseline of `kanesens-workprecision`) on the
// undamped oscillator x'' = −(k/m) x, x(0) = x0, v(0) = 0: x = x0 cos ωt, ω = √(k/m),
// ∂x/∂k = −x0 t sin(ωt) / (2 m ω).
//   - fourth order: halving h divides the error by ≈ 16, for the state and the sensitivity;
//   - step bookkeeping: every output time is hit, 4 RHS evaluations per step;
//   - instability: with hω beyond RK4's stability limit on the imaginary axis (2√2) the
//     solution grows until it is not finite → status rk4_nonfinite, the outputs stop;
//     just inside the limit it stays bounded;
//   - an RHS that throws gives rk4_callback_failed with the message.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "sim/solve/rk4.hpp"
#include "spring_problem.hpp"
#include "kane_test_support.hpp"
#include "layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;  // every layer by name (tests/support/layers.hpp)

namespace {

using kanesens::testing::Spring;

struct Rk4Run {
  ks::IntegrationResult result;
  std::vector<double> x, s;
};

Rk4Run run(Spring& p, double h, const std::vector<double>& times) {
  Rk4Run r;
  ks::Rk4Options o;
  o.h = h;
  r.result = ks::integrate_rk4(p, o, times, [&](int k, double t, const double* y, const double* const* s) {
    EXPECT_EQ(t, times[static_cast<std::size_t>(k)]);
    r.x.push_back(y[0]);
    r.s.push_back(s[0][0]);
  });
  return r;
}

}  // namespace

TEST(Rk4, FourthOrderForStatesAndSensitivities) {
  Spring p(4.0);
  const std::vector<double> times = ks::output_grid(10.0, 11);
  double prev_x = 0, prev_s = 0;
  for (double h : {0.02, 0.01, 0.005}) {
    const Rk4Run r = run(p, h, times);
    ASSERT_TRUE(r.result.ok()) << r.result.message;
    double ex = 0, es = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      ex = std::max(ex, std::abs(r.x[k] - p.x(times[k])));
      es = std::max(es, std::abs(r.s[k] - p.dx_dk(times[k])));
    }
    if (prev_x > 0) {
      EXPECT_NEAR(prev_x / ex, 16.0, 2.0) << "h = " << h;
      EXPECT_NEAR(prev_s / es, 16.0, 2.0) << "h = " << h;
    }
    prev_x = ex;
    prev_s = es;
  }
  EXPECT_LT(prev_x, 2e-7);
}

TEST(Rk4, StepsHitEveryOutput) {
  Spring p(1.0);
  // Intervals 0.25 and 0.5 with h = 0.1: 3 steps of 1/12 and 5 steps of 0.1.
  const std::vector<double> times = {0.0, 0.25, 0.75};
  const Rk4Run r = run(p, 0.1, times);
  ASSERT_TRUE(r.result.ok());
  EXPECT_EQ(r.result.stats.steps, 8);
  EXPECT_EQ(r.result.stats.rhs_evals, 32);
  EXPECT_EQ(r.result.stats.sens_rhs_evals, 32);
  EXPECT_EQ(r.result.outputs_recorded, 3);
}

TEST(Rk4, BlowsUpBeyondTheStabilityLimit) {
  Spring p(1e6);  // ω = 1000 rad/s: stable for h < 2√2/1000 ≈ 2.83e-3
  const std::vector<double> times = ks::output_grid(2.0, 21);
  const Rk4Run unstable = run(p, 4e-3, times);  // |R(4i)| ≈ 7.6 per step: overflows within 2 s
  EXPECT_EQ(unstable.result.status, ks::rk4_nonfinite);
  EXPECT_NE(unstable.result.message.find("RK4_NONFINITE"), std::string::npos) << unstable.result.message;
  EXPECT_LT(unstable.result.outputs_recorded, 21);
  EXPECT_GT(unstable.result.t_fail, 0.0);

  const Rk4Run stable = run(p, 2.5e-3, times);  // hω = 2.5, inside the limit
  ASSERT_TRUE(stable.result.ok()) << stable.result.message;
  for (double x : stable.x) EXPECT_LE(std::abs(x), 1.0 + 1e-9);  // RK4 damps slightly, never grows
}

TEST(Rk4, ThrowingRhsIsAStatus) {
  Spring p(1.0);
  p.throw_after = 0.5;
  const Rk4Run r = run(p, 0.1, ks::output_grid(1.0, 11));
  EXPECT_EQ(r.result.status, ks::rk4_callback_failed);
  EXPECT_NE(r.result.message.find("spring broke"), std::string::npos) << r.result.message;
  EXPECT_EQ(r.result.outputs_recorded, 6);  // t = 0 .. 0.5
}

TEST(Rk4, RejectsBadInput) {
  Spring p(1.0);
  auto noop = [](int, double, const double*, const double* const*) {};
  ks::Rk4Options o;
  o.h = 0;
  EXPECT_THROW(ks::integrate_rk4(p, o, std::vector<double>{0.0, 1.0}, noop), std::invalid_argument);
  o.h = 0.1;
  EXPECT_THROW(ks::integrate_rk4(p, o, std::vector<double>{0.0, 0.0}, noop), std::invalid_argument);
}

}  // namespace KANESENS_UNITY_ID
