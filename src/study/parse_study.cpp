#include <algorithm>
#include <cmath>
#include <filesystem>

#include "scene/parse_scene.hpp"
#include "scene/yaml_util.hpp"
#include "study/study_spec.hpp"
#include "util/parse_number.hpp"

namespace kanesens {
namespace {

using namespace kanesens::yaml;

double read_number(const YAML::Node& n, const std::string& file, const std::string& key) {
  const ExprText e = read_expr(n, file, key);
  try {
    return parse_number(e.text, key);
  } catch (const InputError&) {
    fail(n, file, key, "expected a number, found '" + e.text + "'");
  }
}

long read_integer(const YAML::Node& n, const std::string& file, const std::string& key, long min,
                  long max = 9'000'000'000'000'000L) {
  const double v = read_number(n, file, key);
  if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max))
    fail(n, file, key,
         "expected a whole number " +
             (max < 9'000'000'000'000'000L ? "from " + std::to_string(min) + " to " + std::to_string(max)
                                           : "≥ " + std::to_string(min)) +
             ", found " + n.Scalar());
  return static_cast<long>(v);
}

template <class E>
E read_choice(const YAML::Node& n, const std::string& file, const std::string& key,
              const std::vector<std::pair<std::string, E>>& choices) {
  const std::string s = read_string(n, file, key);
  std::string names;
  for (const auto& [name, value] : choices) {
    if (name == s) return value;
    names += (names.empty() ? "" : ", ") + name;
  }
  fail(n, file, key, "expected one of " + names + ", found '" + s + "'");
}

bool read_bool(const YAML::Node& n, const std::string& file, const std::string& key) {
  const std::string s = read_string(n, file, key);
  if (s == "true" || s == "on" || s == "yes") return true;
  if (s == "false" || s == "off" || s == "no") return false;
  fail(n, file, key, "expected true or false, found '" + s + "'");
}

void parse_time(const YAML::Node& n, const std::string& file, StudySpec& st) {
  const std::string key = "time";
  check_keys(n, file, key, {"start", "end", "outputs", "times"});
  if (n["times"]) {
    if (n["end"] || n["outputs"]) fail(n, file, key, "give either 'times' (a list) or 'end' and 'outputs', not both");
    require_sequence(n["times"], file, key + ".times");
    for (std::size_t i = 0; i < n["times"].size(); ++i)
      st.output_times.push_back(read_number(n["times"][i], file, key + ".times[" + std::to_string(i) + "]"));
    if (st.output_times.empty()) fail(n["times"], file, key + ".times", "needs at least one time");
    for (std::size_t i = 1; i < st.output_times.size(); ++i)
      if (!(st.output_times[i] > st.output_times[i - 1]))
        fail(n["times"][i], file, key + ".times[" + std::to_string(i) + "]", "times must be strictly increasing");
    return;
  }
  const double start = n["start"] ? read_number(n["start"], file, key + ".start") : 0.0;
  const double end = read_number(required(n, "end", file, key), file, key + ".end");
  const long outputs = n["outputs"] ? read_integer(n["outputs"], file, key + ".outputs", 2) : 101;
  if (!(end > start)) fail(n["end"], file, key + ".end", "must be greater than time.start (" + std::to_string(start) + ")");
  if (outputs > 10000000) fail(n["outputs"], file, key + ".outputs", "at most 10000000 outputs");
  for (long k = 0; k < outputs; ++k)
    st.output_times.push_back(k == outputs - 1 ? end : start + (end - start) * static_cast<double>(k) / static_cast<double>(outputs - 1));
  // end − start can overflow, and a span tiny against |start| rounds outputs onto each other.
  for (std::size_t i = 0; i < st.output_times.size(); ++i)
    if (!std::isfinite(st.output_times[i]) || (i > 0 && !(st.output_times[i] > st.output_times[i - 1])))
      fail(n, file, key,
           "the " + std::to_string(outputs) + " output times from " + n["start"].as<std::string>("0") + " to " +
               n["end"].Scalar() + " are not " + (std::isfinite(st.output_times[i]) ? "distinct" : "finite") +
               " in double precision (output " + std::to_string(i) + "); use fewer outputs or a smaller start");
}

