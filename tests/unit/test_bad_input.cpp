// Bad input, table-driven: every row is one bad scene, study or expression. Each must give an
// InputError (never a crash, a NaN or another exception type) whose one line names where it was
// written (file:line:column), the key path and what was expected. The CLI-level behaviour (exit
// code 2, one stderr line, no output file) is checked in tests/mpi/test_bad_input_cli.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "model/expr/expression.hpp"
#include "model/build_model.hpp"
#include "parallel/ensemble.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"
#include "../support/scratch_dir.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

// Line numbers below refer to these texts.
const std::string kScene = R"(kanesens: 1
scene:
  name: two
  gravity: [0, -9.81, 0]
  parameters: {m: 1, L: 1}
  bodies:
    - {name: a, mass: m, inertia: {shape: rod, length: L, axis: y}}
    - {name: b, mass: m, inertia: {xx: 1, yy: 1, zz: 1}}
  joints:
    - {name: j1, type: revolute, parent: ground, child: a, axis: [0, 0, 1]}
    - {name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1], child_point: [0, "L/2", 0]}
)";

const std::string kStudy = R"(kanesens: 1
scene:
  name: pend
  gravity: [0, -9.81, 0]
  parameters: {m: 1, L: 1}
  bodies:
    - {name: rod, mass: m, inertia: {shape: rod, length: L, axis: y}}
  joints:
    - {name: hinge, type: revolute, parent: ground, child: rod, axis: [0, 0, 1], q0: 0.3}
time: {end: 1, outputs: 11}
sampling: {method: mc, samples: 4, seed: 1}
vary:
  m: {dist: uniform, low: 0.5, high: 1.5}
sensitivities: [m]
)";

enum class Kind { scene, study, expr };

struct Case {
  const char* name;
  Kind kind;
  std::string text;                  // scene / study text, or the expression
  std::vector<std::string> expect;   // substrings of the one-line message
  std::vector<std::string> set = {}; // --set for studies
};

std::string edit(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  if (p == std::string::npos) throw std::logic_error("test table: '" + from + "' not in base text");
  return s.replace(p, from.size(), to);
}

std::filesystem::path temp_dir() {
  static const ScratchDir dir("kanesens_bad_input");
  return dir.path();
}

// Runs the case; returns the InputError's line. Any other outcome fails the test.
std::string error_of(const Case& c) {
  try {
    switch (c.kind) {
      case Kind::scene: {  // what `kanesens check` does
        const Model m = build_model(parse_scene_text(c.text, "s.yaml"));
        KaneProblem(m, {}).validate_initial_state();
        break;
      }
      case Kind::study: {
        const auto path = temp_dir() / (std::string(c.name) + ".yaml");
        std::ofstream(path) << c.text;
        parallel::RunOptions o;
        o.set = c.set;
        parallel::validate_study(path.string(), o);
        break;
      }
      case Kind::expr: {
        expr::NameTable names;
        names.add("L", {expr::VarKind::parameter, 0});
        names.add("t", {expr::VarKind::time, 0});
        const expr::Expression e = expr::compile(c.text, names, {"e.yaml", 3, 5}, "scene.x");
        const double L = 1;
        expr::Inputs<double> in;
        in.parameters = &L;
        const double v = e.evaluate(in);
        return "(no error; value " + std::to_string(v) + ")";
      }
    }
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(wrong exception type: ") + e.what() + ")";
  }
  return "(no error)";
}

// A scene row with one constraint added to kScene (line 12) and, with `weld`, a welded body w.
std::string with_constraint(const std::string& constraint, bool weld = false) {
  std::string s = kScene;
  if (weld) {
    s = edit(s, "  joints:\n", "    - {name: w, mass: 1, inertia: {shape: point}}\n  joints:\n");
    s += "    - {name: jw, type: weld, parent: ground, child: w, parent_point: [0, 2, 0]}\n";
  }
  return s + "  constraints:\n    - " + constraint + "\n";
}

// A spherical pendulum (quaternion coordinates), for rows about them.
const std::string kBall = R"(kanesens: 1
scene:
  name: ball
  gravity: [0, -9.81, 0]
  bodies:
    - {name: b, mass: 1, inertia: {xx: 1, yy: 1, zz: 1}}
  joints:
    - {name: j, type: spherical, parent: ground, child: b, child_point: [0, 1, 0]}
)";

