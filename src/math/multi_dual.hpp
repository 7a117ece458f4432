// Multi-tangent dual numbers: x = v + Σ_i d_i ε_i with ε_i ε_j = 0 — one value and N tangents,
// N fixed at compile time. Evaluating the templated dynamics on MultiDual<N> gives f and N
// directional derivatives in one pass: the value work (kinematics, M, f) is done once and each
// tangent adds one multiply-add per operation. More directions than a compiled width are done
// in blocks of passes, so no width needs the heap. DualT<MultiDual<N>> nests for the second
// derivatives of general constraints.
//
// Why hand-written (bench/multitangent_kernels.cpp measures it against ceres::Jet and Eigen's
// AutoDiffScalar): the tangents are stored as SIMD packs (with the value in the first one when
// that takes no pack more), and every operation is forced inline, so the compiler keeps them in
// vector registers and never reloads a pack from two scalar stores (a stalled store-to-load
// forward); the library types lose 2-10x at N ≥ 4 to exactly that.
// Eigen is told the operations are expensive so that it keeps its reductions as loops (unrolled
// reductions call Eigen's functors out of line).
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#if defined(__AVX__)
#include <immintrin.h>
#endif

#define KANESENS_MD_INLINE [[gnu::always_inline]] inline

namespace kanesens::math {

namespace detail {
// A pack of L doubles (the attribute needs a size known where the type is spelled).
template <int L>
struct PackOf;
template <>
struct PackOf<2> {
  using type = double __attribute__((vector_size(16), aligned(8)));
};
template <>
struct PackOf<4> {
  using type = double __attribute__((vector_size(32), aligned(8)));
};
template <>
struct PackOf<8> {
  using type = double __attribute__((vector_size(64), aligned(8)));
};

// Tangents travel in packs of `lanes` doubles (GCC/Clang vector extension): one SIMD register
// (8 with AVX-512, 4 with AVX, 2 with SSE2: the build's instruction set, KANESENS_ARCH in
// CMakeLists.txt), narrowed to 2 or 4 for N ≤ 2 or ≤ 4: idle lanes are not free (processors
// that split 512-bit operations in two halves pay for all eight; docs/benchmarks.md), and the
// tangent arithmetic is lane by lane, so the values do not depend on the width.
#if defined(__AVX512F__)
inline constexpr int register_lanes = 8;
#elif defined(__AVX__)
inline constexpr int register_lanes = 4;
#else
inline constexpr int register_lanes = 2;
#endif
constexpr int multi_dual_lanes(int n) { return std::min(register_lanes, n <= 2 ? 2 : n <= 4 ? 4 : 8); }
// The value rides in lane 0 of the first pack where that takes no pack more: with AVX-512 for at
// most 7 tangents (one register), with AVX where N + 1 lanes fill as many 4-lane packs as N do (3,
// 5, 6, 7, 10, 11, … tangents). An operation is then one vector operation per pack (masked or
// blended where the value's rule differs from the tangents'), not vector ones and a scalar one
// competing for the same units, and a number occupies one register fewer.
constexpr bool multi_dual_value_in_pack(int n) {
  const int lanes = multi_dual_lanes(n);
  if (lanes == 8) return n < 8;
  return lanes == 4 && (n + lanes) / lanes == (n + lanes - 1) / lanes;
}

// The members of MultiDual<N>. 8-byte aligned so that the struct has no padding (GCC copies
// padding through the stack, which stalls the next load of the value).
template <int N, int Lanes, bool ValueInPack>
struct MultiDualStorage {
  using Pack = typename PackOf<Lanes>::type;
  static constexpr int packs = (N + Lanes - 1) / Lanes;  // unused lanes of the last pack stay 0
  Pack t[packs];  // tangents: t[k] holds d_{lanes·k} … d_{lanes·k + lanes − 1}
  double v;       // value
};
// N + 1 lanes, aligned to a pack so that no load of one spans two cache lines (no more: Eigen's
// fixed-size arrays align to at most the register width, and clang rejects a larger element
// alignment there).
template <int N, int Lanes>
struct alignas(Lanes * 8) MultiDualStorage<N, Lanes, true> {
  using Pack = typename PackOf<Lanes>::type;
  static constexpr int packs = (N + Lanes) / Lanes;
  union {
    Pack t[packs];  // lane 0 of t[0] the value, the next N lanes the tangents, the rest 0
    double v;       // the value: lane 0 of t[0]
  };
};

// s b + c, rounded once where the processor has fused multiply-adds: the tangent part of a
// product, a' b + a b', as a' b then a b' added to it.
template <class Pack>
KANESENS_MD_INLINE Pack multiply_add(double s, Pack b, Pack c) {
#if defined(__FMA__)
  if constexpr (sizeof(Pack) == 16) {
    return reinterpret_cast<Pack>(_mm_fmadd_pd(_mm_set1_pd(s), reinterpret_cast<__m128d>(b), reinterpret_cast<__m128d>(c)));
  } else if constexpr (sizeof(Pack) == 32) {
    return reinterpret_cast<Pack>(
        _mm256_fmadd_pd(_mm256_set1_pd(s), reinterpret_cast<__m256d>(b), reinterpret_cast<__m256d>(c)));
  } else {
    return reinterpret_cast<Pack>(
        _mm512_fmadd_pd(_mm512_set1_pd(s), reinterpret_cast<__m512d>(b), reinterpret_cast<__m512d>(c)));
  }
#else
  return s * b + c;
#endif
}

#if defined(__AVX__)
// The value's lane (lane 0 of the first pack) apart from the tangents': AVX-512's masked
// operations on a 64-byte pack, blends on a 32-byte one.
// Lane 0 from a, the others from b (32-byte packs).
template <class Pack>
KANESENS_MD_INLINE Pack first_lane_from(Pack a, Pack b) {
  return reinterpret_cast<Pack>(
      _mm256_blend_pd(reinterpret_cast<__m256d>(b), reinterpret_cast<__m256d>(a), 1));
}
// Lane 0 (the value) a, the other lanes (tangents) from b.
template <class Pack>
KANESENS_MD_INLINE Pack value_then_tangents(double a, Pack b) {
#if defined(__AVX512F__)
  if constexpr (sizeof(Pack) == 64)
    return reinterpret_cast<Pack>(
        _mm512_mask_mov_pd(reinterpret_cast<__m512d>(b), 1, reinterpret_cast<__m512d>(Pack{a})));
  else
#endif
    return first_lane_from(reinterpret_cast<Pack>(_mm256_set1_pd(a)), b);
}
// Lane 0 x, the others 0. On 32-byte packs as a broadcast and a mask rather than the zero-extending
// move GCC would pick (vmovq from a high register, an encoding that Debian's valgrind does not
// decode, so that callgrind could not run the program).
template <class Pack>
KANESENS_MD_INLINE Pack value_lane(double x) {
  if constexpr (sizeof(Pack) == 32) {
    const __m256d first = _mm256_castsi256_pd(_mm256_set_epi64x(0, 0, 0, -1));
    return reinterpret_cast<Pack>(_mm256_and_pd(_mm256_set1_pd(x), first));
  } else {
    return Pack{x};
  }
}
// multiply_add on the tangents' lanes, c on the value's.
template <class Pack>
KANESENS_MD_INLINE Pack multiply_add_to_tangents(double s, Pack b, Pack c) {
#if defined(__AVX512F__)
  if constexpr (sizeof(Pack) == 64)
    return reinterpret_cast<Pack>(_mm512_mask3_fmadd_pd(_mm512_set1_pd(s), reinterpret_cast<__m512d>(b),
                                                        reinterpret_cast<__m512d>(c), 0xFE));
  else
#endif
    return first_lane_from(c, multiply_add(s, b, c));
}
// a + b on the tangents' lanes, a on the value's.
template <class Pack>
KANESENS_MD_INLINE Pack add_to_tangents(Pack a, Pack b) {
#if defined(__AVX512F__)
  if constexpr (sizeof(Pack) == 64) {
    const __m512d x = reinterpret_cast<__m512d>(a);
    return reinterpret_cast<Pack>(_mm512_mask_add_pd(x, 0xFE, x, reinterpret_cast<__m512d>(b)));
  } else
#endif
    return first_lane_from(a, a + b);
}
// a − b on the tangents' lanes, a on the value's.
template <class Pack>
KANESENS_MD_INLINE Pack subtract_from_tangents(Pack a, Pack b) {
#if defined(__AVX512F__)
  if constexpr (sizeof(Pack) == 64) {
    const __m512d x = reinterpret_cast<__m512d>(a);
    return reinterpret_cast<Pack>(_mm512_mask_sub_pd(x, 0xFE, x, reinterpret_cast<__m512d>(b)));
  } else
#endif
    return first_lane_from(a, a - b);
}
// a + s on the value's lane, a on the tangents'.
template <class Pack>
KANESENS_MD_INLINE Pack add_to_value(Pack a, double s) {
#if defined(__AVX512F__)
  if constexpr (sizeof(Pack) == 64) {
    const __m512d x = reinterpret_cast<__m512d>(a);
    return reinterpret_cast<Pack>(_mm512_mask_add_pd(x, 1, x, _mm512_set1_pd(s)));
  } else
#endif
    return value_then_tangents(a[0] + s, a);
}
#else
// The value rides in a pack only with AVX or AVX-512: elsewhere these are only named, in
// discarded branches, and need no definition.
template <class Pack>
Pack multiply_add_to_tangents(double s, Pack b, Pack c);
template <class Pack>
Pack value_then_tangents(double a, Pack b);
template <class Pack>
Pack value_lane(double x);
template <class Pack>
Pack add_to_tangents(Pack a, Pack b);
template <class Pack>
Pack subtract_from_tangents(Pack a, Pack b);
template <class Pack>
Pack add_to_value(Pack a, double s);
#endif
}  // namespace detail

template <int N>
struct MultiDual : detail::MultiDualStorage<N, detail::multi_dual_lanes(N), detail::multi_dual_value_in_pack(N)> {
  static_assert(N >= 1, "at least one tangent");
  using Storage = detail::MultiDualStorage<N, detail::multi_dual_lanes(N), detail::multi_dual_value_in_pack(N)>;
  using typename Storage::Pack;
  using Storage::v;
  static constexpr int register_lanes = detail::register_lanes;
  static constexpr int lanes = detail::multi_dual_lanes(N);
  static constexpr bool value_in_pack = detail::multi_dual_value_in_pack(N);
  static constexpr int tangents = N;
  static constexpr int packs = Storage::packs;
  static constexpr int first_tangent_pack = value_in_pack ? 1 : 0;  // the first without the value

