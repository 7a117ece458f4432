// A study's `events:` (docs/reference/study.md, "events") through simulate(), under bdf, adams
// and dop853:
//   - a rod pendulum (pivot at its end, θ'' = −(3g/2L) sin θ) released from θ0 at rest: the first
//     falling zero crossing of pivot.q is the quarter period K(sin(θ0/2))·√(2L/(3g)) (Boost.Math
//     ellint_1), its sensitivities to L and pivot.q0 the closed-form derivatives; crossings
//     counted in both directions; max_count caps the count; an event that never happens has
//     count 0 and time NaN; a scalar expression reads the event time;
//   - an event function of t, a state and a parameter: dτ/dp against fourth-order central
//     differences of τ;
//   - action: stop ends the sample at τ with an ok status; later outputs stay NaN;
//   - the quarter period and its sensitivities on a pendulum built from a pin constraint, under
//     projection, Baumgarte and the embedding.
#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <cmath>
#include <string>

#include "../support/output_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

constexpr double g = 9.81;

std::string pendulum(const std::string& method, const std::string& events, double end = 3.0) {
  return pendulum_study_head(method, end) + "events:\n" + events;
}

class EventsStudy : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(EventsStudy, PendulumQuarterPeriodCountsAndSensitivities) {
  const OutputRun r = run_output_study(pendulum(GetParam(),
                                                "  - {name: zero, when: pivot.q, direction: falling}\n"
                                                "  - {name: cross, when: pivot.q, direction: both}\n"
                                                "  - {name: capped, when: pivot.q, max_count: 2}\n"
                                                "  - {name: never, when: \"pivot.q - 2\"}\n"
                                                "outputs:\n"
                                                "  half: {expression: \"zero.time / 2\"}\n"),
                                       "events_pendulum_" + GetParam() + ".yaml");
  const double L = 1.2, theta0 = 0.9, k = std::sin(theta0 / 2);
  const double K = boost::math::ellint_1(k), E = boost::math::ellint_2(k), scale = std::sqrt(2 * L / (3 * g));
  const double tau = K * scale, dtau_dL = tau / (2 * L);
  const double dtau_dtheta0 = scale * (E / (k * (1 - k * k)) - K / k) * std::cos(theta0 / 2) / 2;
  std::printf("%s: tau %.14f (closed form %.14f), dtau/dL %.12f (%.12f), dtau/dtheta0 %.12f (%.12f)\n",
              GetParam().c_str(), r.scalar("zero.time"), tau, r.scalar_sens("zero.time", 0), dtau_dL,
              r.scalar_sens("zero.time", 1), dtau_dtheta0);
  EXPECT_NEAR(r.scalar("zero.time"), tau, 1e-8);
  EXPECT_NEAR(r.scalar_sens("zero.time", 0), dtau_dL, 1e-7);
  EXPECT_NEAR(r.scalar_sens("zero.time", 1), dtau_dtheta0, 1e-7);
  EXPECT_NEAR(r.scalar("half"), tau / 2, 1e-8);
  EXPECT_NEAR(r.scalar_sens("half", 0), dtau_dL / 2, 1e-7);
  // Crossings at τ, 3τ, 5τ, ... (falling at τ, 5τ, ...) within 3 s.
  const int all = static_cast<int>(std::floor((3.0 / tau + 1) / 2));
  ASSERT_GE(all, 3);
  EXPECT_EQ(r.scalar("zero.count"), std::floor((3.0 / tau - 1) / 4) + 1);
  EXPECT_EQ(r.scalar("cross.count"), all);
  EXPECT_NEAR(r.scalar("cross.time"), tau, 1e-8);
  EXPECT_EQ(r.scalar("capped.count"), 2);
  EXPECT_EQ(r.scalar_sens("cross.count", 0), 0);
  EXPECT_EQ(r.scalar("never.count"), 0);
  EXPECT_TRUE(std::isnan(r.scalar("never.time")));
  EXPECT_TRUE(std::isnan(r.scalar_sens("never.time", 0)));
}

TEST_P(EventsStudy, EventTimeSensitivitiesMatchFiniteDifferences) {
  // g reads t, a state and a parameter: ∂g/∂t and ∂g/∂p enter dτ/dp.
  const std::string text = pendulum(GetParam(), "  - {name: e, when: \"pivot.q - 0.1*L + 0.05*t\", direction: falling}\n");
  expect_scalar_sensitivities_match_differences(text, "events_fd_" + GetParam() + ".yaml", {"e.time"}, 1e-3, 1e-6);
}

