#include "model/yaml_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <unordered_set>

#include "util/input_text.hpp"

namespace kanesens::model {

YAML::Node load_yaml(const std::string& text, const std::string& file) {
  check_input_text(text, file);  // UTF-8 without control characters, or file:line:column of the byte
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {  // ParserException, and anything else the loader throws
    if (e.mark.is_null()) throw InputError({file, 0, 0}, "", "malformed YAML: " + e.msg);
    throw InputError({file, e.mark.line + 1, e.mark.column + 1}, "", "malformed YAML: " + e.msg);
  }
}

std::string read_text_file(const std::string& path) { return read_input_file(path); }

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined()) return "nothing";
  switch (node.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
    case YAML::NodeType::Null: return "nothing (null)";
    case YAML::NodeType::Undefined: break;
  }
  return "nothing";
}

SourceLocation YamlReader::location(const YAML::Node& node) const {
  SourceLocation where{file_, 0, 0};
  if (node.IsDefined()) {
    const YAML::Mark mark = node.Mark();
    if (mark.line >= 0) where.line = mark.line + 1;
    if (mark.column >= 0) where.column = mark.column + 1;
  }
  return where;
}

void YamlReader::fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
  throw InputError(location(node), key, what);
}

void YamlReader::require_map(const YAML::Node& node, const std::string& key) const {
  if (!node.IsMap()) fail(node, key, "expected a map, got " + describe(node));
}

void YamlReader::require_sequence(const YAML::Node& node, const std::string& key) const {
  if (!node.IsSequence()) fail(node, key, "expected a list, got " + describe(node));
}

void YamlReader::check_keys(const YAML::Node& node, const std::string& key,
                            std::span<const std::string_view> allowed) const {
  require_map(node, key);
  std::unordered_set<std::string> seen;  // a map of 100 000 keys is checked in linear time
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) fail(kv.first, key, "expected a plain key, got " + describe(kv.first));
    const std::string& name = kv.first.Scalar();
    const std::string path = key.empty() ? name : key + "." + name;
    // yaml-cpp keeps both entries of a repeated key and node[k] returns the first: refuse it
    // rather than silently ignoring the second value.
    if (!seen.insert(name).second) fail(kv.first, path, "key '" + name + "' is given twice");
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      fail(kv.first, path,
           "unknown key '" + name + "'" + did_you_mean(name, allowed) + "; expected one of: " + join_names(allowed));
  }
}

YAML::Node YamlReader::required(const YAML::Node& map, const char* name, const std::string& key) const {
  const YAML::Node n = map[name];
  if (!n) fail(map, key, std::string("missing required key '") + name + "'");
  return n;
}

std::string YamlReader::read_string(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar()) fail(node, key, "expected a name, got " + describe(node));
  return node.Scalar();
}

ExprText YamlReader::read_expr(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar()) fail(node, key, "expected a number or expression, got " + describe(node));
  if (node.Scalar().empty()) fail(node, key, "empty value");
  // YAML's special floats (.nan, .inf, -.Inf, ...) are never valid values here.
  std::string lower;
  for (char c : node.Scalar()) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  if (lower == ".nan" || lower == ".inf" || lower == "+.inf" || lower == "-.inf")
    fail(node, key, "expected a finite number or expression, got " + describe(node));
  return {node.Scalar(), location(node), key};
}

Vec3Text YamlReader::read_vec3(const YAML::Node& node, const std::string& key) const {
  if (!node.IsSequence() || node.size() != 3)
    fail(node, key, "expected a list of 3 numbers or expressions, got " + describe(node));
  Vec3Text v;
  for (int i = 0; i < 3; ++i) v[i] = read_expr(node[i], key + "[" + std::to_string(i) + "]");
  return v;
}

std::vector<ExprText> YamlReader::read_expr_list(const YAML::Node& node, const std::string& key) const {
  std::vector<ExprText> out;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) out.push_back(read_expr(node[i], key + "[" + std::to_string(i) + "]"));
  } else {
    out.push_back(read_expr(node, key));
  }
  return out;
}

double YamlReader::read_number(const YAML::Node& node, const std::string& key) const {
  double x = 0;
  bool ok = node.IsScalar();
  if (ok) {
    try {
      x = node.as<double>();
    } catch (const YAML::Exception&) {
      ok = false;  // yaml-cpp also refuses numbers out of range (1e400) here
    }
  }
  if (!ok || !std::isfinite(x)) fail(node, key, "expected a finite number, got " + describe(node));
  return x;
}

std::int64_t YamlReader::read_integer(const YAML::Node& node, const std::string& key) const {
  if (node.IsScalar()) {
    const std::string& text = node.Scalar();
    std::int64_t n = 0;
    const char* end = text.data() + text.size();
    const auto res = std::from_chars(text.data(), end, n);
    if (res.ec == std::errc() && res.ptr == end) return n;
    double x = 0;
    const auto resd = std::from_chars(text.data(), end, x);
    // 2^63 is exactly representable; anything at or above it does not fit.
    if (resd.ec == std::errc() && resd.ptr == end && std::isfinite(x) && x == std::trunc(x) && std::fabs(x) < 0x1.0p63)
      return static_cast<std::int64_t>(x);
  }
  fail(node, key, "expected an integer, got " + describe(node));
}

std::uint64_t YamlReader::read_unsigned(const YAML::Node& node, const std::string& key) const {
  if (node.IsScalar()) {
    const std::string& text = node.Scalar();
    std::uint64_t n = 0;
    const char* end = text.data() + text.size();
    const auto res = std::from_chars(text.data(), end, n);
    if (res.ec == std::errc() && res.ptr == end) return n;
  }
  fail(node, key, "expected a non-negative integer below 2^64, got " + describe(node));
}

bool YamlReader::read_bool(const YAML::Node& node, const std::string& key) const {
  if (node.IsScalar()) {
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
    }
  }
  fail(node, key, "expected true or false, got " + describe(node));
}

}  // namespace kanesens::model
