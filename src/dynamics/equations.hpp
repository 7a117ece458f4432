// Kane's equations of a tree of rigid bodies, as plain functions over (Model, Workspace).
//
// Stages (each uses the ones before):
//   set_parameters            masses, inertias, axes, points        (dynamics/workspace.hpp)
//   evaluate_state_expressions force and spring expressions of t, q, u
//   compute_position          rotations, mass centers, joint points, partial velocities
//   compute_velocity          body velocities, bias accelerations (u̇ = 0)
//   compute_mass_matrix       M (nu×nu)
//   compute_forcing           f (nu): generalized active forces + inertia forces at u̇ = 0
//   solve_accelerations       u̇ = M⁻¹ f (tree LᵀDL or dense Cholesky)
//   (or, for unconstrained chains, articulated_body_accelerations: u̇ in O(nu))
//   compute_kinematic_derivatives  q̇ = N(q) u
//
// For speed k of joint j with child body C and joint point Q, the partial angular velocity is
// Ω_k and the partial velocity of a point P moved by C is V_k(P) = L_k + Ω_k × (P − Q)
// (Kane & Levinson 1985, ch. 2). Each is held as the spatial vector s_k = (Ω_k, L_k) at Q, with
// world-aligned axes (dynamics/workspace.hpp); M_kl = Σ_i m_i V_ik·V_il + Ω_ik·I_i Ω_il =
// s_k · I^c s_l with I^c the composite spatial inertia of the bodies both speeds move, and
// f_k = s_k · (Σ of the bodies' applied minus inertial wrenches), which is SymPy KanesMethod's
// `mass_matrix` / `forcing`. The sums are formed by the composite-rigid-body and Newton–Euler
// recursions (Featherstone 2008 ch. 5–6), each body's quantities at its own joint point and
// carried between neighbours by the joint's offset, so the numbers do not depend on where the
// mechanism stands.
#pragma once
#include "dynamics/options.hpp"
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

template <class S>
void evaluate_state_expressions(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u);
template <class S>
void compute_position(const Model& m, Workspace<S>& ws, const S* q);
template <class S>
void compute_velocity(const Model& m, Workspace<S>& ws, const S* u);
template <class S>
void compute_mass_matrix(const Model& m, Workspace<S>& ws);
template <class S>
void compute_forcing(const Model& m, Workspace<S>& ws, const S* q, const S* u);
// The first part of compute_forcing (3-D evaluation): each body's applied minus inertial wrench
// at u̇ = 0, at its Q, in ws.wrench (not yet summed over subtrees).
template <class S>
void compute_body_wrenches(const Model& m, Workspace<S>& ws);
// Returns false if M is not positive definite (a singular configuration or bad inertia).
template <class S>
bool solve_accelerations(const Model& m, Workspace<S>& ws);
// M's factor alone, as solve_accelerations leaves it (for solves with other right-hand sides).
template <class S>
bool factor_mass_matrix(const Model& m, Workspace<S>& ws);
// x ← M⁻¹ x (nu entries) with the factor of the last solve_accelerations. On a multi-tangent
// scalar the factor is of M's value and the tangents solve M0 x_i = b_i − M_i x0 (the derivative
// of M x = b), so no factorisation is done on tangents.
template <class S>
void apply_mass_inverse(const Model& m, Workspace<S>& ws, S* x);
// The same on a `support` of speeds (dynamics/tree_factor.hpp) when ws.tree_factor: x must be
// zero outside the support's ancestor closure; entries outside the support are neither read
// nor written.
template <class S>
void apply_mass_inverse(const Model& m, Workspace<S>& ws, S* x, const int* support, int ns);
// X ← M⁻¹ X for the nu×ncols row-major X (leading dimension ldx), every column at once, with the
// factor of the last solve_accelerations or factor_mass_matrix on double.
void apply_mass_inverse_rows(const Model& m, Workspace<double>& ws, double* X, std::ptrdiff_t ldx, int ncols);
template <class S>
void compute_kinematic_derivatives(const Model& m, Workspace<S>& ws, const S* q, const S* u);
// u̇ of an unconstrained tree by the articulated-body algorithm (Featherstone 2008 §7.3), in
// O(nu) without forming or factoring M (dynamics/articulated_body.cpp; double). Needs the
// position and velocity stages, compute_body_wrenches, and the joints' own generalized forces
// (spring-dampers) in ws.forcing. False if a joint's articulated inertia is not positive
// definite (M is not). evaluate_rhs uses it when ws.articulated_body.
template <class S>
bool articulated_body_accelerations(const Model& m, Workspace<S>& ws);

