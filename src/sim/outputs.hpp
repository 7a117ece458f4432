// What a trajectory records besides the state, at a full state y = [q; u] (nstate) and time t:
// the mechanical energy, the constraint multipliers and residuals, and their sensitivities along
// a state sensitivity s (nstate). The constrained outputs use the multiplier form of the
// equations (also for the embedding, which gives the same λ on the constraint manifold).
#pragma once
#include <vector>

#include "dynamics/options.hpp"
#include "dynamics/workspace.hpp"
#include "math/dual.hpp"

namespace kanesens::sim {

using DualWorkspace = dynamics::Workspace<math::Dual>;
// The state and its rate on duals (nstate each): the dual outputs' scratch, so that recording
// them allocates nothing.
struct DualScratch {
  math::Dual* y;
  math::Dual* ydot;
};

// T + V with the workspace's parameters.
double energy(const model::Model& m, dynamics::Workspace<double>& ws, double t, const double* y);
// λ (m) of M u̇ = f + Aᵀλ; ydot (nstate) is scratch, so that recording λ allocates nothing.
void multipliers(const model::Model& m, dynamics::Workspace<double>& ws, const dynamics::DynamicsOptions& options,
                 double t, const double* y, double* ydot, double* lambda);
// dλ/dε along (s, the workspace's parameter tangent), one dual evaluation: row r in
// dlambda[r · stride], so that one sensitivity's column of a row-major m × ns array is written in place.
void multiplier_sensitivity(const model::Model& m, DualWorkspace& ws, const dynamics::DynamicsOptions& options,
                            double t, const double* y, const double* s, DualScratch scratch, double* dlambda,
                            int stride = 1);
// max |g| over the holonomic rows, max |A u + a0| over all rows (NaN if any is not finite).
void constraint_residuals(const model::Model& m, dynamics::Workspace<double>& ws,
                          const dynamics::DynamicsOptions& options, const std::vector<int>& holonomic_rows, double t,
                          const double* y, double& position, double& velocity);
// The same for the sensitivity: max |G s_q + ∂g/∂p|, max |d(A u + a0)/dε| (both should be 0).
void sensitivity_constraint_residuals(const model::Model& m, DualWorkspace& ws,
                                      const dynamics::DynamicsOptions& options,
                                      const std::vector<int>& holonomic_rows, double t, const double* y,
                                      const double* s, DualScratch scratch, double& position, double& velocity);

}  // namespace kanesens::sim
