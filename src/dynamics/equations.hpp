// Kane's equations of a tree of rigid bodies, as plain functions over (Model, Workspace).
//
// Stages (each uses the ones before):
//   set_parameters            masses, inertias, axes, points        (dynamics/workspace.hpp)
//   evaluate_state_expressions force and spring expressions of t, q, u
//   compute_position          rotations, mass centers, joint points, partial velocities
//   compute_velocity          body velocities, bias accelerations (u̇ = 0)
//   compute_mass_matrix       M (nu×nu)
//   compute_forcing           f (nu): generalized active forces + inertia forces at u̇ = 0
//   solve_accelerations       u̇ = M⁻¹ f (Cholesky)
//   compute_kinematic_derivatives  q̇ = N(q) u
//
// For speed k of joint j with child body C and joint point Q, the partial angular velocity is
// Ω_k and the partial velocity of a point P moved by C is V_k(P) = L_k + Ω_k × (P − Q)
// (Kane & Levinson 1985, ch. 2). Stored as the spatial vector s_k = (Ω_k, L_k + Q × Ω_k) at the
// world origin, M_kl = Σ_i m_i V_ik·V_il + Ω_ik·I_i Ω_il = s_kᵀ I^c s_l with I^c the composite
// spatial inertia of the bodies both speeds move, and f_k = s_k · (Σ of the bodies' applied
// minus inertial wrenches), which is SymPy KanesMethod's `mass_matrix` / `forcing`.
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
// Returns false if M is not positive definite (a singular configuration or bad inertia).
template <class S>
bool solve_accelerations(const Model& m, Workspace<S>& ws);
template <class S>
void compute_kinematic_derivatives(const Model& m, Workspace<S>& ws, const S* q, const S* u);

// Constraint rows at (q, u): A, a0-velocity residual, position residual and bias −(Ȧu + ȧ0),
// minus the Baumgarte terms of `options` (dynamics/constraints.cpp). Needs position, velocity
// and q̇ (compute_kinematic_derivatives).
template <class S>
void compute_constraints(const Model& m, Workspace<S>& ws, const S* q, const S* u,
                         const DynamicsOptions& options = {});
// The holonomic part of a `rolling` constraint after compute_position: the contact point's height
// above the plane, n̂·P − height. Its rows keep no position residual (they are the contact
// point's velocity, world components), but their combination n̂·(A u) is exactly the rate of this
// height, so it is a position constraint that linearization (sim/linearize.hpp) can solve for.
template <class S>
S rolling_height(const Workspace<S>& ws, const Constraint& c);
// After solve_accelerations (ws.udot = M⁻¹ f): the multipliers λ and u̇ = M⁻¹(f + Aᵀλ).
template <class S>
bool solve_constrained_accelerations(const Model& m, Workspace<S>& ws);

// The whole right-hand side: y = [q; u] (nq + nu) → ydot = [q̇; u̇]. Returns false if M is
// singular. Parameters must have been set.
template <class S>
bool evaluate_rhs(const Model& m, Workspace<S>& ws, const S& t, const S* y, S* ydot,
                  const DynamicsOptions& options = {});
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

}  // namespace kanesens::dynamics
