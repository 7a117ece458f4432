// sin and cos of two angles at once (SSE2, the x86-64 baseline; four with AVX2), for the joint
// angles of the position stage. Written by hand because glibc's sincos is a call per angle of some hundred
// instructions with branches, which the position stage of a chain of revolute joints spent a
// tenth of the right-hand side in; SLEEF's 1-ulp SSE2 version is no faster without FMA and its
// 3.5-ulp one is less accurate than this.
//
// The method is the classical one (Cody and Waite's reduction, the minimax polynomials of
// fdlibm's kernels): x = n π/2 + y with y carried as a double-double (y0, y1), π/2 split into
// three 33-bit parts and their tails so that n times a part is exact for |n| < 2^20; then
// sin y and cos y by polynomials on |y| ≤ π/4 and the quadrant n mod 4. Error below one unit in
// the last place (tests/unit/test_sincos.cpp against long double). Angles beyond ±2^19 π/2 and
// non-finite ones go to the C library (same results as std::sin, std::cos there).
#pragma once

#include <cmath>

#include "math/two_lane.hpp"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace kanesens::math {

namespace sincos_detail {
inline constexpr double kInvPio2 = 6.36619772367581382433e-01;
inline constexpr double kPio2_1 = 1.57079632673412561417e+00;   // first 33 bits of π/2
inline constexpr double kPio2_2 = 6.07710050630396597660e-11;   // second 33 bits
inline constexpr double kPio2_3 = 2.02226624871116645580e-21;   // third 33 bits
inline constexpr double kPio2_3t = 8.47842766036889956997e-32;  // π/2 − the three parts
// Beyond this |x| the reduction's products are no longer exact.
inline constexpr double kMaxReduced = 823549.6554103942;  // 2^19 π/2
// sin y = y + y³ (S1 + y² S2 + …), |y| ≤ π/4 (fdlibm k_sin.c's minimax coefficients).
inline constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                        S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                        S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
// cos y = 1 − y²/2 + y⁴ (C1 + y² C2 + …) (fdlibm k_cos.c's).
inline constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                        C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                        C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
}  // namespace sincos_detail

#if defined(__SSE2__)
namespace sincos_detail {
// The arithmetic of a packet of angles, the same operations in each lane whatever the width:
// sincos2 and sincos4 give an angle the same bits.
struct Lanes2 {
  using V = __m128d;
  static V splat(double x) { return _mm_set1_pd(x); }
  static V add(V x, V y) { return _mm_add_pd(x, y); }
  static V sub(V x, V y) { return _mm_sub_pd(x, y); }
  static V mul(V x, V y) { return _mm_mul_pd(x, y); }
};
#if defined(__AVX2__)
struct Lanes4 {
  using V = __m256d;
  static V splat(double x) { return _mm256_set1_pd(x); }
  static V add(V x, V y) { return _mm256_add_pd(x, y); }
  static V sub(V x, V y) { return _mm256_sub_pd(x, y); }
  static V mul(V x, V y) { return _mm256_mul_pd(x, y); }
};
#endif

// a0 + z (a1 + z (a2 + …)), innermost first.
template <class L, class... More>
inline typename L::V horner(typename L::V z, double a0, More... more) {
  if constexpr (sizeof...(more) == 0) return L::splat(a0);
  else return L::add(L::splat(a0), L::mul(z, horner<L>(z, more...)));
}

// sin and cos of y = x − n π/2 (n the nearest integer to x·2/π, as a double), before the
// quadrant's swap and signs.
template <class L>
inline void reduced_sincos(typename L::V X, typename L::V n, typename L::V& sin_y, typename L::V& cos_y) {
  using V = typename L::V;
  const auto splat = L::splat;
  const auto add = L::add;
  const auto sub = L::sub;
  const auto mul = L::mul;
  // y = x − n π/2 as y0 + y1: the first part's product and difference are exact; the second
  // and third parts' products are exact and each difference's rounding error (e, by Fast2Sum) is
  // kept with the last tail in w (fdlibm's e_rem_pio2, with every step taken).
  V r = sub(X, mul(n, splat(kPio2_1)));
  V t = r, p = mul(n, splat(kPio2_2));
  r = sub(t, p);
  V e = sub(sub(t, r), p);
  t = r, p = mul(n, splat(kPio2_3));
  r = sub(t, p);
  e = add(sub(sub(t, r), p), e);
  const V w = sub(mul(n, splat(kPio2_3t)), e);
  const V y0 = sub(r, w);
  const V y1 = sub(sub(r, y0), w);
  // sin(y0 + y1) ≈ y0 − ((z (y1/2 − v P) − y1) − v S1), z = y0², v = z y0, P = S2 + z (S3 + …).
  const V z = mul(y0, y0);
  const V v = mul(z, y0);
  const V P = horner<L>(z, S2, S3, S4, S5, S6);
  sin_y = sub(y0, sub(sub(mul(z, sub(mul(splat(0.5), y1), mul(v, P))), y1), mul(v, splat(S1))));
  // cos(y0 + y1) ≈ h + (((1 − h) − z/2) + (z Q − y0 y1)), h = 1 − z/2,
  // Q = z (C1 + z (C2 + z C3)) + z⁴ (C4 + z (C5 + z C6)).
  const V z2 = mul(z, z);
  const V Q = add(mul(z, horner<L>(z, C1, C2, C3)), mul(mul(z2, z2), horner<L>(z, C4, C5, C6)));
  const V hz = mul(splat(0.5), z);
  const V h = sub(splat(1.0), hz);
  cos_y = add(h, add(sub(sub(splat(1.0), h), hz), sub(mul(z, Q), mul(y0, y1))));
}
}  // namespace sincos_detail

