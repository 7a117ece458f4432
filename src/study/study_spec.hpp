// A study file: the scene, output times, solver settings, sensitivities, what to
// record, and (for `run`) the sampling design. Plain structs; parse_study_file() fills them.
#pragma once
#include <yaml-cpp/yaml.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene/scene_spec.hpp"
#include "sim/constraint_options.hpp"
#include "solve/solver_options.hpp"

namespace kanesens {

struct StudySpec {
  std::string file;  // path of the study file
  std::string text;  // its exact text (after --set edits are applied, the original is kept here)
  SceneSpec scene;
  std::vector<double> output_times;  // strictly increasing; output 0 is the initial state
  solve::SolverOptions solver;
  ConstraintOptions constraints;
  std::vector<std::string> sensitivities;  // parameter or initial-condition names
  std::vector<SourceLocation> sensitivity_where;  // where each was written
  SourceLocation record_where;
  std::set<std::string> record;  // states, sensitivities, multipliers, energy, constraint_residual
  YAML::Node sampling, vary;     // the `sampling:` and `vary:` maps (may be null)
  SourceLocation sampling_where, vary_where;
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

}  // namespace kanesens
