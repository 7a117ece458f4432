// Kane's equations as a residual at given accelerations (inverse dynamics), and the derivative of
// the forward dynamics obtained from it: the exact Jacobian without the mass matrix's tangents.
//
// At a state y = [q; u] with accelerations u̇* and multipliers λ* (plain numbers: the forward
// dynamics' solution there),
//     r(y) = f(q, u) − M(q) u̇* + A(q)ᵀ λ*      (nu)     Kane's F_r + F*_r at u̇*, plus Aᵀλ*
//     c(y) = A(q) u̇* − b(q, u)                  (m)      the acceleration constraint's residual
// both vanish, and differentiating M u̇ = f + Aᵀλ, A u̇ = b along a direction gives
//     M δu̇ − Aᵀ δλ = δr,    A δu̇ = −δc
// (δr, δc: the tangents of r and c with u̇*, λ* held fixed). So the tangents of u̇ need r and c on
// the tangent scalar — one Newton–Euler pass: positions, velocities, accelerations
// A = bias + Σ s u̇*, body wrenches projected on the partial velocities — and solves with M's
// and A M⁻¹ Aᵀ's factors on values. Neither M nor its factorisation is formed on the tangent
// scalar (Carpentier & Mansard 2018, "Analytical derivatives of rigid body dynamics algorithms";
// here the pass's derivatives come from dual numbers through the same templated stages).
// Redundant constraint rows (minimum-norm λ) are not covered: prepare() says so.
#pragma once
#include <Eigen/Core>

#include "dynamics/options.hpp"
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

// out[0, nq) = q̇, out[nq, nq + nu) = r, constraint_out[0, m) = c at (t, y) (parameters set).
// udot (nu) and multipliers (m; nullptr: λ* = 0) are values.
template <class S>
void evaluate_residual(const Model& m, Workspace<S>& ws, const S& t, const S* y, const double* udot,
                       const double* multipliers, const DynamicsOptions& options, S* out, S* constraint_out);

// The same residual in two parts, so that one pass gives f, then u̇ on values, then the residual
// at that u̇ without repeating the stages that do not depend on u̇ (3-D path only):
//   evaluate_residual_at_rest   the stages at u̇ = 0: out[0, nq) = q̇, constraint_out = −b, each
//                               body's applied minus inertial wrench at u̇ = 0 in ws.wrench (not
//                               yet summed over subtrees), the joints' own forces in ws.forcing;
//   forcing_values              f on values from them (wd: factor_mass_matrix_values's, at the
//                               same pass);
//   residual_from_rest          r = f − M u̇ (nu) and c += A u̇ at u̇ (values): the bodies'
//                               accelerations from u̇ alone, W − I a, then the subtree sums.
template <class S>
void evaluate_residual_at_rest(const Model& m, Workspace<S>& ws, const S& t, const S* y,
                               const DynamicsOptions& options, S* out, S* constraint_out);
template <class S>
void forcing_values(const Model& m, const Workspace<S>& ws, Workspace<double>& wd, double* f);
template <class S>
void residual_from_rest(const Model& m, Workspace<S>& ws, const double* udot, S* r, S* constraint_out);

// wd ← the values of ws's position stage and constraint matrix (ws evaluated at a state on any
// scalar), then M and its factor there on doubles, as solve_accelerations leaves them. False if M
// is not positive definite.
template <class S>
bool factor_mass_matrix_values(const Model& m, const Workspace<S>& ws, Workspace<double>& wd);

// Solves M δu̇ − Aᵀ δλ = δr, A δu̇ = −δc with the factors of M (factor_mass_matrix_values or
// solve_accelerations) and of A M⁻¹ Aᵀ on doubles. Scratch allocated at construction.
class AccelerationTangents {
 public:
  explicit AccelerationTangents(const Model& m);
  // Forms and factors A M⁻¹ Aᵀ (A: ws.constraint_matrix). False when the constraint rows are
  // (nearly) redundant at this state — the minimum-norm multipliers' derivative is not this
  // solve — or the system is not finite.
  bool prepare(const Model& m, Workspace<double>& ws);
  // λ (m) with Aᵀλ = −r0 (r0, nu: f − M u̇ at the forward dynamics' u̇): −(A M⁻¹ Aᵀ)⁻¹ A M⁻¹ r0.
  void multipliers(const Model& m, Workspace<double>& ws, const double* r0, double* lambda);
  // x (nu): δr in, δu̇ out; dc (m): δc in, overwritten. On a multi-tangent scalar every
  // tangent is solved at once (and the value along with them).
  template <class S>
  void solve(const Model& m, Workspace<double>& ws, S* x, S* dc) const;

 private:
  Eigen::MatrixXd minv_at_;  // nu×m: M⁻¹ Aᵀ
  Eigen::MatrixXd schur_;    // m×m: the Cholesky factor of A M⁻¹ Aᵀ (upper)
  Eigen::VectorXd schur_inverse_pivots_;  // m: its reciprocal pivots (the solves multiply)
  Eigen::VectorXd g_, x_;    // m, nu
};

}  // namespace kanesens::dynamics
