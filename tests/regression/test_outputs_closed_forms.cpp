// Study outputs (`outputs:`) against what we did not write:
//   (a) a uniform-rod pendulum hinged at its end: tip position, velocity, acceleration and the
//       pivot load against the textbook closed forms at the recorded states (θ̈ = −3g sin θ/(2L),
//       pivot force m a_cm − m g), on the planar and the general 3-D evaluation;
//   (b) the double pendulum's joint loads against the same pendulum built with a free planar
//       joint and a coincident constraint at the elbow: the elbow load equals the constraint's λ,
//       and the shoulder load (whose subtree the λ acts on) is the same in both models;
//   (c) a harmonic oscillator: ∫, mean and rms of the kinetic energy and `at:` values of x(t)
//       against the closed forms, with their sensitivities to k, m, x0 (closed forms
//       differentiated by the complex step), CVODES and DOP853 quadratures;
//   (d) a heavy symmetric top in steady precession (Goldstein §5.7): the pivot load is
//       −m φ̇² r_⊥ + m g ẑ (r_⊥ the horizontal position of the mass center), no moment.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "../support/output_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

constexpr double g = 9.81;

// ---- (a) ----------------------------------------------------------------------------------------
const std::string kPendulum = kanesens::test_scenes::rod_pendulum_scene("pendulum", "{m: 1.3, L: 0.9}", ", q0: 1.1, u0: 0.4") +
                               R"(time: {end: 2.0, outputs: 41}
solver: {rtol: 1.0e-10, atol: 1.0e-12}
outputs:
  tip:  {type: position, body: rod, point: [0, "-L/2", 0]}
  tipv: {type: velocity, body: rod, point: [0, "-L/2", 0]}
  tipa: {type: acceleration, body: rod, point: [0, "-L/2", 0]}
  load: {type: joint_load, joint: pivot}
)";

class PendulumClosedForm : public ::testing::TestWithParam<bool> {};

TEST_P(PendulumClosedForm, TipKinematicsAndPivotLoad) {
  const OutputRun r = run_output_study(kPendulum, "pendulum.yaml", {}, {}, GetParam());
  const double m = 1.3, L = 0.9;
  double worst = 0;
  for (std::size_t k = 0; k < r.T; ++k) {
    const double q = r.state("pivot.q", k), u = r.state("pivot.u", k);
    const double c = std::cos(q), s = std::sin(q), qdd = -3 * g * s / (2 * L);
    const double ax = L * qdd * c - L * u * u * s, ay = L * qdd * s + L * u * u * c;
    const double expect[][2] = {{L * s, r.series("tip.x", k)},       {-L * c, r.series("tip.y", k)},
                                {L * u * c, r.series("tipv.x", k)},  {L * u * s, r.series("tipv.y", k)},
                                {ax, r.series("tipa.x", k)},         {ay, r.series("tipa.y", k)},
                                {m * ax / 2, r.series("load.fx", k)}, {m * ay / 2 + m * g, r.series("load.fy", k)},
                                {0, r.series("load.fz", k)},         {0, r.series("load.mx", k)},
                                {0, r.series("load.my", k)},         {0, r.series("load.mz", k)},
                                {0, r.series("tip.z", k)},           {0, r.series("tipa.z", k)}};
    for (const auto& e : expect) worst = std::max(worst, std::abs(e[0] - e[1]) / (m * g));
  }
  RecordProperty("max_error_relative_to_mg", std::to_string(worst));
  std::printf("pendulum: max |closed form - output| / (m g) = %.3g\n", worst);
  EXPECT_LT(worst, 1e-12) << "largest error relative to m g";
}

INSTANTIATE_TEST_SUITE_P(Evaluation, PendulumClosedForm, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "General3d" : "Planar"; });

// ---- (b) ----------------------------------------------------------------------------------------
const std::string kScene = R"(  gravity: [0, -9.81, 0]
  parameters: {m1: 1.0, L1: 1.0, m2: 0.7, L2: 0.8}
  bodies:
    - {name: rod1, mass: m1, inertia: {shape: rod, length: L1, axis: y}}
    - {name: rod2, mass: m2, inertia: {shape: rod, length: L2, axis: y}}
)";
const std::string kTail = R"(time: {end: 1.5, outputs: 31}
solver: {rtol: 1.0e-11, atol: 1.0e-12}
)";

