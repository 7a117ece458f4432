// Tests of solve/dop853 (solver.method: dop853) on the undamped oscillator x'' = −(k/m) x,
// x(0) = x0, v(0) = 0: x = x0 cos ωt, ω = √(k/m), ∂x/∂k = −x0 t sin(ωt) / (2 m ω).
//   - eighth order (steps forced constant): halving h divides the error by ≈ 2⁸ = 256, for the
//     state and the sensitivity; a wrong tableau entry drops the order (this test fails);
//   - error control: the error falls with rtol and stays within a modest factor of it;
//   - dense output: outputs inside steps are interpolated (order 7 extension) as accurately as
//     the steps, and many output times do not change the steps;
//   - bookkeeping: every output time is recorded at its time, 12 evaluations per step (+3 per
//     step with outputs inside), the Integrator dispatches method dop853 here;
//   - failures as statuses: max_steps (−1), a blow-up in finite time (−3, outputs before it
//     kept), an RHS that throws (−8, with its message);
//   - step-size control on a swinging mechanism (configs/nlink_chain_4.yaml): few rejected
//     trial steps, and the error at the output times within a small factor of rtol.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "sim/solve/dop853.hpp"
#include "sim/solve/integrator.hpp"
#include "spring_problem.hpp"
#include "kane_test_support.hpp"
#include "layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;  // every layer by name (tests/support/layers.hpp)

namespace {

using kanesens::testing::Spring;

// y' = y², y(0) = 1: y = 1/(1 − t), infinite at t = 1.
class BlowUp : public ks::OdeProblem {
 public:
  int size() const override { return 1; }
  void initial_state(double* y0) const override { y0[0] = 1; }
  void rhs(double, const double* y, double* ydot) override { ydot[0] = y[0] * y[0]; }
};

// y' = −y, except that f cannot be evaluated (RecoverableError) on calls first..last, or at
// any t > after.
class Recovering : public ks::OdeProblem {
 public:
  Recovering(long first, long last, double after) : first_(first), last_(last), after_(after) {}
  int size() const override { return 1; }
  void initial_state(double* y0) const override { y0[0] = 1; }
  void rhs(double t, const double* y, double* ydot) override {
    ++calls_;
    if ((calls_ >= first_ && calls_ <= last_) || t > after_) throw ks::RecoverableError("mass matrix is singular here");
    ydot[0] = -y[0];
  }

 private:
  long calls_ = 0, first_, last_;
  double after_;
};

struct Trajectory {
  ks::IntegrationResult result;
  std::vector<double> t, x, s;
};

Trajectory run(ks::OdeProblem& p, const ks::SolverOptions& o, const std::vector<double>& times) {
  Trajectory r;
  r.result = ks::integrate_dop853(p, o, times, [&](int k, double t, const double* y, const double* const* s) {
    EXPECT_EQ(t, times[static_cast<std::size_t>(k)]);
    r.t.push_back(t);
    r.x.push_back(y[0]);
    if (s) r.s.push_back(s[0][0]);
  });
  return r;
}

ks::SolverOptions dop853(double rtol, double atol) {
  ks::SolverOptions o;
  o.method = ks::Method::dop853;
  o.rtol = rtol;
  o.atol = atol;
  o.max_steps = 1000000;
  return o;
}

// A tolerance no step can fail and a step bound: constant steps h (when the outputs are
// multiples of h), so the error is the method's global error at step h.
ks::SolverOptions dop853_constant_steps(double h) {
  ks::SolverOptions o = dop853(1e3, 1e3);
  o.initial_step = h;
  o.max_step = h;
  return o;
}

struct MaxErrors {
  double x = 0, s = 0;  // max |x error|, max |dx/dk error|
};

// Errors of outputs [first, end) against the closed form.
MaxErrors max_errors(const Spring& p, const Trajectory& r, const std::vector<double>& times, std::size_t first,
                     std::size_t end) {
  MaxErrors e;
  for (std::size_t k = first; k < end; ++k) {
    e.x = std::max(e.x, std::abs(r.x[k] - p.x(times[k])));
    e.s = std::max(e.s, std::abs(r.s[k] - p.dx_dk(times[k])));
  }
  return e;
}
MaxErrors max_errors(const Spring& p, const Trajectory& r, const std::vector<double>& times) {
  return max_errors(p, r, times, 0, times.size());
}

}  // namespace

