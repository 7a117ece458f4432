// Evaluation of a study's outputs (sim/output_plan.hpp) at one state: the one function every use
// goes through (recorded series, `at:` values, quadrature integrands), templated on the scalar.
// On dual numbers — y seeded with a state sensitivity s and the workspace carrying ∂/∂p — each
// value's tangent is the output's exact sensitivity ∂out/∂y·s + ∂out/∂p; acceleration-level
// outputs (point accelerations, joint loads, λ) differentiate u̇ and λ exactly.
#pragma once
#include <vector>

#include "dynamics/options.hpp"
#include "dynamics/queries.hpp"
#include "dynamics/workspace.hpp"
#include "sim/output_plan.hpp"

namespace kanesens::sim {

// Scratch of evaluate_series (allocated once, per thread and scalar type).
template <class S>
struct OutputScratch {
  explicit OutputScratch(const model::Model& m) : ydot(static_cast<std::size_t>(m.nstate())), loads(m.joints.size()) {}
  std::vector<S> ydot;
  std::vector<dynamics::JointLoad<S>> loads;
};

// Evaluates the series nodes of `program` at (t, y), y = [q; u] the full state, into
// values[slot] (values: plan.nvalues entries; the slots of other nodes are read by expressions
// and left as they are), with the workspace's parameters. Runs only the stages program.level
// needs; acceleration-level nodes use the multiplier form of the equations with `options` (the
// problem's Baumgarte gains). Returns false if the mass matrix is not positive definite (the
// acceleration-level values are then not set). Allocates nothing.
template <class S>
bool evaluate_series(const OutputPlan& plan, const OutputProgram& program, const model::Model& m,
                     dynamics::Workspace<S>& ws, const dynamics::DynamicsOptions& options, const S& t, const S* y,
                     S* values, OutputScratch<S>& scratch);

// The scalar expression nodes (plan.scalar_expressions), once the reductions' slots hold their
// values: values[slot] = expression of parameters and scalar slots.
template <class S>
void evaluate_scalar_expressions(const OutputPlan& plan, const S* parameters, S* values);

}  // namespace kanesens::sim
