// Small 3-D and spatial-vector helpers, templated on the scalar.
// Spatial vectors are 6-vectors in Plücker coordinates (Featherstone 2008 ch. 2) taken at a
// reference point A, with world-aligned axes: a motion vector is (ω, v_A), v_A = velocity of the
// body-fixed point at A; a force vector is (τ_A, F), τ_A = moment about A. Their pairing
// m·f = ω·τ_A + v_A·F is power, the same at every point. The dynamics layer takes each body's
// inboard joint point as its reference point and moves vectors between neighbours with the
// small offset r = A_child − A_parent (motion_to_child, force_to_parent, SpatialInertia::
// to_parent), so no large world position enters a difference.
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

// R_P R(e_i, q): a rotation about a coordinate axis e_i leaves column i and mixes the other two
// (c, s = cos q, sin q) — 12 multiplications instead of the 27 of R_P times axis_angle, with the
// same rounding (the other products are by exact zeros and ones). Inlined where it is called (the
// 3-D position stage runs it once per joint): out of line, the call costs about as much as the
// twelve products.
template <int i, class S>
[[gnu::always_inline]] inline void rotate_about_coordinate_axis(const Mat3<S>& R_P, const S& c, const S& s,
                                                                Mat3<S>& R_C) {
  constexpr int j = (i + 1) % 3, k = (i + 2) % 3;
  R_C.col(i) = R_P.col(i);
  for (int r = 0; r < 3; ++r) {
    const S pj = R_P(r, j), pk = R_P(r, k);
    R_C(r, j) = pj * c + pk * s;
    R_C(r, k) = pk * c - pj * s;
  }
}
template <class S>
[[gnu::always_inline]] inline void rotate_about_coordinate_axis(const Mat3<S>& R_P, int i, const S& c, const S& s,
                                                                Mat3<S>& R_C) {
  switch (i) {  // constant column indices: straight-line code
    case 0: return rotate_about_coordinate_axis<0>(R_P, c, s, R_C);
    case 1: return rotate_about_coordinate_axis<1>(R_P, c, s, R_C);
    default: return rotate_about_coordinate_axis<2>(R_P, c, s, R_C);
  }
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

// A motion vector at A moved to B = A + r: (ω, v + ω × r).
// Formed in scalars (the same sums as m.tail + m.head × r): a vector written in halves and read
// back in pairs stalls store-to-load forwarding, and a chain of bodies reads each result next.
template <class S>
Vec6<S> motion_to_child(const Vec6<S>& m, const Vec3<S>& r) {
  Vec6<S> x;
  x << m[0], m[1], m[2], m[3] + (m[1] * r[2] - m[2] * r[1]), m[4] + (m[2] * r[0] - m[0] * r[2]),
      m[5] + (m[0] * r[1] - m[1] * r[0]);
  return x;
}

// A force vector at A moved to B = A − r: (τ + r × F, F).
template <class S>
Vec6<S> force_to_parent(const Vec6<S>& f, const Vec3<S>& r) {
  Vec6<S> x;
  x.template head<3>() = f.template head<3>() + r.cross(f.template tail<3>());
  x.template tail<3>() = f.template tail<3>();
  return x;
}

// parent += force_to_parent(f, r), one scalar at a time (the same sums): summing a subtree's
// wrenches runs this once per joint, each reading the previous one's result, and a Vec6
// temporary written in halves and read back in pairs stalls the store-to-load forwarding.
template <class S>
void add_force_to_parent(const Vec6<S>& f, const Vec3<S>& r, Vec6<S>& parent) {
  parent[0] += f[0] + (r[1] * f[5] - r[2] * f[4]);
  parent[1] += f[1] + (r[2] * f[3] - r[0] * f[5]);
  parent[2] += f[2] + (r[0] * f[4] - r[1] * f[3]);
  parent[3] += f[3];
  parent[4] += f[4];
  parent[5] += f[5];
}

// Spatial inertia at a reference point A in compact form (Featherstone 2008 §2.13): mass m,
// first moment h = m (c − A) (c the mass center) and rotational inertia about A,
// I = I_c + m (|c − A|² 1 − (c − A)(c − A)ᵀ), symmetric; world-aligned components. Sums
// (composite inertias) cost 13 additions and applying one to a motion vector 24
// multiplications, not the 36 of the 6×6 matrix.
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
  // (ω, v_A) ↦ (I ω + h × v_A, m v_A − h × ω): angular momentum about A and linear momentum.
  Vec6<S> operator*(const Vec6<S>& x) const {
    const Vec3<S> w = x.template head<3>(), v = x.template tail<3>();
    Vec6<S> r;
    r.template head<3>() = I * w + h.cross(v);
    r.template tail<3>() = m * v - h.cross(w);
    return r;
  }
  // The momentum of a rotation (a, 0) about an axis a through A, and of a translation (0, a).
  Vec6<S> times_rotation(const Vec3<S>& a) const {
    Vec6<S> r;
    r.template head<3>() = I * a;
    r.template tail<3>() = a.cross(h);
    return r;
  }
  Vec6<S> times_translation(const Vec3<S>& a) const {
    Vec6<S> r;
    r.template head<3>() = h.cross(a);
    r.template tail<3>() = m * a;
    return r;
  }
  // The same inertia at B = A − r (a body's composite inertia seen from its parent's point):
  // h' = h + m r, I' = I + 2 (k·r) 1 − (k rᵀ + r kᵀ) with k = h + m r / 2 (the parallel-axis
  // theorem between two points a body length apart).
  void add_to_parent(const Vec3<S>& r, SpatialInertia& parent) const {
    const Vec3<S> k = h + S(0.5) * m * r;
    const S kr2 = S(2) * k.dot(r);
    parent.m += m;
    parent.h += h + m * r;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        const S x = I(i, j) - (k[i] * r[j] + r[i] * k[j]) + (i == j ? kr2 : S(0));
        parent.I(i, j) += x;
        if (j != i) parent.I(j, i) += x;
      }
  }
  Mat6<S> matrix() const {  // the 6×6 form [I h×; −h× m1]
    Mat6<S> M;
    to_matrix(M);
    return M;
  }
  // The same into M, entry by entry (no 3×3 temporaries to copy: the articulated-body sweep
  // starts from it for every body).
  void to_matrix(Mat6<S>& M) const {
    const S H[3][3] = {{S(0), -h[2], h[1]}, {h[2], S(0), -h[0]}, {-h[1], h[0], S(0)}};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        M(i, j) = I(i, j);
        M(i, 3 + j) = H[i][j];
        M(3 + i, j) = -H[i][j];
        M(3 + i, 3 + j) = i == j ? m : S(0);
      }
  }
};

