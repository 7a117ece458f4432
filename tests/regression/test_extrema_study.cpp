// Extrema of series outputs (`reduce: max | min | argmax | argmin`) and values at events
// (`at_event:`, `occurrence:`) through simulate(), under bdf, adams and dop853
// (docs/reference/study.md, "outputs"):
//   - an underdamped oscillator m ẍ + c ẋ + k x = 0 kicked from rest, x(0) = 0, ẋ(0) = v0:
//     x = e^{−at} (v0/ω) sin ωt, its first maximum at t* = atan(ω/a)/ω with x* = v0 e^{−at*}/√(k/m)
//     and the next minimum half a period later; values, times and their sensitivities to (m, c, k,
//     v0) against these closed forms, differentiated by the complex step;
//   - maxima at the ends: released from x0 at rest the maximum is x0 at t = 0 (argmax
//     sensitivities 0), and 5t − x peaks at the final time (sensitivities −∂x(t1)/∂p, closed form);
//   - the rod pendulum released from θ0: its angular velocity where it falls through zero is
//     −√((3g/L)(1 − cos θ0)) (energy), also at the second falling crossing, with its L and θ0
//     derivatives; the time of that crossing, 5 quarter periods (elliptic integral K); the event function's own value there is 0 with sensitivities 0; an occurrence
//     that does not happen gives NaN and a note; a value at an event and an interior maximum with
//     its time against finite differences.
#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <cmath>
#include <complex>
#include <string>

#include "../support/closed_forms.hpp"
#include "../support/output_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

using cplx = std::complex<double>;

std::string oscillator(const std::string& method, double x0, double v0, const std::string& outputs) {
  return "kanesens: 1\n"
         "scene:\n"
         "  name: oscillator\n"
         "  gravity: [0, 0, 0]\n"
         "  parameters: {m: 2.0, c: 0.8, k: 20.0}\n"
         "  bodies:\n"
         "    - {name: cart, mass: m, inertia: {shape: box, size: [0.4, 0.2, 0.2]}}\n"
         "  joints:\n"
         "    - {name: slide, type: prismatic, parent: ground, child: cart, axis: [1, 0, 0],\n"
         "       spring: {k: k, rest: 0}, damper: {c: c}, q0: " + std::to_string(x0) + ", u0: " + std::to_string(v0) + "}\n"
         "time: {end: 3.0, outputs: 31}\n"
         "solver: {method: " + method + ", rtol: 1.0e-11, atol: 1.0e-13}\n"
         "sensitivities: [m, c, k, slide.u0]\n"
         "outputs:\n" + outputs;
}

// The n-th root (n = 0, 1, ...) of ẋ for x(0) = 0, ẋ(0) = v0: t_n = (atan(ω/a) + nπ)/ω, and x there.
template <class T>
void kicked_extremum(int n, T m, T c, T k, T v0, T& t, T& x) {
  const T a = c / (2.0 * m), w = std::sqrt(k / m - a * a);
  t = (std::atan(w / a) + n * M_PI) / w;
  x = std::exp(-a * t) * (v0 / w) * std::sin(w * t);
}

// d/d(m, c, k, v0) of kicked_extremum's t and x by the complex step.
void kicked_extremum_derivatives(int n, double p[4], double& t, double& x, double dt[4], double dx[4]) {
  kicked_extremum<double>(n, p[0], p[1], p[2], p[3], t, x);
  const double h = 1e-30;
  for (int i = 0; i < 4; ++i) {
    cplx q[4] = {p[0], p[1], p[2], p[3]};
    q[i] += cplx(0, h);
    cplx tc, xc;
    kicked_extremum<cplx>(n, q[0], q[1], q[2], q[3], tc, xc);
    dt[i] = tc.imag() / h;
    dx[i] = xc.imag() / h;
  }
}

