// Projection onto the constraint manifold (solver.constraints.stabilization: projection): the
// state after every step (CVODES's projection callback, DOP853 after each accepted step), and the
// recorded sensitivities onto the tangent space (CVODES projects the state only).
#pragma once
#include <Eigen/Dense>
#include <vector>

#include "dynamics/options.hpp"
#include "dynamics/workspace.hpp"
#include "math/dual.hpp"
#include "math/min_norm_solver.hpp"
#include "sim/holonomic.hpp"

namespace kanesens::sim {

class Projector {
 public:
  Projector(const model::Model& model, HolonomicConstraints& holonomic);

  // The nearest consistent state (cvsPendulum_dns.c): positions by Newton on g(q) = 0 with
  // minimum-norm steps, then (unless `speeds_are_states` is false: the embedding, whose speeds
  // satisfy the constraints by construction) speeds by the minimum-norm correction of
  // A u + a0 = 0. y + corr is the projected state (n = nq + the speeds that are states); err,
  // when not null, is replaced by its projection onto the tangent space. 0, or 1 (recoverable)
  // when the correction is not finite. Its storage is allocated once; G comes from A where it can.
  int project(dynamics::Workspace<double>& ws, double t, const double* y, int n, bool speeds_are_states, double* corr,
              double* err);

  // Sensitivity s (nstate, in place) onto the tangent space of the constraints at (t, y): the
  // linearisation of project() — s_q ← s_q − G⁺(G s_q + ∂g/∂p), then s_u ← s_u − A⁺ d(A u + a0)/dε
  // along (s, e_p). `ws` carries the sensitivity's parameter tangent.
  void project_sensitivity(dynamics::Workspace<math::Dual>& ws, const dynamics::DynamicsOptions& options, double t,
                           const double* y, double* s);
  // The two corrections of project_sensitivity for k sensitivities s[0..k) at once, each
  // factorisation formed once: s_i,q ← s_i,q − G⁺ r_i, with r (holonomic rows × k) the tangents of
  // the holonomic residuals along (s_i, e_p) at (t, y); s_i,u ← s_i,u − A⁺ v_i, with A (m × nu) at
  // the state and v (m × k) the tangents of A u + a0 (taken after the position correction).
  void correct_sensitivity_positions(double t, const double* y, const Eigen::MatrixXd& r, double* const* s);
  void correct_sensitivity_speeds(const Eigen::MatrixXd& A, const Eigen::MatrixXd& v, double* const* s);
  // Throws the projection's failure at t unless the dual evaluation it needs succeeded (`ok`).
  static void check_evaluated(bool ok, double t);

 private:
  // Holonomic residual (and G) at q into g_ (G_): from the holonomic rows of A with q̇ = u for
  // every joint (one evaluation, ġ = G q̇ = G u), else by nq dual evaluations.
  void holonomic_residual(dynamics::Workspace<double>& ws, double t, const double* q, bool jacobian);

  const model::Model& model_;
  HolonomicConstraints& holonomic_;
  Eigen::VectorXd q_, dq_, du_, g_, zero_u_;
  Eigen::MatrixXd G_;
  math::MinNormSolver position_, velocity_;
};

}  // namespace kanesens::sim