TEST(OutputsJointLoad, ElbowLoadIsTheLambdaOfAConstraintClosingTheJoint) {
  const std::string jointed = "kanesens: 1\nscene:\n  name: jointed\n" + kScene + R"(  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1],
       child_point: [0, "L1/2", 0], q0: 0.6}
    - {name: elbow, type: revolute, parent: rod1, child: rod2, axis: [0, 0, 1],
       parent_point: [0, "-L1/2", 0], child_point: [0, "L2/2", 0], q0: -0.4}
)" + kTail + R"(outputs:
  shoulder_load: {type: joint_load, joint: shoulder}
  elbow_load: {type: joint_load, joint: elbow}
)";
  // rod2 free in the plane, its top end pinned to rod1's bottom end; q0 puts it where the
  // jointed model starts (absolute angle 0.2).
  const std::string pinned = "kanesens: 1\nscene:\n  name: pinned\n" + kScene + R"Y(  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1],
       child_point: [0, "L1/2", 0], q0: 0.6}
    - {name: free2, type: planar, parent: ground, child: rod2, axis: [0, 0, 1],
       q0: ["L1*sin(0.6) + L2/2*sin(0.2)", "-L1*cos(0.6) - L2/2*cos(0.2)", 0.2]}
  constraints:
    - {name: pin, type: coincident, body_a: rod2, point_a: [0, "L2/2", 0], body_b: rod1, point_b: [0, "-L1/2", 0]}
)Y" + kTail + R"(outputs:
  shoulder_load: {type: joint_load, joint: shoulder}
  free_load: {type: joint_load, joint: free2}
  pin: {type: constraint_force, constraint: pin}
)";
  const OutputRun a = run_output_study(jointed, "jointed.yaml");
  const OutputRun b = run_output_study(pinned, "pinned.yaml");
  const double scale = (1.0 + 0.7) * g;
  double elbow = 0, shoulder = 0, free_joint = 0;
  for (std::size_t k = 0; k < a.T; ++k) {
    elbow = std::max({elbow, std::abs(a.series("elbow_load.fx", k) - b.series("pin.x", k)),
                      std::abs(a.series("elbow_load.fy", k) - b.series("pin.y", k))});
    for (const char* c : {"fx", "fy", "mz"})
      shoulder = std::max(shoulder, std::abs(a.series(std::string("shoulder_load.") + c, k) -
                                             b.series(std::string("shoulder_load.") + c, k)));
    // The planar joint transmits no in-plane force or moment about z: the pin carries rod2.
    for (const char* c : {"fx", "fy", "mz"})
      free_joint = std::max(free_joint, std::abs(b.series(std::string("free_load.") + c, k)));
  }
  std::printf("joint load vs lambda: elbow %.3g, shoulder %.3g, free joint %.3g (relative to the weight)\n",
              elbow / scale, shoulder / scale, free_joint / scale);
  EXPECT_LT(elbow / scale, 1e-7);
  EXPECT_LT(shoulder / scale, 1e-7);
  EXPECT_LT(free_joint / scale, 1e-9);
  EXPECT_GT(std::abs(a.series("elbow_load.fy", a.T - 1)), 1.0);  // not trivially zero
}

// ---- (c) ----------------------------------------------------------------------------------------
const std::string kOscillator = R"Y(kanesens: 1
scene:
  name: oscillator
  gravity: [0, 0, 0]
  parameters: {m: 1.7, k: 5.0, x0: 0.3}
  bodies:
    - {name: block, mass: m, inertia: {shape: point}}
  joints:
    - {name: slider, type: prismatic, parent: ground, child: block, axis: [1, 0, 0],
       q0: x0, u0: 0, spring: {k: k, rest: 0}}
time: {end: 2.3, outputs: 24}
solver: {method: bdf, rtol: 1.0e-11, atol: 1.0e-13}
sensitivities: [k, m, x0]
outputs:
  ke: {type: energy, kind: kinetic}
  work_in: {of: ke, reduce: integral}
  ke_mean: {of: ke, reduce: mean}
  ke_rms: {of: ke, reduce: rms}
  x_end: {of: slider.q, at: end}
  x_mid: {of: slider.q, at: 0.37}
  ratio: {expression: "work_in / (k * x0^2)"}
)Y";

using C = std::complex<double>;
// Closed forms of (c) with ω = √(k/m), T = 2.3: KE = ½ k x0² sin²ωt.
C closed_form(const std::string& what, C k, C m, C x0) {
  const double T = 2.3;
  const C w = std::sqrt(k / m);
  const C I = 0.5 * k * x0 * x0 * (T / 2 - std::sin(2.0 * w * T) / (4.0 * w));
  if (what == "work_in") return I;
  if (what == "ke_mean") return I / T;
  if (what == "ratio") return I / (k * x0 * x0);
  if (what == "ke_rms") {
    const C s4 = 3 * T / 8 - std::sin(2.0 * w * T) / (4.0 * w) + std::sin(4.0 * w * T) / (32.0 * w);
    return std::sqrt(0.25 * k * k * x0 * x0 * x0 * x0 * s4 / T);
  }
  if (what == "x_end") return x0 * std::cos(w * T);
  return x0 * std::cos(w * 0.37);  // x_mid
}

