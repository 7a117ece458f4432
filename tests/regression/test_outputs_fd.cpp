// Every kind of study output, series and scalar, has exact sensitivities: compared with central
// finite differences of whole runs (each input moved by ±h and ±2h, the study run again; the
// fourth-order difference) to 1e-6
// relative (to the largest sensitivity of that output over its components and time, or 1e-9
// absolute). Three scenes:
// a planar double pendulum with a spring-damper (point kinematics, joint loads, force element,
// energies, expressions, at/integral/mean/rms), a 3-D ball-jointed pair of bodies (orientation,
// angular velocity, 3-D joint loads), and the pinned double pendulum (constraint forces, joint
// loads carrying λ). The planar scene also runs with DOP853 (its quadratures).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "../support/output_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

const std::string kPlanar = R"Y(kanesens: 1
scene:
  name: planar
  gravity: [0, -9.81, 0]
  parameters: {m1: 1.0, L1: 1.0, m2: 0.8, L2: 0.7, ks: 12.0, cs: 0.3}
  bodies:
    - {name: rod1, mass: m1, inertia: {shape: rod, length: L1, axis: y}}
    - {name: rod2, mass: m2, inertia: {shape: rod, length: L2, axis: y}}
  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1],
       child_point: [0, "L1/2", 0], q0: 0.7, u0: 0.2}
    - {name: elbow, type: revolute, parent: rod1, child: rod2, axis: [0, 0, 1],
       parent_point: [0, "-L1/2", 0], child_point: [0, "L2/2", 0], q0: -0.3,
       spring: {k: 2.0, rest: 0.1}}
  forces:
    - {name: s1, type: spring_damper, body_a: ground, point_a: [1.0, 0.5, 0], body_b: rod2,
       point_b: [0, "-L2/2", 0], k: ks, c: cs, rest: 0.8}
time: {end: 1.0, outputs: 11}
solver: {method: bdf, rtol: 1.0e-12, atol: 1.0e-14}
sensitivities: [m2, L1, ks, shoulder.q0, elbow.u0]
record: [states]
outputs:
  tip:  {type: position, body: rod2, point: [0, "-L2/2", 0]}
  tipv: {type: velocity, body: rod2, point: [0.1, "-L2/2", 0]}
  tipa: {type: acceleration, body: rod2, point: [0, "-L2/2", 0]}
  att:  {type: orientation, body: rod2}
  spin: {type: angular_velocity, body: rod1}
  elbow_load: {type: joint_load, joint: elbow}
  shoulder_load: {type: joint_load, joint: shoulder}
  spring: {type: force_element, force: s1}
  ke: {type: energy, kind: kinetic}
  pe: {type: energy, kind: potential}
  te: {type: energy}
  reach: {expression: "sqrt(tip.x^2 + tip.y^2) + 0.1*spring.tension*t"}
  tip_y_end: {of: tip.y, at: end}
  tip_x_mid: {of: "tip.x*elbow.u", at: 0.43}
  work: {of: "elbow_load.mz*elbow.u + shoulder_load.fx", reduce: integral}
  ke_mean: {of: ke, reduce: mean}
  load_rms: {of: elbow_load.fy, reduce: rms}
  combo: {expression: "work * ke_mean / m2"}
)Y";

const std::string kSpatial = R"Y(kanesens: 1
scene:
  name: spatial
  gravity: [0, -9.81, 0]
  parameters: {m: 1.2, L: 0.8, mb: 0.7}
  bodies:
    - {name: a, mass: m, inertia: {xx: 0.1, yy: 0.02, zz: 0.09, xy: 0.01}}
    - {name: b, mass: mb, inertia: {shape: box, size: [0.1, 0.5, 0.2]}}
  joints:
    - {name: ball, type: spherical, parent: ground, child: a, child_point: [0, "L/2", 0],
       q0: [0.95, 0.2, 0.1, 0.2], u0: [0.3, -0.5, 1.1]}
    - {name: hinge, type: revolute, parent: a, child: b, axis: [1, 0.2, 0.3],
       parent_point: [0, "-L/2", 0.05], child_point: [0, 0.25, 0], q0: 0.4, u0: -0.6}
time: {end: 1.0, outputs: 11}
solver: {method: bdf, rtol: 1.0e-12, atol: 1.0e-14}
sensitivities: [m, L, mb, "ball.u0[1]", hinge.q0]
record: [states]
outputs:
  pb: {type: position, body: b, point: [0.05, -0.25, "L/10"]}
  vb: {type: velocity, body: b, point: [0.05, -0.25, 0]}
  ab: {type: acceleration, body: b, point: [0.05, -0.25, 0]}
  att: {type: orientation, body: b}
  wa: {type: angular_velocity, body: a}
  ball_load: {type: joint_load, joint: ball}
  hinge_load: {type: joint_load, joint: hinge}
  te: {type: energy}
  power: {of: "hinge_load.mx*wa.x + ab.z", reduce: integral}
)Y";

