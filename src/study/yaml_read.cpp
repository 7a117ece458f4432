#include "study/yaml_read.hpp"

#include <charconv>
#include <cmath>
#include <unordered_set>
#include <vector>

#include "util/did_you_mean.hpp"

namespace kanesens::study {

SourceLocation location_of(const YAML::Node& node, const SourceLocation& file) {
  SourceLocation where{file.file, 0, 0};
  if (node.IsDefined()) {
    const YAML::Mark mark = node.Mark();
    if (mark.line >= 0) where.line = mark.line + 1;
    if (mark.column >= 0) where.column = mark.column + 1;
  }
  return where;
}

std::string describe_node(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Undefined:
      break;
  }
  return "nothing";
}

void require_map(const YAML::Node& node, const std::string& path, const SourceLocation& file) {
  if (!node.IsMap()) {
    throw InputError(location_of(node, file), path, "expected a map, got " + describe_node(node));
  }
}

void check_keys(const YAML::Node& map, std::span<const std::string_view> allowed,
                const std::string& path, const SourceLocation& file) {
  require_map(map, path, file);
  std::unordered_set<std::string> seen;
  for (const auto& kv : map) {
    const YAML::Node& key = kv.first;
    if (!key.IsScalar()) {
      throw InputError(location_of(key, file), path,
                       "expected a plain key, got " + describe_node(key));
    }
    const std::string& name = key.Scalar();
    const std::string key_path = path.empty() ? name : path + "." + name;
    bool known = false;
    for (const std::string_view a : allowed) known = known || a == name;
    if (!known) {
      throw InputError(location_of(key, file), key_path,
                       "unknown key '" + name + "'" + did_you_mean(name, allowed) +
                           "; expected one of: " + join_names(allowed));
    }
    if (!seen.insert(name).second) {
      throw InputError(location_of(key, file), key_path, "key '" + name + "' is given twice");
    }
  }
}

std::string read_string(const YAML::Node& node, const std::string& path,
                        const SourceLocation& file) {
  if (!node.IsScalar()) {
    throw InputError(location_of(node, file), path, "expected a name, got " + describe_node(node));
  }
  return node.Scalar();
}

double read_finite(const YAML::Node& node, const std::string& path, const SourceLocation& file) {
  double x = 0;
  bool ok = node.IsScalar();
  if (ok) {
    try {
      x = node.as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (!ok) {  // yaml-cpp also refuses numbers out of range (1e400) here
    throw InputError(location_of(node, file), path,
                     "expected a finite number, got " + describe_node(node));
  }
  if (!std::isfinite(x)) {
    throw InputError(location_of(node, file), path,
                     "expected a finite number, got " + describe_node(node));
  }
  return x;
}

std::int64_t read_integer(const YAML::Node& node, const std::string& path,
                          const SourceLocation& file) {
  if (node.IsScalar()) {
    const std::string& text = node.Scalar();
    std::int64_t n = 0;
    const char* end = text.data() + text.size();
    const auto res = std::from_chars(text.data(), end, n);
    if (res.ec == std::errc() && res.ptr == end) return n;
    double x = 0;
    const auto resd = std::from_chars(text.data(), end, x);
    // 2^63 is exactly representable; anything at or above it does not fit.
    if (resd.ec == std::errc() && resd.ptr == end && std::isfinite(x) && x == std::trunc(x) &&
        std::fabs(x) < 0x1.0p63) {
      return static_cast<std::int64_t>(x);
    }
  }
  throw InputError(location_of(node, file), path,
                   "expected an integer, got " + describe_node(node));
}

std::uint64_t read_unsigned(const YAML::Node& node, const std::string& path,
                            const SourceLocation& file) {
  if (node.IsScalar()) {
    const std::string& text = node.Scalar();
    std::uint64_t n = 0;
    const char* end = text.data() + text.size();
    const auto res = std::from_chars(text.data(), end, n);
    if (res.ec == std::errc() && res.ptr == end) return n;
  }
  throw InputError(location_of(node, file), path,
                   "expected a non-negative integer below 2^64, got " + describe_node(node));
}

bool read_bool(const YAML::Node& node, const std::string& path, const SourceLocation& file) {
  if (node.IsScalar()) {
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
    }
  }
  throw InputError(location_of(node, file), path,
                   "expected true or false, got " + describe_node(node));
}

}  // namespace kanesens::study
