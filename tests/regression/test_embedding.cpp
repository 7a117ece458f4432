// The two constraint formulations (multipliers and embedding) must agree: states, state
// sensitivities, multipliers and their sensitivities, on a pendulum pinned by a coincident
// constraint and on a crank-rocker four-bar closed by a coincident constraint.
#include <gtest/gtest.h>

#include <cmath>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "model/yaml_reader.hpp"
#include "sim/simulate.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

const char* kFourBar = R"yaml(kanesens: 1
scene:
  name: four_bar
  gravity: [0, -9.81, 0]
  parameters: {a: 0.3, b: 1.0, c: 0.8, d: 1.0, m: 1.0}
  bodies:
    - {name: crank, mass: m, inertia: {shape: rod, length: a, axis: x}}
    - {name: coupler, mass: m, inertia: {shape: rod, length: b, axis: x}}
    - {name: rocker, mass: m, inertia: {shape: rod, length: c, axis: x}}
  joints:
    - {name: j1, type: revolute, parent: ground, child: crank, axis: [0, 0, 1],
       child_point: ["-a/2", 0, 0], q0: 1.2, u0: 2.0}
    - {name: j2, type: revolute, parent: crank, child: coupler, axis: [0, 0, 1],
       parent_point: ["a/2", 0, 0], child_point: ["-b/2", 0, 0], q0: -0.9}
    - {name: j3, type: revolute, parent: ground, child: rocker, axis: [0, 0, 1],
       parent_point: [d, 0, 0], child_point: ["-c/2", 0, 0], q0: 1.9}
  constraints:
    - {name: loop, type: coincident, body_a: coupler, point_a: ["b/2", 0, 0], body_b: rocker, point_b: ["c/2", 0, 0]}
)yaml";

struct Run {
  Trajectory traj;
  int n = 0, ns = 0, m = 0;
};

Run run(const std::string& text, ConstraintOptions::Formulation f, const std::vector<std::string>& sens) {
  const Model model = build_model(parse_scene_text(text, "inline.yaml"));
  std::vector<InputRef> refs;
  for (const auto& s : sens) refs.push_back(resolve_input(model, s, "test"));
  ConstraintOptions co;
  co.formulation = f;
  co.stabilization = ConstraintOptions::Stabilization::projection;
  KaneProblem problem(model, refs, co);
  problem.set_sample(SampleInputs(model));
  sim::SolverOptions so;
  so.rtol = 1e-11;
  so.atol = 1e-12;
  sim::Integrator integ(so);
  std::vector<double> times;
  for (int k = 0; k <= 40; ++k) times.push_back(0.05 * k);
  RecordFlags flags;
  flags.multipliers = true;
  flags.constraint_residual = true;
  Run r;
  simulate(problem, integ, times, flags, r.traj);
  EXPECT_EQ(r.traj.result.status, 1) << r.traj.result.message;
  r.n = model.nstate();
  r.ns = static_cast<int>(refs.size());
  r.m = model.nconstraint_rows;
  return r;
}

double max_rel(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double scale = 1e-3, d = 0;
  for (double x : a) scale = std::max(scale, std::abs(x));
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d / scale;
}

void compare(const std::string& text, const std::vector<std::string>& sens) {
  const Run a = run(text, ConstraintOptions::Formulation::multipliers, sens);
  const Run b = run(text, ConstraintOptions::Formulation::embedding, sens);
  const double ds = max_rel(a.traj.states, b.traj.states);
  const double dsens = max_rel(a.traj.sensitivities, b.traj.sensitivities);
  const double dl = max_rel(a.traj.multipliers, b.traj.multipliers);
  const double dls = max_rel(a.traj.multiplier_sensitivities, b.traj.multiplier_sensitivities);
  std::printf("measure: states %.2e sensitivities %.2e multipliers %.2e multiplier sensitivities %.2e; steps %ld vs %ld\n",
              ds, dsens, dl, dls, a.traj.result.stats.steps, b.traj.result.stats.steps);
  EXPECT_LT(ds, 1e-7);
  EXPECT_LT(dsens, 1e-6);
  EXPECT_LT(dl, 1e-6);
  EXPECT_LT(dls, 1e-5);
  for (double r : b.traj.position_residual) EXPECT_LT(r, 1e-9);
  for (double r : b.traj.velocity_residual) EXPECT_LT(r, 1e-9);
}

}  // namespace

TEST(Embedding, AgreesWithMultipliersOnPinnedPendulum) {
  compare(model::read_text_file(std::string(KANESENS_SOURCE_DIR) + "/configs/constrained_pendulum.yaml"), {"m", "L", "base.q0[2]"});
}

TEST(Embedding, AgreesWithMultipliersOnFourBar) { compare(kFourBar, {"a", "m", "j1.u0"}); }

}  // namespace KANESENS_UNITY_ID
