// SceneSpec → Model: validates everything (names, references, topology, axes, masses, inertias)
// and compiles every expression once. Errors are InputErrors naming file:line:column and key.
#pragma once
#include <map>
#include <optional>
#include <string>

#include "model/model.hpp"
#include "scene/scene_spec.hpp"

namespace kanesens {

// Size limits of a scene (kanesens's mass matrix and constraint system are dense: nu² and m²).
inline constexpr std::size_t kMaxBodies = 4096;
inline constexpr int kMaxSpeeds = 4096;  // also the limit of constraint rows

// `overrides`: parameter name → value (from --set), replacing the scene's value.
Model build_model(const SceneSpec& spec, const std::map<std::string, double>& overrides = {});

// Checks physical validity of a parameter set (mass > 0, inertia positive semi-definite and
// satisfying the triangle inequality, non-zero axes, finite values). Returns "" when valid, else
// a message naming the body/joint. Used at build (nominal values) and for every sample.
std::string check_parameters(const Model& model, const double* parameters);

// The first problem check_parameters() finds, with where it was written: the offending
// expression, the body's mass or inertia, the joint's axis (file:line:column and key path).
struct ParameterProblem {
  std::string message;
  SourceLocation where;
  std::string key;
};
std::optional<ParameterProblem> find_parameter_problem(const Model& model, const double* parameters);

}  // namespace kanesens
