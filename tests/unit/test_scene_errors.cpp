// Bad scenes give one clear error naming file:line:column and the key.
#include <gtest/gtest.h>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {
const char* kGood = R"(kanesens: 1
scene:
  name: two
  gravity: [0, -9.81, 0]
  parameters: {m: 1, L: 1}
  bodies:
    - {name: a, mass: m, inertia: {shape: rod, length: L, axis: y}}
    - {name: b, mass: m, inertia: {xx: 1, yy: 1, zz: 1}}
  joints:
    - {name: j1, type: revolute, parent: ground, child: a, axis: [0, 0, 1]}
    - {name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1]}
)";

std::string error_of(const std::string& text) {
  try {
    build_model(parse_scene_text(text, "s.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}
void expect_has(const std::string& e, const std::string& what) {
  EXPECT_NE(e.find(what), std::string::npos) << "expected '" << what << "' in: " << e;
}
}  // namespace

TEST(SceneErrors, GoodSceneBuilds) { EXPECT_EQ(error_of(kGood), "(no error)"); }

TEST(SceneErrors, Cycle) {
  const std::string e = error_of(std::string(kGood) + "    - {name: j3, type: revolute, parent: ground, child: b, axis: [0, 0, 1]}\n");
  expect_has(e, "s.yaml:12:");
  expect_has(e, "scene.joints[2].child");
  expect_has(e, "constraint");
}

TEST(SceneErrors, UnknownParent) {
  const std::string e = error_of(replace(kGood, "parent: a,", "parent: aa,"));
  expect_has(e, "s.yaml:11:");
  expect_has(e, "scene.joints[1].parent");
  expect_has(e, "'aa' is not a body");
  expect_has(e, "did you mean 'a'");
}

TEST(SceneErrors, MissingKey) {
  const std::string e = error_of(replace(kGood, "{name: b, mass: m,", "{name: b,"));
  expect_has(e, "s.yaml:8:");
  expect_has(e, "scene.bodies[1]");
  expect_has(e, "missing required key 'mass'");
}

TEST(SceneErrors, UnknownKeyDidYouMean) {
  const std::string e = error_of(replace(kGood, "gravity:", "gravty:"));
  expect_has(e, "s.yaml:4:3: scene.gravty");
  expect_has(e, "did you mean 'gravity'");
}

TEST(SceneErrors, InertiaNotPositiveDefinite) {
  const std::string e = error_of(replace(kGood, "{xx: 1, yy: 1, zz: 1}", "{xx: 1, yy: -1, zz: 1}"));
  expect_has(e, "body 'b'");
  expect_has(e, "positive semi-definite");
}

TEST(SceneErrors, TriangleInequality) {
  expect_has(error_of(replace(kGood, "{xx: 1, yy: 1, zz: 1}", "{xx: 1, yy: 1, zz: 3}")), "triangle inequality");
}

TEST(SceneErrors, MassMustBePositive) {
  expect_has(error_of(replace(kGood, "parameters: {m: 1,", "parameters: {m: 0,")), "mass must be > 0");
}

TEST(SceneErrors, ZeroAxis) {
  expect_has(error_of(replace(kGood, "child: b, axis: [0, 0, 1]", "child: b, axis: [0, 0, 0]")), "axis has zero length");
}

TEST(SceneErrors, ExpressionErrorNamesKey) {
  const std::string e = error_of(replace(kGood, "length: L,", "length: Lx,"));
  expect_has(e, "s.yaml:7:");
  expect_has(e, "scene.bodies[0].inertia.length");
  expect_has(e, "unknown name 'Lx'");
}

TEST(SceneErrors, MalformedYaml) {
  const std::string e = error_of(replace(kGood, "bodies:", "bodies: [\n"));
  expect_has(e, "s.yaml:");
  expect_has(e, "malformed YAML");
}

TEST(SceneErrors, UnknownJointType) {
  expect_has(error_of(replace(kGood, "type: revolute, parent: a", "type: revolut, parent: a")), "did you mean 'revolute'");
}

TEST(SceneErrors, WrongNumberOfInitialValues) {
  expect_has(error_of(replace(kGood, "child: b, axis: [0, 0, 1]}", "child: b, axis: [0, 0, 1], q0: [1, 2]}")),
             "has 1 coordinate, found 2 values");
}

TEST(SceneErrors, DuplicateBody) {
  expect_has(error_of(replace(kGood, "{name: b, mass", "{name: a, mass")), "duplicate body name 'a'");
}

TEST(SceneErrors, SetUnknownParameter) {
  try {
    build_model(parse_scene_text(kGood, "s.yaml"), {{"mm", 2.0}});
    FAIL();
  } catch (const InputError& e) {
    expect_has(e.what(), "no parameter 'mm'");
    expect_has(e.what(), "did you mean 'm'");
  }
}

// A coincident constraint keeps at most the three world components, each once (a repeated one
// used to write past the end of the model's component array).
TEST(SceneErrors, RepeatedConstraintComponent) {
  const std::string e = error_of(std::string(kGood) +
                                 "  constraints:\n    - {type: coincident, body_a: b, body_b: ground, components: [x, y, z, x]}\n");
  expect_has(e, "s.yaml:13:");
  expect_has(e, "scene.constraints[0].components");
  expect_has(e, "component 'x' is given twice");
}

}  // namespace KANESENS_UNITY_ID
