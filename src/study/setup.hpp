// A study made ready to run, for every command that runs one (`simulate`, `run`, the benchmarks):
// the parsed study with its --set values applied, the compiled model, and every name of the
// study resolved against it. Construction validates all of it and throws InputError naming
// file:line:column and the key path, so a command fails before it computes or writes anything.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "sim/inputs.hpp"
#include "sim/simulate.hpp"
#include "study/design.hpp"
#include "study/study_spec.hpp"

namespace kanesens::study {

struct StudySetup {
  std::vector<std::string> set;  // the --set arguments, as given (provenance)
  StudySpec spec;
  // --set parameters are compiled in (a derived parameter given a value becomes a constant).
  model::Model model;
  // The nominal sample: the scene's values, with the initial conditions given by --set.
  sim::SampleInputs base;
  Design design;
  std::vector<sim::InputRef> varied;         // one per design input (spec.vary), in order
  std::vector<sim::InputRef> sensitivities;  // the study's list, resolved
  // The study's `outputs:`, resolved (empty plan: none). Shared: record.outputs points into it.
  std::shared_ptr<const sim::OutputPlan> outputs;
  // What the study records (`record:`, and the outputs); multipliers and residuals only for
  // constrained scenes, sensitivities only when the study lists some.
  sim::RecordFlags record;

  // The sensitivities to compute: the study's when state sensitivities are recorded or the study
  // has outputs (whose sensitivities are then recorded), else none.
  std::vector<sim::InputRef> recorded_sensitivities() const;
  // Run i's inputs: base with the design's values of the varied inputs (values: P entries).
  sim::SampleInputs sample(std::int64_t i, std::span<double> values) const;
};

// Reads and prepares the study at `path`. `set`: NAME=VALUE from --set (study settings such as
// solver.rtol, parameters, initial conditions).
StudySetup setup_study(const std::string& path, const std::vector<std::string>& set = {});

}  // namespace kanesens::study