const std::string kPinned = R"Y(kanesens: 1
scene:
  name: pinned
  gravity: [0, -9.81, 0]
  parameters: {m1: 1.0, L1: 1.0, m2: 0.7, L2: 0.8}
  bodies:
    - {name: rod1, mass: m1, inertia: {shape: rod, length: L1, axis: y}}
    - {name: rod2, mass: m2, inertia: {shape: rod, length: L2, axis: y}}
  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1],
       child_point: [0, "L1/2", 0], q0: 0.6, u0: 0.3}
    - {name: free2, type: planar, parent: ground, child: rod2, axis: [0, 0, 1],
       q0: ["L1*sin(0.6) + L2/2*sin(0.2)", "-L1*cos(0.6) - L2/2*cos(0.2)", 0.2]}
  constraints:
    - {name: pin, type: coincident, body_a: rod2, point_a: [0, "L2/2", 0], body_b: rod1, point_b: [0, "-L1/2", 0]}
time: {end: 1.0, outputs: 11}
solver: {method: bdf, rtol: 1.0e-12, atol: 1.0e-14}
sensitivities: [m2, L1, shoulder.u0]
record: [states]
outputs:
  pin_force: {type: constraint_force, constraint: pin}
  shoulder_load: {type: joint_load, joint: shoulder}
  tipa: {type: acceleration, body: rod2, point: [0, "-L2/2", 0]}
  lam: {expression: "pin.x^2 + pin.y"}
  pin_end: {of: pin.y, at: end}
  pin_mean: {of: pin.x, reduce: mean}
)Y";

struct Worst {
  double error = 0;
  std::string where;
};

// Central differences of every output of `text` with respect to each of its sensitivities.
// Returns the worst relative error per output (component names folded to the output's name).
std::map<std::string, Worst> compare(const std::string& text, const std::string& file,
                                     const std::vector<std::string>& set = {}) {
  const OutputRun base = run_output_study(text, file, set);
  const auto& sens = base.problem->sensitivities();
  std::map<std::string, Worst> worst;
  auto note = [&](const std::string& name, double err, const std::string& where) {
    const std::string key = name.substr(0, name.find('.'));
    if (err >= worst[key].error) worst[key] = {err, name + " " + where};
  };
  for (std::size_t i = 0; i < sens.size(); ++i) {
    const InputRef ref = sens[i];
    const double x = base.sensitivity_input(i);
    const double h = 1e-3 * std::max(1.0, std::abs(x));
    auto moved = [&](double dx) {
      return run_output_study(text, file, set, [&](const Model&, SampleInputs& in) { in.set(ref, x + dx); });
    };
    const OutputRun plus = moved(h), minus = moved(-h), plus2 = moved(2 * h), minus2 = moved(-2 * h);
    // Fourth-order central difference: truncation O(h⁴), so h can stay well above the noise.
    auto fd = [&](auto value) {
      return (8 * (value(plus) - value(minus)) - (value(plus2) - value(minus2))) / (12 * h);
    };
    // Scale: the largest sensitivity of the output (all its components, all times), so that a
    // component that is zero by construction (a revolute joint's moment about its axis) is
    // compared with the sizes around it, not with its own rounding noise.
    std::map<std::string, double> scale;
    for (const auto& name : base.plan().series_names) {
      double& sc = scale[name.substr(0, name.find('.'))];
      for (std::size_t k = 0; k < base.T; ++k) sc = std::max({sc, 1e-9, std::abs(base.series_sens(name, k, i))});
    }
    for (const auto& name : base.plan().series_names) {
      double err = 0;
      for (std::size_t k = 0; k < base.T; ++k) {
        const double d = fd([&](const OutputRun& r) { return r.series(name, k); });
        err = std::max(err, std::abs(d - base.series_sens(name, k, i)) / scale[name.substr(0, name.find('.'))]);
      }
      note(name, err, "d/d" + ref.name);
    }
    for (const auto& name : base.plan().scalar_names) {
      const double d = fd([&](const OutputRun& r) { return r.scalar(name); });
      const double exact = base.scalar_sens(name, i);
      note(name, std::abs(d - exact) / std::max(1e-9, std::abs(exact)), "d/d" + ref.name);
    }
  }
  return worst;
}

void check(const std::map<std::string, Worst>& worst, const char* scene) {
  for (const auto& [name, w] : worst) {
    std::printf("%-8s %-14s %.2e  (%s)\n", scene, name.c_str(), w.error, w.where.c_str());
    EXPECT_LT(w.error, 1e-6) << scene << " " << w.where;
  }
}

TEST(OutputSensitivitiesFd, PlanarEveryKindBdf) { check(compare(kPlanar, "fd_planar.yaml"), "planar"); }
TEST(OutputSensitivitiesFd, PlanarEveryKindDop853) {
  check(compare(kPlanar, "fd_planar_dop.yaml", {"solver.method=dop853"}), "dop853");
}
TEST(OutputSensitivitiesFd, SpatialEveryKind) { check(compare(kSpatial, "fd_spatial.yaml"), "spatial"); }
TEST(OutputSensitivitiesFd, ConstraintForcesAndLoads) { check(compare(kPinned, "fd_pinned.yaml"), "pinned"); }

}  // namespace

}  // namespace KANESENS_UNITY_ID