class Extrema : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(Extrema, UnderdampedOscillatorPeakAndTroughAgainstClosedForms) {
  const double v0 = 1.5;
  const OutputRun r = run_output_study(oscillator(GetParam(), 0.0, v0,
                                                  "  peak: {of: slide.q, reduce: max}\n"
                                                  "  t_peak: {of: slide.q, reduce: argmax}\n"
                                                  "  trough: {of: slide.q, reduce: min}\n"
                                                  "  t_trough: {of: slide.q, reduce: argmin}\n"),
                                       "extrema_oscillator_" + GetParam() + ".yaml");
  ASSERT_TRUE(r.traj.result.ok()) << r.traj.result.message;
  const char* names[4] = {"m", "c", "k", "v0"};
  double p[4] = {2.0, 0.8, 20.0, v0};
  for (int n = 0; n < 2; ++n) {
    double t, x, dt[4], dx[4];
    kicked_extremum_derivatives(n, p, t, x, dt, dx);
    const std::string value = n == 0 ? "peak" : "trough", time = n == 0 ? "t_peak" : "t_trough";
    std::printf("%s %s: %.14f (closed form %.14f) at t = %.14f (%.14f)\n", GetParam().c_str(), value.c_str(),
                r.scalar(value), x, r.scalar(time), t);
    EXPECT_NEAR(r.scalar(value), x, 1e-9);
    EXPECT_NEAR(r.scalar(time), t, 1e-9);
    for (std::size_t i = 0; i < 4; ++i) {
      std::printf("  d/d%s: value %.10f (%.10f), time %.10f (%.10f), errors %.1e %.1e\n", names[i],
                  r.scalar_sens(value, i), dx[i], r.scalar_sens(time, i), dt[i], r.scalar_sens(value, i) - dx[i],
                  r.scalar_sens(time, i) - dt[i]);
      // Exact derivatives: what is left is the integration error at rtol 1e-11.
      EXPECT_NEAR(r.scalar_sens(value, i), dx[i], 1e-9 * std::max(1.0, std::abs(dx[i])));
      EXPECT_NEAR(r.scalar_sens(time, i), dt[i], 1e-9 * std::max(1.0, std::abs(dt[i])));
    }
  }
  // Located between the output times, not the largest recorded sample.
  double largest = -INFINITY;
  for (std::size_t k = 0; k < r.T; ++k) largest = std::max(largest, r.state("slide.q", k));
  EXPECT_GT(r.scalar("peak") - largest, 1e-4);
}

TEST_P(Extrema, MaximaAtTheEnds) {
  const double x0 = 0.7;
  const OutputRun r = run_output_study(oscillator(GetParam(), x0, 0.0,
                                                  "  first: {of: slide.q, reduce: max}\n"
                                                  "  t_first: {of: slide.q, reduce: argmax}\n"
                                                  "  last: {of: \"5*t - slide.q\", reduce: max}\n"
                                                  "  t_last: {of: \"5*t - slide.q\", reduce: argmax}\n"),
                                       "extrema_ends_" + GetParam() + ".yaml");
  ASSERT_TRUE(r.traj.result.ok()) << r.traj.result.message;
  EXPECT_EQ(r.scalar("first"), x0);
  EXPECT_EQ(r.scalar("t_first"), 0.0);
  EXPECT_EQ(r.scalar("t_last"), 3.0);
  // x(3) and ∂x(3)/∂(x0, v0, m, c, k) (closed form); sensitivities are to (m, c, k, v0).
  const OscillatorSolution s = damped_oscillator(3.0, x0, 0.0, 2.0, 0.8, 20.0);
  EXPECT_NEAR(r.scalar("last"), 15 - s.x, 1e-9);
  const double dx[4] = {s.dx[2], s.dx[3], s.dx[4], s.dx[1]};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(r.scalar_sens("first", i), 0.0);  // x(0) = x0 does not depend on (m, c, k, v0)
    EXPECT_EQ(r.scalar_sens("t_first", i), 0.0);
    EXPECT_EQ(r.scalar_sens("t_last", i), 0.0);
    EXPECT_NEAR(r.scalar_sens("last", i), -dx[i], 1e-7 * std::max(1.0, std::abs(dx[i])));
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, Extrema, ::testing::Values("bdf", "adams", "dop853"),
                         [](const auto& info) { return info.param; });

