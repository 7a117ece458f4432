#include "study/parse_vary.hpp"

#include <array>

#include "study/yaml_read.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::study {
namespace {

struct KindKeys {
  std::string_view kind;
  std::vector<std::string_view> keys;  // with "dist" first
};

const std::array<KindKeys, 7>& kinds() {
  static const std::array<KindKeys, 7> table = {{
      {"uniform", {"dist", "low", "high"}},
      {"normal", {"dist", "mean", "std"}},
      {"truncnormal", {"dist", "mean", "std", "low", "high"}},
      {"lognormal", {"dist", "mu", "sigma"}},
      {"triangular", {"dist", "low", "mode", "high"}},
      {"choice", {"dist", "values"}},
      {"fixed", {"dist", "value"}},
  }};
  return table;
}

}  // namespace

Distribution parse_distribution(const YAML::Node& node, const SourceLocation& file,
                                const std::string& path) {
  require_map(node, path, file);
  std::vector<std::string_view> kind_names;
  for (const auto& k : kinds()) kind_names.push_back(k.kind);
  if (!node["dist"]) {
    // A misspelt `dist` reads better as an unknown key than as a missing one.
    std::vector<std::string_view> any_key;
    for (const auto& k : kinds()) any_key.insert(any_key.end(), k.keys.begin(), k.keys.end());
    check_keys(node, any_key, path, file);
    throw InputError(location_of(node, file), path,
                     "missing key 'dist'; expected one of: " + join_names(kind_names));
  }
  const YAML::Node& dist_node = node["dist"];
  const std::string kind = read_string(dist_node, path + ".dist", file);
  const KindKeys* spec = nullptr;
  for (const auto& k : kinds()) {
    if (k.kind == kind) spec = &k;
  }
  if (!spec) {
    throw InputError(location_of(dist_node, file), path + ".dist",
                     "unknown distribution '" + kind + "'" + did_you_mean(kind, kind_names) +
                         "; expected one of: " + join_names(kind_names));
  }
  check_keys(node, spec->keys, path, file);
  for (const std::string_view key : spec->keys) {
    if (!node[std::string(key)]) {
      std::vector<std::string_view> params(spec->keys.begin() + 1, spec->keys.end());
      throw InputError(
          location_of(node, file), path,
          "missing key '" + std::string(key) + "'; " + kind + " needs: " + join_names(params));
    }
  }
  const auto num = [&](const char* key) { return read_finite(node[key], path + "." + key, file); };

  Distribution d;
  if (kind == "uniform") {
    d.params = Uniform{num("low"), num("high")};
  } else if (kind == "normal") {
    d.params = Normal{num("mean"), num("std")};
  } else if (kind == "truncnormal") {
    d.params = TruncNormal{num("mean"), num("std"), num("low"), num("high")};
  } else if (kind == "lognormal") {
    d.params = LogNormal{num("mu"), num("sigma")};
  } else if (kind == "triangular") {
    d.params = Triangular{num("low"), num("mode"), num("high")};
  } else if (kind == "fixed") {
    d.params = Fixed{num("value")};
  } else {  // choice
    const YAML::Node& list = node["values"];
    if (!list.IsSequence()) {
      throw InputError(location_of(list, file), path + ".values",
                       "expected a list of numbers, got " + describe_node(list));
    }
    std::vector<double> values;
    for (std::size_t k = 0; k < list.size(); ++k) {
      values.push_back(read_finite(list[k], path + ".values[" + std::to_string(k) + "]", file));
    }
    d = make_choice(std::move(values));
  }

  if (const auto problem = d.find_problem()) {
    const YAML::Node& at = node[problem->key] ? node[problem->key] : node;
    throw InputError(location_of(at, file), path + "." + problem->key,
                     kind + ": " + problem->message);
  }
  return d;
}

std::vector<VariedInput> parse_vary(const YAML::Node& node, const SourceLocation& file,
                                    const std::string& path) {
  std::vector<VariedInput> inputs;
  if (!node || node.IsNull()) return inputs;
  require_map(node, path, file);
  for (const auto& kv : node) {
    const std::string name = read_string(kv.first, path, file);
    const std::string key_path = path + "." + name;
    if (name.empty()) {
      throw InputError(location_of(kv.first, file), path, "expected an input name, got ''");
    }
    for (const auto& in : inputs) {
      if (in.name == name) {
        throw InputError(location_of(kv.first, file), key_path,
                         "input '" + name + "' is varied twice");
      }
    }
    inputs.push_back({name, parse_distribution(kv.second, file, key_path)});
  }
  return inputs;
}

}  // namespace kanesens::study
