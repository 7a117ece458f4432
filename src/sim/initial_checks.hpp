// Checks of a sample at its initial state, before anything is integrated (docs/reference/scene.md,
// "Degenerate constraints"). The consistent initial conditions and the integrator would find the
// same problems later — a constraint that constrains nothing there divides by a 0-column
// decomposition, a mass matrix that is not finite fails every step — after a run has created
// its output; validation finds them first and names where they were written.
#pragma once
#include "dynamics/workspace.hpp"
#include "model/model.hpp"

namespace kanesens::sim {

// After evaluate_constraints at (t, q, u): throws InputError at the constraint's place in the
// scene when one of its values (A, residuals, bias) is not finite, or when every one of its rows
// of A vanishes (|a_k| ≤ 1e-12 max(1, max |A|)): it then constrains nothing at this state, and
// its multiplier is undetermined. A vanishing row of a constraint whose other rows do not (the
// z row of a point-on-point constraint in a planar scene) is a redundant row, left alone.
template <class S>
void check_constraint_rows(const model::Model& m, const dynamics::Workspace<S>& ws, double t);

}  // namespace kanesens::sim