namespace {

constexpr double g = 9.81;

std::string pendulum(const std::string& method, const std::string& events, const std::string& outputs) {
  return pendulum_study_head(method) + "events:\n" + events + "outputs:\n" + outputs;
}

class AtEvent : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(AtEvent, PendulumSpeedAtTheBottomAgainstEnergy) {
  const OutputRun r = run_output_study(pendulum(GetParam(),
                                                "  - {name: down, when: pivot.q, direction: falling}\n"
                                                "  - {name: cross, when: pivot.q}\n",
                                                "  w1: {of: pivot.u, at_event: down}\n"
                                                "  w2: {of: pivot.u, at_event: down, occurrence: 2}\n"
                                                "  w3: {of: pivot.u, at_event: down, occurrence: 3}\n"
                                                "  q2: {of: pivot.q, at_event: cross, occurrence: 2}\n"
                                                "  t2: {of: t, at_event: down, occurrence: 2}\n"),
                                       "at_event_pendulum_" + GetParam() + ".yaml");
  ASSERT_TRUE(r.traj.result.ok()) << r.traj.result.message;
  const double L = 1.2, theta0 = 0.9;
  const double w = -std::sqrt(3 * g * (1 - std::cos(theta0)) / L);
  const double dw_dL = -w / (2 * L);
  const double dw_dtheta0 = -std::sqrt(3 * g / L) * std::sin(theta0) / (2 * std::sqrt(1 - std::cos(theta0)));
  for (const char* name : {"w1", "w2"}) {
    std::printf("%s %s: %.12f (energy %.12f), d/dL %.10f (%.10f), d/dtheta0 %.10f (%.10f)\n", GetParam().c_str(), name,
                r.scalar(name), w, r.scalar_sens(name, 0), dw_dL, r.scalar_sens(name, 1), dw_dtheta0);
    EXPECT_NEAR(r.scalar(name), w, 1e-8);
    EXPECT_NEAR(r.scalar_sens(name, 0), dw_dL, 1e-7);
    EXPECT_NEAR(r.scalar_sens(name, 1), dw_dtheta0, 1e-7);
  }
  // The second falling crossing at five quarter periods, K(sin(θ0/2))·√(2L/(3g)) each.
  const double k = std::sin(theta0 / 2), K = boost::math::ellint_1(k), E = boost::math::ellint_2(k);
  const double scale = std::sqrt(2 * L / (3 * g)), tau = K * scale;
  EXPECT_NEAR(r.scalar("t2"), 5 * tau, 5e-8);
  EXPECT_NEAR(r.scalar_sens("t2", 0), 5 * tau / (2 * L), 5e-7);
  EXPECT_NEAR(r.scalar_sens("t2", 1), 5 * scale * (E / (k * (1 - k * k)) - K / k) * std::cos(theta0 / 2) / 2, 5e-7);
  // Every crossing's time (the HDF5 /events/cross/time row): (2k − 1) quarter periods, with
  // (2k − 1) times the quarter period's sensitivities; NaN after the last.
  const auto& plan = r.plan();
  std::size_t e = 0;
  while (plan.nodes[static_cast<std::size_t>(plan.event_nodes[e])].name != "cross") ++e;
  const std::size_t W = static_cast<std::size_t>(plan.event_occurrences);
  ASSERT_EQ(W, 100u);  // max_count not given: the first 100 are kept
  const int crossings = static_cast<int>(r.scalar("cross.count"));
  ASSERT_GE(crossings, 3);
  EXPECT_EQ(r.traj.event_counts[e], crossings);
  for (int k = 1; k <= crossings + 1; ++k) {
    const double tk = r.traj.event_times[e * W + static_cast<std::size_t>(k - 1)];
    const double sk = r.traj.event_time_sensitivities[(e * W + static_cast<std::size_t>(k - 1)) * 2];
    if (k > crossings) {
      EXPECT_TRUE(std::isnan(tk) && std::isnan(sk)) << k;
      continue;
    }
    EXPECT_NEAR(tk, (2 * k - 1) * tau, 5e-8) << k;
    EXPECT_NEAR(sk, (2 * k - 1) * tau / (2 * L), 5e-7) << k;
  }
  // The event function at its own event: 0, and s_q + q̇·dτ/dp = 0.
  EXPECT_NEAR(r.scalar("q2"), 0.0, 1e-10);
  EXPECT_NEAR(r.scalar_sens("q2", 0), 0.0, 1e-8);
  EXPECT_NEAR(r.scalar_sens("q2", 1), 0.0, 1e-8);
  // Falling crossings at τ and 5τ only within 3 s: the third is NaN, with a note, not a failure.
  EXPECT_TRUE(std::isnan(r.scalar("w3")));
  EXPECT_TRUE(std::isnan(r.scalar_sens("w3", 0)));
  EXPECT_NE(r.traj.result.message.find("w3 is NaN: event 'down' occurred 2 times, not 3"), std::string::npos)
      << r.traj.result.message;
}

TEST_P(AtEvent, ValuesAtEventsMatchFiniteDifferences) {
  const std::string text = pendulum(GetParam(), "  - {name: e, when: \"pivot.q - 0.1*L + 0.05*t\", direction: falling}\n",
                                    "  tip: {type: position, body: rod, point: [0, \"-L/2\", 0]}\n"
                                    "  x: {of: tip.x, at_event: e}\n"
                                    "  peak: {of: \"tip.x + 0.1*t\", reduce: max}\n"
                                    "  t_peak: {of: \"tip.x + 0.1*t\", reduce: argmax}\n");
  expect_scalar_sensitivities_match_differences(text, "at_event_fd_" + GetParam() + ".yaml", {"x", "peak", "t_peak"},
                                                1e-3, 1e-6);
}


// The times of interior extrema of a position, of an expression with a parameter and of a joint
// load (acceleration level: its rate involves the derivative of u̇) at rtol 1e-12, against
// differences of runs at rtol 1e-13 (at 1e-12 the load's integration error, some 5e-11, divided by
// h would be as large as the tolerance).
TEST_P(AtEvent, ArgExtremumSensitivitiesMatchFiniteDifferences) {
  std::string head = pendulum_study_head(GetParam());
  const std::string loose = "rtol: 1.0e-10, atol: 1.0e-12";
  head.replace(head.find(loose), loose.size(), "rtol: 1.0e-12, atol: 1.0e-14");
  const std::string text = head +
                           "outputs:\n"
                           "  tip: {type: position, body: rod, point: [0, \"-L/2\", 0]}\n"
                           "  load: {type: joint_load, joint: pivot}\n"
                           "  t_low: {of: \"tip.y + 0.05*L*t\", reduce: argmin}\n"
                           "  t_right: {of: \"tip.x + 0.1*t\", reduce: argmax}\n"
                           "  t_pull: {of: \"load.fy - 2*t\", reduce: argmax}\n"
                           "  pull: {of: \"load.fy - 2*t\", reduce: max}\n";
  expect_scalar_sensitivities_match_differences(text, "argextremum_fd_" + GetParam() + ".yaml",
                                                {"t_low", "t_right", "t_pull", "pull"}, 1e-3, 1e-8,
                                                {"solver.rtol=1e-13", "solver.atol=1e-15"});
}

INSTANTIATE_TEST_SUITE_P(Methods, AtEvent, ::testing::Values("bdf", "adams", "dop853"),
                         [](const auto& info) { return info.param; });

// The four-bar crank-rocker (configs/four_bar.yaml, closed by a constraint): the rocker's
// extreme angles (every crank turn reaches the same ones, so a drift in t picks the first) and
// their times, with multipliers and projection, and with the embedding (the
// rate's derivative then comes from the multiplier form at the reconstructed full state).
class ConstrainedExtrema : public ::testing::TestWithParam<std::string> {};

TEST_P(ConstrainedExtrema, FourBarRockerExtremaMatchFiniteDifferences) {
  const std::string formulation = GetParam();
  const std::string text = std::string("kanesens: 1\nscene: ") + KANESENS_SOURCE_DIR + "/configs/four_bar.yaml\n" +
                           "time: {end: 1.0, outputs: 11}\n"
                           "solver: {method: " + (formulation == "embedding" ? "dop853" : "bdf") +
                           ", rtol: 1.0e-12, atol: 1.0e-14,\n"
                           "         constraints: {formulation: " + formulation + ", stabilization: projection}}\n"
                           "sensitivities: [c, m2]\n"
                           "outputs:\n"
                           "  t_up: {of: \"rocker.q - 0.2*t\", reduce: argmax}\n"
                           "  up: {of: \"rocker.q - 0.2*t\", reduce: max}\n"
                           "  t_down: {of: \"rocker.q + 0.2*t\", reduce: argmin}\n";
  expect_scalar_sensitivities_match_differences(text, "four_bar_extrema_" + formulation + ".yaml",
                                                {"t_up", "up", "t_down"}, 1e-4, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Formulations, ConstrainedExtrema, ::testing::Values("multipliers", "embedding"),
                         [](const auto& info) { return info.param; });

}  // namespace KANESENS_UNITY_ID
