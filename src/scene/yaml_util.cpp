#include "scene/yaml_util.hpp"

#include <algorithm>
#include <cctype>
#include <unordered_set>

#include "util/did_you_mean.hpp"
#include "util/input_text.hpp"

namespace kanesens::yaml {

SourceLocation location(const YAML::Node& node, const std::string& file) {
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return {file, 0, 0};
  return {file, m.line + 1, m.column + 1};
}

void fail(const YAML::Node& node, const std::string& file, const std::string& key,
          const std::string& what) {
  throw InputError(location(node, file), key, what);
}

static const char* type_name(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return "a scalar";
    case YAML::NodeType::Null: return "nothing (null)";
    default: return "undefined";
  }
}

void require_map(const YAML::Node& node, const std::string& file, const std::string& key) {
  if (!node.IsMap()) fail(node, file, key, std::string("expected a map, found ") + type_name(node));
}

void require_sequence(const YAML::Node& node, const std::string& file, const std::string& key) {
  if (!node.IsSequence())
    fail(node, file, key, std::string("expected a list, found ") + type_name(node));
}

void check_keys(const YAML::Node& node, const std::string& file, const std::string& key,
                std::initializer_list<const char*> allowed) {
  require_map(node, file, key);
  std::vector<std::string> names(allowed.begin(), allowed.end());
  std::unordered_set<std::string> seen;  // a map of 100 000 keys is checked in linear time
  for (const auto& kv : node) {
    if (!kv.first.IsScalar())
      fail(kv.first, file, key, std::string("expected a plain key, found ") + type_name(kv.first));
    const std::string k = kv.first.Scalar();
    // yaml-cpp keeps both entries of a repeated key and node[k] returns the first: refuse it
    // rather than silently ignoring the second value.
    if (!seen.insert(k).second)
      fail(kv.first, file, key.empty() ? k : key + "." + k, "key '" + k + "' is given twice");
    bool ok = false;
    for (const auto& a : names) ok = ok || a == k;
    if (!ok)
      fail(kv.first, file, key.empty() ? k : key + "." + k,
           "unknown key '" + k + "'" + did_you_mean(k, names) + "; allowed keys: " + join_names(names));
  }
}

YAML::Node required(const YAML::Node& map, const char* name, const std::string& file,
                    const std::string& key) {
  const YAML::Node n = map[name];
  if (!n) fail(map, file, key, std::string("missing required key '") + name + "'");
  return n;
}

std::string read_string(const YAML::Node& node, const std::string& file, const std::string& key) {
  if (!node.IsScalar()) fail(node, file, key, std::string("expected a name, found ") + type_name(node));
  return node.Scalar();
}

ExprText read_expr(const YAML::Node& node, const std::string& file, const std::string& key) {
  if (!node.IsScalar())
    fail(node, file, key, std::string("expected a number or expression, found ") + type_name(node));
  if (node.Scalar().empty()) fail(node, file, key, "empty value");
  // YAML's special floats (.nan, .inf, -.Inf, ...) are never valid values here.
  std::string lower;
  for (char c : node.Scalar()) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  if (lower == ".nan" || lower == ".inf" || lower == "+.inf" || lower == "-.inf")
    fail(node, file, key, "expected a finite number or expression, found '" + node.Scalar() + "'");
  return {node.Scalar(), location(node, file), key};
}

Vec3Text read_vec3(const YAML::Node& node, const std::string& file, const std::string& key) {
  if (!node.IsSequence() || node.size() != 3)
    fail(node, file, key, "expected a list of 3 numbers or expressions");
  Vec3Text v;
  for (int i = 0; i < 3; ++i) v[i] = read_expr(node[i], file, key + "[" + std::to_string(i) + "]");
  return v;
}

std::vector<ExprText> read_expr_list(const YAML::Node& node, const std::string& file,
                                     const std::string& key) {
  std::vector<ExprText> out;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      out.push_back(read_expr(node[i], file, key + "[" + std::to_string(i) + "]"));
  } else {
    out.push_back(read_expr(node, file, key));
  }
  return out;
}

YAML::Node load(const std::string& text, const std::string& file) {
  check_input_text(text, file);
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {  // ParserException, and anything else the loader throws
    if (e.mark.is_null()) throw InputError({file, 0, 0}, "", "malformed YAML: " + e.msg);
    throw InputError({file, e.mark.line + 1, e.mark.column + 1}, "", "malformed YAML: " + e.msg);
  }
}

std::string read_file(const std::string& path) { return read_input_file(path); }

}  // namespace kanesens::yaml
