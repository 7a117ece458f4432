// cos and sin of the joint angles that the position stages rotate by (Workspace::coordinate_angles),
// four or two at a time on their values (math::sincos4, sincos2), and their dual-number forms from
// those values: every scalar type then uses the same values, so a dual pass's values are the
// double pass's bits.
// Internal to dynamics/ (kinematics.cpp, planar.cpp).
#pragma once
#include "dynamics/workspace.hpp"
#include "math/dual.hpp"
#include "math/multi_dual.hpp"
#include "math/sincos.hpp"

namespace kanesens::dynamics::detail {

template <class S>
void compute_joint_angles(Workspace<S>& ws, const S* q) {
  const std::size_t count = ws.coordinate_angles.size();  // even
  std::size_t k = 0;
  for (; k + 4 <= count; k += 4) {
    const int* a = ws.coordinate_angles.data() + k;
    const double x[4] = {math::value_of(q[a[0]]), math::value_of(q[a[1]]), math::value_of(q[a[2]]),
                         math::value_of(q[a[3]])};
    double s[4], c[4];
    math::sincos4(x, s, c);
    for (int i = 0; i < 4; ++i) ws.angle_cos[a[i]] = c[i], ws.angle_sin[a[i]] = s[i];
  }
  for (; k < count; k += 2) {
    const int a = ws.coordinate_angles[k], b = ws.coordinate_angles[k + 1];
    const double x[2] = {math::value_of(q[a]), math::value_of(q[b])};
    double s[2], c[2];
    math::sincos2(x, s, c);
    ws.angle_cos[a] = c[0], ws.angle_sin[a] = s[0];
    ws.angle_cos[b] = c[1], ws.angle_sin[b] = s[1];
  }
}

// cos q and sin q on scalar S from c = cos and s = sin of q's value: the tangents as std::cos and
// std::sin of S form them (the chain rule at each level of a nested dual).
inline void angle_functions(double, double c, double s, double& cos_q, double& sin_q) {
  cos_q = c, sin_q = s;
}
template <class T>
void angle_functions(const math::DualT<T>& q, double c, double s, math::DualT<T>& cos_q, math::DualT<T>& sin_q) {
  T cv, sv;
  angle_functions(q.v, c, s, cv, sv);
  cos_q = {cv, -sv * q.d};
  sin_q = {sv, cv * q.d};
}
template <int N>
void angle_functions(const math::MultiDual<N>& q, double c, double s, math::MultiDual<N>& cos_q,
                     math::MultiDual<N>& sin_q) {
  cos_q = math::multi_dual_detail::chain(c, -s, q);
  sin_q = math::multi_dual_detail::chain(s, c, q);
}

// cos and sin of coordinate i (one of the coordinate_angles) on S.
template <class S>
void joint_angle(const Workspace<S>& ws, const S* q, int i, S& cos_q, S& sin_q) {
  angle_functions(q[i], ws.angle_cos[static_cast<std::size_t>(i)], ws.angle_sin[static_cast<std::size_t>(i)], cos_q,
                  sin_q);
}

}  // namespace kanesens::dynamics::detail
