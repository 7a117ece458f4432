// Strict reading of the YAML of scene and study files. Every problem is an InputError naming
// file:line:column (from the node's mark; yaml-cpp counts from 0, InputError from 1), the key
// path, and what was expected against what was found:
//   "study.yaml:9:36: vary.m2.high: expected a finite number, got 'abc'"
#pragma once
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "model/scene/scene_spec.hpp"
#include "util/did_you_mean.hpp"
#include "util/error.hpp"

namespace kanesens::model {

// Parses text; a syntax error becomes an InputError with its position.
YAML::Node load_yaml(const std::string& text, const std::string& file);
// Reads a whole file; a missing file is an InputError naming it ("cannot open file").
std::string read_text_file(const std::string& path);
// What the user wrote, for messages: "a map", "a list", "'1.5'", "nothing (null)".
std::string describe(const YAML::Node& node);

// The readers of one file's nodes: `key` is the node's key path ("scene.bodies[1].mass").
class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  // The file with the node's 1-based line and column (0 when the node has no mark).
  SourceLocation location(const YAML::Node& node) const;
  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const;

  void require_map(const YAML::Node& node, const std::string& key) const;
  void require_sequence(const YAML::Node& node, const std::string& key) const;
  // Throws unless `node` is a map whose keys are unique plain scalars, all in `allowed`; an
  // unknown key is reported at the key, with a did-you-mean and the allowed keys.
  void check_keys(const YAML::Node& node, const std::string& key, std::span<const std::string_view> allowed) const;
  void check_keys(const YAML::Node& node, const std::string& key, std::initializer_list<std::string_view> allowed) const {
    check_keys(node, key, std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  // map[name], which must exist.
  YAML::Node required(const YAML::Node& map, const char* name, const std::string& key) const;

  std::string read_string(const YAML::Node& node, const std::string& key) const;
  // A number or expression as text (not evaluated: the model compiles it).
  ExprText read_expr(const YAML::Node& node, const std::string& key) const;
  Vec3Text read_vec3(const YAML::Node& node, const std::string& key) const;
  // A scalar or a list of scalars, as expression texts.
  std::vector<ExprText> read_expr_list(const YAML::Node& node, const std::string& key) const;
  // A finite number (YAML's float syntax).
  double read_number(const YAML::Node& node, const std::string& key) const;
  // An integer, also written as an integral float ("1e6", "1024.0").
  std::int64_t read_integer(const YAML::Node& node, const std::string& key) const;
  std::uint64_t read_unsigned(const YAML::Node& node, const std::string& key) const;
  // YAML 1.1 booleans: true/false, yes/no, on/off, y/n.
  bool read_bool(const YAML::Node& node, const std::string& key) const;
  // One of `choices` by name; anything else: "expected one of a, b, found 'c'" with a did-you-mean.
  template <class E>
  E read_choice(const YAML::Node& node, const std::string& key,
                std::span<const std::pair<std::string_view, E>> choices) const {
    const std::string s = read_string(node, key);
    std::vector<std::string_view> names;
    for (const auto& [name, value] : choices) {
      if (name == s) return value;
      names.push_back(name);
    }
    fail(node, key, "expected one of " + join_names(names) + ", found '" + s + "'" + did_you_mean(s, names));
  }
  template <class E>
  E read_choice(const YAML::Node& node, const std::string& key,
                std::initializer_list<std::pair<std::string_view, E>> choices) const {
    return read_choice<E>(node, key, std::span<const std::pair<std::string_view, E>>(choices.begin(), choices.size()));
  }

 private:
  std::string file_;
};

}  // namespace kanesens::model