// Scene rows.
std::vector<Case> scene_cases() {
  const std::string s = kScene;
  return {
      // Constraints that constrain nothing, or not finitely, at the initial state: named before
      // the consistent initial conditions (which decomposed an empty matrix: a segfault).
      {"CoincidentOnWeldedBody", Kind::scene, with_constraint("{name: fix, type: coincident, body_a: w, body_b: ground, point_b: [0, 2, 0]}", true), {"s.yaml:15:7", "scene.constraints[0]", "constraint 'fix' constrains nothing at the initial state"}},
      {"CoincidentZInPlanarScene", Kind::scene, with_constraint("{name: up, type: coincident, body_a: b, body_b: ground, components: [z]}"), {"s.yaml:13:7", "constraint 'up' constrains nothing"}},
      {"GeneralPositionZeroGradient", Kind::scene, with_constraint("{name: g, type: general, position: \"j1.q^2\"}"), {"s.yaml:13:7", "constraint 'g' constrains nothing"}},
      {"DistanceBetweenCoincidentPoints", Kind::scene, with_constraint("{name: rod, type: distance, body_a: a, body_b: ground, length: 1}"), {"s.yaml:13:7", "constraint 'rod' is not finite at the initial state", "row 'rod'"}},
      {"DistanceZeroLength", Kind::scene, with_constraint("{name: rod, type: distance, body_a: b, body_b: ground, length: 0}"), {"s.yaml:13:", "scene.constraints[0].length", "length must be > 0"}},
      {"CouplerWithItself", Kind::scene, with_constraint("{name: gear, type: coupler, joint_a: j1, joint_b: j1}"), {"s.yaml:13:7", "scene.constraints[0].joint_b", "two different joints"}},
      {"RollingZeroNormal", Kind::scene, with_constraint("{name: r, type: rolling, body: b, radius: 0.1, axis: [0, 0, 1], normal: [0, 0, 0]}"), {"s.yaml:13:", "scene.constraints[0].normal", "normal has zero length"}},
      {"RollingWheelLyingFlat", Kind::scene, with_constraint("{name: r, type: rolling, body: b, radius: 0.1, axis: [0, 0, 1], normal: [0, 0, 1]}"), {"s.yaml:13:7", "scene.constraints[0]", "the wheel of rolling constraint 'r' lies flat on its plane"}},
      {"RollingZeroRadius", Kind::scene, with_constraint("{name: r, type: rolling, body: b, radius: \"L - 1\", axis: [0, 0, 1]}"), {"s.yaml:13:", "scene.constraints[0].radius", "radius must be > 0"}},
      {"GeneralPositionOfNoCoordinate", Kind::scene, with_constraint("{name: g, type: general, position: \"L - 1 + t\"}"), {"s.yaml:13:", "scene.constraints[0].position", "does not depend on any coordinate"}},
      {"GeneralPositionOfQuaternion", Kind::scene, kBall + "  constraints:\n    - {name: g, type: general, position: \"j.qx - 0.1\"}\n", {"s.yaml:10:", "scene.constraints[0].position", "'j.qx' is a quaternion component"}},
      // Lists and names that become indices and sizes.
      {"ComponentsEmpty", Kind::scene, with_constraint("{name: pin, type: coincident, body_a: b, body_b: ground, components: []}"), {"s.yaml:13:", "scene.constraints[0].components", "empty list"}},
      {"ComponentsRepeated", Kind::scene, with_constraint("{name: pin, type: coincident, body_a: b, body_b: ground, components: [x, y, z, x]}"), {"s.yaml:13:", "scene.constraints[0].components", "'x' is given twice"}},
      {"ComponentsNotAList", Kind::scene, with_constraint("{name: pin, type: coincident, body_a: b, body_b: ground, components: xy}"), {"s.yaml:13:", "scene.constraints[0].components", "expected a list"}},
      {"ConstraintNameWithDot", Kind::scene, with_constraint("{name: pin.x, type: coupler, joint_a: j1, joint_b: j2}"), {"s.yaml:13:", "scene.constraints[0].name", "'pin.x' is not a valid name"}},
      {"ConstraintNamedLikeAnotherRow", Kind::scene, with_constraint("{name: coincident1, type: coupler, joint_a: j1, joint_b: j2}\n    - {type: coincident, body_a: b, body_b: ground}"), {"s.yaml:14:", "scene.constraints[1].name", "duplicate constraint name 'coincident1'"}},
      {"GeneralSpeedTwice", Kind::scene, with_constraint("{name: g, type: general, a: {j1.u: 1, j1.u: 2}}"), {"s.yaml:13:", "scene.constraints[0].a.j1.u", "given twice"}},
      {"GeneralNonScalarSpeedKey", Kind::scene, with_constraint("{name: g, type: general, a: {[j1.u]: 1}}"), {"s.yaml:13:", "scene.constraints[0].a", "expected a name, got a list"}},
      {"UniversalParallelAxes", Kind::scene, edit(s, "{name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1]", "{name: j2, type: universal, parent: a, child: b, axes: [[0, 0, 1], [0, 0, \"-L\"]]"), {"s.yaml:11:", "scene.joints[1].axes[1]", "two axes are parallel"}},
      {"NoDegreesOfFreedom", Kind::scene, edit(edit(s, "type: revolute, parent: ground, child: a, axis: [0, 0, 1]", "type: weld, parent: ground, child: a"), "type: revolute, parent: a, child: b, axis: [0, 0, 1]", "type: weld, parent: a, child: b"), {"s.yaml:3:3", "scene.joints", "no degrees of freedom"}},
      {"TooManyBodies", Kind::scene, [] {
         std::string t = "kanesens: 1\nscene:\n  name: many\n  bodies:\n";
         for (int i = 0; i < 4097; ++i) t += "    - {name: b" + std::to_string(i) + ", mass: 1, inertia: {shape: point}}\n";
         return t + "  joints: []\n";
       }(), {"s.yaml:3:3", "scene.bodies", "4097 bodies; kanesens handles at most 4096"}},
      // Magnitudes: the equations at the initial state must be finite.
      {"MassOverflowsTheMassMatrix", Kind::scene, edit(edit(s, "{name: a, mass: m,", "{name: a, mass: 1e308,"), "child_point: [0, \"L/2\", 0]", "child_point: [0, 1e10, 0]"), {"s.yaml:3:3", "scene", "at the initial state (t = 0) the forcing of j1.u is", "out of range"}},
      {"MassMatrixSingularAtT0", Kind::scene, edit(edit(edit(s, "{xx: 1, yy: 1, zz: 1}", "{shape: point}"), "{name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1], child_point: [0, \"L/2\", 0]}", "{name: j2, type: prismatic, parent: a, child: b, axis: [0, 0, 1]}\n    - {name: j3, type: revolute, parent: ground, child: c, axis: [0, 0, 1]}"), "  joints:", "    - {name: c, mass: 1, inertia: {shape: point}}\n  joints:"), {"s.yaml:3:3", "at the initial state (t = 0): mass matrix is not positive definite"}},
      {"QuaternionNotFinite", Kind::scene, edit(kBall, "child_point: [0, 1, 0]}", "child_point: [0, 1, 0], q0: [1e308, 1e308, 0, \"1e308*1e10\"]}"), {"s.yaml:", "scene.joints[0].q0"}},
      {"MalformedYamlUnclosedFlow", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1"), {"s.yaml:", "malformed YAML"}},
      {"MalformedYamlBadIndent", Kind::scene, edit(s, "  name: two", "  name: two\n name2: x"), {"s.yaml:", "malformed YAML"}},
      {"MalformedYamlTab", Kind::scene, edit(s, "  name: two", "\tname: two"), {"s.yaml:", "malformed YAML"}},
      {"EmptyDocument", Kind::scene, "", {"s.yaml:1:1", "expected a YAML map"}},
      {"RootIsList", Kind::scene, "- a\n- b\n", {"s.yaml:1:1", "expected a YAML map"}},
      {"UnsupportedVersion", Kind::scene, edit(s, "kanesens: 1", "kanesens: 2"), {"s.yaml:1:11", "kanesens", "version 1"}},
      {"MissingVersion", Kind::scene, edit(s, "kanesens: 1\n", ""), {"s.yaml:1:1", "missing required key 'kanesens'"}},
      {"UnknownTopKey", Kind::scene, edit(s, "scene:", "scene:\n  nmae: x"), {"s.yaml:3:3", "scene.nmae", "did you mean 'name'"}},
      {"UnknownBodyKeyDidYouMean", Kind::scene, edit(s, "{name: a, mass: m,", "{name: a, mas: m,"), {"s.yaml:7:", "scene.bodies[0].mas", "did you mean 'mass'"}},
      {"UnknownJointKeyDidYouMean", Kind::scene, edit(s, "child: a, axis", "child: a, axsi"), {"s.yaml:10:", "scene.joints[0].axsi", "did you mean 'axis'"}},
      {"UnknownInertiaShape", Kind::scene, edit(s, "shape: rod", "shape: rdo"), {"s.yaml:7:", "scene.bodies[0].inertia.shape", "unknown shape"}},
      {"UnknownInertiaAxisName", Kind::scene, edit(s, "axis: y}", "axis: w}"), {"s.yaml:7:", "scene.bodies[0].inertia.axis", "expected x, y or z"}},
      {"WrongTypeMassIsList", Kind::scene, edit(s, "mass: m,", "mass: [1, 2],"), {"s.yaml:7:", "scene.bodies[0].mass", "expected a number or expression"}},
      {"WrongTypeBodiesIsMap", Kind::scene, edit(s, "  bodies:\n    - {name: a, mass: m, inertia: {shape: rod, length: L, axis: y}}\n    - {name: b, mass: m, inertia: {xx: 1, yy: 1, zz: 1}}", "  bodies: {a: 1}"), {"s.yaml:6:", "scene.bodies", "expected a list"}},
      {"WrongTypeGravityTwoComponents", Kind::scene, edit(s, "[0, -9.81, 0]", "[0, -9.81]"), {"s.yaml:4:", "scene.gravity", "list of 3"}},
      {"WrongTypeNameIsMap", Kind::scene, edit(s, "{name: a, mass", "{name: {x: 1}, mass"), {"s.yaml:7:", "scene.bodies[0].name", "expected a name"}},
      {"WrongTypeEmptyValue", Kind::scene, edit(s, "mass: m,", "mass: '',"), {"s.yaml:7:", "scene.bodies[0].mass", "empty value"}},
      {"MissingSceneName", Kind::scene, edit(s, "  name: two\n", ""), {"s.yaml:", "scene", "missing required key 'name'"}},
      {"MissingBodyMass", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b,"), {"s.yaml:8:", "scene.bodies[1]", "missing required key 'mass'"}},
      {"MissingJointChild", Kind::scene, edit(s, "parent: ground, child: a,", "parent: ground,"), {"s.yaml:10:", "scene.joints[0]", "missing required key 'child'"}},
      {"MissingRevoluteAxis", Kind::scene, edit(s, "child: a, axis: [0, 0, 1]}", "child: a}"), {"s.yaml:10:", "scene.joints[0]", "missing required key 'axis'"}},
      {"MissingInertia", Kind::scene, edit(s, "{name: b, mass: m, inertia: {xx: 1, yy: 1, zz: 1}}", "{name: b, mass: m}"), {"s.yaml:8:", "scene.bodies[1]", "missing required key 'inertia'"}},
      {"UnknownParentBody", Kind::scene, edit(s, "parent: a,", "parent: aa,"), {"s.yaml:11:", "scene.joints[1].parent", "'aa' is not a body", "did you mean 'a'"}},
      {"UnknownChildBody", Kind::scene, edit(s, "child: b,", "child: c,"), {"s.yaml:11:", "scene.joints[1].child", "'c' is not a body"}},
      {"UnknownParameterInMass", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b, mass: mm,"), {"s.yaml:8:", "scene.bodies[1].mass", "unknown name 'mm'", "did you mean 'm'"}},
      {"UnknownJointType", Kind::scene, edit(s, "type: revolute, parent: a", "type: revolut, parent: a"), {"s.yaml:11:", "scene.joints[1].type", "did you mean 'revolute'"}},
      {"UnknownForceBody", Kind::scene, s + "  forces:\n    - {type: force, body: z, vector: [1, 0, 0]}\n", {"s.yaml:13:", "scene.forces[0].body", "'z' is not a body"}},
      {"UnknownForceType", Kind::scene, s + "  forces:\n    - {type: push, body: a, vector: [1, 0, 0]}\n", {"s.yaml:13:", "scene.forces[0].type", "unknown force type"}},
      {"DuplicateBodyName", Kind::scene, edit(s, "{name: b, mass", "{name: a, mass"), {"s.yaml:8:", "scene.bodies[1].name", "duplicate body name 'a'"}},
      {"DuplicateJointName", Kind::scene, edit(s, "{name: j2,", "{name: j1,"), {"s.yaml:11:", "scene.joints[1].name", "duplicate joint name 'j1'"}},
      {"DuplicateParameterKey", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, m: 2}"), {"s.yaml:5:", "scene.parameters.m", "duplicate parameter 'm'"}},
      {"DuplicateYamlKeyInBody", Kind::scene, edit(s, "{name: a, mass: m,", "{name: a, mass: m, mass: 2,"), {"s.yaml:7:", "scene.bodies[0].mass", "given twice"}},
      {"DuplicateForceName", Kind::scene, s + "  forces:\n    - {type: force, name: f, body: a, vector: [1, 0, 0]}\n    - {type: torque, name: f, body: b, vector: [0, 0, 1]}\n", {"s.yaml:14:", "scene.forces[1].name", "duplicate force name 'f'"}},
      {"CycleWithoutGround", Kind::scene, edit(edit(s, "parent: ground, child: a", "parent: b, child: a"), "", ""), {"s.yaml:1", "scene.joints[", "cycle", "constraint"}},
      {"LoopSecondJointToSameChild", Kind::scene, s + "    - {name: j3, type: revolute, parent: ground, child: b, axis: [0, 0, 1]}\n", {"s.yaml:12:", "scene.joints[2].child", "kinematic loop", "constraint"}},
      {"JointToItself", Kind::scene, edit(s, "parent: a, child: b", "parent: b, child: b"), {"s.yaml:11:", "scene.joints[1].child", "to itself"}},
      {"GroundAsChild", Kind::scene, edit(s, "parent: ground, child: a", "parent: a, child: ground"), {"s.yaml:10:", "scene.joints[0].child", "ground cannot be"}},
      {"BodyNotConnected", Kind::scene, edit(s, "    - {name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1], child_point: [0, \"L/2\", 0]}\n", ""), {"s.yaml:8:", "scene.bodies[1]", "not the child of any joint"}},
      {"MassZero", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b, mass: 0,"), {"s.yaml:8:", "scene.bodies[1].mass", "mass must be > 0"}},
      {"MassNegative", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b, mass: -2,"), {"s.yaml:8:", "scene.bodies[1].mass", "mass must be > 0"}},
      {"MassZeroFromParameters", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b, mass: \"m - 1\","), {"s.yaml:8:", "scene.bodies[1].mass", "mass must be > 0"}},
      {"InertiaNotPsd", Kind::scene, edit(s, "{xx: 1, yy: 1, zz: 1}", "{xx: -1, yy: 1, zz: 1}"), {"s.yaml:8:", "scene.bodies[1].inertia", "not positive semi-definite"}},
      {"InertiaOffDiagonalNotPsd", Kind::scene, edit(s, "{xx: 1, yy: 1, zz: 1}", "{xx: 1, yy: 1, zz: 1, xy: 2}"), {"s.yaml:8:", "scene.bodies[1].inertia", "not positive semi-definite"}},
      {"InertiaTriangleInequality", Kind::scene, edit(s, "{xx: 1, yy: 1, zz: 1}", "{xx: 1, yy: 1, zz: 3}"), {"s.yaml:8:", "scene.bodies[1].inertia", "triangle inequality"}},
      {"NanMassYaml", Kind::scene, edit(s, "{name: b, mass: m,", "{name: b, mass: .nan,"), {"s.yaml:8:", "scene.bodies[1].mass", "finite"}},
      {"InfGravityYaml", Kind::scene, edit(s, "[0, -9.81, 0]", "[0, -.inf, 0]"), {"s.yaml:4:", "scene.gravity[1]", "finite"}},
      {"NanParameterWord", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: nan, L: 1}"), {"s.yaml:5:", "scene.parameters.m", "unknown name 'nan'"}},
      {"NumberOverflowInAxis", Kind::scene, edit(s, "child: a, axis: [0, 0, 1]", "child: a, axis: [0, 0, 1e400]"), {"s.yaml:10:", "scene.joints[0].axis[2]", "out of range"}},
      {"NumberOverflowInParameter", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1e999, L: 1}"), {"s.yaml:5:", "scene.parameters.m", "out of range"}},
      {"OverflowAtEvaluation", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, big: \"exp(1000*L)\"}"), {"s.yaml:5:", "scene.parameters.big", "not finite"}},
      {"ZeroLengthAxis", Kind::scene, edit(s, "child: a, axis: [0, 0, 1]", "child: a, axis: [0, 0, 0]"), {"s.yaml:10:", "scene.joints[0].axis", "zero length"}},
      {"ZeroLengthAxisFromParameters", Kind::scene, edit(s, "child: a, axis: [0, 0, 1]", "child: a, axis: [0, 0, \"L - 1\"]"), {"s.yaml:10:", "scene.joints[0].axis", "zero length"}},
      {"DivisionByZeroAtEvaluation", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, k: \"1/(L-1)\"}"), {"s.yaml:5:", "scene.parameters.k", "not finite", "division by zero"}},
      {"DivisionByZeroInBodyExpression", Kind::scene, edit(s, "{xx: 1, yy: 1, zz: 1}", "{xx: \"1/(L-1)\", yy: 1, zz: 1}"), {"s.yaml:8:", "scene.bodies[1].inertia.xx", "not finite"}},
      {"LogOfZeroInParameter", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, k: \"log(L-1)\"}"), {"s.yaml:5:", "scene.parameters.k", "not finite"}},
      {"SqrtOfNegativeInParameter", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, k: \"sqrt(L-2)\"}"), {"s.yaml:5:", "scene.parameters.k", "not finite"}},
      {"ExpressionSyntaxError", Kind::scene, edit(s, "\"L/2\"", "\"L/(2\""), {"s.yaml:11:", "scene.joints[1].child_point[1]", "missing ')'"}},
      {"ExpressionUnknownFunction", Kind::scene, edit(s, "\"L/2\"", "\"sine(L)\""), {"s.yaml:11:", "scene.joints[1].child_point[1]", "unknown function 'sine'", "did you mean 'sin'"}},
      {"ExpressionConstantDivisionByZero", Kind::scene, edit(s, "\"L/2\"", "\"L/(2-2)\""), {"s.yaml:11:", "scene.joints[1].child_point[1]", "division by zero"}},
      {"ParameterNameReserved", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: 1, L: 1, t: 2}"), {"s.yaml:5:", "scene.parameters.t", "cannot be a parameter name"}},
      {"ParameterUsesLaterParameter", Kind::scene, edit(s, "{m: 1, L: 1}", "{m: \"2*L\", L: 1}"), {"s.yaml:5:", "scene.parameters.m", "unknown name 'L'"}},
      {"WrongNumberOfInitialValues", Kind::scene, edit(s, "child: a, axis: [0, 0, 1]}", "child: a, axis: [0, 0, 1], q0: [1, 2]}"), {"s.yaml:10:", "scene.joints[0].q0", "1 coordinate, found 2"}},
      {"SpringOnSphericalJoint", Kind::scene, edit(s, "type: revolute, parent: a, child: b, axis: [0, 0, 1],", "type: spherical, parent: a, child: b, spring: {k: 1},"), {"s.yaml:11:", "scene.joints[1].spring", "1-DOF"}},
      {"AxisOnSphericalJoint", Kind::scene, edit(s, "type: revolute, parent: a", "type: spherical, parent: a"), {"s.yaml:11:", "scene.joints[1].axis", "takes no axis"}},
      {"ConstraintMissingBody", Kind::scene, s + "  constraints:\n    - {name: c, type: coincident}\n", {"s.yaml:13:", "scene.constraints[0]", "missing required key 'body_a'"}},
      {"ConstraintUnknownType", Kind::scene, s + "  constraints:\n    - {name: c, type: welded}\n", {"s.yaml:13:", "scene.constraints[0].type", "unknown constraint type 'welded'"}},
      {"ConstraintUnknownBody", Kind::scene, s + "  constraints:\n    - {name: c, type: coincident, body_a: aa, body_b: ground}\n", {"s.yaml:13:", "scene.constraints[0].body_a", "'aa' is not a body"}},
      {"ConstraintUnknownSpeed", Kind::scene, s + "  constraints:\n    - {name: c, type: general, a: {j9.u: 1}}\n", {"s.yaml:13:", "scene.constraints[0].a.j9.u", "not a speed"}},
      {"NoBodies", Kind::scene, "kanesens: 1\nscene: {name: x, bodies: [], joints: []}\n", {"s.yaml", "scene.bodies", "at least one body"}},
      {"InvalidBodyName", Kind::scene, edit(s, "{name: b, mass", "{name: \"b c\", mass"), {"s.yaml:8:", "scene.bodies[1].name", "not a valid name"}},
      // Classic parser crashers (fuzzing seeds): deep nesting must not exhaust the stack, an
      // alias that refers to its own anchor must not recurse forever.
      {"DeepYamlNesting", Kind::scene, "kanesens: 1\nscene: " + std::string(20000, '[') + std::string(20000, ']') + "\n", {"s.yaml:", "malformed YAML"}},
      {"YamlAliasToItself", Kind::scene, "kanesens: 1\nscene: &a {name: x, bodies: [*a], joints: []}\n", {"s.yaml:2:", "scene.bodies[0]", "unknown key"}},
      {"NonScalarMapKey", Kind::scene, edit(s, "{m: 1, L: 1}", "{[a]: 1, L: 1}"), {"s.yaml:5:", "scene.parameters", "expected a parameter name"}},
      // Input is UTF-8 text: names end up in JSON, HDF5 strings and messages.
      {"InvalidUtf8InName", Kind::scene, edit(s, "name: two", "name: \"tw\xC3\x28\""), {"s.yaml:3:12", "invalid UTF-8 (byte 0xC3)"}},
      {"OverlongUtf8", Kind::scene, edit(s, "name: two", "name: \"t\xC0\xAFo\""), {"s.yaml:3:", "invalid UTF-8 (byte 0xC0)"}},
      {"Utf8Surrogate", Kind::scene, edit(s, "name: two", "name: \"t\xED\xA0\x80o\""), {"s.yaml:3:", "invalid UTF-8 (byte 0xED)"}},
      {"TruncatedUtf8AtEnd", Kind::scene, s + "# \xE2\x82", {"invalid UTF-8 (byte 0xE2)"}},
      {"ControlCharacter", Kind::scene, edit(s, "name: two", "name: \"t\x01o\""), {"s.yaml:3:", "control character 0x01"}},
      {"NulCharacter", Kind::scene, edit(s, "name: two", std::string("name: \"t\0o\"", 12)), {"s.yaml:3:", "control character 0x00"}},
      // An unknown name of 250 000 characters: the did-you-mean search stays linear and the
      // message stays one readable line.
      {"HugeUnknownName", Kind::scene, edit(s, "parent: a,", "parent: " + std::string(250000, 'a') + ","), {"s.yaml:11:", "scene.joints[1].parent", "bytes ...]"}},
  };
}

