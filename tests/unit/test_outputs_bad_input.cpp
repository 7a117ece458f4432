// Bad `outputs:` sections: each is one InputError line naming file:line:column, the key path
// and what is wrong (the CLI's exit code 2 and untouched output: tests/mpi/test_outputs_cli.sh).
// Rows: unknown body, joint, constraint and force names (with a did-you-mean), unknown names in
// a point or expression, a vector output used without a component (in an expression, or
// reduced), cycles between outputs, `at:` outside the time span, and the shape of the section.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "study/setup.hpp"
#include "../support/layers.hpp"
#include "../support/scratch_dir.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

const std::string kHead = R"(kanesens: 1
scene:
  name: two
  gravity: [0, -9.81, 0]
  parameters: {m: 1, L: 1}
  bodies:
    - {name: rod1, mass: m, inertia: {shape: rod, length: L, axis: y}}
    - {name: rod2, mass: m, inertia: {shape: rod, length: L, axis: y}}
  joints:
    - {name: shoulder, type: revolute, parent: ground, child: rod1, axis: [0, 0, 1], child_point: [0, "L/2", 0]}
    - {name: elbow, type: revolute, parent: rod1, child: rod2, axis: [0, 0, 1], parent_point: [0, "-L/2", 0]}
  forces:
    - {name: s1, type: spring_damper, body_a: ground, body_b: rod2, k: 1, c: 0, rest: 1}
    - {name: push, type: force, body: rod1, vector: [1, 0, 0]}
  constraints:
    - {name: pin, type: distance, body_a: ground, point_a: [1, 0, 0], body_b: rod2, point_b: [0, "-L/2", 0], length: 1.8027756377319946}
time: {end: 2.0, outputs: 5}
outputs:
)";
constexpr int kFirstLine = 19;  // the line of the first output below

struct Case {
  const char* name;
  std::string outputs;             // lines under `outputs:`
  std::vector<std::string> expect;  // substrings of the message
};

std::string error_of(const Case& c) {
  static const ScratchDir dir("kanesens_bad_outputs");
  const auto path = dir.path() / (std::string(c.name) + ".yaml");
  std::ofstream(path) << kHead << c.outputs;
  try {
    setup_study(path.string());
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(wrong exception type: ") + e.what() + ")";
  }
  return "(no error)";
}

std::string at(int line, int column) {
  return ".yaml:" + std::to_string(kFirstLine + line) + ":" + std::to_string(column) + ": ";
}

