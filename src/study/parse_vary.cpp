#include "study/parse_vary.hpp"

#include <array>

#include "model/yaml_reader.hpp"
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


Distribution read_distribution(const YAML::Node& node, const model::YamlReader& r,
                                const std::string& path) {
  r.require_map(node, path);
  std::vector<std::string_view> kind_names;
  for (const auto& k : kinds()) kind_names.push_back(k.kind);
  if (!node["dist"]) {
    // A misspelt `dist` reads better as an unknown key than as a missing one.
    std::vector<std::string_view> any_key;
    for (const auto& k : kinds()) any_key.insert(any_key.end(), k.keys.begin(), k.keys.end());
    r.check_keys(node, path, any_key);
    throw InputError(r.location(node), path,
                     "missing key 'dist'; expected one of: " + join_names(kind_names));
  }
  const YAML::Node& dist_node = node["dist"];
  const std::string kind = r.read_string(dist_node, path + ".dist");
  const KindKeys* spec = nullptr;
  for (const auto& k : kinds()) {
    if (k.kind == kind) spec = &k;
  }
  if (!spec) {
    throw InputError(r.location(dist_node), path + ".dist",
                     "unknown distribution '" + kind + "'" + did_you_mean(kind, kind_names) +
                         "; expected one of: " + join_names(kind_names));
  }
  r.check_keys(node, path, spec->keys);
  for (const std::string_view key : spec->keys) {
    if (!node[std::string(key)]) {
      std::vector<std::string_view> params(spec->keys.begin() + 1, spec->keys.end());
      throw InputError(
          r.location(node), path,
          "missing key '" + std::string(key) + "'; " + kind + " needs: " + join_names(params));
    }
  }
  const auto num = [&](const char* key) { return r.read_number(node[key], path + "." + key); };

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
      throw InputError(r.location(list), path + ".values",
                       "expected a list of numbers, got " + model::describe(list));
    }
    std::vector<double> values;
    for (std::size_t k = 0; k < list.size(); ++k) {
      values.push_back(r.read_number(list[k], path + ".values[" + std::to_string(k) + "]"));
    }
    d = make_choice(std::move(values));
  }

  if (const auto problem = d.find_problem()) {
    const YAML::Node& at = node[problem->key] ? node[problem->key] : node;
    throw InputError(r.location(at), path + "." + problem->key,
                     kind + ": " + problem->message);
  }
  return d;
}

std::vector<VariedInput> read_vary(const YAML::Node& node, const model::YamlReader& r,
                                    const std::string& path) {
  std::vector<VariedInput> inputs;
  if (!node || node.IsNull()) return inputs;
  r.require_map(node, path);
  for (const auto& kv : node) {
    const std::string name = r.read_string(kv.first, path);
    const std::string key_path = path + "." + name;
    if (name.empty()) {
      throw InputError(r.location(kv.first), path, "expected an input name, got ''");
    }
    for (const auto& in : inputs) {
      if (in.name == name) {
        throw InputError(r.location(kv.first), key_path,
                         "input '" + name + "' is varied twice");
      }
    }
    inputs.push_back({name, read_distribution(kv.second, r, key_path)});
  }
  return inputs;
}

}  // namespace

Distribution parse_distribution(const YAML::Node& node, const SourceLocation& file, const std::string& path) {
  return read_distribution(node, model::YamlReader(file.file), path);
}

std::vector<VariedInput> parse_vary(const YAML::Node& node, const SourceLocation& file, const std::string& path) {
  return read_vary(node, model::YamlReader(file.file), path);
}

}  // namespace kanesens::study
