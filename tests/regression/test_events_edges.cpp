// Edge cases of a study's events and extrema (docs/reference/study.md, "events"), under bdf,
// adams and dop853, on the rod pendulum released from θ0 = 0.9 at rest:
//   - a function that is zero at t0 is not an event there (t: count 0), one that crosses zero at
//     an output time is (t − 0.5: once, at 0.5);
//   - a grazing touch without a crossing is not counted (pivot.q², which touches zero at every
//     swing through the bottom);
//   - two events 1e-6 apart, within one step of the solver: both found, in time order (an earlier
//     one that stops the sample keeps the later one, listed first, from happening);
//   - an event function not defined everywhere (the square root of a negative number): the
//     sample fails with a message that names the event, it does not crash.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../support/output_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

std::string pendulum(const std::string& method, const std::string& events, int outputs = 31) {
  return pendulum_study_head(method, 3.0, outputs) + "events:\n" + events;
}

class EventEdges : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(EventEdges, ZeroAtTheStartIsNotAnEventACrossingAtAnOutputTimeIs) {
  const OutputRun r = run_output_study(pendulum(GetParam(),
                                                "  - {name: start, when: t}\n"
                                                "  - {name: half, when: \"t - 0.5\"}\n"),
                                       "events_t0_" + GetParam() + ".yaml");
  ASSERT_TRUE(r.traj.result.ok()) << r.traj.result.message;
  EXPECT_EQ(r.scalar("start.count"), 0);
  EXPECT_TRUE(std::isnan(r.scalar("start.time")));
  EXPECT_EQ(r.scalar("half.count"), 1);
  EXPECT_NEAR(r.scalar("half.time"), 0.5, 1e-12);
  EXPECT_EQ(r.scalar_sens("half.time", 0), 0.0);  // dτ/dp = −(∂g/∂p)/(∂g/∂t) = 0
}

TEST_P(EventEdges, AGrazingTouchIsNotCounted) {
  const OutputRun r = run_output_study(pendulum(GetParam(),
                                                "  - {name: touch, when: \"pivot.q^2\"}\n"
                                                "  - {name: cross, when: pivot.q}\n"),
                                       "events_grazing_" + GetParam() + ".yaml");
  ASSERT_TRUE(r.traj.result.ok()) << r.traj.result.message;
  EXPECT_GE(r.scalar("cross.count"), 3);  // pivot.q itself crosses zero (a sign change)
  EXPECT_EQ(r.scalar("touch.count"), 0);
}

TEST_P(EventEdges, TwoEventsInOneStepInTimeOrder) {
  // Two outputs: no output time between the events to end a step there.
  const OutputRun both = run_output_study(pendulum(GetParam(),
                                                   "  - {name: later, when: \"t - 1.000001\"}\n"
                                                   "  - {name: earlier, when: \"t - 1\"}\n", 2),
                                          "events_two_" + GetParam() + ".yaml");
  ASSERT_TRUE(both.traj.result.ok()) << both.traj.result.message;
  EXPECT_EQ(both.scalar("earlier.count"), 1);
  EXPECT_EQ(both.scalar("later.count"), 1);
  EXPECT_NEAR(both.scalar("earlier.time"), 1.0, 1e-12);
  EXPECT_NEAR(both.scalar("later.time"), 1.000001, 1e-12);
  const OutputRun stop = run_output_study(pendulum(GetParam(),
                                                   "  - {name: later, when: \"t - 1.000001\"}\n"
                                                   "  - {name: earlier, when: \"t - 1\", action: stop}\n", 2),
                                          "events_two_stop_" + GetParam() + ".yaml");
  ASSERT_TRUE(stop.traj.result.ok()) << stop.traj.result.message;
  EXPECT_NEAR(stop.traj.result.stopped_at, 1.0, 1e-12);
  EXPECT_EQ(stop.scalar("earlier.count"), 1);
  EXPECT_EQ(stop.scalar("later.count"), 0);
}

TEST_P(EventEdges, AFunctionNotDefinedEverywhereFailsTheSampleWithAMessage) {
  // run_output_study throws with the sample's message when its status is not ok.
  std::string message;
  try {
    run_output_study(pendulum(GetParam(), "  - {name: odd, when: \"sqrt(pivot.q - 0.5) - 0.3\"}\n"),
                     "events_undefined_" + GetParam() + ".yaml");
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  std::printf("%s: %s\n", GetParam().c_str(), message.c_str());
  EXPECT_NE(message.find("integration failed"), std::string::npos) << message;
  EXPECT_NE(message.find("event 'odd': 'when' is not a number at t = "), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Methods, EventEdges, ::testing::Values("bdf", "adams", "dop853"),
                         [](const auto& info) { return info.param; });

}  // namespace KANESENS_UNITY_ID