// s[i] = sin x[i], c[i] = cos x[i] for i = 0, 1.
inline void sincos2(const double x[2], double s[2], double c[2]) {
  using namespace sincos_detail;
  using namespace two_lane;
  V2 X = load(x);
  // Lanes out of range (or NaN) are reduced as 0 here and taken from the C library below, so that
  // each angle's result does not depend on the angle it is paired with.
  const V2 in_range = _mm_cmple_pd(_mm_andnot_pd(splat(-0.0), X), splat(kMaxReduced));
  const int lanes_in_range = _mm_movemask_pd(in_range);
  X = _mm_and_pd(X, in_range);
  // n = nearest integer to x·2/π (the rounding mode's, nearest-even), exactly representable.
  const __m128i N = _mm_cvtpd_epi32(mul(X, splat(kInvPio2)));
  V2 sin_y, cos_y;
  reduced_sincos<Lanes2>(X, _mm_cvtepi32_pd(N), sin_y, cos_y);
  // Quadrant n mod 4: odd n swaps sin and cos; sin is negated for n ≡ 2, 3, cos for n ≡ 1, 2.
  const __m128i n64 = _mm_shuffle_epi32(N, _MM_SHUFFLE(1, 1, 0, 0));  // each lane's n in both halves
  const V2 odd = _mm_castsi128_pd(_mm_cmpeq_epi32(_mm_and_si128(n64, _mm_set1_epi32(1)), _mm_set1_epi32(1)));
  const V2 S = _mm_or_pd(_mm_and_pd(odd, cos_y), _mm_andnot_pd(odd, sin_y));
  const V2 C = _mm_or_pd(_mm_and_pd(odd, sin_y), _mm_andnot_pd(odd, cos_y));
  const __m128i bit1 = _mm_slli_epi64(_mm_and_si128(n64, _mm_set1_epi32(2)), 62);  // n & 2 → sign
  const __m128i bit0 = _mm_slli_epi64(_mm_and_si128(n64, _mm_set1_epi32(1)), 63);  // n & 1
  store(s, _mm_xor_pd(S, _mm_castsi128_pd(bit1)));
  store(c, _mm_xor_pd(C, _mm_castsi128_pd(_mm_xor_si128(bit1, bit0))));
  if (lanes_in_range != 3) [[unlikely]]
    for (int i = 0; i < 2; ++i)
      if (!(lanes_in_range >> i & 1)) s[i] = std::sin(x[i]), c[i] = std::cos(x[i]);
}
#else
inline void sincos2(const double x[2], double s[2], double c[2]) {
  for (int i = 0; i < 2; ++i) s[i] = std::sin(x[i]), c[i] = std::cos(x[i]);
}
#endif

// s[i] = sin x[i], c[i] = cos x[i] for i = 0 … 3: with AVX2, sincos2's operations on four lanes
// at once (one chain of dependent steps instead of two; the same bits as sincos2, lane by
// lane); otherwise sincos2 twice.
#if defined(__AVX2__)
inline void sincos4(const double x[4], double s[4], double c[4]) {
  using namespace sincos_detail;
  using V4 = Lanes4::V;
  V4 X = _mm256_loadu_pd(x);
  const V4 in_range = _mm256_cmp_pd(_mm256_andnot_pd(Lanes4::splat(-0.0), X), Lanes4::splat(kMaxReduced), _CMP_LE_OS);
  const int lanes_in_range = _mm256_movemask_pd(in_range);
  X = _mm256_and_pd(X, in_range);
  const __m128i N = _mm256_cvtpd_epi32(Lanes4::mul(X, Lanes4::splat(kInvPio2)));
  V4 sin_y, cos_y;
  reduced_sincos<Lanes4>(X, _mm256_cvtepi32_pd(N), sin_y, cos_y);
  // Quadrant n mod 4 as in sincos2, with each lane's n widened to 64 bits.
  const __m256i n64 = _mm256_cvtepi32_epi64(N);
  const __m256i one = _mm256_set1_epi64x(1);
  const V4 odd = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(n64, one), one));
  const V4 S = _mm256_or_pd(_mm256_and_pd(odd, cos_y), _mm256_andnot_pd(odd, sin_y));
  const V4 C = _mm256_or_pd(_mm256_and_pd(odd, sin_y), _mm256_andnot_pd(odd, cos_y));
  const __m256i bit1 = _mm256_slli_epi64(_mm256_and_si256(n64, _mm256_set1_epi64x(2)), 62);
  const __m256i bit0 = _mm256_slli_epi64(_mm256_and_si256(n64, one), 63);
  _mm256_storeu_pd(s, _mm256_xor_pd(S, _mm256_castsi256_pd(bit1)));
  _mm256_storeu_pd(c, _mm256_xor_pd(C, _mm256_castsi256_pd(_mm256_xor_si256(bit1, bit0))));
  if (lanes_in_range != 15) [[unlikely]]
    for (int i = 0; i < 4; ++i)
      if (!(lanes_in_range >> i & 1)) s[i] = std::sin(x[i]), c[i] = std::cos(x[i]);
}
#else
inline void sincos4(const double x[4], double s[4], double c[4]) {
  sincos2(x, s, c);
  sincos2(x + 2, s + 2, c + 2);
}
#endif

}  // namespace kanesens::math
