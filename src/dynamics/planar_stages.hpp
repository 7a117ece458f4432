// The planar evaluation's stages (dynamics/planar.cpp), called by compute_position,
// compute_velocity, compute_mass_matrix and compute_forcing when Model::evaluate_planar().
// Internal to dynamics/. Same outputs as the 3-D stages: M, f, R, joint offsets, tree positions, velocity.
#pragma once
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics::detail {

template <class S>
void compute_position_planar(const Model& m, Workspace<S>& ws, const S* q);
template <class S>
void compute_velocity_planar(const Model& m, Workspace<S>& ws, const S* u);
template <class S>
void compute_mass_matrix_planar(const Model& m, Workspace<S>& ws);
// Fills ws.forcing from gravity, inertia and force elements (not joint springs/dampers).
template <class S>
void compute_forcing_planar(const Model& m, Workspace<S>& ws);
// Its first part: each body's applied minus inertial wrench at u̇ = 0, at its Q, in
// ws.wrench_planar (not yet summed over subtrees).
template <class S>
void compute_body_wrenches_planar(const Model& m, Workspace<S>& ws);
// u̇ of an unconstrained planar tree of one-speed joints by the articulated-body algorithm
// (dynamics/articulated_body.cpp), after compute_body_wrenches_planar.
template <class S>
bool articulated_body_accelerations_planar(const Model& m, Workspace<S>& ws);

// True for a speed k whose partial velocity is a rotation about ±z through Q_C with a constant
// axis, s = (σ, 0, 0), σ = ±1 (returned in sign): the stages multiply by the number σ and skip
// the zero entries, with the same values as the general sums (up to the sign of a zero).
template <class S>
bool constant_planar_rotation(const Model& m, const Workspace<S>& ws, int k, double& sign) {
  using math::has_tangent, math::value_of;  // and, by argument lookup, the tangent scalars' own
  const S& s0 = ws.partial_planar[static_cast<std::size_t>(k)][0];
  if (!m.speed_rotation[static_cast<std::size_t>(k)] || has_tangent(s0)) return false;
  sign = value_of(s0);
  return true;
}

// x σ for such a σ: x itself when σ = 1 (the usual axis, +z), whose product would be an exact
// copy on every scalar.
template <class S>
S times_sign(const S& x, double sign) {
  return sign == 1.0 ? x : S(x * sign);
}

}  // namespace kanesens::dynamics::detail