TEST(Dop853, EighthOrderForStatesAndSensitivities) {
  Spring p(4.0);
  const std::vector<double> times = ks::output_grid(8.0, 11);  // outputs 0.8 apart: multiples of every h
  double prev_x = 0, prev_s = 0;
  for (double h : {0.4, 0.2, 0.1}) {
    const Trajectory r = run(p, dop853_constant_steps(h), times);  // the outputs are multiples of h
    ASSERT_TRUE(r.result.ok()) << r.result.message;
    EXPECT_EQ(r.result.stats.error_test_fails, 0);
    EXPECT_NEAR(static_cast<double>(r.result.stats.steps), 8.0 / h, 0.5);
    const auto [ex, es] = max_errors(p, r, times);
    std::printf("h = %.3f: max |x error| %.3e, max |dx/dk error| %.3e\n", h, ex, es);
    if (prev_x > 0) {
      EXPECT_GT(prev_x / ex, 180) << "order below 7.5 at h = " << h;
      EXPECT_LT(prev_x / ex, 360) << "order above 8.5 at h = " << h;
      EXPECT_GT(prev_s / es, 150) << "sensitivity order below 7.2 at h = " << h;
    }
    prev_x = ex;
    prev_s = es;
  }
}

// Outputs inside the steps come from the continuous extension: with steps forced constant,
// its error at those times falls like the method's (order 7 extension, local error O(h⁸)), for
// the state and the sensitivity; a wrong dense-output coefficient breaks the ratio.
TEST(Dop853, DenseOutputIsAccurateInsideTheSteps) {
  Spring p(4.0);
  std::vector<double> times{0.0};
  for (int j = 0; j < 10; ++j) times.push_back(0.13 + 0.8 * j);  // never a multiple of h
  times.push_back(8.0);
  double prev_x = 0, prev_s = 0;
  for (double h : {0.4, 0.2, 0.1}) {
    const Trajectory r = run(p, dop853_constant_steps(h), times);
    ASSERT_TRUE(r.result.ok()) << r.result.message;
    EXPECT_NEAR(static_cast<double>(r.result.stats.steps), 8.0 / h, 0.5);
    EXPECT_EQ(r.result.stats.dense_outputs, 10);
    const auto [ex, es] = max_errors(p, r, times, 1, times.size() - 1);
    std::printf("h = %.3f: interpolated max |x error| %.3e, max |dx/dk error| %.3e\n", h, ex, es);
    if (prev_x > 0) {
      EXPECT_GT(prev_x / ex, 128) << "interpolation order below 7 at h = " << h;
      EXPECT_GT(prev_s / es, 100) << "interpolated sensitivity order below 6.6 at h = " << h;
    }
    prev_x = ex;
    prev_s = es;
  }
}

// The steps follow the error control alone: 1001 output times take the same steps as 2, end
// on the same bits, and every interpolated output is within the tolerance's error.
TEST(Dop853, OutputTimesDoNotCutTheSteps) {
  Spring p(4.0);
  const ks::SolverOptions o = dop853(1e-9, 1e-11);
  const Trajectory two = run(p, o, ks::output_grid(10.0, 2));
  const std::vector<double> times = ks::output_grid(10.0, 1001);
  const Trajectory many = run(p, o, times);
  ASSERT_TRUE(two.result.ok() && many.result.ok());
  EXPECT_EQ(many.result.stats.steps, two.result.stats.steps);
  EXPECT_EQ(many.result.stats.error_test_fails, two.result.stats.error_test_fails);
  EXPECT_EQ(many.x.back(), two.x.back());
  EXPECT_EQ(many.s.back(), two.s.back());
  EXPECT_LT(many.result.stats.steps, 200) << "fewer steps than outputs";
  const auto [ex, es] = max_errors(p, many, times);
  std::printf("1001 outputs, %ld steps: max |x error| %.2e, max |dx/dk error| %.2e\n", many.result.stats.steps, ex, es);
  EXPECT_LT(ex, 100 * 1e-9);
  EXPECT_LT(es, 1000 * 1e-9);
}

