#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>

#include "model/scene/parse_scene.hpp"
#include "model/yaml_reader.hpp"
#include "study/parse_sampling.hpp"
#include "study/parse_vary.hpp"
#include "study/study_spec.hpp"
#include "util/parse_number.hpp"

namespace kanesens::study {
namespace {

using model::ExprText;
using model::YamlReader;
using sim::ConstraintOptions;

// Time and solver settings can also be given with --set, as text: they are parsed by the rules
// of command-line numbers (util/parse_number.hpp) whichever way they come.
double read_setting(const YamlReader& r, const YAML::Node& n, const std::string& key) {
  const ExprText e = r.read_expr(n, key);
  try {
    return parse_number(e.text, key);
  } catch (const InputError&) {
    r.fail(n, key, "expected a number, found '" + e.text + "'");
  }
}

long read_whole_setting(const YamlReader& r, const YAML::Node& n, const std::string& key, long min,
                        long max = 9'000'000'000'000'000L) {
  const double v = read_setting(r, n, key);
  if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max))
    r.fail(n, key,
           "expected a whole number " +
               (max < 9'000'000'000'000'000L ? "from " + std::to_string(min) + " to " + std::to_string(max)
                                             : "≥ " + std::to_string(min)) +
               ", found " + n.Scalar());
  return static_cast<long>(v);
}

void parse_time(const YAML::Node& n, const YamlReader& r, StudySpec& st) {
  const std::string key = "time";
  r.check_keys(n, key, {"start", "end", "outputs", "times"});
  if (n["times"]) {
    // The first listed time is the initial time; a `start` beside it would be silently ignored.
    if (n["start"] || n["end"] || n["outputs"])
      r.fail(n, key, "give either 'times' (a list; the first is the initial time) or 'start', 'end' and 'outputs', not both");
    r.require_sequence(n["times"], key + ".times");
    for (std::size_t i = 0; i < n["times"].size(); ++i)
      st.output_times.push_back(read_setting(r, n["times"][i], key + ".times[" + std::to_string(i) + "]"));
    if (st.output_times.empty()) r.fail(n["times"], key + ".times", "needs at least one time");
    for (std::size_t i = 1; i < st.output_times.size(); ++i)
      if (!(st.output_times[i] > st.output_times[i - 1]))
        r.fail(n["times"][i], key + ".times[" + std::to_string(i) + "]", "times must be strictly increasing");
    return;
  }
  const double start = n["start"] ? read_setting(r, n["start"], key + ".start") : 0.0;
  const double end = read_setting(r, r.required(n, "end", key), key + ".end");
  const long outputs = n["outputs"] ? read_whole_setting(r, n["outputs"], key + ".outputs", 2) : 101;
  if (!(end > start)) r.fail(n["end"], key + ".end", "must be greater than time.start (" + std::to_string(start) + ")");
  if (outputs > 10000000) r.fail(n["outputs"], key + ".outputs", "at most 10000000 outputs");
  for (long k = 0; k < outputs; ++k)
    st.output_times.push_back(k == outputs - 1 ? end : start + (end - start) * static_cast<double>(k) / static_cast<double>(outputs - 1));
  // end − start can overflow, and a span tiny against |start| rounds outputs onto each other.
  for (std::size_t i = 0; i < st.output_times.size(); ++i)
    if (!std::isfinite(st.output_times[i]) || (i > 0 && !(st.output_times[i] > st.output_times[i - 1])))
      r.fail(n, key,
             "the " + std::to_string(outputs) + " output times from " + n["start"].as<std::string>("0") + " to " +
                 n["end"].Scalar() + " are not " + (std::isfinite(st.output_times[i]) ? "distinct" : "finite") +
                 " in double precision (output " + std::to_string(i) + "); use fewer outputs or a smaller start");
}

void parse_constraint_options(const YAML::Node& c, const YamlReader& r, const std::string& key, ConstraintOptions& co) {
  using Formulation = ConstraintOptions::Formulation;
  using Stabilization = ConstraintOptions::Stabilization;
  r.check_keys(c, key, {"formulation", "stabilization", "alpha", "beta", "correct_initial", "project_sensitivities"});
  if (c["formulation"])
    co.formulation = r.read_choice<Formulation>(
        c["formulation"], key + ".formulation",
        {{"multipliers", Formulation::multipliers}, {"embedding", Formulation::embedding}});
  if (c["stabilization"])
    co.stabilization = r.read_choice<Stabilization>(
        c["stabilization"], key + ".stabilization",
        {{"none", Stabilization::none}, {"baumgarte", Stabilization::baumgarte}, {"projection", Stabilization::projection}});
  if (co.formulation == Formulation::embedding && co.stabilization == Stabilization::baumgarte)
    r.fail(c, key, "embedding satisfies the velocity constraints exactly; use stabilization: projection or none");
  if (c["alpha"]) co.alpha = read_setting(r, c["alpha"], key + ".alpha");
  if (c["beta"]) co.beta = read_setting(r, c["beta"], key + ".beta");
  if (co.alpha < 0 || co.beta < 0) r.fail(c, key, "alpha and beta must be >= 0");
  if (c["correct_initial"]) co.correct_initial = r.read_bool(c["correct_initial"], key + ".correct_initial");
  if (c["project_sensitivities"])
    co.project_sensitivities = r.read_bool(c["project_sensitivities"], key + ".project_sensitivities");
}

