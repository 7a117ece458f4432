// Planar spatial algebra (Featherstone 2008 §2.16) for scenes whose motion stays in the world
// x–y plane (Model::planar; see model/model.hpp for the criterion). A planar motion vector is
// (ω, v_x, v_y) = the z angular velocity and the in-plane velocity of the body-fixed point at a
// reference point A; a planar force vector is (τ, F_x, F_y), τ the z moment about A. They are
// the three components of the 6-D vectors of spatial.hpp that such motions can have non-zero
// (ω_z, v_x, v_y) and the three a planar motion's power sees (τ_z, F_x, F_y), so M and f come
// out identical to the 3-D evaluation, for about a quarter of its work. As in 3-D, each body's
// reference point is its inboard joint point and vectors move between neighbours by the
// in-plane offset r = A_child − A_parent.
#pragma once
#include "math/spatial.hpp"

namespace kanesens::math {

template <class S> using PVec = Vec3<S>;  // planar motion or force vector

// Planar inertia at A of a body or subtree: mass m, first moment h = m ((c − A)_x, (c − A)_y)
// and moment of inertia about the z axis through A, I = I_zz + m |c − A|²_xy. As a matrix
// [[I, −h_y, h_x], [−h_y, m, 0], [h_x, 0, m]].
template <class S>
struct PlanarInertia {
  S m = S(0), hx = S(0), hy = S(0), I = S(0);
  PlanarInertia& operator+=(const PlanarInertia& o) {
    m += o.m;
    hx += o.hx;
    hy += o.hy;
    I += o.I;
    return *this;
  }
  PVec<S> operator*(const PVec<S>& x) const {
    return {I * x[0] - hy * x[1] + hx * x[2], m * x[1] - hy * x[0], m * x[2] + hx * x[0]};
  }
  // The same inertia at B = A − r: h' = h + m r, I' = I + 2 h·r + m |r|².
  void add_to_parent(const S& rx, const S& ry, PlanarInertia& parent) const {
    parent.m += m;
    parent.I += I + (S(2) * hx + m * rx) * rx + (S(2) * hy + m * ry) * ry;
    parent.hx += hx + m * rx;
    parent.hy += hy + m * ry;
  }
};

// A planar motion vector at A moved to B = A + r: (ω, v_x − ω r_y, v_y + ω r_x).
template <class S>
PVec<S> motion_to_child_planar(const PVec<S>& m, const S& rx, const S& ry) {
  return {m[0], m[1] - m[0] * ry, m[2] + m[0] * rx};
}

// A planar force vector at A moved to B = A − r: (τ + r_x F_y − r_y F_x, F_x, F_y).
template <class S>
PVec<S> force_to_parent_planar(const PVec<S>& f, const S& rx, const S& ry) {
  return {f[0] + rx * f[2] - ry * f[1], f[1], f[2]};
}

// Motion × motion: (ω1, v1) × (ω2, v2) = (0, ω2 v1_y − ω1 v2_y, ω1 v2_x − ω2 v1_x).
template <class S>
PVec<S> cross_motion_planar(const PVec<S>& a, const PVec<S>& b) {
  return {S(0), b[0] * a[2] - a[0] * b[2], a[0] * b[1] - b[0] * a[1]};
}

// Motion ×* force: (ω, v) ×* (τ, F) = (v_x F_y − v_y F_x, −ω F_y, ω F_x).
template <class S>
PVec<S> cross_force_planar(const PVec<S>& m, const PVec<S>& f) {
  return {m[1] * f[2] - m[2] * f[1], -m[0] * f[2], m[0] * f[1]};
}

}  // namespace kanesens::math
