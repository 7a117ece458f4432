// Strict YAML reading helpers: every error names file:line:column and the key path.
#pragma once
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "model/scene/scene_spec.hpp"
#include "util/error.hpp"

namespace kanesens::model {

SourceLocation location(const YAML::Node& node, const std::string& file);

[[noreturn]] void fail(const YAML::Node& node, const std::string& file, const std::string& key,
                       const std::string& what);

// Throws unless `node` is a map whose keys are all in `allowed` ("did you mean" for typos).
void check_keys(const YAML::Node& node, const std::string& file, const std::string& key,
                std::initializer_list<const char*> allowed);
void require_map(const YAML::Node& node, const std::string& file, const std::string& key);
void require_sequence(const YAML::Node& node, const std::string& file, const std::string& key);
// node[name] which must exist.
YAML::Node required(const YAML::Node& map, const char* name, const std::string& file,
                    const std::string& key);
std::string read_string(const YAML::Node& node, const std::string& file, const std::string& key);
ExprText read_expr(const YAML::Node& node, const std::string& file, const std::string& key);
Vec3Text read_vec3(const YAML::Node& node, const std::string& file, const std::string& key);
// A scalar or a list of scalars, as expression texts.
std::vector<ExprText> read_expr_list(const YAML::Node& node, const std::string& file,
                                     const std::string& key);
// Parses text; a syntax error becomes an InputError with the position.
YAML::Node load(const std::string& text, const std::string& file);
// Reads a whole file; a missing file is an InputError naming it.
std::string read_file(const std::string& path);

}  // namespace kanesens::model