// Study rows (the scene is inline, see kStudy).
std::vector<Case> study_cases() {
  const std::string s = kStudy;
  return {
      {"StudyMalformedYaml", Kind::study, edit(s, "seed: 1}", "seed: 1"), {"StudyMalformedYaml.yaml:", "malformed YAML"}},
      {"StudyUnknownTopKeyDidYouMean", Kind::study, edit(s, "sampling:", "smapling:"), {"StudyUnknownTopKeyDidYouMean.yaml:11:1", "smapling", "did you mean 'sampling'"}},
      {"StudyMissingTime", Kind::study, edit(s, "time: {end: 1, outputs: 11}\n", ""), {"StudyMissingTime.yaml:1:1", "missing required key 'time'"}},
      {"StudyTimeEndBeforeStart", Kind::study, edit(s, "{end: 1,", "{start: 2, end: 1,"), {"StudyTimeEndBeforeStart.yaml:10:", "time.end", "greater than time.start"}},
      {"StudyTimeEndNan", Kind::study, edit(s, "{end: 1,", "{end: .nan,"), {"StudyTimeEndNan.yaml:10:", "time.end", "finite"}},
      {"StudyTimeEndHuge", Kind::study, edit(s, "{end: 1,", "{end: 1e400,"), {"StudyTimeEndHuge.yaml:10:", "time.end"}},
      {"StudyOutputsOne", Kind::study, edit(s, "outputs: 11", "outputs: 1"), {"StudyOutputsOne.yaml:10:", "time.outputs", "whole number"}},
      {"StudyTimesWithStart", Kind::study, edit(s, "{end: 1, outputs: 11}", "{start: 0, times: [1, 2]}"), {"StudyTimesWithStart.yaml:10:", "time", "not both"}},
      {"StudyNegativeMaxOrder", Kind::study, s + "solver: {max_order: -1}\n", {"StudyNegativeMaxOrder.yaml:15:", "solver.max_order", "from 0 to 12"}},
      {"StudyTimesNotIncreasing", Kind::study, edit(s, "{end: 1, outputs: 11}", "{times: [0, 1, 1]}"), {"StudyTimesNotIncreasing.yaml:10:", "time.times[2]", "strictly increasing"}},
      {"StudyNegativeRtol", Kind::study, s + "solver: {rtol: -1}\n", {"StudyNegativeRtol.yaml:15:", "solver", "rtol"}},
      {"StudyRtolWrongType", Kind::study, s + "solver: {rtol: tight}\n", {"StudyRtolWrongType.yaml:15:", "solver.rtol", "expected a number"}},
      {"StudyUnknownSolverMethod", Kind::study, s + "solver: {method: rk4}\n", {"StudyUnknownSolverMethod.yaml:15:", "solver.method", "expected one of bdf, adams"}},
      {"StudyEventUnknownName", Kind::study, s + "events:\n  - {name: fall, when: \"hinge.qq - 1\"}\n", {"StudyEventUnknownName.yaml:16:", "events.fall.when", "unknown name 'hinge.qq'"}},
      {"StudyEventBadDirection", Kind::study, s + "events:\n  - {name: fall, when: hinge.q, direction: up}\n", {"StudyEventBadDirection.yaml:16:", "events.fall.direction", "rising, falling, both"}},
      {"StudyEventBadAction", Kind::study, s + "events:\n  - {name: fall, when: hinge.q, action: halt}\n", {"StudyEventBadAction.yaml:16:", "events.fall.action", "record, stop"}},
      {"StudyEventNoWhen", Kind::study, s + "events:\n  - {name: fall}\n", {"StudyEventNoWhen.yaml:16:", "events.fall", "when"}},
      {"StudyEventNotOfTime", Kind::study, s + "events:\n  - {name: fall, when: \"L - 1\"}\n", {"StudyEventNotOfTime.yaml:16:", "events.fall.when", "does not change with time"}},
      {"StudyEventTwice", Kind::study, s + "events:\n  - {name: fall, when: hinge.q}\n  - {name: fall, when: hinge.u}\n", {"StudyEventTwice.yaml:17:", "events[1].name", "defined twice"}},
      {"StudyEventMaxCount", Kind::study, s + "events:\n  - {name: fall, when: hinge.q, max_count: 0}\n", {"StudyEventMaxCount.yaml:16:", "events.fall.max_count", ">= 1"}},
      {"StudyEventMaxCountLarge", Kind::study, s + "events:\n  - {name: fall, when: hinge.q, max_count: 200000}\n", {"StudyEventMaxCountLarge.yaml:16:", "events.fall.max_count", "at most 100000"}},
      {"StudyUnknownLinearSolver", Kind::study, s + "solver: {linear_solver: gmres}\n", {"StudyUnknownLinearSolver.yaml:15:", "solver.linear_solver", "expected one of dense, krylov, auto"}},
      {"StudyKrylovWithDop853", Kind::study, s + "solver: {method: dop853, linear_solver: krylov}\n", {"StudyKrylovWithDop853.yaml:15:", "solver.linear_solver", "without Newton iteration", "got krylov"}},
      {"StudyDenseWithFunctional", Kind::study, s + "solver: {method: adams, iteration: functional, linear_solver: dense}\n", {"StudyDenseWithFunctional.yaml:15:", "solver.linear_solver", "iteration: functional"}},
      {"StudyDop853MaxOrder", Kind::study, s + "solver: {method: dop853, max_order: 5}\n", {"StudyDop853MaxOrder.yaml:15:", "solver.max_order", "dop853"}},
      {"StudyAdamsProjection", Kind::study, s + "solver: {method: adams, constraints: {stabilization: projection}}\n", {"StudyAdamsProjection.yaml:15:", "solver", "projection needs method: bdf or dop853"}},
      {"StudyUniformLowNotBelowHigh", Kind::study, edit(s, "low: 0.5, high: 1.5", "low: 1.5, high: 0.5"), {"StudyUniformLowNotBelowHigh.yaml:13:", "vary.m.high", "expected low < high"}},
      {"StudyUniformLowEqualsHigh", Kind::study, edit(s, "low: 0.5, high: 1.5", "low: 1, high: 1"), {"StudyUniformLowEqualsHigh.yaml:13:", "vary.m.high", "expected low < high"}},
      {"StudyNormalStdZero", Kind::study, edit(s, "{dist: uniform, low: 0.5, high: 1.5}", "{dist: normal, mean: 1, std: 0}"), {"StudyNormalStdZero.yaml:13:", "vary.m.std", "std > 0"}},
      {"StudyNormalStdNegative", Kind::study, edit(s, "{dist: uniform, low: 0.5, high: 1.5}", "{dist: normal, mean: 1, std: -0.1}"), {"StudyNormalStdNegative.yaml:13:", "vary.m.std", "std > 0"}},
      {"StudyLognormalSigmaZero", Kind::study, edit(s, "{dist: uniform, low: 0.5, high: 1.5}", "{dist: lognormal, mu: 0, sigma: 0}"), {"StudyLognormalSigmaZero.yaml:13:", "vary.m.sigma", "sigma > 0"}},
      {"StudyTriangularModeOutside", Kind::study, edit(s, "{dist: uniform, low: 0.5, high: 1.5}", "{dist: triangular, low: 0.5, mode: 2, high: 1.5}"), {"StudyTriangularModeOutside.yaml:13:", "vary.m.high", "mode <= high"}},
      {"StudyTruncnormalEmpty", Kind::study, edit(s, "{dist: uniform, low: 0.5, high: 1.5}", "{dist: truncnormal, mean: 0, std: 0.001, low: 50, high: 60}"), {"StudyTruncnormalEmpty.yaml:13:", "vary.m.low", "probability"}},
      {"StudyDistributionNan", Kind::study, edit(s, "high: 1.5", "high: .nan"), {"StudyDistributionNan.yaml:13:", "vary.m.high", "finite"}},
      {"StudyDistributionInf", Kind::study, edit(s, "high: 1.5", "high: .inf"), {"StudyDistributionInf.yaml:13:", "vary.m.high", "finite"}},
      {"StudyDistributionOverflow", Kind::study, edit(s, "high: 1.5", "high: 1e400"), {"StudyDistributionOverflow.yaml:13:", "vary.m.high", "finite"}},
      {"StudyUnknownDistribution", Kind::study, edit(s, "dist: uniform", "dist: unifrom"), {"StudyUnknownDistribution.yaml:13:", "vary.m.dist", "did you mean 'uniform'"}},
      {"StudyDistributionMissingKey", Kind::study, edit(s, ", high: 1.5", ""), {"StudyDistributionMissingKey.yaml:13:", "vary.m", "missing key 'high'"}},
      {"StudyDistributionUnknownKey", Kind::study, edit(s, "low: 0.5", "lwo: 0.5"), {"StudyDistributionUnknownKey.yaml:13:", "vary.m.lwo", "did you mean 'low'"}},
      {"StudyVaryUnknownInput", Kind::study, edit(s, "  m: {dist", "  mm: {dist"), {"StudyVaryUnknownInput.yaml:13:3", "vary.mm", "neither a parameter nor an initial condition"}},
      {"StudyVaryTwice", Kind::study, edit(s, "sensitivities: [m]", "  m: {dist: fixed, value: 1}\nsensitivities: [m]"), {"StudyVaryTwice.yaml:14:", "vary.m", "varied twice"}},
      {"StudySensitivityUnknown", Kind::study, edit(s, "sensitivities: [m]", "sensitivities: [m, Lx]"), {"StudySensitivityUnknown.yaml:14:20", "sensitivities[1]", "'Lx' is neither"}},
      {"StudySamplesZero", Kind::study, edit(s, "samples: 4", "samples: 0"), {"StudySamplesZero.yaml:11:", "sampling.samples", "expected an integer in [1,"}},
      {"StudySamplesNegative", Kind::study, edit(s, "samples: 4", "samples: -5"), {"StudySamplesNegative.yaml:11:", "sampling.samples", "expected an integer in [1,"}},
      {"StudySamplesHuge", Kind::study, edit(s, "samples: 4", "samples: 1e12"), {"StudySamplesHuge.yaml:11:", "sampling.samples", "likely typo"}},
      {"StudySamplesNotInteger", Kind::study, edit(s, "samples: 4", "samples: 2.5"), {"StudySamplesNotInteger.yaml:11:", "sampling.samples", "expected an integer"}},
      {"StudySamplesWord", Kind::study, edit(s, "samples: 4", "samples: many"), {"StudySamplesWord.yaml:11:", "sampling.samples", "expected an integer"}},
      {"StudyUnknownSamplingMethod", Kind::study, edit(s, "method: mc", "method: sobel"), {"StudyUnknownSamplingMethod.yaml:11:", "sampling.method", "did you mean 'sobol'"}},
      {"StudySamplingKeyOfOtherMethod", Kind::study, edit(s, "seed: 1}", "seed: 1, trajectories: 3}"), {"StudySamplingKeyOfOtherMethod.yaml:11:", "sampling.trajectories", "does not apply to method mc"}},
      {"StudySeedNegative", Kind::study, edit(s, "seed: 1", "seed: -1"), {"StudySeedNegative.yaml:11:", "sampling.seed", "non-negative integer"}},
      {"StudyRecordUnknown", Kind::study, s + "record: [states, torques]\n", {"StudyRecordUnknown.yaml:15:", "record[1]", "unknown record item"}},
      {"StudyRecordSensitivitiesWithoutList", Kind::study, edit(s, "sensitivities: [m]", "record: [states, sensitivities]"), {"StudyRecordSensitivitiesWithoutList.yaml:14:", "record", "lists no sensitivities"}},
      {"StudySceneFileMissing", Kind::study, "kanesens: 1\nscene: no_such_scene.yaml\ntime: {end: 1}\n", {"StudySceneFileMissing.yaml:2:8", "scene", "cannot open scene file"}},
      {"StudyBadSceneInside", Kind::study, edit(s, "mass: m,", "mass: -m,"), {"StudyBadSceneInside.yaml:7:", "scene.bodies[0].mass", "mass must be > 0"}},
      {"StudySetUnknownParameter", Kind::study, s, {"--set m9", "'m9' is neither a parameter", "did you mean 'm'"}, {"m9=2"}},
      {"StudySetNotAssignment", Kind::study, s, {"--set", "expected NAME=VALUE"}, {"m"}},
      {"StudySetNotNumber", Kind::study, s, {"--set m", "expected a number"}, {"m=heavy"}},
      {"StudySetSettingWithoutSection", Kind::study, s, {"--set sensitivity.error_control", "expected a number", "under time, solver or sampling", "solver.sensitivity.error_control=false"}, {"sensitivity.error_control=false"}},
      {"StudySetNan", Kind::study, s, {"--set m", "finite"}, {"m=nan"}},
      {"StudySetZeroMass", Kind::study, s, {"mass must be > 0"}, {"m=0"}},
      {"StudySetBadSetting", Kind::study, s, {"sampling.samples", "expected an integer in [1,"}, {"sampling.samples=0"}},
      // Found too late before: while integrating, in every sample, after the file existed.
      {"StudyAtolListShort", Kind::study, s + "solver: {atol: [1e-8]}\n", {"StudyAtolListShort.yaml:15:16", "solver.atol", "one entry per state (2: hinge.q, hinge.u), found 1"}},
      {"StudySensitivityTwice", Kind::study, edit(s, "sensitivities: [m]", "sensitivities: [m, L, m]"), {"StudySensitivityTwice.yaml:14:23", "sensitivities[2]", "'m' is listed twice"}},
      {"StudyOutputTimesOverflow", Kind::study, edit(s, "{end: 1, outputs: 11}", "{start: -1e308, end: 1e308, outputs: 11}"), {"StudyOutputTimesOverflow.yaml:10:", "time", "not finite in double precision"}},
      {"StudyOutputTimesRepeated", Kind::study, edit(s, "{end: 1, outputs: 11}", "{start: 1e16, end: 1.000000000000002e16, outputs: 101}"), {"StudyOutputTimesRepeated.yaml:10:", "time", "not distinct in double precision"}},
      {"StudyTimesNan", Kind::study, edit(s, "{end: 1, outputs: 11}", "{times: [0, nan, 1]}"), {"StudyTimesNan.yaml:10:", "time.times[1]"}},
      {"StudyAdamsOnConstrainedSceneByDefault", Kind::study, edit(s, "q0: 0.3}", "q0: 0.3}\n  constraints:\n    - {name: g, type: general, position: \"hinge.q - 0.3\"}") + "solver: {method: adams}\n", {"StudyAdamsOnConstrainedSceneByDefault.yaml:17:18", "solver.method", "default stabilization is projection", "baumgarte"}},
      {"StudyDegenerateConstraint", Kind::study, edit(s, "q0: 0.3}", "q0: 0}\n  constraints:\n    - {name: g, type: general, position: \"hinge.q^2\"}"), {"StudyDegenerateConstraint.yaml:11:7", "scene.constraints[0]", "constraint 'g' constrains nothing at the initial state"}},
      {"StudyMassMatrixSingularAtT0", Kind::study, edit(s, "{shape: rod, length: L, axis: y}}", "{shape: point}}"), {"StudyMassMatrixSingularAtT0.yaml:3:3", "mass matrix is not positive definite"}},
      {"StudyMaxOrderOverflow", Kind::study, s + "solver: {max_order: 4294967297}\n", {"StudyMaxOrderOverflow.yaml:15:", "solver.max_order", "from 0 to 12"}},
  };
}