  // Default construction leaves the members uninitialised, as for double (Eigen
  // default-constructs its fixed-size temporaries; zero-filling them cost more than the
  // arithmetic).
  MultiDual() = default;
  KANESENS_MD_INLINE constexpr MultiDual(double value) {  // NOLINT: implicit from constants is intended
    if constexpr (value_in_pack) {
      this->t[0] = detail::value_lane<Pack>(value);
      for (int k = 1; k < packs; ++k) this->t[k] = Pack{};
    } else {
      for (int k = 0; k < packs; ++k) this->t[k] = Pack{};
      v = value;
    }
  }
  // Copies member by member, pack by pack: as an aggregate the compiler copies arrays of these
  // (Eigen's vectors of them) in a few wide moves, whose loads then span several narrower stores
  // just made and stall (no store-to-load forwarding).
  KANESENS_MD_INLINE MultiDual(const MultiDual& o) { *this = o; }
  KANESENS_MD_INLINE MultiDual& operator=(const MultiDual& o) {
    for (int k = 0; k < packs; ++k) this->t[k] = o.t[k];
    if constexpr (!value_in_pack) v = o.v;
    return *this;
  }

  KANESENS_MD_INLINE double d(int i) const {
    if constexpr (value_in_pack) return this->t[(i + 1) / lanes][(i + 1) % lanes];
    else return this->t[i / lanes][i % lanes];
  }
  KANESENS_MD_INLINE void set_d(int i, double x) {
    if constexpr (value_in_pack) this->t[(i + 1) / lanes][(i + 1) % lanes] = x;
    else this->t[i / lanes][i % lanes] = x;
  }
  // Tangent i = tangent_i(i) for i < count ≤ N, the rest 0; written a pack at a time (a pack
  // assembled from two scalar stores would stall its next vector load).
  template <class F>
  KANESENS_MD_INLINE void set_tangents(F&& tangent_i, int count) {
    const double value = v;
    constexpr int first = value_in_pack ? 1 : 0;  // the lane of tangent 0
    for (int k = 0; k < packs; ++k) {
      Pack q = {};
      for (int l = 0; l < lanes; ++l) {
        const int i = lanes * k + l - first;
        q[l] = i < 0 ? value : i < count ? tangent_i(i) : 0.0;
      }
      this->t[k] = q;
    }
  }
  // Tangents −= a's tangents · s (the tangent right-hand sides of a reused factorisation).
  KANESENS_MD_INLINE void subtract_tangents(const MultiDual& a, double s) {
    if constexpr (value_in_pack) this->t[0] = detail::subtract_from_tangents(this->t[0], a.t[0] * s);
    for (int k = first_tangent_pack; k < packs; ++k) this->t[k] -= a.t[k] * s;
  }
  // Value with tangent 1 in direction i and 0 in the others (seeding an input).
  static MultiDual seeded(double value, int i) {
    MultiDual x(value);
    x.set_d(i, 1.0);
    return x;
  }

