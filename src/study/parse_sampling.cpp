#include "study/parse_sampling.hpp"

#include <array>
#include <vector>

#include "model/yaml_reader.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::study {
namespace {

std::vector<std::string_view> keys_of(SamplingMethod m) {
  std::vector<std::string_view> keys = {"method", "seed"};
  switch (m) {
    case SamplingMethod::mc:
    case SamplingMethod::lhs:
      keys.push_back("samples");
      break;
    case SamplingMethod::sobol:
    case SamplingMethod::halton:
      keys.insert(keys.end(), {"samples", "randomize"});
      break;
    case SamplingMethod::grid:
      keys.push_back("levels");
      break;
    case SamplingMethod::saltelli:
      keys.insert(keys.end(), {"samples", "base", "randomize"});
      break;
    case SamplingMethod::morris:
      keys.insert(keys.end(), {"trajectories", "levels"});
      break;
  }
  return keys;
}

constexpr std::array<std::string_view, 7> all_methods = {"mc",   "lhs",      "sobol", "halton",
                                                         "grid", "saltelli", "morris"};

// A key valid for some other method gets "does not apply" rather than "unknown".
void check_method_keys(const YAML::Node& node, SamplingMethod method, const std::string& path,
                       const model::YamlReader& r) {
  const auto allowed = keys_of(method);
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) continue;
    const std::string& key = kv.first.Scalar();
    bool here = false;
    for (const auto a : allowed) here = here || a == key;
    if (here) continue;
    std::string users;
    for (const auto name : all_methods) {
      for (const auto k : keys_of(*method_from_name(name))) {
        if (k == key) users += (users.empty() ? "" : ", ") + std::string(name);
      }
    }
    if (!users.empty()) {
      throw InputError(r.location(kv.first), path + "." + key,
                       "'" + key + "' does not apply to method " +
                           std::string(method_name(method)) + " (it is for " + users + "); " +
                           std::string(method_name(method)) + " takes: " + join_names(allowed));
    }
  }
  r.check_keys(node, path, allowed);  // typos, duplicates
}

std::int64_t read_count(const YAML::Node& node, const std::string& path, const model::YamlReader& r,
                        std::int64_t max) {
  const std::int64_t n = r.read_integer(node, path);
  if (n < 1 || n > max) {
    throw InputError(r.location(node), path,
                     "expected an integer in [1, " + std::to_string(max) + "], got " +
                         std::to_string(n) +
                         (n > max ? " (larger designs are refused as a likely typo)" : ""));
  }
  return n;
}

SamplingMethod read_method(const YAML::Node& node, const std::string& path,
                           const model::YamlReader& r) {
  const std::string name = r.read_string(node, path);
  if (const auto m = method_from_name(name)) return *m;
  throw InputError(r.location(node), path,
                   "unknown sampling method '" + name + "'" + did_you_mean(name, all_methods) +
                       "; expected one of: " + join_names(all_methods));
}

void read_grid_levels(const YAML::Node& node, const std::string& path, const model::YamlReader& r,
                      SamplingSpec& spec) {
  if (node.IsScalar()) {
    spec.grid_levels = read_count(node, path, r, max_design_runs);
    return;
  }
  if (!node.IsMap()) {
    throw InputError(r.location(node), path,
                     "expected a level count or a map {input: count}, got " + model::describe(node));
  }
  // Input names are checked against `vary` when the Design is built (GridLevels::where).
  for (const auto& kv : node) {
    const std::string input = r.read_string(kv.first, path);
    const std::string key_path = path + "." + input;
    for (const GridLevels& g : spec.grid_levels_by_input) {
      if (g.input == input) {
        throw InputError(r.location(kv.first), key_path,
                         "input '" + input + "' is given twice");
      }
    }
    spec.grid_levels_by_input.push_back({input,
                                         read_count(kv.second, key_path, r, max_design_runs),
                                         r.location(kv.second)});
  }
}

}  // namespace

SamplingSpec parse_sampling(const YAML::Node& node, const SourceLocation& file_ctx, const std::string& path) {
  const model::YamlReader r(file_ctx.file);
  r.require_map(node, path);
  SamplingSpec spec;
  spec.where = r.location(node);
  if (node["method"]) spec.method = read_method(node["method"], path + ".method", r);
  check_method_keys(node, spec.method, path, r);
  const std::string name(method_name(spec.method));

  if (node["seed"]) spec.seed = r.read_unsigned(node["seed"], path + ".seed");

  const bool wants_samples =
      spec.method != SamplingMethod::grid && spec.method != SamplingMethod::morris;
  if (wants_samples) {
    if (!node["samples"]) {
      throw InputError(spec.where, path,
                       "missing key 'samples': method " + name + " needs " +
                           (spec.method == SamplingMethod::saltelli
                                ? "the base sample count N (runs = N·(inputs + 2))"
                                : "the number of runs"));
    }
    spec.samples = read_count(node["samples"], path + ".samples", r, max_design_runs);
  }

  if (node["base"]) {
    const YAML::Node& b = node["base"];
    const SamplingMethod base = read_method(b, path + ".base", r);
    if (base != SamplingMethod::mc && base != SamplingMethod::lhs &&
        base != SamplingMethod::sobol && base != SamplingMethod::halton) {
      throw InputError(r.location(b), path + ".base",
                       "expected a base sequence mc, lhs, sobol or halton, got '" +
                           std::string(method_name(base)) + "'");
    }
    spec.base = base;
  }

  if (node["randomize"]) {
    const YAML::Node& rnd = node["randomize"];
    spec.randomize = r.read_bool(rnd, path + ".randomize");
    if (spec.randomize && spec.method == SamplingMethod::saltelli &&
        spec.base != SamplingMethod::sobol && spec.base != SamplingMethod::halton) {
      throw InputError(r.location(rnd), path + ".randomize",
                       "randomize applies to a sobol or halton base; the base is " +
                           std::string(method_name(spec.base)) + ", which is random already");
    }
  }

  if (spec.method == SamplingMethod::grid && node["levels"]) {
    read_grid_levels(node["levels"], path + ".levels", r, spec);
  }

  if (spec.method == SamplingMethod::morris) {
    if (!node["trajectories"]) {
      throw InputError(spec.where, path,
                       "missing key 'trajectories': method morris needs the number of "
                       "trajectories r (runs = r·(inputs + 1))");
    }
    spec.trajectories =
        read_count(node["trajectories"], path + ".trajectories", r, max_design_runs);
    if (node["levels"]) {
      const YAML::Node& p = node["levels"];
      spec.morris_levels = r.read_integer(p, path + ".levels");
      if (spec.morris_levels < 2 || spec.morris_levels % 2 != 0 || spec.morris_levels > 1000) {
        throw InputError(r.location(p), path + ".levels",
                         "expected an even number of levels in [2, 1000] (steps are p/2 levels), "
                         "got " +
                             std::to_string(spec.morris_levels));
      }
    }
  }
  return spec;
}

}  // namespace kanesens::study