std::vector<Case> expr_cases() {
  return {
      {"ExprEmpty", Kind::expr, " ", {"e.yaml:3:5", "scene.x", "empty expression"}},
      {"ExprTrailingOperator", Kind::expr, "L+", {"e.yaml:3:5", "scene.x", "ends early"}},
      {"ExprUnbalancedParen", Kind::expr, "(L+1", {"scene.x", "missing ')'"}},
      {"ExprStrayParen", Kind::expr, "L+1)", {"scene.x", "unexpected ')'"}},
      {"ExprUnknownName", Kind::expr, "Lx*2", {"scene.x", "unknown name 'Lx'", "did you mean 'L'"}},
      {"ExprUnknownFunction", Kind::expr, "sinh(L)", {"scene.x", "unknown function 'sinh'"}},
      {"ExprWrongArity", Kind::expr, "atan2(L)", {"scene.x", "takes 2 arguments"}},
      {"ExprBadCharacter", Kind::expr, "L # 2", {"scene.x", "unexpected '#'"}},
      {"ExprNumberOverflow", Kind::expr, "1e400*L", {"scene.x", "out of range"}},
      {"ExprConstantDivisionByZero", Kind::expr, "L + 1/0", {"scene.x", "division by zero"}},
      {"ExprConstantLogZero", Kind::expr, "L*log(0)", {"scene.x", "not finite"}},
      {"ExprConstantOverflow", Kind::expr, "L*10^400", {"scene.x", "not finite"}},
      {"ExprNestedTooDeep", Kind::expr, std::string(200, '(') + "L" + std::string(200, ')'), {"scene.x", "nested too deeply"}},
      {"ExprUnaryChainTooDeep", Kind::expr, std::string(500, '-') + "L", {"scene.x", "nested too deeply"}},
      {"ExprStackTooDeep", Kind::expr, [] { std::string e = "L"; for (int i = 0; i < 40; ++i) e = "L*(L+" + e + ")"; return e; }(), {"scene.x", "nested too deeply"}},
  };
}

