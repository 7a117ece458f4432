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

}  // namespace kanesens::dynamics::detail
