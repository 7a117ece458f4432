// Helpers of the output tests (tests/regression/test_outputs_*.cpp): run a study given as text
// (written to a temporary file, read by the study setup as `simulate` and `run` read it) and
// look its outputs up by name.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/simulate.hpp"
#include "study/setup.hpp"
#include "layers.hpp"
#include "scratch_dir.hpp"
#include "test_scenes.hpp"

namespace kanesens::testing {

inline std::filesystem::path output_test_dir() {
  static const ScratchDir dir("kanesens_outputs");
  return dir.path();
}

// One study run: the setup (model, plan) and the trajectory of its nominal sample, or of
// `inputs` when given.
struct OutputRun {
  std::unique_ptr<StudySetup> setup;
  std::unique_ptr<KaneProblem> problem;
  Trajectory traj;
  std::size_t T = 0, ns = 0;

  const OutputPlan& plan() const { return *setup->outputs; }
  std::size_t series_index(const std::string& name) const {
    const auto& n = plan().series_names;
    const auto it = std::find(n.begin(), n.end(), name);
    if (it == n.end()) throw std::invalid_argument("no series output " + name);
    return static_cast<std::size_t>(it - n.begin());
  }
  std::size_t scalar_index(const std::string& name) const {
    const auto& n = plan().scalar_names;
    const auto it = std::find(n.begin(), n.end(), name);
    if (it == n.end()) throw std::invalid_argument("no scalar output " + name);
    return static_cast<std::size_t>(it - n.begin());
  }
  double series(const std::string& name, std::size_t k) const { return traj.outputs[series_index(name) * T + k]; }
  double series_sens(const std::string& name, std::size_t k, std::size_t i) const {
    return traj.output_sensitivities[(series_index(name) * T + k) * ns + i];
  }
  double scalar(const std::string& name) const { return traj.scalar_outputs[scalar_index(name)]; }
  double scalar_sens(const std::string& name, std::size_t i) const {
    return traj.scalar_output_sensitivities[scalar_index(name) * ns + i];
  }
  double state(const std::string& name, std::size_t k) const {
    const auto& n = setup->model.state_names;
    const auto r = static_cast<std::size_t>(std::find(n.begin(), n.end(), name) - n.begin());
    if (r == n.size()) throw std::invalid_argument("no state " + name);
    return traj.states[k * n.size() + r];
  }
  double time(std::size_t k) const { return setup->spec.output_times[k]; }
  // The nominal value of sensitivity input i (a parameter, or a component of the consistent
  // initial state), the point finite differences move away from.
  double sensitivity_input(std::size_t i) const {
    const InputRef ref = problem->sensitivities()[i];
    if (ref.kind == InputRef::Kind::parameter) return setup->base.parameters[static_cast<std::size_t>(ref.index)];
    std::vector<double> y0(static_cast<std::size_t>(setup->model.nstate()));
    problem->initial_state(y0.data());
    return y0[static_cast<std::size_t>(ref.index)];
  }
};

// The simple pendulum of the event and extrema tests (a uniform rod of length L = 1.2 hinged at
// its top, released from 0.9 rad; quarter period K(sin(0.45))·√(2L/(3g))) as a study up to its
// sensitivities to L and pivot.q0; the caller appends events:, outputs:, ...
inline std::string pendulum_study_head(const std::string& method, double end = 3.0, int outputs = 31) {
  std::ostringstream end_text;
  end_text.precision(17);
  end_text << end;
  return test_scenes::rod_pendulum_scene("pendulum", "{m: 1.0, L: 1.2}", ", q0: 0.9, u0: 0") +
         "time: {end: " + end_text.str() + ", outputs: " + std::to_string(outputs) + "}\n"
         "solver: {method: " + method + ", rtol: 1.0e-10, atol: 1.0e-12}\n"
         "sensitivities: [L, pivot.q0]\n";
}

// Writes `text` to <tmp>/<file> and runs its nominal sample (with `set` as --set), or sample
// `inputs` edited by `edit` (for finite differences: one input moved).
inline OutputRun run_output_study(const std::string& text, const std::string& file,
                                  const std::vector<std::string>& set = {},
                                  const std::function<void(const Model&, SampleInputs&)>& edit = {},
                                  bool force_general_3d = false) {
  const auto path = output_test_dir() / file;
  std::ofstream(path) << text;
  OutputRun run;
  run.setup = std::make_unique<StudySetup>(setup_study(path.string(), set));
  StudySetup& s = *run.setup;
  s.model.force_general_3d = force_general_3d;
  run.problem = std::make_unique<KaneProblem>(s.model, s.recorded_sensitivities(), s.spec.constraints,
                                              s.spec.output_times.front());
  SampleInputs in = s.base;
  if (edit) edit(s.model, in);
  run.problem->set_sample(in);
  Integrator integ(s.spec.solver);
  simulate(*run.problem, integ, s.spec.output_times, s.record, run.traj);
  if (!run.traj.result.ok()) throw std::runtime_error("integration failed: " + run.traj.result.message);
  run.T = s.spec.output_times.size();
  run.ns = static_cast<std::size_t>(run.problem->num_sensitivities());
  return run;
}

// Central differences (fourth order) of full re-runs of `text` moving sensitivity input i, for the
// scalar outputs `names`, against the run's exact sensitivities. `fd_set`: overrides for the
// re-runs only (tighter tolerances where their integration error, divided by h, would reach tol).
inline void expect_scalar_sensitivities_match_differences(const std::string& text, const std::string& file,
                                                          const std::vector<std::string>& names, double h_rel,
                                                          double tol, const std::vector<std::string>& fd_set = {}) {
  const OutputRun base = run_output_study(text, file);
  const auto& sens = base.problem->sensitivities();
  for (std::size_t i = 0; i < sens.size(); ++i) {
    const InputRef ref = sens[i];
    const double x = base.sensitivity_input(i), h = h_rel * std::max(1.0, std::abs(x));
    std::vector<OutputRun> runs;
    for (double dx : {h, -h, 2 * h, -2 * h})
      runs.push_back(run_output_study(text, file, fd_set, [&](const Model&, SampleInputs& in) { in.set(ref, x + dx); }));
    for (const std::string& name : names) {
      const double fd = (8 * (runs[0].scalar(name) - runs[1].scalar(name)) - (runs[2].scalar(name) - runs[3].scalar(name))) /
                        (12 * h);
      const double exact = base.scalar_sens(name, i);
      std::printf("%s: d%s/dp%zu exact %.12f, finite differences %.12f (difference %.1e)\n", file.c_str(), name.c_str(), i,
                  exact, fd, exact - fd);
      EXPECT_NEAR(exact, fd, tol * std::max(1.0, std::abs(fd))) << name << " " << i;
    }
  }
}

}  // namespace kanesens::testing
