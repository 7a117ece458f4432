// A parameter set's values and its physical validity. The values are what every evaluation of the
// model starts from (dynamics/workspace.hpp set_parameters); the check runs at build on the nominal
// values and for every sample.
#pragma once
#include <optional>
#include <string>

#include "model/model.hpp"

namespace kanesens::model {

// parameters (np): `given` with derived parameters recomputed from those before them
// (declaration order); values (one per expression slot): every parameter-only slot evaluated.
// Other slots of `values` are left as they are.
template <class S>
void evaluate_parameter_values(const Model& model, const S* given, S* parameters, S* values);

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

}  // namespace kanesens::model
