// Small 3-D and spatial-vector helpers, templated on the scalar.
// Spatial vectors are 6-vectors in world components taken at the world origin O (Plücker
// coordinates, Featherstone 2008 ch. 2): a motion vector is (ω, v_O), v_O = velocity of the
// body-fixed point at O; a force vector is (τ_O, F), τ_O = moment about O. Their pairing
// m·f = ω·τ_O + v_O·F is power.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "math/dual.hpp"

namespace kanesens::math {

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S> using Vec6 = Eigen::Matrix<S, 6, 1>;
template <class S> using Mat6 = Eigen::Matrix<S, 6, 6>;
template <class S> using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S> using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

template <class S>
Mat3<S> skew(const Vec3<S>& a) {
  Mat3<S> m;
  m << S(0), -a[2], a[1], a[2], S(0), -a[0], -a[1], a[0], S(0);
  return m;
}

// v / |v|, or 0 when |v| is not positive (a degenerate axis; parameter checks report it).
template <class S>
Vec3<S> unit_or_zero(const Vec3<S>& v) {
  using std::sqrt;
  const S n = sqrt(v.squaredNorm());
  if (!(value_of(n) > 0)) return Vec3<S>::Zero();
  return v / n;
}

// Rotation by angle q about unit axis a (Rodrigues).
template <class S>
Mat3<S> axis_angle(const Vec3<S>& a, const S& q) {
  using std::cos, std::sin;
  const S c = cos(q), s = sin(q), v = S(1) - c;
  Mat3<S> R;
  R << c + a[0] * a[0] * v, a[0] * a[1] * v - a[2] * s, a[0] * a[2] * v + a[1] * s,
       a[1] * a[0] * v + a[2] * s, c + a[1] * a[1] * v, a[1] * a[2] * v - a[0] * s,
       a[2] * a[0] * v - a[1] * s, a[2] * a[1] * v + a[0] * s, c + a[2] * a[2] * v;
  return R;
}

// Rotation matrix of the quaternion (w, x, y, z), normalised first (so a drifting norm does not
// distort the rotation).
template <class S>
Mat3<S> quaternion_rotation(const S& w0, const S& x0, const S& y0, const S& z0) {
  using std::sqrt;
  const S n = sqrt(w0 * w0 + x0 * x0 + y0 * y0 + z0 * z0);
  const S w = w0 / n, x = x0 / n, y = y0 / n, z = z0 / n;
  Mat3<S> R;
  R << S(1) - S(2) * (y * y + z * z), S(2) * (x * y - w * z), S(2) * (x * z + w * y),
       S(2) * (x * y + w * z), S(1) - S(2) * (x * x + z * z), S(2) * (y * z - w * x),
       S(2) * (x * z - w * y), S(2) * (y * z + w * x), S(1) - S(2) * (x * x + y * y);
  return R;
}

// Motion × motion: (ω1, v1) × (ω2, v2) = (ω1×ω2, ω1×v2 + v1×ω2).
template <class S>
Vec6<S> cross_motion(const Vec6<S>& a, const Vec6<S>& b) {
  Vec6<S> r;
  const Vec3<S> w1 = a.template head<3>(), v1 = a.template tail<3>();
  const Vec3<S> w2 = b.template head<3>(), v2 = b.template tail<3>();
  r.template head<3>() = w1.cross(w2);
  r.template tail<3>() = w1.cross(v2) + v1.cross(w2);
  return r;
}

// Motion ×* force: (ω, v) ×* (τ, F) = (ω×τ + v×F, ω×F).
template <class S>
Vec6<S> cross_force(const Vec6<S>& m, const Vec6<S>& f) {
  Vec6<S> r;
  const Vec3<S> w = m.template head<3>(), v = m.template tail<3>();
  const Vec3<S> t = f.template head<3>(), F = f.template tail<3>();
  r.template head<3>() = w.cross(t) + v.cross(F);
  r.template tail<3>() = w.cross(F);
  return r;
}

// Spatial inertia at O of a body of mass m, mass center c (world) and central inertia I (world):
// [[I + m [c]×[c]×ᵀ, m [c]×], [m [c]×ᵀ, m 1]], mapping (ω, v_O) to (angular momentum about O, p).
template <class S>
Mat6<S> spatial_inertia(const S& m, const Vec3<S>& c, const Mat3<S>& I) {
  const Mat3<S> C = skew<S>(c);
  Mat6<S> M;
  M.template topLeftCorner<3, 3>() = I - m * C * C;
  M.template topRightCorner<3, 3>() = m * C;
  M.template bottomLeftCorner<3, 3>() = -m * C;
  M.template bottomRightCorner<3, 3>() = m * Mat3<S>::Identity();
  return M;
}

// Spatial inertia at O in compact form (Featherstone 2008 §2.13): mass m, first moment h = m c
// (c the mass center, world) and rotational inertia about O, I = I_c + m (|c|² 1 − c cᵀ)
// (world, symmetric). The same operator as spatial_inertia()'s 6×6 matrix, but sums (composite
// inertias) cost 13 additions and applying one to a motion vector 24 multiplications, not 36.
template <class S>
struct SpatialInertia {
  S m = S(0);
  Vec3<S> h = Vec3<S>::Zero();
  Mat3<S> I = Mat3<S>::Zero();

  SpatialInertia& operator+=(const SpatialInertia& o) {
    m += o.m;
    h += o.h;
    I += o.I;
    return *this;
  }
  // (ω, v_O) ↦ (I ω + h × v_O, m v_O − h × ω): angular momentum about O and linear momentum.
  Vec6<S> operator*(const Vec6<S>& x) const {
    const Vec3<S> w = x.template head<3>(), v = x.template tail<3>();
    Vec6<S> r;
    r.template head<3>() = I * w + h.cross(v);
    r.template tail<3>() = m * v - h.cross(w);
    return r;
  }
  Mat6<S> matrix() const {  // the 6×6 form (tests)
    const Mat3<S> H = skew<S>(h);
    Mat6<S> M;
    M << I, H, -H, m * Mat3<S>::Identity();
    return M;
  }
};

// Compact spatial inertia of a body of mass m, mass center c (world), rotation R (body → world)
// and central inertia I_b (body frame): I_c = R I_b Rᵀ (only its 6 distinct entries are formed),
// then the parallel-axis shift to O. `inertia_world` receives I_c.
template <class S>
SpatialInertia<S> body_spatial_inertia(const S& m, const Vec3<S>& c, const Mat3<S>& R, const Mat3<S>& I_b,
                                       Mat3<S>& inertia_world) {
  const Mat3<S> T = R * I_b;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const S x = T(i, 0) * R(j, 0) + T(i, 1) * R(j, 1) + T(i, 2) * R(j, 2);
      inertia_world(i, j) = x;
      inertia_world(j, i) = x;
    }
  SpatialInertia<S> X;
  X.m = m;
  X.h = m * c;
  const S hc = X.h.dot(c);
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const S x = inertia_world(i, j) - X.h[i] * c[j] + (i == j ? hc : S(0));
      X.I(i, j) = x;
      X.I(j, i) = x;
    }
  return X;
}

// A force F applied at point r (world), as a force vector at O.
template <class S>
Vec6<S> wrench_at_origin(const Vec3<S>& r, const Vec3<S>& F) {
  Vec6<S> w;
  w.template head<3>() = r.cross(F);
  w.template tail<3>() = F;
  return w;
}

}  // namespace kanesens::math
