// Scenes for tests and benchmarks, as YAML text (docs/reference/scene.md).
// chain_scene: the benchmark chain — a planar N-link chain of uniform rods (mass 1, length 1),
// revolute about z, gravity −y, hanging along −y at q = 0. Each rod has a tiny inertia about its
// own axis (1e-4) so that MuJoCo, which rejects a zero principal inertia, models the same bodies
// (bench/peers/mujoco_chain_bench.cpp). `tilt` > 0 tips the last joint's axis out of the plane by
// that angle (rad), which makes the scene 3-D.
#pragma once
#include <cmath>
#include <sstream>
#include <string>

namespace kanesens::test_scenes {

inline std::string chain_scene(int n, double tilt = 0.0) {
  std::string s = "kanesens: 1\nscene:\n  name: chain" + std::to_string(n) +
                  "\n  gravity: [0, -9.81, 0]\n  parameters: {m: 1.0, L: 1.0}\n  bodies:\n";
  for (int i = 1; i <= n; ++i)
    s += "    - {name: link" + std::to_string(i) +
         ", mass: m, inertia: {xx: \"m*L^2/12\", yy: 1.0e-4, zz: \"m*L^2/12\"}}\n";
  s += "  joints:\n";
  for (int i = 1; i <= n; ++i) {
    const bool tipped = tilt != 0.0 && i == n;
    char axis[96] = "[0, 0, 1]";
    if (tipped) std::snprintf(axis, sizeof axis, "[%.17g, 0, %.17g]", std::sin(tilt), std::cos(tilt));
    s += "    - {name: j" + std::to_string(i) + ", type: revolute, parent: " +
         (i == 1 ? std::string("ground") : "link" + std::to_string(i - 1)) + ", child: link" +
         std::to_string(i) + ", axis: " + axis + ", parent_point: [0, " +
         (i == 1 ? "0" : "\"-L/2\"") + ", 0], child_point: [0, \"L/2\", 0]}\n";
  }
  return s;
}

// A chain of n boxes on spherical joints (3 speeds each, quaternion coordinates), hanging along −y.
inline std::string ball_chain(int n) {
  std::ostringstream s;  // (string concatenation here trips GCC 12's false -Wrestrict)
  s << "kanesens: 1\nscene:\n  name: balls\n  gravity: [0, -9.81, 0]\n  bodies:\n";
  for (int i = 1; i <= n; ++i) s << "    - {name: b" << i << ", mass: 1, inertia: {shape: box, size: [0.1, 1, 0.2]}}\n";
  s << "  joints:\n";
  for (int i = 1; i <= n; ++i) {
    s << "    - {name: j" << i << ", type: spherical, parent: ";
    if (i == 1) s << "ground";
    else s << "b" << i - 1;
    s << ", child: b" << i << ", parent_point: [0, " << (i == 1 ? "0" : "-0.5") << ", 0], child_point: [0, 0.5, 0]}\n";
  }
  return s.str();
}

// bench/n_four_bar.py's scene, the IFToMM N four-bar mechanism: N+1 cranks on the ground, coupler
// i on crank i's tip, closed onto crank i+1's tip by a coincident constraint; cranks at φ0 = 0.7
// turning at −1.4 rad/s, on the constraint manifold.
inline std::string n_four_bar(int n) {
  const auto num = [](int i) { return std::to_string(i); };
  std::string s =
      "kanesens: 1\nscene:\n  name: n_four_bar\n  gravity: [0, -9.81, 0]\n"
      "  parameters: {L: 1.0, m: 1.0, phi0: 0.7, w0: -1.4}\n  bodies:\n";
  for (int i = 0; i <= n; ++i) s += "    - {name: crank" + num(i) + ", mass: m, inertia: {shape: rod, length: L, axis: x}}\n";
  for (int i = 0; i < n; ++i) s += "    - {name: coupler" + num(i) + ", mass: m, inertia: {shape: rod, length: L, axis: x}}\n";
  s += "  joints:\n";
  for (int i = 0; i <= n; ++i)
    s += "    - {name: crank" + num(i) + ", type: revolute, parent: ground, child: crank" + num(i) +
         ", axis: [0, 0, 1], parent_point: [\"" + num(i) + "*L\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: phi0, u0: w0}\n";
  for (int i = 0; i < n; ++i)
    s += "    - {name: coupler" + num(i) + ", type: revolute, parent: crank" + num(i) + ", child: coupler" + num(i) +
         ", axis: [0, 0, 1], parent_point: [\"L/2\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: \"-phi0\", u0: \"-w0\"}\n";
  s += "  constraints:\n";
  for (int i = 0; i < n; ++i)
    s += "    - {name: loop" + num(i) + ", type: coincident, body_a: coupler" + num(i) + ", point_a: [\"L/2\", 0, 0], body_b: crank" +
         num(i + 1) + ", point_b: [\"L/2\", 0, 0]}\n";
  return s;
}

// A ball-jointed rod carrying a revolute second rod (quaternion coordinates, 3-D).
inline const char* kSphericalScene = R"yaml(kanesens: 1
scene:
  name: spherical
  gravity: [0, -9.81, 0]
  parameters: {m: 1.2, L: 0.8}
  bodies:
    - {name: a, mass: m, inertia: {xx: 0.1, yy: 0.02, zz: 0.09, xy: 0.01}}
    - {name: b, mass: 0.7, inertia: {shape: box, size: [0.1, 0.5, 0.2]}}
  joints:
    - {name: ball, type: spherical, parent: ground, child: a, parent_point: [0, 0, 0],
       child_point: [0, "L/2", 0]}
    - {name: hinge, type: revolute, parent: a, child: b, axis: [1, 0.2, 0.3],
       parent_point: [0, "-L/2", 0.05], child_point: [0, 0.25, 0]}
)yaml";

