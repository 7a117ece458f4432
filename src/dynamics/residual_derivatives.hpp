// The derivatives of Kane's residual r = f(q, u) − M(q) u̇ (u̇ held fixed) with respect to q and
// u in closed form, for trees of one-axis joints: Carpentier & Mansard 2018, "Analytical
// derivatives of rigid body dynamics algorithms", their recursive Newton–Euler derivatives in
// world-aligned spatial vectors.
//
// Why by hand: the residual's Jacobian by dual numbers (dynamics/inverse_dynamics.hpp) carries
// 2·nu tangents through every stage, O(nu²) work with the stages' whole constant; here the
// position and velocity stages run once on doubles and the derivatives are a few spatial dot
// products per pair of speeds (a speed and one of its ancestors), so on 3-D chains of 8 to 10
// joints the Jacobian costs a fraction of the dual pass (docs/benchmarks.md, "What a sensitivity
// and the exact Jacobian cost").
//
// Each speed k is a rotation about, or a translation along, an axis S_k (a motion vector about
// its tree's anchor, world components) carried by the speeds before it on the way to the root
// (Model::speed_parent); moving speed j's coordinate moves everything after it: ∂S_k/∂q_j =
// S_j × S_k. With v_k, a_k the velocity and acceleration after speed k (gravity as the base's
// acceleration −g), Ψ̇_k = v_λ(k) × S_k, Ψ̈_k = a_λ(k) × S_k + v_λ(k) × Ψ̇_k, each body's
// f = I a + v ×* I v and B = (v ×*) I − I (v ×) + X(I v) (X(h) x = x ×* h), and their sums
// I^C, B^C, f^C over the bodies k moves, the inverse dynamics τ_k = S_k · f^C_k has, for j on k's
// way to the root
// (j ⪯ k),
//     ∂τ_k/∂u_j = 2 (I^C_k S_k)·Ψ̇_j + (B^Cᵀ_k S_k)·S_j,   ∂τ_k/∂q_j = (I^C_k S_k)·Ψ̈_j + (B^Cᵀ_k S_k)·Ψ̇_j,
//     ∂τ_j/∂u_k = S_j · (2 I^C_k Ψ̇_k + B^C_k S_k),       ∂τ_j/∂q_k = S_j · (S_k ×* f^C_k + I^C_k Ψ̈_k + B^C_k Ψ̇_k)
// (j ≠ k in the second line), and zero for speeds on different branches. r = Q − τ, Q the
// generalized applied forces other than gravity: the joints' spring-dampers in closed form, or,
// with force elements, Q on dual numbers (add_applied_forces).
#pragma once
#include <vector>

#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

class ResidualDerivatives {
 public:
  // Whether the closed form covers the model: the 3-D path (not Model::evaluate_planar), every
  // joint revolute, prismatic, cylindrical, universal, planar or weld (q̇ = u, one axis per
  // speed), no constraints.
  static bool applies(const Model& m);
  // Whether the applied forces need add_applied_forces (on dual numbers): the model has force
  // elements or expressions of t, q or u (which only force elements and joint spring-dampers
  // may read). Otherwise evaluate() includes the joints' spring-dampers.
  static bool needs_applied_pass(const Model& m) { return !m.forces.empty() || !m.state_slots.empty(); }

  explicit ResidualDerivatives(const Model& m);  // scratch for m (no allocation afterwards)

  // At the state (q, u) whose position and velocity stages ws holds (double; compute_position and
  // compute_velocity), with accelerations udot: r (nu) and its derivatives, row-major nu×2nu:
  // dr[k·2nu + j] = ∂r_k/∂q_j, dr[k·2nu + nu + j] = ∂r_k/∂u_j. r_scale (nu): the largest
  // magnitude among the terms of each r_k, to judge whether r vanishes to round-off.
  // joint_forces: include the joints' own spring-dampers (else r is gravity and inertia only).
  // mass_matrix (nu×nu, column-major): M, M_kj = S_j · I^C_k S_k for j ⪯ k, 0 elsewhere (the
  // composite-rigid-body sums, formed from the same composite inertias).
  void evaluate(const Model& m, const Workspace<double>& ws, const double* q, const double* u, const double* udot,
                bool joint_forces, double* r, double* r_scale, double* dr, double* mass_matrix);

  // After evaluate(…, joint_forces = false) at the same state (wd its workspace): the generalized
  // forces of the force elements and of the joints' spring-dampers, Q_k = S_k · Σ W over the
  // bodies k moves, and their derivatives along the directions [first, first + count) of y,
  // whose seeded state y (value and unit tangents) is on a multi-tangent scalar S. The kinematics
  // the force elements read (rotations, points, velocities) get their tangents in closed form
  // from the speeds' axes (∂X/∂q_j: the motion S_j of everything j moves; ∂v/∂q_j = S_j × v +
  // Ψ̇_j; ∂v/∂u_j = S_j), not from a pass of the position and velocity stages; the force elements
  // and expressions then run on S, and ∂Q_k/∂q_j gains (S_j × S_k)·Σ W for j before k. Q's
  // values are added to r and r_scale by the block with first == 0; the tangents to dr.
  template <class S>
  void add_applied_forces(const Model& m, const Workspace<double>& wd, Workspace<S>& ws, double t, const S* y,
                          int first, int count, double* r, double* r_scale, double* dr);

 private:
  struct Speed {
    Vec6<double> S, dS, ddS;  // axis, Ψ̇, Ψ̈
    Vec6<double> v, a;        // velocity and acceleration after the speed
    Vec6<double> IS;          // I^C S
    Vec3<double> BS;          // B^Cᵀ S (its force half is zero)
  };
  std::vector<Speed> speeds_;
  std::vector<SpatialInertia<double>> inertia_;  // nb: about the tree's anchor, then summed over subtrees
  // B = [B11 0; −2 p× 0] (residual_derivatives.cpp), p the linear momentum: B11 and p, summed.
  std::vector<Mat3<double>> b11_;                // nb
  std::vector<Vec3<double>> momentum_;           // nb
  std::vector<Vec6<double>> f_;                  // nb: f, then summed
  std::vector<Vec6<double>> f_abs_;              // nb: the magnitudes of f's terms, then summed
  // add_applied_forces: the bodies force elements act on; for one of them, the tangents of its
  // rotation, reference point (from a fixed point, and its tree's anchor) and velocity along
  // each speed's coordinate; per speed, the force elements' wrench (value) over the bodies it moves.
  struct KinematicTangents {
    Mat3<double> dR;
    Vec3<double> dQ, dAnchor;
    Vec6<double> dVq;
  };
  std::vector<int> loaded_;
  std::vector<KinematicTangents> kinematic_tangents_;  // nu
  std::vector<Vec6<double>> applied_wrench_;           // nu
};

}  // namespace kanesens::dynamics