TEST(Dop853, ErrorFallsWithTheTolerance) {
  Spring p(4.0);
  const std::vector<double> times = ks::output_grid(10.0, 6);
  double prev = 1;
  for (double rtol : {1e-6, 1e-9, 1e-12}) {
    const Trajectory r = run(p, dop853(rtol, rtol * 1e-2), times);
    ASSERT_TRUE(r.result.ok()) << r.result.message;
    const auto [e, es] = max_errors(p, r, times);
    std::printf("rtol %.0e: steps %ld (rejected %ld), rhs %ld, max error x %.2e, dx/dk %.2e\n", rtol,
                r.result.stats.steps, r.result.stats.error_test_fails, r.result.stats.rhs_evals, e, es);
    EXPECT_LT(e, 100 * rtol);
    EXPECT_LT(es, 1000 * rtol);
    EXPECT_LT(e, prev / 10);
    prev = e;
    // 12 evaluations per step attempt (11 stages + f at the new point), plus the first and
    // the initial-step estimate, plus 3 per step that holds output times (dense output).
    const long attempts = r.result.stats.steps + r.result.stats.error_test_fails;
    EXPECT_EQ(r.result.stats.rhs_evals, 12 * attempts + 2 + 3 * r.result.stats.dense_outputs);
    EXPECT_GT(r.result.stats.dense_outputs, 0);
    EXPECT_LE(r.result.stats.dense_outputs, static_cast<long>(times.size()) - 2);
    EXPECT_LT(r.result.stats.error_test_fails, r.result.stats.steps / 5 + 3) << "the step control rejects too often";
  }
}

TEST(Dop853, IntegratorDispatchesTheMethod) {
  Spring p(4.0);
  const std::vector<double> times = ks::output_grid(3.0, 4);
  const Trajectory direct = run(p, dop853(1e-8, 1e-10), times);
  std::vector<double> x;
  ks::Integrator integ(dop853(1e-8, 1e-10));
  const ks::IntegrationResult r = integ.integrate(p, times, [&](int, double, const double* y, const double* const*) {
    x.push_back(y[0]);
  });
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(x, direct.x);
  EXPECT_EQ(r.stats.steps, direct.result.stats.steps);
}

TEST(Dop853, SensitivityErrorControlTakesMoreSteps) {
  // ∂x/∂k grows like t: controlling its error too needs at least as many steps.
  Spring p(4.0);
  const std::vector<double> times = ks::output_grid(10.0, 2);
  ks::SolverOptions on = dop853(1e-8, 1e-10), off = on;
  off.sens_error_control = false;
  const Trajectory a = run(p, on, times), b = run(p, off, times);
  ASSERT_TRUE(a.result.ok() && b.result.ok());
  EXPECT_GE(a.result.stats.steps, b.result.stats.steps);
  p.sensitivities = false;
  const Trajectory c = run(p, off, times);
  EXPECT_EQ(c.result.stats.steps, b.result.stats.steps);  // uncontrolled sensitivities do not steer
  EXPECT_EQ(c.x, b.x);
}

