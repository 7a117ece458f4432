// Forward-mode dual number with one tangent: x = v + d ε, ε² = 0.
// Evaluating the model on Dual gives exact directional derivatives: with tangents (ẏ, ṗ) seeded
// on the state and parameters, the tangent of the right-hand side is J ẏ + (∂f/∂p) ṗ — one
// Jacobian column, or one CVODES sensitivity right-hand side, per evaluation.
#pragma once
#include <Eigen/Core>
#include <cmath>

namespace kanesens {

struct Dual {
  double v = 0;  // value
  double d = 0;  // tangent
  constexpr Dual() = default;
  constexpr Dual(double value) : v(value) {}  // NOLINT: implicit from constants is intended
  constexpr Dual(double value, double tangent) : v(value), d(tangent) {}

  Dual& operator+=(const Dual& o) { v += o.v; d += o.d; return *this; }
  Dual& operator-=(const Dual& o) { v -= o.v; d -= o.d; return *this; }
  Dual& operator*=(const Dual& o) { d = d * o.v + v * o.d; v *= o.v; return *this; }
  Dual& operator/=(const Dual& o) {
    const double inv = 1.0 / o.v;
    v *= inv;
    d = (d - v * o.d) * inv;
    return *this;
  }
};

inline Dual operator+(Dual a, const Dual& b) { return a += b; }
inline Dual operator-(Dual a, const Dual& b) { return a -= b; }
inline Dual operator*(Dual a, const Dual& b) { return a *= b; }
inline Dual operator/(Dual a, const Dual& b) { return a /= b; }
inline Dual operator+(const Dual& a, double b) { return {a.v + b, a.d}; }
inline Dual operator+(double a, const Dual& b) { return {a + b.v, b.d}; }
inline Dual operator-(const Dual& a, double b) { return {a.v - b, a.d}; }
inline Dual operator-(double a, const Dual& b) { return {a - b.v, -b.d}; }
inline Dual operator*(const Dual& a, double b) { return {a.v * b, a.d * b}; }
inline Dual operator*(double a, const Dual& b) { return {a * b.v, a * b.d}; }
inline Dual operator/(const Dual& a, double b) { return {a.v / b, a.d / b}; }
inline Dual operator/(double a, const Dual& b) {
  const double r = a / b.v;
  return {r, -r * b.d / b.v};
}
inline Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
inline Dual operator+(const Dual& a) { return a; }

inline bool operator==(const Dual& a, const Dual& b) { return a.v == b.v; }
inline bool operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }
inline bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
inline bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
inline bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
inline bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }

inline Dual sin(const Dual& a) { return {std::sin(a.v), std::cos(a.v) * a.d}; }
inline Dual cos(const Dual& a) { return {std::cos(a.v), -std::sin(a.v) * a.d}; }
inline Dual tan(const Dual& a) {
  const double t = std::tan(a.v);
  return {t, (1 + t * t) * a.d};
}
inline Dual asin(const Dual& a) { return {std::asin(a.v), a.d / std::sqrt(1 - a.v * a.v)}; }
inline Dual acos(const Dual& a) { return {std::acos(a.v), -a.d / std::sqrt(1 - a.v * a.v)}; }
inline Dual atan(const Dual& a) { return {std::atan(a.v), a.d / (1 + a.v * a.v)}; }
inline Dual atan2(const Dual& y, const Dual& x) {
  const double r2 = x.v * x.v + y.v * y.v;
  return {std::atan2(y.v, x.v), (x.v * y.d - y.v * x.d) / r2};
}
inline Dual exp(const Dual& a) {
  const double e = std::exp(a.v);
  return {e, e * a.d};
}
inline Dual log(const Dual& a) { return {std::log(a.v), a.d / a.v}; }
inline Dual sqrt(const Dual& a) {
  const double s = std::sqrt(a.v);
  return {s, s > 0 ? a.d / (2 * s) : 0.0};
}
inline Dual abs(const Dual& a) { return {std::abs(a.v), a.v < 0 ? -a.d : a.d}; }
inline Dual pow(const Dual& a, const Dual& b) {
  const double p = std::pow(a.v, b.v);
  double d = b.v * std::pow(a.v, b.v - 1) * a.d;
  if (b.d != 0 && a.v > 0) d += p * std::log(a.v) * b.d;
  return {p, d};
}
inline Dual min(const Dual& a, const Dual& b) { return a.v <= b.v ? a : b; }
inline Dual max(const Dual& a, const Dual& b) { return a.v >= b.v ? a : b; }
inline bool isfinite(const Dual& a) { return std::isfinite(a.v) && std::isfinite(a.d); }

// Scalar-generic helpers so templated code reads the same for double and Dual.
inline double value_of(double x) { return x; }
inline double value_of(const Dual& x) { return x.v; }
inline double tangent_of(double) { return 0.0; }
inline double tangent_of(const Dual& x) { return x.d; }

}  // namespace kanesens

namespace Eigen {
template <>
struct NumTraits<kanesens::Dual> : NumTraits<double> {
  using Real = kanesens::Dual;
  using NonInteger = kanesens::Dual;
  using Nested = kanesens::Dual;
  using Literal = kanesens::Dual;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 0,
         ReadCost = 2, AddCost = 2, MulCost = 3 };
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<kanesens::Dual, double, BinaryOp> { using ReturnType = kanesens::Dual; };
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, kanesens::Dual, BinaryOp> { using ReturnType = kanesens::Dual; };
}  // namespace Eigen
