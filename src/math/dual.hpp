// Forward-mode dual numbers: x = v + d ε, ε² = 0, with v and d of type T (double, or a dual
// number again for second derivatives).
// Evaluating the model on Dual gives exact directional derivatives: with tangents (ẏ, ṗ) seeded
// on the state and parameters, the tangent of the right-hand side is J ẏ + (∂f/∂p) ṗ — one
// Jacobian column, or one CVODES sensitivity right-hand side, per evaluation. DualT<Dual> gives
// the second time derivatives that constraint biases need (Ȧu + ȧ0 of a position constraint).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <type_traits>

namespace kanesens::math {

template <class T>
struct DualT {
  T v = T(0);  // value
  T d = T(0);  // tangent
  constexpr DualT() = default;
  constexpr DualT(double value) : v(value) {}  // NOLINT: implicit from constants is intended
  template <class U = T, std::enable_if_t<!std::is_same_v<U, double>, int> = 0>
  constexpr DualT(const T& value) : v(value) {}  // NOLINT
  constexpr DualT(const T& value, const T& tangent) : v(value), d(tangent) {}

  DualT& operator+=(const DualT& o) { v += o.v; d += o.d; return *this; }
  DualT& operator-=(const DualT& o) { v -= o.v; d -= o.d; return *this; }
  DualT& operator*=(const DualT& o) { d = d * o.v + v * o.d; v *= o.v; return *this; }
  DualT& operator/=(const DualT& o) {
    const T inv = T(1) / o.v;
    v *= inv;
    d = (d - v * o.d) * inv;
    return *this;
  }
};
using Dual = DualT<double>;

template <class T> DualT<T> operator+(DualT<T> a, const DualT<T>& b) { return a += b; }
template <class T> DualT<T> operator-(DualT<T> a, const DualT<T>& b) { return a -= b; }
template <class T> DualT<T> operator*(DualT<T> a, const DualT<T>& b) { return a *= b; }
template <class T> DualT<T> operator/(DualT<T> a, const DualT<T>& b) { return a /= b; }
template <class T> DualT<T> operator+(const DualT<T>& a, double b) { return {a.v + b, a.d}; }
template <class T> DualT<T> operator+(double a, const DualT<T>& b) { return {a + b.v, b.d}; }
template <class T> DualT<T> operator-(const DualT<T>& a, double b) { return {a.v - b, a.d}; }
template <class T> DualT<T> operator-(double a, const DualT<T>& b) { return {a - b.v, -b.d}; }
template <class T> DualT<T> operator*(const DualT<T>& a, double b) { return {a.v * b, a.d * b}; }
template <class T> DualT<T> operator*(double a, const DualT<T>& b) { return {a * b.v, a * b.d}; }
template <class T> DualT<T> operator/(const DualT<T>& a, double b) { return {a.v / b, a.d / b}; }
template <class T> DualT<T> operator/(double a, const DualT<T>& b) {
  const T r = a / b.v;
  return {r, -r * b.d / b.v};
}
template <class T> DualT<T> operator-(const DualT<T>& a) { return {-a.v, -a.d}; }
template <class T> DualT<T> operator+(const DualT<T>& a) { return a; }

template <class T> bool operator==(const DualT<T>& a, const DualT<T>& b) { return a.v == b.v; }
template <class T> bool operator!=(const DualT<T>& a, const DualT<T>& b) { return a.v != b.v; }
template <class T> bool operator<(const DualT<T>& a, const DualT<T>& b) { return a.v < b.v; }
template <class T> bool operator>(const DualT<T>& a, const DualT<T>& b) { return a.v > b.v; }
template <class T> bool operator<=(const DualT<T>& a, const DualT<T>& b) { return a.v <= b.v; }
template <class T> bool operator>=(const DualT<T>& a, const DualT<T>& b) { return a.v >= b.v; }

// Scalar-generic helpers so templated code reads the same for double and duals.
inline double value_of(double x) { return x; }
template <class T> double value_of(const DualT<T>& x) { return value_of(x.v); }
inline double tangent_of(double) { return 0.0; }
inline double tangent_of(const Dual& x) { return x.d; }
// Whether x carries a nonzero tangent at any depth (false: a constant on this scalar).
inline bool has_tangent(double) { return false; }
template <class T> bool has_tangent(const DualT<T>& x) { return has_tangent(x.v) || value_of(x.d) != 0 || has_tangent(x.d); }

template <class T> DualT<T> sin(const DualT<T>& a) { using std::sin, std::cos; return {sin(a.v), cos(a.v) * a.d}; }
template <class T> DualT<T> cos(const DualT<T>& a) { using std::sin, std::cos; return {cos(a.v), -sin(a.v) * a.d}; }
// sin a and cos a with the value's sine and cosine taken once (the bits of sin and cos, at every
// level of a nested dual); s and c must not alias a.
inline void sin_cos(double a, double& s, double& c) { s = std::sin(a), c = std::cos(a); }
template <class T> void sin_cos(const DualT<T>& a, DualT<T>& s, DualT<T>& c) {
  sin_cos(a.v, s.v, c.v);
  s.d = c.v * a.d;
  c.d = -s.v * a.d;
}
template <class T> DualT<T> tan(const DualT<T>& a) {
  using std::tan;
  const T t = tan(a.v);
  return {t, (T(1) + t * t) * a.d};
}
template <class T> DualT<T> asin(const DualT<T>& a) { using std::asin, std::sqrt; return {asin(a.v), a.d / sqrt(T(1) - a.v * a.v)}; }
template <class T> DualT<T> acos(const DualT<T>& a) { using std::acos, std::sqrt; return {acos(a.v), -a.d / sqrt(T(1) - a.v * a.v)}; }
template <class T> DualT<T> atan(const DualT<T>& a) { using std::atan; return {atan(a.v), a.d / (T(1) + a.v * a.v)}; }
template <class T> DualT<T> atan2(const DualT<T>& y, const DualT<T>& x) {
  using std::atan2;
  const T r2 = x.v * x.v + y.v * y.v;
  return {atan2(y.v, x.v), (x.v * y.d - y.v * x.d) / r2};
}
template <class T> DualT<T> exp(const DualT<T>& a) {
  using std::exp;
  const T e = exp(a.v);
  return {e, e * a.d};
}
template <class T> DualT<T> log(const DualT<T>& a) { using std::log; return {log(a.v), a.d / a.v}; }
template <class T> DualT<T> sqrt(const DualT<T>& a) {
  using std::sqrt;
  const T s = sqrt(a.v);
  return {s, value_of(s) > 0 ? a.d / (T(2) * s) : T(0)};
}
template <class T> DualT<T> abs(const DualT<T>& a) { using std::abs; return {abs(a.v), value_of(a.v) < 0 ? -a.d : a.d}; }
template <class T> DualT<T> pow(const DualT<T>& a, const DualT<T>& b) {
  using std::pow, std::log;
  const T p = pow(a.v, b.v);
  T d = b.v * pow(a.v, b.v - T(1)) * a.d;
  if (value_of(b.d) != 0 && value_of(a.v) > 0) d += p * log(a.v) * b.d;
  return {p, d};
}
template <class T> DualT<T> min(const DualT<T>& a, const DualT<T>& b) { return a.v <= b.v ? a : b; }
template <class T> DualT<T> max(const DualT<T>& a, const DualT<T>& b) { return a.v >= b.v ? a : b; }
template <class T> bool isfinite(const DualT<T>& a) { using std::isfinite; return isfinite(a.v) && isfinite(a.d); }

// Eigen's view of a dual scalar D: a signed real whose operations cost ReadCost_, AddCost_ and
// MulCost_ operations on doubles (Dual below; Dual2 in math/dual2.hpp).
template <class D, int ReadCost_, int AddCost_, int MulCost_>
struct DualNumTraits : Eigen::NumTraits<double> {
  using Real = D;
  using NonInteger = D;
  using Nested = D;
  using Literal = D;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 0,
         ReadCost = ReadCost_, AddCost = AddCost_, MulCost = MulCost_ };
};

}  // namespace kanesens::math

namespace Eigen {
template <>
struct NumTraits<kanesens::math::Dual> : kanesens::math::DualNumTraits<kanesens::math::Dual, 2, 2, 3> {};
// A dual number and a double combine to a dual number, at every order.
template <class T, typename BinaryOp>
struct ScalarBinaryOpTraits<kanesens::math::DualT<T>, double, BinaryOp> { using ReturnType = kanesens::math::DualT<T>; };
template <class T, typename BinaryOp>
struct ScalarBinaryOpTraits<double, kanesens::math::DualT<T>, BinaryOp> { using ReturnType = kanesens::math::DualT<T>; };
}  // namespace Eigen
