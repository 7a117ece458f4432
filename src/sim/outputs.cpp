#include "sim/outputs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dynamics/equations.hpp"

namespace kanesens::sim {

using dynamics::DynamicsOptions;
using dynamics::Workspace;
using math::Dual;
using model::Model;

namespace {
// The multiplier-form right-hand side on duals at (y, s), in scratch.y and scratch.ydot.
// False where u̇ (and λ) cannot be computed: the outputs that need them are then NaN.
bool evaluate_dual(const Model& m, DualWorkspace& ws, const DynamicsOptions& options, double t, const double* y,
                   const double* s, DualScratch scratch) {
  const int n = m.nstate();
  for (int r = 0; r < n; ++r) scratch.y[r] = Dual(y[r], s[r]);
  return dynamics::evaluate_rhs(m, ws, Dual(t), scratch.y, scratch.ydot, options);
}
}  // namespace

double energy(const Model& m, Workspace<double>& ws, double t, const double* y) {
  const double* q = y;
  const double* u = y + m.nq;
  dynamics::evaluate_state_expressions(m, ws, t, q, u);
  dynamics::compute_position(m, ws, q);
  dynamics::compute_velocity(m, ws, u);
  return dynamics::kinetic_energy(m, ws) + dynamics::potential_energy(m, ws, q);
}

void multipliers(const Model& m, Workspace<double>& ws, const DynamicsOptions& options, double t, const double* y,
                 double* ydot, double* lambda) {
  // Where λ cannot be determined it is recorded as NaN, never as a silent 0.
  const bool ok = dynamics::evaluate_rhs(m, ws, t, y, ydot, options);
  for (int r = 0; r < m.nconstraint_rows; ++r) lambda[r] = ok ? ws.multipliers[r] : std::nan("");
}

void multiplier_sensitivity(const Model& m, DualWorkspace& ws, const DynamicsOptions& options, double t,
                            const double* y, const double* s, DualScratch scratch, double* dlambda, int stride) {
  const bool ok = evaluate_dual(m, ws, options, t, y, s, scratch);
  for (int r = 0; r < m.nconstraint_rows; ++r) dlambda[r * stride] = ok ? ws.multipliers[r].d : std::nan("");
}

void constraint_residuals(const Model& m, Workspace<double>& ws, const DynamicsOptions& options,
                          const std::vector<int>& holonomic_rows, double t, const double* y, double& position,
                          double& velocity) {
  // The constraints' own stages (positions, velocities, the rows): no mass matrix, no solve.
  dynamics::evaluate_constraints(m, ws, t, y, y + m.nq, options);
  position = 0;
  velocity = 0;
  bool finite = true;
  for (int r : holonomic_rows) {
    finite = std::isfinite(ws.position_residual[r]) && finite;
    position = std::max(position, std::abs(ws.position_residual[r]));
  }
  for (int r = 0; r < m.nconstraint_rows; ++r) {
    finite = std::isfinite(ws.velocity_residual[r]) && finite;
    velocity = std::max(velocity, std::abs(ws.velocity_residual[r]));
  }
  if (!finite) position = velocity = std::nan("");  // std::max would drop a NaN
}

void sensitivity_constraint_residuals(const Model& m, DualWorkspace& ws, const DynamicsOptions& options,
                                      const std::vector<int>& holonomic_rows, double t, const double* y,
                                      const double* s, DualScratch scratch, double& position,
                                      double& velocity) {
  if (!evaluate_dual(m, ws, options, t, y, s, scratch)) {
    position = velocity = std::nan("");
    return;
  }
  position = 0;
  velocity = 0;
  for (int r : holonomic_rows) position = std::max(position, std::abs(ws.position_residual[r].d));
  for (int r = 0; r < m.nconstraint_rows; ++r) velocity = std::max(velocity, std::abs(ws.velocity_residual[r].d));
}

}  // namespace kanesens::sim