// X x = (I ω + h × v, m v − h × ω) for x = (ω, v), written in scalars (the same sums as
// operator*): the dynamics' per-body loops keep it in registers, without Eigen temporaries.
template <class S>
[[gnu::always_inline]] inline void momentum(const SpatialInertia<S>& X, const S* x, S* out) {
  const S w0 = x[0], w1 = x[1], w2 = x[2], v0 = x[3], v1 = x[4], v2 = x[5];
  const S h0 = X.h[0], h1 = X.h[1], h2 = X.h[2];
  const S Ixx = X.I(0, 0), Iyy = X.I(1, 1), Izz = X.I(2, 2), Ixy = X.I(0, 1), Ixz = X.I(0, 2), Iyz = X.I(1, 2);
  out[0] = Ixx * w0 + Ixy * w1 + Ixz * w2 + (h1 * v2 - h2 * v1);
  out[1] = Ixy * w0 + Iyy * w1 + Iyz * w2 + (h2 * v0 - h0 * v2);
  out[2] = Ixz * w0 + Iyz * w1 + Izz * w2 + (h0 * v1 - h1 * v0);
  out[3] = X.m * v0 - (h1 * w2 - h2 * w1);
  out[4] = X.m * v1 - (h2 * w0 - h0 * w2);
  out[5] = X.m * v2 - (h0 * w1 - h1 * w0);
}

// A body's spatial inertia at its reference point A in body-frame components (constant: set
// once per parameter set): mass m, central inertia I_c and mass center at c − A = −p.
template <class S>
SpatialInertia<S> body_inertia_at(const S& m, const Mat3<S>& I_c, const Vec3<S>& p) {
  SpatialInertia<S> X;
  X.m = m;
  X.h = -m * p;
  X.I = I_c + m * (p.squaredNorm() * Mat3<S>::Identity() - p * p.transpose());
  return X;
}

