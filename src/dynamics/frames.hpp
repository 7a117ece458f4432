// Points of bodies in the local frames of the Workspace (dynamics/workspace.hpp): where a point
// is relative to its body's reference point, how far apart two points are, and — only when
// asked — where it is in the world. Valid after compute_position (velocities after
// compute_velocity). Templated on the scalar.
//
// A point is held as base + rel: base is large (its tree's anchor, or the point itself on
// ground), rel = tree_position + offset is a mechanism's size. Two points of one tree share the
// base, so their separation never subtracts world positions; points of two trees (or ground)
// subtract the two bases first, the best a double can do.
#pragma once
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

template <class S>
struct BodyPoint {
  int body = -1;   // -1: ground
  Vec3<S> offset;  // from the body's reference point Q_b, world components (ground: 0)
  Vec3<S> base;    // tree anchor (ground: the point)
  Vec3<S> rel;     // tree_position + offset (ground: 0)
};

// Offset of point r (body frame, from the mass center) of body b from Q_b: R_b (r − p_b).
template <class S>
Vec3<S> point_offset(const Workspace<S>& ws, int b, const Vec3<S>& r) {
  return ws.R[b] * (r - ws.reference_point[b]);
}

// Point r of body b (−1: ground, r in world components).
template <class S>
BodyPoint<S> body_point(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r) {
  BodyPoint<S> p;
  p.body = b;
  if (b < 0) {
    p.offset.setZero();
    p.base = r;
    p.rel.setZero();
    return p;
  }
  p.offset = point_offset(ws, b, r);
  p.base = ws.tree_anchor[m.bodies[b].root_joint];
  p.rel = ws.tree_position[b] + p.offset;
  return p;
}

// b − a.
template <class S>
Vec3<S> separation(const BodyPoint<S>& a, const BodyPoint<S>& b) {
  return (b.base - a.base) + (b.rel - a.rel);
}

// World position (formed on request: outputs, poses, the gravity potential).
template <class S>
Vec3<S> world_position(const BodyPoint<S>& p) {
  return p.base + p.rel;
}

// World position of point r (body frame, from the mass center) of body b.
template <class S>
Vec3<S> world_point(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r) {
  return world_position(body_point(m, ws, b, r));
}

// Velocity of a body point (after compute_velocity): v_Q + ω × offset.
template <class S>
Vec3<S> velocity_of(const Workspace<S>& ws, const BodyPoint<S>& p) {
  if (p.body < 0) return Vec3<S>::Zero();
  const Vec6<S>& V = ws.velocity[p.body];
  return V.template tail<3>() + V.template head<3>().cross(p.offset);
}

}  // namespace kanesens::dynamics
