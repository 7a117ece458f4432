#include "sim/outputs.hpp"

#include <algorithm>
#include <cmath>

#include "dynamics/equations.hpp"

namespace kanesens::sim {

using dynamics::DynamicsOptions;
using dynamics::Workspace;
using math::Dual;
using model::Model;

namespace {
// The multiplier-form right-hand side on duals at (y, s).
void evaluate_dual(const Model& m, DualWorkspace& ws, const DynamicsOptions& options, double t, const double* y,
                   const double* s) {
  const int n = m.nstate();
  std::vector<Dual> yd(static_cast<std::size_t>(n)), ydot(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) yd[static_cast<std::size_t>(r)] = Dual(y[r], s[r]);
  dynamics::evaluate_rhs(m, ws, Dual(t), yd.data(), ydot.data(), options);
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
                 double* lambda) {
  std::vector<double> ydot(static_cast<std::size_t>(m.nstate()));
  dynamics::evaluate_rhs(m, ws, t, y, ydot.data(), options);
  for (int r = 0; r < m.nconstraint_rows; ++r) lambda[r] = ws.multipliers[r];
}

void multiplier_sensitivity(const Model& m, DualWorkspace& ws, const DynamicsOptions& options, double t,
                            const double* y, const double* s, double* dlambda) {
  evaluate_dual(m, ws, options, t, y, s);
  for (int r = 0; r < m.nconstraint_rows; ++r) dlambda[r] = ws.multipliers[r].d;
}

void constraint_residuals(const Model& m, Workspace<double>& ws, const DynamicsOptions& options,
                          const std::vector<int>& holonomic_rows, double t, const double* y, double& position,
                          double& velocity) {
  std::vector<double> ydot(static_cast<std::size_t>(m.nstate()));
  dynamics::evaluate_rhs(m, ws, t, y, ydot.data(), options);
  position = 0;
  velocity = 0;
  for (int r : holonomic_rows) position = std::max(position, std::abs(ws.position_residual[r]));
  for (int r = 0; r < m.nconstraint_rows; ++r) velocity = std::max(velocity, std::abs(ws.velocity_residual[r]));
}

void sensitivity_constraint_residuals(const Model& m, DualWorkspace& ws, const DynamicsOptions& options,
                                      const std::vector<int>& holonomic_rows, double t, const double* y,
                                      const double* s, double& position, double& velocity) {
  evaluate_dual(m, ws, options, t, y, s);
  position = 0;
  velocity = 0;
  for (int r : holonomic_rows) position = std::max(position, std::abs(ws.position_residual[r].d));
  for (int r = 0; r < m.nconstraint_rows; ++r) velocity = std::max(velocity, std::abs(ws.velocity_residual[r].d));
}

}  // namespace kanesens::sim
