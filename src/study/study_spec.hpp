// A study file: the scene, output times, solver settings, sensitivities, what to record, and
// (for `run`) the sampling design and the varied inputs. Plain structs; parse_study_file() fills
// them strictly. Whether the names it holds (sensitivities, varied inputs, --set values) are
// inputs of the scene is checked by the study setup (study/setup.hpp).
#pragma once
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "model/scene/scene_spec.hpp"
#include "sim/constraint_options.hpp"
#include "sim/solve/solver_options.hpp"
#include "study/output_spec.hpp"
#include "study/sampling_spec.hpp"
#include "study/varied_input.hpp"

namespace kanesens::study {

// What a study records per output time (the `record:` list).
enum class RecordItem { states, sensitivities, multipliers, energy, constraint_residual, poses };
std::string_view record_item_name(RecordItem item);

struct StudySpec {
  std::string file;  // path of the study file
  std::string text;  // its exact text (after --set edits are applied, the original is kept here)
  model::SceneSpec scene;
  std::vector<double> output_times;  // strictly increasing; output 0 is the initial state
  sim::SolverOptions solver;
  sim::ConstraintOptions constraints;
  std::vector<std::string> sensitivities;         // parameter or initial-condition names
  std::vector<SourceLocation> sensitivity_where;  // where each was written
  std::set<RecordItem> record;                    // default: states, energy (+ sensitivities)
  SourceLocation record_where;
  std::vector<OutputSpec> outputs;                // `outputs:`, in file order
  // `sampling:`; without one, the nominal sample (mc, 1 run; where = the file).
  SamplingSpec sampling;
  std::vector<VariedInput> vary;        // `vary:`, in file order
  std::vector<SourceLocation> vary_where;  // where each varied input's name is written
  SourceLocation time_where;  // the `time:` map (messages about the number of outputs)
  SourceLocation atol_where;  // solver.atol, when given
  // Parameter and initial-condition values given with --set ("m2" → 0.9, "elbow.q0" → 0.3).
  std::map<std::string, double> set_inputs;
};

// Reads a study file. `set` holds NAME=VALUE strings from --set: study settings
// ("solver.rtol=1e-10", "time.end=5") edit the YAML before it is parsed; other names are
// parameters or initial conditions, returned in set_inputs (checked against the scene later).
StudySpec parse_study_file(const std::string& path, const std::vector<std::string>& set = {});

// The names --set may use for study settings: the first component of a dotted name.
bool is_study_setting(const std::string& name);

}  // namespace kanesens::study