void parse_solver(const YAML::Node& n, const YamlReader& r, sim::SolverOptions& o, ConstraintOptions& co,
                  bool has_constraints, StudySpec& st) {
  using namespace kanesens::sim;
  const std::string key = "solver";
  r.check_keys(n, key, {"method", "iteration", "rtol", "atol", "max_steps", "max_order", "initial_step", "max_step",
                        "jacobian", "linear_solver", "sensitivity", "constraints"});
  if (n["method"])
    o.method = r.read_choice<Method>(n["method"], key + ".method", std::span(kMethodNames));
  if (n["iteration"])
    o.iteration = r.read_choice<Iteration>(n["iteration"], key + ".iteration", std::span(kIterationNames));
  if (n["rtol"]) o.rtol = read_setting(r, n["rtol"], key + ".rtol");
  if (n["atol"]) {
    st.atol_where = r.location(n["atol"]);
    if (n["atol"].IsSequence()) {
      for (std::size_t i = 0; i < n["atol"].size(); ++i)
        o.atol_per_state.push_back(read_setting(r, n["atol"][i], key + ".atol[" + std::to_string(i) + "]"));
    } else {
      o.atol = read_setting(r, n["atol"], key + ".atol");
    }
  }
  if (n["max_steps"]) o.max_steps = read_whole_setting(r, n["max_steps"], key + ".max_steps", 1);
  if (n["max_order"]) o.max_order = static_cast<int>(read_whole_setting(r, n["max_order"], key + ".max_order", 0, 12));
  if (n["initial_step"]) o.initial_step = read_setting(r, n["initial_step"], key + ".initial_step");
  if (n["max_step"]) o.max_step = read_setting(r, n["max_step"], key + ".max_step");
  if (n["jacobian"])
    o.jacobian = r.read_choice<JacobianKind>(n["jacobian"], key + ".jacobian", std::span(kJacobianKindNames));
  if (n["linear_solver"])
    o.linear_solver =
        r.read_choice<LinearSolver>(n["linear_solver"], key + ".linear_solver", std::span(kLinearSolverNames));
  if (const YAML::Node s = n["sensitivity"]) {
    const std::string k2 = key + ".sensitivity";
    r.check_keys(s, k2, {"method", "error_control", "rhs", "atol"});
    if (s["method"])
      o.sensitivity_method =
          r.read_choice<SensitivityMethod>(s["method"], k2 + ".method", std::span(kSensitivityMethodNames));
    if (s["error_control"]) o.sens_error_control = r.read_bool(s["error_control"], k2 + ".error_control");
    if (s["rhs"])
      o.sens_rhs = r.read_choice<SensitivityRhs>(s["rhs"], k2 + ".rhs", std::span(kSensitivityRhsNames));
    if (s["atol"]) o.sens_atol = read_setting(r, s["atol"], k2 + ".atol");
  }
  if (const YAML::Node c = n["constraints"]) parse_constraint_options(c, r, key + ".constraints", co);
  // Projection is the default stabilization, so a constrained scene with adams and no explicit
  // solver.constraints would fail at its first step: refuse it here.
  if (co.stabilization == ConstraintOptions::Stabilization::projection && o.method == Method::adams &&
      (n["constraints"] || has_constraints))
    r.fail(n["constraints"] ? n["constraints"] : n["method"], n["constraints"] ? key + ".constraints" : key + ".method",
           std::string(n["constraints"] ? "" : "the scene has constraints and their default stabilization is projection; ") +
               "constraint projection needs method: bdf or dop853 (CVODES projects only with BDF); with adams set "
               "solver.constraints.stabilization: baumgarte (or none)");
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    r.fail(n, key, e.what());
  }
}

constexpr std::pair<std::string_view, RecordItem> kRecordItems[] = {
    {"states", RecordItem::states},
    {"sensitivities", RecordItem::sensitivities},
    {"multipliers", RecordItem::multipliers},
    {"energy", RecordItem::energy},
    {"constraint_residual", RecordItem::constraint_residual},
    {"poses", RecordItem::poses}};