// Constraint rows at (q, u): A, a0-velocity residual, position residual and bias −(Ȧu + ȧ0),
// minus the Baumgarte terms of `options` (dynamics/constraints.cpp). Needs position, velocity
// and q̇ (compute_kinematic_derivatives).
template <class S>
void compute_constraints(const Model& m, Workspace<S>& ws, const S* q, const S* u,
                         const DynamicsOptions& options = {});
// A `rolling` constraint's rows are in the plane's basis (t1, t2, n): n the unit normal, t1 the
// world x axis projected onto the plane (the y axis when n is within ~25° of ±x), t2 = n × t1.
// Rows t1, t2 are the no-slip (nonholonomic) rows; row n is holonomic: its velocity form is the
// derivative of the contact height h = n·P − height of the wheel's lowest point P = c − r ŵ,
// ŵ = unit(n − (n·a) a) (a the axle), so A's n row is ∂h/∂q N(q). Needs the position stage.
template <class S>
void rolling_plane_basis(const Vec3<S>& n, Vec3<S>& t1, Vec3<S>& t2);
template <class S>
S rolling_contact_height(const Model& m, const Workspace<S>& ws, const Constraint& c);

// After solve_accelerations (ws.udot = M⁻¹ f): the multipliers λ and u̇ = M⁻¹(f + Aᵀλ).
// Returns false when no multiplier can be determined: every constraint row vanishes (rank 0)
// or the system is not finite. Redundant rows (0 < rank < rows) get the minimum-norm λ.
template <class S>
bool solve_constrained_accelerations(const Model& m, Workspace<S>& ws);

// Why evaluate_rhs could not compute u̇ at a state.
enum class RhsFailure { none, mass_matrix_not_positive_definite, constraints_degenerate };
// "mass matrix is not positive definite", ... (for messages).
const char* describe(RhsFailure failure);

// The whole right-hand side: y = [q; u] (nq + nu) → ydot = [q̇; u̇]. Returns false if u̇ could
// not be computed (then `failure`, if given, says why, and ydot must not be used): M is not
// positive definite, or the constraint system is degenerate. Parameters must have been set.
template <class S>
bool evaluate_rhs(const Model& m, Workspace<S>& ws, const S& t, const S* y, S* ydot,
                  const DynamicsOptions& options = {}, RhsFailure* failure = nullptr);
// The constraint rows at (t, q, u), without M and f: state expressions, position, velocity, q̇,
// then A, the residuals and the bias (compute_constraints). What every constraint-level use
// evaluates (projection, consistent initial state, the embedding's speeds).
template <class S>
void evaluate_constraints(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u,
                          const DynamicsOptions& options = {});
// Position, velocity, M and f at (t, q, u), without the solve.
template <class S>
void evaluate_mass_matrix_and_forcing(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u);

// Energies after compute_velocity (kinetic) / compute_position + state expressions (potential):
// kinetic ½ Σ V_iᵀ I_i V_i; potential −Σ m g·r_cm + joint springs + spring-dampers.
template <class S>
S kinetic_energy(const Model& m, const Workspace<S>& ws);
template <class S>
S potential_energy(const Model& m, const Workspace<S>& ws, const S* q);

// Rate of quaternion-norm correction in q̇ = ½ q ⊗ (0, ω) + κ (1 − |q|²) q, 1/s. On the unit
// sphere the term vanishes, so exact solutions are unchanged; off it, |q| relaxes back to 1.
inline constexpr double kQuaternionStabilization = 1.0;

namespace detail {
// s · F for a partial velocity s = (a, 0) (rotation: a·τ) or (0, a) (translation: a·F).
template <class S>
S power(const Vec6<S>& s, bool rotation, const Vec6<S>& F) {
  return rotation ? S(s.template head<3>().dot(F.template head<3>())) : S(s.template tail<3>().dot(F.template tail<3>()));
}

// The bodies' wrenches in ws.wrench, each at its joint point, summed over their subtrees (leaves
// to roots): afterwards a body's slot holds the wrench on its whole subtree.
template <class S>
void sum_over_subtrees(const Model& m, Workspace<S>& ws) {
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) math::add_force_to_parent<S>(ws.wrench[J.child], ws.joint_offset[*it], ws.wrench[J.parent]);
  }
}
}  // namespace detail

}  // namespace kanesens::dynamics