void parse_solver(const YAML::Node& n, const std::string& file, solve::SolverOptions& o, ConstraintOptions& co,
                  bool has_constraints, StudySpec& st) {
  const std::string key = "solver";
  check_keys(n, file, key, {"method", "iteration", "rtol", "atol", "max_steps", "max_order", "initial_step",
                            "max_step", "jacobian", "sensitivity", "constraints"});
  using namespace kanesens::solve;
  if (n["method"]) o.method = read_choice<Method>(n["method"], file, key + ".method", {{"bdf", Method::bdf}, {"adams", Method::adams}, {"dop853", Method::dop853}});
  if (n["iteration"])
    o.iteration = read_choice<Iteration>(n["iteration"], file, key + ".iteration",
                                         {{"newton", Iteration::newton}, {"functional", Iteration::functional}});
  if (n["rtol"]) o.rtol = read_number(n["rtol"], file, key + ".rtol");
  if (n["atol"]) {
    st.atol_where = location(n["atol"], file);
    if (n["atol"].IsSequence()) {
      for (std::size_t i = 0; i < n["atol"].size(); ++i)
        o.atol_per_state.push_back(read_number(n["atol"][i], file, key + ".atol[" + std::to_string(i) + "]"));
    } else {
      o.atol = read_number(n["atol"], file, key + ".atol");
    }
  }
  if (n["max_steps"]) o.max_steps = read_integer(n["max_steps"], file, key + ".max_steps", 1);
  if (n["max_order"]) o.max_order = static_cast<int>(read_integer(n["max_order"], file, key + ".max_order", 1, 12));
  if (n["initial_step"]) o.initial_step = read_number(n["initial_step"], file, key + ".initial_step");
  if (n["max_step"]) o.max_step = read_number(n["max_step"], file, key + ".max_step");
  if (n["jacobian"])
    o.jacobian = read_choice<JacobianKind>(n["jacobian"], file, key + ".jacobian",
                                           {{"exact", JacobianKind::exact}, {"dq", JacobianKind::dq}});
  if (const YAML::Node s = n["sensitivity"]) {
    const std::string k2 = key + ".sensitivity";
    check_keys(s, file, k2, {"method", "error_control", "rhs", "atol"});
    if (s["method"])
      o.sensitivity_method = read_choice<SensitivityMethod>(
          s["method"], file, k2 + ".method",
          {{"simultaneous", SensitivityMethod::simultaneous}, {"staggered", SensitivityMethod::staggered},
           {"staggered1", SensitivityMethod::staggered1}});
    if (s["error_control"]) o.sens_error_control = read_bool(s["error_control"], file, k2 + ".error_control");
    if (s["rhs"])
      o.sens_rhs = read_choice<SensitivityRhs>(s["rhs"], file, k2 + ".rhs",
                                               {{"exact", SensitivityRhs::exact}, {"dq", SensitivityRhs::dq}});
    if (s["atol"]) o.sens_atol = read_number(s["atol"], file, k2 + ".atol");
  }
  if (const YAML::Node c = n["constraints"]) {
    const std::string k2 = key + ".constraints";
    check_keys(c, file, k2, {"formulation", "stabilization", "alpha", "beta", "correct_initial", "project_sensitivities"});
    if (c["formulation"])
      co.formulation = read_choice<ConstraintOptions::Formulation>(
          c["formulation"], file, k2 + ".formulation",
          {{"multipliers", ConstraintOptions::Formulation::multipliers}, {"embedding", ConstraintOptions::Formulation::embedding}});
    if (c["stabilization"])
      co.stabilization = read_choice<ConstraintOptions::Stabilization>(
          c["stabilization"], file, k2 + ".stabilization",
          {{"none", ConstraintOptions::Stabilization::none}, {"baumgarte", ConstraintOptions::Stabilization::baumgarte},
           {"projection", ConstraintOptions::Stabilization::projection}});
    if (co.formulation == ConstraintOptions::Formulation::embedding &&
        co.stabilization == ConstraintOptions::Stabilization::baumgarte)
      fail(c, file, k2, "embedding satisfies the velocity constraints exactly; use stabilization: projection or none");
    if (c["alpha"]) co.alpha = read_number(c["alpha"], file, k2 + ".alpha");
    if (c["beta"]) co.beta = read_number(c["beta"], file, k2 + ".beta");
    if (co.alpha < 0 || co.beta < 0) fail(c, file, k2, "alpha and beta must be >= 0");
    if (c["correct_initial"]) co.correct_initial = read_bool(c["correct_initial"], file, k2 + ".correct_initial");
    if (c["project_sensitivities"])
      co.project_sensitivities = read_bool(c["project_sensitivities"], file, k2 + ".project_sensitivities");
  }
  // Projection is the default stabilization, so a constrained scene with adams and no explicit
  // solver.constraints would fail at its first step: refuse it here.
  if (co.stabilization == ConstraintOptions::Stabilization::projection && o.method == solve::Method::adams &&
      (n["constraints"] || has_constraints))
    fail(n["constraints"] ? n["constraints"] : n["method"], file, n["constraints"] ? key + ".constraints" : key + ".method",
         std::string(n["constraints"] ? "" : "the scene has constraints and their default stabilization is projection; ") +
             "constraint projection needs method: bdf or dop853 (CVODES projects only with BDF); with adams set "
             "solver.constraints.stabilization: baumgarte (or none)");
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    fail(n, file, key, e.what());
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

bool is_study_setting(const std::string& name) {
  const auto dot = name.find('.');
  const std::string head = name.substr(0, dot);
  return dot != std::string::npos && (head == "time" || head == "solver" || head == "sampling");
}

StudySpec parse_study_file(const std::string& path, const std::vector<std::string>& set) {
  StudySpec st;
  st.file = path;
  st.text = read_file(path);
  YAML::Node doc = load(st.text, path);
  if (!doc.IsMap()) throw InputError({path, 1, 1}, "", "expected a YAML map (a study: kanesens, scene, time, solver, ...)");
  for (const auto& [name, value] : parse_assignments(set)) {
    if (is_study_setting(name)) apply_setting(doc, name, value);
    else st.set_inputs[name] = parse_number(value, "--set " + name);
  }
  check_keys(doc, path, "", {"kanesens", "scene", "time", "solver", "sampling", "vary", "sensitivities", "record"});
  const YAML::Node version = required(doc, "kanesens", path, "");
  if (!version.IsScalar() || version.Scalar() != "1") fail(version, path, "kanesens", "unsupported schema version; this kanesens reads version 1");
  const YAML::Node scene = required(doc, "scene", path, "");
  if (scene.IsScalar()) {
    const std::filesystem::path scene_path = std::filesystem::path(path).parent_path() / scene.Scalar();
    try {
      st.scene = parse_scene_file(scene_path.string());
    } catch (const InputError& e) {
      if (e.where().line == 0 && e.detail() == "cannot open file")
        fail(scene, path, "scene", "cannot open scene file '" + scene_path.string() + "' (relative to the study file)");
      throw;
    }
  } else {
    st.scene = parse_scene_node(scene, path, st.text);
  }
  parse_time(required(doc, "time", path, ""), path, st);
  st.time_where = location(doc["time"], path);
  if (doc["solver"]) parse_solver(doc["solver"], path, st.solver, st.constraints, !st.scene.constraints.empty(), st);
  if (const YAML::Node s = doc["sensitivities"]; s && !s.IsNull()) {
    require_sequence(s, path, "sensitivities");
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::string key = "sensitivities[" + std::to_string(i) + "]";
      const std::string name = read_string(s[i], path, key);
      if (std::find(st.sensitivities.begin(), st.sensitivities.end(), name) != st.sensitivities.end())
        fail(s[i], path, key, "'" + name + "' is listed twice");
      st.sensitivities.push_back(name);
      st.sensitivity_where.push_back(location(s[i], path));
    }
  }
  st.record = {"states", "energy"};
  if (!st.sensitivities.empty()) st.record.insert("sensitivities");
  st.record_where = {path, 0, 0};
  if (const YAML::Node r = doc["record"]; r && !r.IsNull()) {
    require_sequence(r, path, "record");
    st.record_where = location(r, path);
    st.record.clear();
    const std::vector<std::string> allowed = {"states", "sensitivities", "multipliers", "energy", "constraint_residual"};
    for (std::size_t i = 0; i < r.size(); ++i) {
      const std::string key = "record[" + std::to_string(i) + "]";
      const std::string v = read_string(r[i], path, key);
      if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
        fail(r[i], path, key, "unknown record item '" + v + "'; items are: states, sensitivities, multipliers, energy, constraint_residual");
      st.record.insert(v);
    }
  }
  st.sampling = doc["sampling"];
  st.vary = doc["vary"];
  if (st.sampling) st.sampling_where = location(st.sampling, path);
  if (st.vary) st.vary_where = location(st.vary, path);
  return st;
}

}  // namespace kanesens