void parse_record(const YAML::Node& n, const YamlReader& r, StudySpec& st) {
  st.record = {RecordItem::states, RecordItem::energy};
  if (!st.sensitivities.empty()) st.record.insert(RecordItem::sensitivities);
  st.record_where = {r.file(), 0, 0};
  if (!n || n.IsNull()) return;
  r.require_sequence(n, "record");
  st.record_where = r.location(n);
  st.record.clear();
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string key = "record[" + std::to_string(i) + "]";
    const std::string v = r.read_string(n[i], key);
    const auto* item = std::find_if(std::begin(kRecordItems), std::end(kRecordItems), [&](const auto& k) { return k.first == v; });
    if (item == std::end(kRecordItems))
      r.fail(n[i], key, "unknown record item '" + v + "'; items are: states, sensitivities, multipliers, energy, constraint_residual, poses");
    st.record.insert(item->second);
  }
}

// Applies "a.b.c=value" to the YAML document (creating maps as needed).
void apply_setting(YAML::Node doc, const std::string& path, const std::string& value) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const auto dot = path.find('.', start);
    parts.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  std::vector<YAML::Node> chain{doc};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (!next || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[parts[i]];
    }
    if (!next.IsMap()) throw InputError({}, "--set " + path, "'" + parts[i] + "' is not a map in the study file");
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
}

}  // namespace

std::string_view record_item_name(RecordItem item) {
  for (const auto& [name, value] : kRecordItems)
    if (value == item) return name;
  return "?";
}

bool is_study_setting(const std::string& name) {
  const auto dot = name.find('.');
  const std::string head = name.substr(0, dot);
  return dot != std::string::npos && (head == "time" || head == "solver" || head == "sampling");
}

StudySpec parse_study_file(const std::string& path, const std::vector<std::string>& set) {
  StudySpec st;
  st.file = path;
  st.text = model::read_text_file(path);
  YAML::Node doc = model::load_yaml(st.text, path);
  if (!doc.IsMap()) throw InputError({path, 1, 1}, "", "expected a YAML map (a study: kanesens, scene, time, solver, ...)");
  for (const auto& [name, value] : parse_assignments(set)) {
    if (is_study_setting(name)) apply_setting(doc, name, value);
    // A parameter or initial condition takes a number; a word there is more likely a study
    // setting written without its section, so the message says how settings are named.
    else
      st.set_inputs[name] = parse_number(value, "--set " + name,
                                         "a parameter or initial condition takes a number, and a study setting is "
                                         "named by its path from the top of the study file, under time, solver or "
                                         "sampling (solver.method=bdf, solver.sensitivity.error_control=false)");
  }
  const YamlReader r(path);
  r.check_keys(doc, "", {"kanesens", "scene", "time", "solver", "sampling", "vary", "sensitivities", "record", "outputs", "events"});
  const YAML::Node version = r.required(doc, "kanesens", "");
  if (!version.IsScalar() || version.Scalar() != "1") r.fail(version, "kanesens", "unsupported schema version; this kanesens reads version 1");
  const YAML::Node scene = r.required(doc, "scene", "");
  if (scene.IsScalar()) {
    const std::filesystem::path scene_path = std::filesystem::path(path).parent_path() / scene.Scalar();
    try {
      st.scene = model::parse_scene_file(scene_path.string());
    } catch (const InputError& e) {
      if (e.where().line == 0 && e.detail() == "cannot open file")
        r.fail(scene, "scene", "cannot open scene file '" + scene_path.string() + "' (relative to the study file)");
      throw;
    }
  } else {
    st.scene = model::parse_scene_node(scene, path, st.text);
  }
  parse_time(r.required(doc, "time", ""), r, st);
  st.time_where = r.location(doc["time"]);
  if (doc["solver"]) parse_solver(doc["solver"], r, st.solver, st.constraints, !st.scene.constraints.empty(), st);
  if (const YAML::Node s = doc["sensitivities"]; s && !s.IsNull()) {
    r.require_sequence(s, "sensitivities");
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::string key = "sensitivities[" + std::to_string(i) + "]";
      const std::string name = r.read_string(s[i], key);
      if (std::find(st.sensitivities.begin(), st.sensitivities.end(), name) != st.sensitivities.end())
        r.fail(s[i], key, "'" + name + "' is listed twice");
      st.sensitivities.push_back(name);
      st.sensitivity_where.push_back(r.location(s[i]));
    }
  }
  parse_record(doc["record"], r, st);
  st.outputs = parse_outputs(doc["outputs"], r);
  {
    std::vector<OutputSpec> events = parse_events(doc["events"], r, st.outputs);
    for (auto& e : events) st.outputs.push_back(std::move(e));
  }
  if (const YAML::Node s = doc["sampling"]; s && !s.IsNull()) {
    st.sampling = parse_sampling(s, {path, 0, 0});
  } else {
    st.sampling.method = SamplingMethod::mc;
    st.sampling.samples = 1;  // no sampling section: the nominal sample (plus any vary draws)
    st.sampling.where = {path, 0, 0};
  }
  const YAML::Node vary = doc["vary"];
  st.vary = parse_vary(vary, {path, 0, 0});
  for (const auto& kv : vary) st.vary_where.push_back(r.location(kv.first));
  return st;
}

}  // namespace kanesens::study