class OscillatorIntegrals : public ::testing::TestWithParam<const char*> {};

TEST_P(OscillatorIntegrals, ValuesAndSensitivitiesMatchClosedForms) {
  const OutputRun r = run_output_study(kOscillator, std::string("osc_") + GetParam() + ".yaml",
                                       {std::string("solver.method=") + GetParam()});
  const double k = 5.0, m = 1.7, x0 = 0.3, h = 1e-20;
  for (const char* name : {"work_in", "ke_mean", "ke_rms", "x_end", "x_mid", "ratio"}) {
    const double v = closed_form(name, k, m, x0).real();
    EXPECT_NEAR(r.scalar(name), v, 1e-8 * std::abs(v)) << name;
    std::printf("%s %s: relative error %.3g", GetParam(), name, std::abs(r.scalar(name) - v) / std::abs(v));
    const double d[3] = {closed_form(name, C(k, h), m, x0).imag() / h, closed_form(name, k, C(m, h), x0).imag() / h,
                         closed_form(name, k, m, C(x0, h)).imag() / h};
    for (std::size_t i = 0; i < 3; ++i)
    {
      EXPECT_NEAR(r.scalar_sens(name, i), d[i], 1e-7 * (std::abs(d[i]) + std::abs(v))) << name << " d/d" << i;
      std::printf(", d/d%zu %.3g", i, std::abs(r.scalar_sens(name, i) - d[i]) / (std::abs(d[i]) + std::abs(v)));
    }
    std::printf("\n");
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, OscillatorIntegrals, ::testing::Values("bdf", "dop853"));

// ---- (d) ----------------------------------------------------------------------------------------
TEST(OutputsSpinningTop, PivotLoadInSteadyPrecession) {
  // Disc of radius r, thickness h on a massless stick, pivot a distance l below the mass center.
  const double m = 0.5, r = 0.04, h = 0.01, l = 0.05, theta = 0.3, spin = 80.0;
  const double I1 = m * (3 * r * r + h * h) / 12 + m * l * l, I3 = m * r * r / 2;
  // m g l = φ̇ (I3 ω3 − I1 φ̇ cos θ), ω3 = ψ̇ + φ̇ cos θ: the slow root of
  // (I3 − I1) cos θ φ̇² + I3 ψ̇ φ̇ − m g l = 0.
  const double a = (I3 - I1) * std::cos(theta), b = I3 * spin, c = -m * g * l;
  const double phidot = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
  char text[2048];
  std::snprintf(text, sizeof text, R"(kanesens: 1
scene:
  name: top
  gravity: [0, 0, -9.81]
  parameters: {m: %.17g, r: %.17g, h: %.17g, l: %.17g}
  bodies:
    - {name: top, mass: m, inertia: {shape: cylinder, radius: r, length: h, axis: z}}
  joints:
    - {name: tip, type: spherical, parent: ground, child: top, child_point: [0, 0, "-l"],
       q0: [%.17g, %.17g, 0, 0], u0: [0, %.17g, %.17g]}
time: {end: 1.0, outputs: 21}
solver: {rtol: 1.0e-11, atol: 1.0e-13}
outputs:
  pivot: {type: joint_load, joint: tip}
  com: {type: position, body: top}
)",
                m, r, h, l, std::cos(theta / 2), std::sin(theta / 2), phidot * std::sin(theta),
                phidot * std::cos(theta) + spin);
  const OutputRun run = run_output_study(text, "top.yaml");
  double force = 0, moment = 0, tilt = 0;
  for (std::size_t k = 0; k < run.T; ++k) {
    const double x = run.series("com.x", k), y = run.series("com.y", k);
    const double fx = -m * phidot * phidot * x, fy = -m * phidot * phidot * y, fz = m * g;
    force = std::max({force, std::abs(run.series("pivot.fx", k) - fx), std::abs(run.series("pivot.fy", k) - fy),
                      std::abs(run.series("pivot.fz", k) - fz)});
    for (const char* c : {"mx", "my", "mz"}) moment = std::max(moment, std::abs(run.series(std::string("pivot.") + c, k)));
    tilt = std::max(tilt, std::abs(run.series("com.z", k) - l * std::cos(theta)));
  }
  std::printf("top: tilt drift %.3g l, force error %.3g m g, moment %.3g m g l\n", tilt / l, force / (m * g),
              moment / (m * g * l));
  EXPECT_LT(tilt / l, 1e-8) << "not in steady precession";
  EXPECT_LT(force / (m * g), 1e-7);
  EXPECT_LT(moment / (m * g * l), 1e-9);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
