// SceneSpec → Model: validates everything (names, references, topology, axes, masses, inertias)
// and compiles every expression once. Errors are InputErrors naming file:line:column and key.
#pragma once
#include <map>
#include <optional>
#include <string>

#include "model/model.hpp"
#include "model/parameters.hpp"
#include "model/scene/scene_spec.hpp"

namespace kanesens::model {

// Size limits of a scene (kanesens's mass matrix and constraint system are dense: nu² and m²).
inline constexpr std::size_t kMaxBodies = 4096;
inline constexpr int kMaxSpeeds = 4096;  // also the limit of constraint rows

// `overrides`: parameter name → value (from --set), replacing the scene's value.
Model build_model(const SceneSpec& spec, const std::map<std::string, double>& overrides = {});

}  // namespace kanesens::model
