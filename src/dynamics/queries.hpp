// Kinematic and kinetic quantities of bodies, points and joints, read from an evaluated
// Workspace: the stable interface of the dynamics layer for everything outside it (outputs,
// poses, tests). Whatever frames the stages keep internally, these keep their meaning.
//
// Body b ≥ 0 (ground has no entry); r is a point in b's body frame, whose origin is the body's
// mass center (docs/reference/scene.md). All results are world components. Each query is valid
// after the stage named in brackets has run on the workspace:
//   [position]     evaluate_state_expressions + compute_position
//   [velocity]     ... + compute_velocity
//   [rhs]          evaluate_rhs (u̇ in ws.udot and, with constraints, λ in ws.multipliers)
// Templated on the scalar: on dual numbers every result carries its exact derivative.
#pragma once
#include <vector>

#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

// [position] Position of body b's frame origin (its mass center).
template <class S>
Vec3<S> body_position(const Model& m, const Workspace<S>& ws, int b);
// [position] Rotation of body b: world = R · body.
template <class S>
Mat3<S> body_rotation(const Model& m, const Workspace<S>& ws, int b);
// [position] The unit quaternion (w, x, y, z) of a rotation matrix, with w ≥ 0 (q and −q are the
// same rotation; a series crossing w = 0 flips sign there).
template <class S>
Eigen::Matrix<S, 4, 1> rotation_quaternion(const Mat3<S>& R);
// [position] World position of point r of body b.
template <class S>
Vec3<S> point_position(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r);
// [velocity] Angular velocity of body b.
template <class S>
Vec3<S> angular_velocity(const Model& m, const Workspace<S>& ws, int b);
// [velocity] Velocity of point r of body b.
template <class S>
Vec3<S> point_velocity(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r);
// [rhs] Angular acceleration of body b.
template <class S>
Vec3<S> angular_acceleration(const Model& m, const Workspace<S>& ws, int b);
// [rhs] Acceleration of point r of body b.
template <class S>
Vec3<S> point_acceleration(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r);

// The load a joint transmits: force and moment (about the joint point, on the child) that the
// parent exerts on the child.
template <class S>
struct JointLoad {
  Vec3<S> force, moment;
};
// [rhs] Every joint's load (loads.size() == joints), by a backward Newton–Euler pass: the
// load of joint J is Σ over the bodies of J's child subtree of (rate of change of momentum −
// external forces), external = gravity, force elements and the body forces of the constraint
// multipliers λ (coincident: λ on body_a at point_a, −λ on body_b; distance: λ along e_ab on
// body_b, the opposite on body_a; rolling: λ on the wheel at the contact point). Generalized
// forces that act through joint speeds (joint springs and dampers, coupler and general
// constraints) are part of the load of the joint whose speeds they act on. Allocates nothing
// but `loads` is written in place.
template <class S>
void joint_loads(const Model& m, const Workspace<S>& ws, std::vector<JointLoad<S>>& loads);

// A spring-damper's state: distance between its points, its rate, and the tension
// k (length − rest) + c rate (positive: pulling the points together).
template <class S>
struct ForceElementState {
  S length, rate, tension;
};
// [velocity] Force element f (a spring_damper).
template <class S>
ForceElementState<S> force_element_state(const Model& m, const Workspace<S>& ws, int f);

}  // namespace kanesens::dynamics
