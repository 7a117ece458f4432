// The study's `outputs:` section as written (docs/reference/study.md, "outputs"): one entry per
// output, names and texts with where they were written. parse_outputs() reads it strictly;
// build_output_plan() (study/build_outputs.hpp) resolves it against the model.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "model/scene/scene_spec.hpp"
#include "model/yaml_reader.hpp"
#include "sim/output_plan.hpp"
#include "util/error.hpp"

namespace kanesens::study {

struct OutputSpec {
  std::string name;
  SourceLocation where;  // of the name
  sim::OutputKind kind = sim::OutputKind::expression;
  // The body, joint, constraint or force the kind reads, under its key ("body", "joint", ...).
  std::string target, target_key;
  SourceLocation target_where;
  model::Vec3Text point;  // body frame; default the origin (the mass center)
  sim::EnergyKind energy = sim::EnergyKind::total;
  // `expression:` (kind expression) or `of:` (kind reduction).
  model::ExprText expression;
  // Reductions: `at: T` / `at: end`, `reduce: integral | mean | rms | max | min | argmax |
  // argmin`, or `at_event: EVENT` with `occurrence: k` (1-based; default 1).
  sim::Reduction reduce = sim::Reduction::at;
  bool at_end = false;
  double at = 0;
  SourceLocation reduce_where;
  std::string at_event;
  long occurrence = 1;
  // An `events:` entry (kind reduction, reduce event; `when:` in expression).
  bool event = false;
  int direction = 0;  // rising +1, falling −1, both 0
  bool stop = false;  // action: stop
  long max_count = 0;
  long recorded_times = 0;  // occurrence times kept: max_count if given, else 100
  // Kind eigenvalues: `count:` (0: all), `coordinates:` / `speeds:` (empty: chosen as by
  // `kanesens linearize`), where each was written.
  long count = 0;
  std::vector<std::string> coordinates, speeds;
  SourceLocation coordinates_where, speeds_where;
  // The key its messages name: "outputs.NAME" or "events.NAME".
  std::string key() const { return (event ? "events." : "outputs.") + name; }
};

// Reads the `outputs:` map (null: none). Throws InputError at the offending key.
std::vector<OutputSpec> parse_outputs(const YAML::Node& node, const model::YamlReader& r);
// Reads the `events:` list (null: none) as outputs of kind reduction (reduce event); `outputs`:
// the outputs already read (an event may not take an output's name).
std::vector<OutputSpec> parse_events(const YAML::Node& node, const model::YamlReader& r,
                                     const std::vector<OutputSpec>& outputs);

}  // namespace kanesens::study
