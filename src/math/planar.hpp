// Planar spatial algebra (Featherstone 2008 §2.16) for scenes whose motion stays in the world
// x–y plane (Model::planar; see model/model.hpp for the criterion). A planar motion vector is
// (ω, v_x, v_y) = the z angular velocity and the in-plane velocity of the body-fixed point at
// the world origin O; a planar force vector is (τ, F_x, F_y), τ the z moment about O. They are
// the three components of the 6-D vectors of spatial.hpp that such motions can have non-zero
// (ω_z, v_x, v_y) and the three a planar motion's power sees (τ_z, F_x, F_y), so M and f come
// out identical to the 3-D evaluation, for about a quarter of its work.
#pragma once
#include "math/spatial.hpp"

namespace kanesens::math {

template <class S> using PVec = Vec3<S>;  // planar motion or force vector

// Planar inertia at O of a body or subtree: mass m, first moment h = m (c_x, c_y) and moment of
// inertia about the z axis through O, I = I_zz + m (c_x² + c_y²). As a matrix
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
};

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