// X (body-frame components) in world-aligned components for the body rotation R (body →
// world): h_w = R h, I_w = R I Rᵀ (only its 6 distinct entries are formed).
template <class S>
void rotate_inertia(const SpatialInertia<S>& X, const Mat3<S>& R, SpatialInertia<S>& out) {
  out.m = X.m;
  out.h.noalias() = R * X.h;
  // T = R I from I's 6 distinct entries, then the upper triangle of T Rᵀ, in scalars (no 3×3
  // temporaries): 45 multiplications.
  const S a = X.I(0, 0), b = X.I(1, 1), c = X.I(2, 2), d = X.I(0, 1), e = X.I(1, 2), f = X.I(0, 2);
  S T[3][3];
  for (int i = 0; i < 3; ++i) {
    const S r0 = R(i, 0), r1 = R(i, 1), r2 = R(i, 2);
    T[i][0] = r0 * a + r1 * d + r2 * f;
    T[i][1] = r0 * d + r1 * b + r2 * e;
    T[i][2] = r0 * f + r1 * e + r2 * c;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const S x = T[i][0] * R(j, 0) + T[i][1] * R(j, 1) + T[i][2] * R(j, 2);
      out.I(i, j) = x;
      if (j != i) out.I(j, i) = x;
    }
}

// rotate_inertia for an X whose I is diagonal (a body whose mass center lies on a principal axis
// through its reference point, as a link's does): I_w = Σ_k I_kk R_k R_kᵀ, R_k column k of R,
// 27 multiplications instead of 45 and the same values bit for bit (rotate_inertia's products by
// the zero entries add exact zeros). With h_axis = k (X.h along e_k, its other components exact
// zeros), R X.h is column k of R times h_k: the same values again.
template <class S>
void rotate_diagonal_inertia(const SpatialInertia<S>& X, const Mat3<S>& R, SpatialInertia<S>& out,
                             int h_axis = -1) {
  out.m = X.m;
  if (h_axis >= 0)
    out.h = R.col(h_axis) * X.h[h_axis];
  else
    out.h.noalias() = R * X.h;
  const S d[3] = {X.I(0, 0), X.I(1, 1), X.I(2, 2)};
  S T[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) T[i][k] = R(i, k) * d[k];
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const S x = T[i][0] * R(j, 0) + T[i][1] * R(j, 1) + T[i][2] * R(j, 2);
      out.I(i, j) = x;
      if (j != i) out.I(j, i) = x;
    }
}

// rotate_inertia for an X that carries no tangent (a body's inertia when no parameter is
// differentiated) and an R that may. With T = R₀ I on values, P = R Tᵀ has the value R₀ I R₀ᵀ and
// in each tangent δR I R₀ᵀ, one half of the product's tangent δR I R₀ᵀ + R₀ I δRᵀ; the other half
// is its transpose. Products of duals by plain numbers replace products of duals. The values
// are rotate_inertia's, bit for bit.
template <class S>
void rotate_constant_inertia(const SpatialInertia<S>& X, const Mat3<S>& R, SpatialInertia<S>& out) {
  out.m = X.m;
  const double hx = value_of(X.h[0]), hy = value_of(X.h[1]), hz = value_of(X.h[2]);
  for (int i = 0; i < 3; ++i) out.h[i] = R(i, 0) * hx + R(i, 1) * hy + R(i, 2) * hz;
  const double a = value_of(X.I(0, 0)), b = value_of(X.I(1, 1)), c = value_of(X.I(2, 2));
  const double d = value_of(X.I(0, 1)), e = value_of(X.I(1, 2)), f = value_of(X.I(0, 2));
  double T[3][3];
  for (int i = 0; i < 3; ++i) {
    const double r0 = value_of(R(i, 0)), r1 = value_of(R(i, 1)), r2 = value_of(R(i, 2));
    T[i][0] = r0 * a + r1 * d + r2 * f;
    T[i][1] = r0 * d + r1 * b + r2 * e;
    T[i][2] = r0 * f + r1 * e + r2 * c;
  }
  S P[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P[i][j] = R(i, 0) * T[j][0] + R(i, 1) * T[j][1] + R(i, 2) * T[j][2];
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const S x = P[j][i] + (P[i][j] - value_of(P[i][j]));
      out.I(i, j) = x;
      if (j != i) out.I(j, i) = x;
    }
}

// A force F applied at offset r from the reference point, as a force vector there.
template <class S>
Vec6<S> wrench_at(const Vec3<S>& r, const Vec3<S>& F) {
  Vec6<S> w;
  w.template head<3>() = r.cross(F);
  w.template tail<3>() = F;
  return w;
}

}  // namespace kanesens::math