TEST_P(EventsStudy, StopEndsTheSampleWithAnOkStatus) {
  const OutputRun r = run_output_study(pendulum(GetParam(), "  - {name: down, when: pivot.q, direction: falling, action: stop}\n"),
                                       "events_stop_" + GetParam() + ".yaml");
  const double tau = r.scalar("down.time");
  EXPECT_TRUE(r.traj.result.ok());
  EXPECT_NEAR(r.traj.result.stopped_at, tau, 1e-12);
  EXPECT_NE(r.traj.result.message.find("stopped by an event"), std::string::npos) << r.traj.result.message;
  EXPECT_EQ(r.scalar("down.count"), 1);
  for (std::size_t k = 0; k < r.T; ++k)
    EXPECT_EQ(std::isnan(r.state("pivot.q", k)), r.time(k) > tau) << "output " << k << " at t = " << r.time(k);
}

INSTANTIATE_TEST_SUITE_P(Methods, EventsStudy, ::testing::Values("bdf", "adams", "dop853"),
                         [](const auto& info) { return info.param; });

// The same quarter period on the pendulum made of a planar joint and a pin constraint
// (configs/constrained_pendulum.yaml): multipliers with projection or Baumgarte, and the
// embedding (whose event functions read the full state through its coordinate map), under bdf
// and dop853; θ0 enters through the initial coordinates.
struct Constrained {
  const char* name;
  const char* method;
  const char* constraints;
};

class EventsConstrained : public ::testing::TestWithParam<Constrained> {};

TEST_P(EventsConstrained, QuarterPeriodAndSensitivities) {
  const Constrained c = GetParam();
  const std::string text = std::string("kanesens: 1\nscene: ") + KANESENS_SOURCE_DIR +
                           "/configs/constrained_pendulum.yaml\n"
                           "time: {end: 3.0, outputs: 31}\n"
                           "solver: {method: " + c.method + ", rtol: 1.0e-10, atol: 1.0e-12, constraints: {" + c.constraints + "}}\n"
                           "sensitivities: [L, theta0]\n"
                           "events:\n  - {name: zero, when: base.q3, direction: falling}\n";
  const OutputRun r = run_output_study(text, std::string("events_constrained_") + c.name + ".yaml");
  const double L = 1.0, theta0 = 0.5, k = std::sin(theta0 / 2);
  const double K = boost::math::ellint_1(k), E = boost::math::ellint_2(k), scale = std::sqrt(2 * L / (3 * g));
  const double tau = K * scale;
  const double dtau_dtheta0 = scale * (E / (k * (1 - k * k)) - K / k) * std::cos(theta0 / 2) / 2;
  std::printf("%s: tau error %.2e, dtau/dL error %.2e, dtau/dtheta0 error %.2e\n", c.name, r.scalar("zero.time") - tau,
              r.scalar_sens("zero.time", 0) - tau / (2 * L), r.scalar_sens("zero.time", 1) - dtau_dtheta0);
  EXPECT_EQ(r.scalar("zero.count"), 2);
  EXPECT_NEAR(r.scalar("zero.time"), tau, 1e-8);
  EXPECT_NEAR(r.scalar_sens("zero.time", 0), tau / (2 * L), 1e-7);
  EXPECT_NEAR(r.scalar_sens("zero.time", 1), dtau_dtheta0, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(
    Formulations, EventsConstrained,
    ::testing::Values(Constrained{"bdf_projection", "bdf", "formulation: multipliers, stabilization: projection"},
                      Constrained{"dop853_projection", "dop853", "formulation: multipliers, stabilization: projection"},
                      Constrained{"bdf_baumgarte", "bdf", "formulation: multipliers, stabilization: baumgarte"},
                      Constrained{"dop853_baumgarte", "dop853", "formulation: multipliers, stabilization: baumgarte"},
                      Constrained{"bdf_embedding", "bdf", "formulation: embedding, stabilization: projection"},
                      Constrained{"dop853_embedding", "dop853", "formulation: embedding, stabilization: projection"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace KANESENS_UNITY_ID
