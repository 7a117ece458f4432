#include "study/parse_sampling.hpp"

#include <array>
#include <vector>

#include "study/yaml_read.hpp"
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
                       const SourceLocation& file) {
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
      throw InputError(location_of(kv.first, file), path + "." + key,
                       "'" + key + "' does not apply to method " +
                           std::string(method_name(method)) + " (it is for " + users + "); " +
                           std::string(method_name(method)) + " takes: " + join_names(allowed));
    }
  }
  check_keys(node, allowed, path, file);  // typos, duplicates
}

std::int64_t read_count(const YAML::Node& node, const std::string& path, const SourceLocation& file,
                        std::int64_t max) {
  const std::int64_t n = read_integer(node, path, file);
  if (n < 1 || n > max) {
    throw InputError(location_of(node, file), path,
                     "expected an integer in [1, " + std::to_string(max) + "], got " +
                         std::to_string(n) +
                         (n > max ? " (larger designs are refused as a likely typo)" : ""));
  }
  return n;
}

SamplingMethod read_method(const YAML::Node& node, const std::string& path,
                           const SourceLocation& file) {
  const std::string name = read_string(node, path, file);
  if (const auto m = method_from_name(name)) return *m;
  throw InputError(location_of(node, file), path,
                   "unknown sampling method '" + name + "'" + did_you_mean(name, all_methods) +
                       "; expected one of: " + join_names(all_methods));
}

void read_grid_levels(const YAML::Node& node, const std::string& path, const SourceLocation& file,
                      SamplingSpec& spec) {
  if (node.IsScalar()) {
    spec.grid_levels = read_count(node, path, file, max_design_runs);
    return;
  }
  if (!node.IsMap()) {
    throw InputError(location_of(node, file), path,
                     "expected a level count or a map {input: count}, got " + describe_node(node));
  }
  // Input names are checked against `vary` when the Design is built (GridLevels::where).
  for (const auto& kv : node) {
    const std::string input = read_string(kv.first, path, file);
    const std::string key_path = path + "." + input;
    for (const GridLevels& g : spec.grid_levels_by_input) {
      if (g.input == input) {
        throw InputError(location_of(kv.first, file), key_path,
                         "input '" + input + "' is given twice");
      }
    }
    spec.grid_levels_by_input.push_back({input,
                                         read_count(kv.second, key_path, file, max_design_runs),
                                         location_of(kv.second, file)});
  }
}

}  // namespace

SamplingSpec parse_sampling(const YAML::Node& node, const SourceLocation& file_ctx,
                            const std::string& path) {
  require_map(node, path, file_ctx);
  SamplingSpec spec;
  spec.where = location_of(node, file_ctx);
  if (node["method"]) spec.method = read_method(node["method"], path + ".method", file_ctx);
  check_method_keys(node, spec.method, path, file_ctx);
  const std::string name(method_name(spec.method));

  if (node["seed"]) spec.seed = read_unsigned(node["seed"], path + ".seed", file_ctx);

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
    spec.samples = read_count(node["samples"], path + ".samples", file_ctx, max_design_runs);
  }

  if (node["base"]) {
    const YAML::Node& b = node["base"];
    const SamplingMethod base = read_method(b, path + ".base", file_ctx);
    if (base != SamplingMethod::mc && base != SamplingMethod::lhs &&
        base != SamplingMethod::sobol && base != SamplingMethod::halton) {
      throw InputError(location_of(b, file_ctx), path + ".base",
                       "expected a base sequence mc, lhs, sobol or halton, got '" +
                           std::string(method_name(base)) + "'");
    }
    spec.base = base;
  }

  if (node["randomize"]) {
    const YAML::Node& r = node["randomize"];
    spec.randomize = read_bool(r, path + ".randomize", file_ctx);
    if (spec.randomize && spec.method == SamplingMethod::saltelli &&
        spec.base != SamplingMethod::sobol && spec.base != SamplingMethod::halton) {
      throw InputError(location_of(r, file_ctx), path + ".randomize",
                       "randomize applies to a sobol or halton base; the base is " +
                           std::string(method_name(spec.base)) + ", which is random already");
    }
  }

  if (spec.method == SamplingMethod::grid && node["levels"]) {
    read_grid_levels(node["levels"], path + ".levels", file_ctx, spec);
  }

  if (spec.method == SamplingMethod::morris) {
    if (!node["trajectories"]) {
      throw InputError(spec.where, path,
                       "missing key 'trajectories': method morris needs the number of "
                       "trajectories r (runs = r·(inputs + 1))");
    }
    spec.trajectories =
        read_count(node["trajectories"], path + ".trajectories", file_ctx, max_design_runs);
    if (node["levels"]) {
      const YAML::Node& p = node["levels"];
      spec.morris_levels = read_integer(p, path + ".levels", file_ctx);
      if (spec.morris_levels < 2 || spec.morris_levels % 2 != 0 || spec.morris_levels > 1000) {
        throw InputError(location_of(p, file_ctx), path + ".levels",
                         "expected an even number of levels in [2, 1000] (steps are p/2 levels), "
                         "got " +
                             std::to_string(spec.morris_levels));
      }
    }
  }
  return spec;
}

}  // namespace kanesens::study