TEST(Dop853, FailuresAreStatuses) {
  Spring p(4.0);
  ks::SolverOptions few = dop853(1e-10, 1e-12);
  few.max_steps = 20;
  const Trajectory r1 = run(p, few, ks::output_grid(10.0, 11));
  EXPECT_EQ(r1.result.status, -1);
  EXPECT_NE(r1.result.message.find("DOP853_TOO_MUCH_WORK"), std::string::npos) << r1.result.message;
  EXPECT_EQ(r1.result.stats.steps, 20);
  EXPECT_LT(r1.result.outputs_recorded, 11);

  BlowUp b;
  const Trajectory r2 = run(b, dop853(1e-8, 1e-10), {0.0, 0.5, 0.9, 2.0});
  EXPECT_EQ(r2.result.status, -3) << r2.result.message;
  EXPECT_EQ(r2.result.outputs_recorded, 3);
  EXPECT_NEAR(r2.x[1], 2.0, 1e-7);
  EXPECT_NEAR(r2.x[2], 10.0, 1e-6);
  // It stops at the pole (an explicit step may land just past it before the stages overflow).
  EXPECT_LT(r2.result.t_fail, 1.01) << r2.result.message;
  EXPECT_GT(r2.result.t_fail, 0.9);

  p.throw_after = 1.5;
  const Trajectory r3 = run(p, dop853(1e-8, 1e-10), ks::output_grid(3.0, 4));
  EXPECT_EQ(r3.result.status, -8);
  EXPECT_NE(r3.result.message.find("spring broke"), std::string::npos) << r3.result.message;
  EXPECT_EQ(r3.result.outputs_recorded, 2);

  // A RecoverableError rejects the trial step, which is retried smaller; a persistent one fails
  // the integration with its message; one at t0 fails at once.
  Recovering transient(10, 11, 1e300);
  const Trajectory r4 = run(transient, dop853(1e-10, 1e-12), ks::output_grid(2.0, 3));
  ASSERT_EQ(r4.result.status, 1) << r4.result.message;
  EXPECT_GE(r4.result.stats.callback_recoverable, 1);
  EXPECT_NEAR(r4.x[2], std::exp(-2.0), 1e-9);
  Recovering persistent(0, -1, 1.0);
  const Trajectory r5 = run(persistent, dop853(1e-10, 1e-12), ks::output_grid(2.0, 3));
  EXPECT_EQ(r5.result.status, -3) << r5.result.message;
  EXPECT_NE(r5.result.message.find("mass matrix is singular here"), std::string::npos) << r5.result.message;
  Recovering at_t0(1, 1, 1e300);
  const Trajectory r6 = run(at_t0, dop853(1e-10, 1e-12), ks::output_grid(2.0, 3));
  EXPECT_EQ(r6.result.status, -8) << r6.result.message;
  EXPECT_NE(r6.result.message.find("mass matrix is singular here"), std::string::npos) << r6.result.message;

  ks::SolverOptions order = dop853(1e-8, 1e-10);
  order.max_order = 5;
  EXPECT_THROW(ks::Integrator{order}, std::invalid_argument);
}

TEST(Dop853, StepControlRejectsFewStepsOnASwingingChain) {
  // The 4-link pendulum chain swings chaotically for 10 s. Step-size control without memory
  // (β = 0) rejects 12–23 % of the steps here at these tolerances; with memory it rejects
  // at most 6 %, and the states at the output times stay within a few rtol of a run at
  // rtol 1e-13.
  const kanesens::model::Model m = kanesens::model::build_model(
      kanesens::model::parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/nlink_chain_4.yaml"));
  const std::vector<double> times = ks::output_grid(10.0, 101);
  const std::size_t n = static_cast<std::size_t>(m.nstate());
  auto states = [&](double rtol, ks::IntegrationResult& result) {
    ks::KaneProblem problem(m, {});
    std::vector<double> y;
    result = ks::integrate_dop853(problem, dop853(rtol, rtol * 1e-2), times,
                                  [&](int, double, const double* x, const double* const*) { y.insert(y.end(), x, x + n); });
    return y;
  };
  ks::IntegrationResult reference_result;
  const std::vector<double> reference = states(1e-13, reference_result);
  ASSERT_TRUE(reference_result.ok()) << reference_result.message;
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    ks::IntegrationResult r;
    const std::vector<double> y = states(rtol, r);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(y.size(), reference.size());
    double error = 0;
    for (std::size_t i = 0; i < y.size(); ++i) error = std::max(error, std::abs(y[i] - reference[i]));
    std::printf("rtol %.0e: steps %ld, rejected %ld, max state error %.2e\n", rtol, r.stats.steps,
                r.stats.error_test_fails, error);
    EXPECT_LT(r.stats.error_test_fails, r.stats.steps / 10) << "the step control rejects too often";
    EXPECT_LT(error, 10 * rtol);
  }
}

}  // namespace KANESENS_UNITY_ID
