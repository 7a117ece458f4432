// Strict readers for YAML scalars and maps that turn every problem into an InputError naming
// file:line:column (from the node's mark; yaml-cpp counts from 0, InputError from 1), the key
// path and expected vs actual. Small enough to move to util/ when the scene parser wants them.
#pragma once
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "util/error.hpp"

namespace kanesens::study {

// file's name with the node's 1-based line and column (0 when the node has no mark).
SourceLocation location_of(const YAML::Node& node, const SourceLocation& file);

// Throws unless `node` is a map whose keys are unique scalars, all in `allowed`. An unknown key
// is reported at the key, with a did-you-mean suggestion and the allowed keys.
void require_map(const YAML::Node& node, const std::string& path, const SourceLocation& file);
void check_keys(const YAML::Node& map, std::span<const std::string_view> allowed,
                const std::string& path, const SourceLocation& file);

std::string read_string(const YAML::Node& node, const std::string& path,
                        const SourceLocation& file);
double read_finite(const YAML::Node& node, const std::string& path, const SourceLocation& file);
// An integer, also written as an integral float ("1e6", "1024.0").
std::int64_t read_integer(const YAML::Node& node, const std::string& path,
                          const SourceLocation& file);
std::uint64_t read_unsigned(const YAML::Node& node, const std::string& path,
                            const SourceLocation& file);
bool read_bool(const YAML::Node& node, const std::string& path, const SourceLocation& file);

// "a number", "a map", "a list", "null" — what the user wrote, for messages.
std::string describe_node(const YAML::Node& node);

}  // namespace kanesens::study
