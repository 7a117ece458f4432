// Scene YAML → SceneSpec (docs/reference/scene.md). Strict: unknown keys, wrong types and missing
// keys are InputErrors naming file:line:column and the key path.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

#include "model/scene/scene_spec.hpp"

namespace kanesens::model {

// Reads a scene file (a document with `kanesens: 1` and `scene:`).
SceneSpec parse_scene_file(const std::string& path);
// Parses the `scene:` map; `file` and `text` are recorded for error messages and provenance.
SceneSpec parse_scene_node(const YAML::Node& scene, const std::string& file, const std::string& text);
// Parses a whole scene document given as text.
SceneSpec parse_scene_text(const std::string& text, const std::string& file);

}  // namespace kanesens::model