std::vector<Case> all_cases() {
  std::vector<Case> all = scene_cases();
  for (auto& c : study_cases()) all.push_back(std::move(c));
  for (auto& c : expr_cases()) all.push_back(std::move(c));
  return all;
}

// gtest prints the case's name instead of its bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(BadInput, OneClearInputError) {
  const Case& c = GetParam();
  const std::string e = error_of(c);
  EXPECT_EQ(e.find('\n'), std::string::npos) << "not one line: " << e;
  EXPECT_NE(e.rfind("(", 0), 0u) << e;  // "(no error)", "(wrong exception type...)"
  for (const auto& want : c.expect) EXPECT_NE(e.find(want), std::string::npos) << "expected '" << want << "' in: " << e;
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(BadInputTable, Count) {
  // The number of distinct bad inputs covered above (reported in the reliability notes).
  const auto n = all_cases().size();
  std::printf("bad inputs tested: %zu\n", n);
  EXPECT_GE(n, 100u);
}

// A SceneSpec is also built by code (not only parsed): components must be valid indices, at
// most three and distinct, or they would write past the 3-element array of a Constraint.
TEST(BadInputTable, ComponentsFromCodeAreCheckedAtBuild) {
  SceneSpec spec = parse_scene_text(with_constraint("{name: pin, type: coincident, body_a: b, body_b: ground}"), "s.yaml");
  for (const auto& [components, says] : std::vector<std::pair<std::vector<int>, std::string>>{
           {{0, 1, 2, 0}, "at most 3 components"}, {{0, 7}, "expected x, y or z"}, {{1, 1}, "'y' is given twice"}}) {
    spec.constraints[0].components = components;
    try {
      build_model(spec);
      ADD_FAILURE() << "accepted components " << says;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

TEST(BadInputTable, GoodTextsAreGood) {
  EXPECT_NO_THROW(build_model(parse_scene_text(kScene, "s.yaml")));
  // Redundant rows are not degenerate ones: the z row of a pin in a planar scene vanishes, x and
  // y do not (tests/regression/test_constraints_pendulum.cpp integrates it).
  {
    const Model m = build_model(parse_scene_text(with_constraint("{name: pin, type: coincident, body_a: b, body_b: ground, point_b: [0, -0.5, 0], components: [x, y, z]}"), "s.yaml"));
    EXPECT_NO_THROW(KaneProblem(m, {}).validate_initial_state());
  }
  // Huge but finite quaternion components are normalised, and a free joint's translation is a
  // coordinate a position function may use.
  {
    const Model m = build_model(parse_scene_text(edit(kBall, "child_point: [0, 1, 0]}", "child_point: [0, 1, 0], q0: [1e200, 1e200, 0, 0]}"), "s.yaml"));
    EXPECT_NO_THROW(KaneProblem(m, {}).validate_initial_state());
    const std::string free = edit(edit(kBall, "type: spherical", "type: free"), "child_point: [0, 1, 0]}", "q0: [0, 1, 0, 1, 0, 0, 0]}") +
                             "  constraints:\n    - {name: g, type: general, position: \"j.x^2 + j.y^2 - 1\"}\n";
    const Model mf = build_model(parse_scene_text(free, "s.yaml"));
    EXPECT_NO_THROW(KaneProblem(mf, {}).validate_initial_state());
  }
  const auto path = temp_dir() / "good.yaml";
  std::ofstream(path) << kStudy;
  EXPECT_NO_THROW(parallel::validate_study(path.string(), {}));
  // max_order 0 is CVODES's own default (docs/reference/study.md, solver), as a value too.
  std::ofstream(path) << kStudy + "solver: {method: adams, max_order: 0}\n";
  EXPECT_NO_THROW(parallel::validate_study(path.string(), {}));
  parallel::RunOptions bdf;
  bdf.set = {"solver.max_order=0", "solver.method=bdf"};
  EXPECT_NO_THROW(parallel::validate_study(path.string(), bdf));
}

}  // namespace KANESENS_UNITY_ID