// A free body with a universal-jointed child and a cylindrical grandchild.
inline const char* kFreeScene = R"yaml(kanesens: 1
scene:
  name: free
  gravity: [0, 0, -9.81]
  bodies:
    - {name: base, mass: 3, inertia: {shape: box, size: [0.4, 0.3, 0.2]}}
    - {name: arm, mass: 1, inertia: {shape: cylinder, radius: 0.05, length: 0.6, axis: x}}
    - {name: tip, mass: 0.3, inertia: {shape: sphere, radius: 0.05}}
  joints:
    - {name: float, type: free, parent: ground, child: base}
    - {name: u, type: universal, parent: base, child: arm, axes: [[0, 0, 1], [0, 1, 0]],
       parent_point: [0.2, 0, 0], child_point: [-0.3, 0, 0]}
    - {name: c, type: cylindrical, parent: arm, child: tip, axis: [1, 0, 0],
       parent_point: [0.3, 0, 0]}
)yaml";

// Every kind of force: joint spring and damper, a spring-damper, a time- and state-dependent
// force and a body-frame torque; with prismatic and planar joints.
inline const char* kForcesScene = R"yaml(kanesens: 1
scene:
  name: forces
  gravity: [0, -9.81, 0]
  parameters: {k: 20, c: 0.3, F0: 2}
  bodies:
    - {name: cart, mass: 2, inertia: {shape: box, size: [0.4, 0.2, 0.2]}}
    - {name: pole, mass: 0.5, inertia: {shape: rod, length: 1, axis: y}}
    - {name: puck, mass: 0.2, inertia: {shape: cylinder, radius: 0.1, length: 0.02, axis: z}}
  joints:
    - {name: slide, type: prismatic, parent: ground, child: cart, axis: [1, 0, 0],
       spring: {k: k, rest: 0.1}, damper: {c: c}}
    - {name: hinge, type: revolute, parent: cart, child: pole, axis: [0, 0, 1],
       child_point: [0, -0.5, 0], damper: {c: "c*hinge.u^2"}}
    - {name: glide, type: planar, parent: ground, child: puck, axis: [0, 0, 1],
       parent_point: [0, 2, 0]}
  forces:
    - {type: spring_damper, name: s, body_a: pole, point_a: [0, 0.5, 0], body_b: puck,
       point_b: [0.1, 0, 0], k: k, c: c, rest: 0.5}
    - {type: force, name: push, body: cart, point: [0, 0.1, 0], vector: ["F0*sin(3*t)", 0, 0],
       frame: world}
    - {type: torque, name: brake, body: pole, vector: [0, 0, "-0.1*hinge.u"], frame: body}
)yaml";

// A uniform rod hinged at its top end to the ground, about z, gravity −y: the physical pendulum
// of the closed-form tests (M = m L²/3, θ̈ = −(3g/2L) sin θ). `parameters` sets m and L
// ("{m: 1.3, L: 0.9}"); `pivot` adds keys to the hinge (", q0: 1.1, u0: 0.4").
inline std::string rod_pendulum_scene(const std::string& name, const std::string& parameters,
                                      const std::string& pivot = "") {
  return "kanesens: 1\n"
         "scene:\n"
         "  name: " + name + "\n"
         "  gravity: [0, -9.81, 0]\n"
         "  parameters: " + parameters + "\n"
         "  bodies:\n"
         "    - {name: rod, mass: m, inertia: {shape: rod, length: L, axis: y}}\n"
         "  joints:\n"
         "    - {name: pivot, type: revolute, parent: ground, child: rod, axis: [0, 0, 1],\n"
         "       child_point: [0, \"L/2\", 0]" + pivot + "}\n";
}

}  // namespace kanesens::test_scenes
