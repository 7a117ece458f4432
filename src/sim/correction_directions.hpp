// The directions along which the consistent initial state (sim/initial_state.hpp) may move the
// coordinates and the speeds, in order of preference. The correction takes, in this order, as
// many directions as the constraints have independent rows (each one only if it raises the rank).
//
// Rolling contacts first (docs/explanation/constraints.md, "Consistent initial state"): for every free joint
// that carries a wheel,
//   coordinates: its translation along each rolling plane's normal (the height), then its
//                rotation about the axle of the nearest wheel it carries, through that wheel's
//                centre (the pitch: it leaves that wheel's contact where it is);
//   speeds:      its translational speeds (the velocity follows from the rolling), its rotation
//                rate about each plane's normal (yaw rate) and about the nearest wheel's axle
//                (pitch rate), then the spin of the wheels on revolute joints, last wheel first.
// Heading, lean, steer, the wheels' angles and the driving speeds are not among them, so they
// keep their given values when the contacts can be closed otherwise. Then the unit directions of
// `fallback` (coordinate or speed indices; quaternion components never). Directions are in speed
// space and mapped to coordinates by q̇ = N(q) u (the quaternion part without its norm term).
#pragma once
#include <Eigen/Dense>
#include <vector>

#include "dynamics/workspace.hpp"

namespace kanesens::sim {

// nq × K. `ws` holds the sample's parameters; its position stage is evaluated at (t, q).
Eigen::MatrixXd coordinate_directions(const model::Model& m, dynamics::Workspace<double>& ws, double t,
                                      const double* q, const std::vector<int>& fallback);
// nu × K.
Eigen::MatrixXd speed_directions(const model::Model& m, dynamics::Workspace<double>& ws, double t, const double* q,
                                 const std::vector<int>& fallback);

}  // namespace kanesens::sim