std::vector<Case> cases() {
  return {
      {"UnknownBody", "  tip: {type: position, body: rod3}\n", {at(0, 31), "outputs.tip.body: unknown body 'rod3' (did you mean 'rod1'?); bodies are: rod1, rod2"}},
      {"Ground", "  tip: {type: velocity, body: ground}\n", {at(0, 31), "outputs.tip.body: 'ground' does not move"}},
      {"UnknownNameInPoint", "  tip: {type: position, body: rod2, point: [0, \"-Lx/2\", 0]}\n", {at(0, 48), "outputs.tip.point[1]: unknown name 'Lx'"}},
      {"StateInPoint", "  tip: {type: position, body: rod2, point: [0, elbow.q, 0]}\n", {"outputs.tip.point[1]: unknown name 'elbow.q'"}},
      {"UnknownJoint", "  l: {type: joint_load, joint: elbw}\n", {at(0, 32), "outputs.l.joint: unknown joint 'elbw' (did you mean 'elbow'?)"}},
      {"UnknownConstraint", "  c: {type: constraint_force, constraint: pn}\n", {at(0, 43), "outputs.c.constraint: unknown constraint 'pn' (did you mean 'pin'?)"}},
      {"UnknownForce", "  f: {type: force_element, force: s2}\n", {at(0, 35), "outputs.f.force: unknown force 's2' (did you mean 's1'?)"}},
      {"ForceNotASpring", "  f: {type: force_element, force: push}\n", {at(0, 35), "'push' is a force; force_element outputs"}},
      {"EigenvaluesAtUnknown", "  modes: {type: eigenvalues, at: end}\n", {at(0, 34), "outputs.modes.at: expected initial"}},
      {"EigenvaluesWithoutAt", "  modes: {type: eigenvalues}\n", {"outputs.modes", "'at'"}},
      {"EigenvaluesCountTooLarge", "  modes: {type: eigenvalues, at: initial, count: 9}\n",
       {"outputs.modes.count: count: 9 but the linearized system has 2 eigenvalues"}},
      {"EigenvaluesCountZero", "  modes: {type: eigenvalues, at: initial, count: 0}\n", {"outputs.modes.count: expected a whole number from 1"}},
      {"EigenvaluesUnknownCoordinate", "  modes: {type: eigenvalues, at: initial, coordinates: [elbw.q]}\n",
       {"outputs.modes.coordinates: unknown name 'elbw.q' (did you mean 'elbow.q'?)"}},
      {"EigenvaluesUnknownKey", "  modes: {type: eigenvalues, at: initial, body: rod1}\n", {"outputs.modes.body: unknown key 'body'"}},
      {"EigenvaluesAsAWhole", "  modes: {type: eigenvalues, at: initial}\n  x: {expression: \"modes + 1\"}\n",
       {"'modes' is a vector output; name one of its components: modes.re0, modes.im0"}},
      {"UnknownType", "  x: {type: positon, body: rod2}\n", {at(0, 13), "outputs.x.type:", "did you mean 'position'"}},
      {"UnknownKey", "  x: {type: energy, body: rod2}\n", {"outputs.x.body: unknown key 'body'"}},
      {"UnknownEnergyKind", "  e: {type: energy, kind: kinetc}\n", {"outputs.e.kind:", "did you mean 'kinetic'"}},
      {"UnknownNameInExpression", "  x: {expression: \"elbow.qq + 1\"}\n", {at(0, 19), "outputs.x.expression: unknown name 'elbow.qq' (did you mean 'elbow.q'?)"}},
      {"VectorInExpression", "  tip: {type: position, body: rod2}\n  r: {expression: \"sqrt(tip^2)\"}\n",
       {at(1, 19), "outputs.r.expression: 'tip' is a vector output; name one of its components: tip.x, tip.y, tip.z"}},
      {"ReduceOfAVector", "  tip: {type: position, body: rod2}\n  r: {of: tip, reduce: integral}\n",
       {at(1, 11), "outputs.r.of: 'tip' is a vector output"}},
      {"AtOfAVector", "  v: {type: angular_velocity, body: rod1}\n  r: {of: v, at: end}\n", {"outputs.r.of: 'v' is a vector output"}},
      {"Cycle", "  a: {expression: \"b + 1\"}\n  b: {expression: \"2*c\"}\n  c: {expression: \"a - t\"}\n",
       {at(0, 3), "outputs.a.expression: outputs depend on each other in a cycle: a -> b -> c -> a"}},
      {"CycleThroughAReduction", "  w: {of: \"w + t\", reduce: integral}\n", {"outputs.w.of: outputs depend on each other in a cycle: w -> w"}},
      {"AtAfterTheEnd", "  r: {of: elbow.q, at: 2.5}\n", {at(0, 24), "outputs.r.at: t = 2.5 is outside the study's time span [0, 2]"}},
      {"AtBeforeTheStart", "  r: {of: elbow.q, at: -0.1}\n", {"outputs.r.at: t = -0.1 is outside"}},
      {"AtNotATime", "  r: {of: elbow.q, at: soon}\n", {"outputs.r.at: expected a time (a number) or end, found 'soon'"}},
      {"AtAndReduce", "  r: {of: elbow.q, at: end, reduce: mean}\n", {"outputs.r: give one of 'at'"}},
      {"OfAlone", "  r: {of: elbow.q}\n", {"outputs.r: 'of' needs 'at'"}},
      {"UnknownReduction", "  r: {of: elbow.q, reduce: median}\n", {"outputs.r.reduce: expected one of integral, mean, rms, max, min, argmax, argmin"}},
      {"AtEventUnknown", "  r: {of: elbow.q, at_event: fall}\n", {"outputs.r.at_event: no event named 'fall' (the study has no events:)"}},
      {"OccurrenceZero", "  r: {of: elbow.q, at_event: fall, occurrence: 0}\n", {"outputs.r.occurrence: expected a whole number >= 1"}},
      {"OccurrenceAlone", "  r: {of: elbow.q, reduce: max, occurrence: 2}\n", {"outputs.r.occurrence: 'occurrence' goes with 'at_event'"}},
      {"AtEventAndReduce", "  r: {of: elbow.q, at_event: e, reduce: max}\n", {"outputs.r: give one of 'at'"}},
      {"OfAConstant", "  r: {of: \"2*m\", reduce: integral}\n", {"outputs.r.of: '2*m' does not change with time"}},
      {"MixesSeriesAndScalars", "  w: {of: elbow.q, reduce: mean}\n  x: {expression: \"elbow.q - w\"}\n",
       {"outputs.x.expression: mixes quantities of time with 'w'"}},
      {"ReservedName", "  energy: {type: energy}\n", {"outputs.energy: 'energy' names a recorded output"}},
      {"NameOfAParameter", "  m: {type: energy}\n", {"outputs.m: 'm' is already a name of the scene"}},
      {"BadName", "  2x: {type: energy}\n", {"outputs.2x: an output name is letters"}},
      {"NotAMap", "  x: 3\n", {"outputs.x: expected a map"}},
      {"NeitherTypeNorExpression", "  x: {body: rod2}\n", {"outputs.x: expected 'type'"}},
      {"Defined twice", "  x: {type: energy}\n  x: {type: energy, kind: kinetic}\n", {"outputs.x: output 'x' is defined twice"}},
  };
}

class BadOutputs : public ::testing::TestWithParam<Case> {};

TEST_P(BadOutputs, OneLineNamingWhereAndWhat) {
  const Case& c = GetParam();
  const std::string msg = error_of(c);
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_NE(msg.find(std::string(c.name) + ".yaml:"), std::string::npos) << msg;
  for (const auto& s : c.expect) EXPECT_NE(msg.find(s), std::string::npos) << "expected '" << s << "' in: " << msg;
}

INSTANTIATE_TEST_SUITE_P(Table, BadOutputs, ::testing::ValuesIn(cases()), [](const auto& info) {
  std::string n = info.param.name;
  std::replace(n.begin(), n.end(), ' ', '_');
  return n;
});

}  // namespace

}  // namespace KANESENS_UNITY_ID