  KANESENS_MD_INLINE MultiDual& operator+=(const MultiDual& o) {
    if constexpr (!value_in_pack) v += o.v;
    for (int k = 0; k < packs; ++k) this->t[k] += o.t[k];
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator-=(const MultiDual& o) {
    if constexpr (!value_in_pack) v -= o.v;
    for (int k = 0; k < packs; ++k) this->t[k] -= o.t[k];
    return *this;
  }
  // (a b)' = a' b + a b': the first product's lane 0 is the value a b.
  KANESENS_MD_INLINE MultiDual& operator*=(const MultiDual& o) {
    const double a = v, b = o.v;
    if constexpr (value_in_pack)
      this->t[0] = detail::multiply_add_to_tangents(a, o.t[0], this->t[0] * b);
    for (int k = first_tangent_pack; k < packs; ++k)
      this->t[k] = detail::multiply_add(a, o.t[k], this->t[k] * b);
    if constexpr (!value_in_pack) v = a * b;
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator/=(const MultiDual& o) {
    const double inv = 1.0 / o.v;
    const double q = v * inv;
    if constexpr (value_in_pack)
      this->t[0] = detail::value_then_tangents(q, (this->t[0] - q * o.t[0]) * inv);
    for (int k = first_tangent_pack; k < packs; ++k) this->t[k] = (this->t[k] - q * o.t[k]) * inv;
    if constexpr (!value_in_pack) v = q;
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator+=(double s) {
    if constexpr (value_in_pack) this->t[0] = detail::add_to_value(this->t[0], s);
    else v += s;
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator-=(double s) {
    if constexpr (value_in_pack) this->t[0] = detail::add_to_value(this->t[0], -s);
    else v -= s;
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator*=(double s) {
    if constexpr (!value_in_pack) v *= s;
    for (int k = 0; k < packs; ++k) this->t[k] *= s;
    return *this;
  }
  KANESENS_MD_INLINE MultiDual& operator/=(double s) { return *this *= (1.0 / s); }
};

template <int N> KANESENS_MD_INLINE MultiDual<N> operator+(MultiDual<N> a, const MultiDual<N>& b) { return a += b; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator-(MultiDual<N> a, const MultiDual<N>& b) { return a -= b; }
template <int N>
KANESENS_MD_INLINE MultiDual<N> operator*(const MultiDual<N>& a, const MultiDual<N>& b) {
  MultiDual<N> r;  // every member is written below
  if constexpr (MultiDual<N>::value_in_pack)
    r.t[0] = detail::multiply_add_to_tangents(a.v, b.t[0], a.t[0] * b.v);
  for (int k = MultiDual<N>::first_tangent_pack; k < MultiDual<N>::packs; ++k)
    r.t[k] = detail::multiply_add(a.v, b.t[k], a.t[k] * b.v);
  if constexpr (!MultiDual<N>::value_in_pack) r.v = a.v * b.v;
  return r;
}
template <int N> KANESENS_MD_INLINE MultiDual<N> operator/(MultiDual<N> a, const MultiDual<N>& b) { return a /= b; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator+(MultiDual<N> a, double b) { return a += b; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator+(double a, MultiDual<N> b) { return b += a; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator-(MultiDual<N> a, double b) { return a -= b; }
template <int N>
KANESENS_MD_INLINE MultiDual<N> operator-(double a, const MultiDual<N>& b) {
  MultiDual<N> r;
  if constexpr (MultiDual<N>::value_in_pack) r.t[0] = detail::value_then_tangents(a - b.v, -b.t[0]);
  for (int k = MultiDual<N>::first_tangent_pack; k < MultiDual<N>::packs; ++k) r.t[k] = -b.t[k];
  if constexpr (!MultiDual<N>::value_in_pack) r.v = a - b.v;
  return r;
}
template <int N> KANESENS_MD_INLINE MultiDual<N> operator*(MultiDual<N> a, double b) { return a *= b; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator*(double a, MultiDual<N> b) { return b *= a; }
template <int N> KANESENS_MD_INLINE MultiDual<N> operator/(MultiDual<N> a, double b) { return a /= b; }
template <int N>
KANESENS_MD_INLINE MultiDual<N> operator/(double a, const MultiDual<N>& b) {
  MultiDual<N> r;
  const double inv = 1.0 / b.v;
  const double q = a * inv;
  const double k = -q * inv;
  if constexpr (MultiDual<N>::value_in_pack) r.t[0] = detail::value_then_tangents(q, k * b.t[0]);
  for (int i = MultiDual<N>::first_tangent_pack; i < MultiDual<N>::packs; ++i) r.t[i] = k * b.t[i];
  if constexpr (!MultiDual<N>::value_in_pack) r.v = q;
  return r;
}
template <int N>
KANESENS_MD_INLINE MultiDual<N> operator-(const MultiDual<N>& a) {
  MultiDual<N> r;
  for (int k = 0; k < MultiDual<N>::packs; ++k) r.t[k] = -a.t[k];
  if constexpr (!MultiDual<N>::value_in_pack) r.v = -a.v;
  return r;
}
template <int N> KANESENS_MD_INLINE MultiDual<N> operator+(const MultiDual<N>& a) { return a; }

// Comparisons look at the value only: branches follow the value.
template <int N> KANESENS_MD_INLINE bool operator==(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v == b.v; }
template <int N> KANESENS_MD_INLINE bool operator!=(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v != b.v; }
template <int N> KANESENS_MD_INLINE bool operator<(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v < b.v; }
template <int N> KANESENS_MD_INLINE bool operator>(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v > b.v; }
template <int N> KANESENS_MD_INLINE bool operator<=(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v <= b.v; }
template <int N> KANESENS_MD_INLINE bool operator>=(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v >= b.v; }

template <class S> inline constexpr bool is_multi_dual_v = false;
template <int N> inline constexpr bool is_multi_dual_v<MultiDual<N>> = true;

template <int N> KANESENS_MD_INLINE double value_of(const MultiDual<N>& x) { return x.v; }
template <int N> KANESENS_MD_INLINE double tangent(const MultiDual<N>& x, int i) { return x.d(i); }

namespace multi_dual_detail {
// f(a) from f(a.v) and f'(a.v): the chain rule on every tangent.
template <int N>
KANESENS_MD_INLINE MultiDual<N> chain(double f, double df, const MultiDual<N>& a) {
  MultiDual<N> r;
  if constexpr (MultiDual<N>::value_in_pack) r.t[0] = detail::value_then_tangents(f, df * a.t[0]);
  for (int k = MultiDual<N>::first_tangent_pack; k < MultiDual<N>::packs; ++k) r.t[k] = df * a.t[k];
  if constexpr (!MultiDual<N>::value_in_pack) r.v = f;
  return r;
}
}  // namespace multi_dual_detail

template <int N> MultiDual<N> sin(const MultiDual<N>& a) { return multi_dual_detail::chain(std::sin(a.v), std::cos(a.v), a); }
template <int N> MultiDual<N> cos(const MultiDual<N>& a) { return multi_dual_detail::chain(std::cos(a.v), -std::sin(a.v), a); }
// sin a and cos a with the value's sine and cosine taken once (the bits of sin and cos); s and c
// must not alias a.
template <int N>
void sin_cos(const MultiDual<N>& a, MultiDual<N>& s, MultiDual<N>& c) {
  const double sv = std::sin(a.v), cv = std::cos(a.v);
  s = multi_dual_detail::chain(sv, cv, a);
  c = multi_dual_detail::chain(cv, -sv, a);
}
template <int N>
MultiDual<N> tan(const MultiDual<N>& a) {
  const double t = std::tan(a.v);
  return multi_dual_detail::chain(t, 1 + t * t, a);
}
template <int N> MultiDual<N> asin(const MultiDual<N>& a) { return multi_dual_detail::chain(std::asin(a.v), 1 / std::sqrt(1 - a.v * a.v), a); }
template <int N> MultiDual<N> acos(const MultiDual<N>& a) { return multi_dual_detail::chain(std::acos(a.v), -1 / std::sqrt(1 - a.v * a.v), a); }
template <int N> MultiDual<N> atan(const MultiDual<N>& a) { return multi_dual_detail::chain(std::atan(a.v), 1 / (1 + a.v * a.v), a); }
template <int N>
MultiDual<N> atan2(const MultiDual<N>& y, const MultiDual<N>& x) {
  const double inv = 1 / (x.v * x.v + y.v * y.v), cy = x.v * inv, cx = -y.v * inv;
  MultiDual<N> r;
  const double value = std::atan2(y.v, x.v);
  if constexpr (MultiDual<N>::value_in_pack)
    r.t[0] = detail::value_then_tangents(value, cy * y.t[0] + cx * x.t[0]);
  for (int k = MultiDual<N>::first_tangent_pack; k < MultiDual<N>::packs; ++k)
    r.t[k] = cy * y.t[k] + cx * x.t[k];
  if constexpr (!MultiDual<N>::value_in_pack) r.v = value;
  return r;
}
template <int N>
MultiDual<N> exp(const MultiDual<N>& a) {
  const double e = std::exp(a.v);
  return multi_dual_detail::chain(e, e, a);
}
template <int N> MultiDual<N> log(const MultiDual<N>& a) { return multi_dual_detail::chain(std::log(a.v), 1 / a.v, a); }
template <int N>
MultiDual<N> sqrt(const MultiDual<N>& a) {
  const double s = std::sqrt(a.v);
  // The derivative at 0 is taken as 0, as DualT does (|x| at its kink).
  return multi_dual_detail::chain(s, s > 0 ? 0.5 / s : 0.0, a);
}
template <int N> MultiDual<N> abs(const MultiDual<N>& a) { return multi_dual_detail::chain(std::abs(a.v), a.v < 0 ? -1.0 : 1.0, a); }
template <int N>
MultiDual<N> pow(const MultiDual<N>& a, const MultiDual<N>& b) {
  const double p = std::pow(a.v, b.v);
  MultiDual<N> r = multi_dual_detail::chain(p, b.v * std::pow(a.v, b.v - 1), a);
  if (a.v > 0) {
    const double db = p * std::log(a.v);
    if constexpr (MultiDual<N>::value_in_pack) r.t[0] = detail::add_to_tangents(r.t[0], db * b.t[0]);
    for (int k = MultiDual<N>::first_tangent_pack; k < MultiDual<N>::packs; ++k) r.t[k] += db * b.t[k];
  }
  return r;
}
template <int N> MultiDual<N> min(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v <= b.v ? a : b; }
template <int N> MultiDual<N> max(const MultiDual<N>& a, const MultiDual<N>& b) { return a.v >= b.v ? a : b; }
template <int N>
bool has_tangent(const MultiDual<N>& a) {
  for (int i = 0; i < N; ++i)
    if (a.d(i) != 0) return true;
  return false;
}
template <int N>
bool isfinite(const MultiDual<N>& a) {
  bool ok = std::isfinite(a.v);
  for (int i = 0; i < N; ++i) ok = ok && std::isfinite(a.d(i));
  return ok;
}

// The compiled widths, widest first: the blocks of the Jacobian's and the sensitivities' passes
// (sim/tangent_blocks.hpp) and every explicit instantiation of the templated engine take them
// from here. X names the type as math::MultiDual<N>, for use inside namespace kanesens.
// KANESENS_FEWER_MULTI_DUAL_WIDTHS (CMake: -DKANESENS_ALL_MULTI_DUAL_WIDTHS=OFF, the sanitizer
// tree's setting) leaves out 12 and 10, which instantiate the same templates once more each, so
// that the engine compiles in less time; their blocks then take width 16 with idle tangents
// (the same values, each tangent being computed lane by lane).
#if defined(KANESENS_FEWER_MULTI_DUAL_WIDTHS)
#define KANESENS_MULTI_DUAL_WIDTHS 16, 8, 6, 4, 2
#define KANESENS_FOR_EACH_MULTI_DUAL(X) \
  X(math::MultiDual<16>) X(math::MultiDual<8>) X(math::MultiDual<6>) X(math::MultiDual<4>) X(math::MultiDual<2>)
#else
#define KANESENS_MULTI_DUAL_WIDTHS 16, 12, 10, 8, 6, 4, 2
#define KANESENS_FOR_EACH_MULTI_DUAL(X)                                                              \
  X(math::MultiDual<16>) X(math::MultiDual<12>) X(math::MultiDual<10>) X(math::MultiDual<8>) \
  X(math::MultiDual<6>) X(math::MultiDual<4>) X(math::MultiDual<2>)
#endif

}  // namespace kanesens::math

namespace Eigen {
template <int N>
struct NumTraits<kanesens::math::MultiDual<N>> : NumTraits<double> {
  using Real = kanesens::math::MultiDual<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  // Up to 4 tangents Eigen may unroll small fixed-size reductions (it pays); wider, HugeCost
  // keeps them as loops (see the file comment).
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = 1,
         AddCost = N <= 4 ? N + 1 : int(HugeCost), MulCost = N <= 4 ? 2 * N + 1 : int(HugeCost) };
};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<kanesens::math::MultiDual<N>, double, BinaryOp> { using ReturnType = kanesens::math::MultiDual<N>; };
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<double, kanesens::math::MultiDual<N>, BinaryOp> { using ReturnType = kanesens::math::MultiDual<N>; };
}  // namespace Eigen
