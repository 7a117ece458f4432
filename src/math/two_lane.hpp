// Two doubles per instruction (SSE2, the x86-64 baseline) for the hand-paired steps of the 3-D
// recursions on double. Each lane performs the scalar form's operations in its order, so the
// paired steps give the same bits as the templated code they stand in for.
#pragma once

#if defined(__SSE2__)
#include <emmintrin.h>

namespace kanesens::math::two_lane {

using V2 = __m128d;
inline V2 splat(double x) {
  return _mm_set1_pd(x);
}
inline V2 pair(double lo, double hi) {
  return _mm_set_pd(hi, lo);
}
inline V2 load(const double* x) {
  return _mm_loadu_pd(x);
}
inline V2 add(V2 x, V2 y) {
  return _mm_add_pd(x, y);
}
inline V2 sub(V2 x, V2 y) {
  return _mm_sub_pd(x, y);
}
inline V2 mul(V2 x, V2 y) {
  return _mm_mul_pd(x, y);
}
inline V2 negate(V2 x) {
  return _mm_xor_pd(x, _mm_set1_pd(-0.0));
}
inline double lo(V2 v) {
  return _mm_cvtsd_f64(v);
}
inline double hi(V2 v) {
  return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v));
}
// (x.lo, y.lo) and (x.hi, y.hi).
inline V2 lows(V2 x, V2 y) {
  return _mm_unpacklo_pd(x, y);
}
inline V2 highs(V2 x, V2 y) {
  return _mm_unpackhi_pd(x, y);
}
// (x.hi, y.lo).
inline V2 high_low(V2 x, V2 y) {
  return _mm_shuffle_pd(x, y, 1);
}
inline V2 zero() {
  return _mm_setzero_pd();
}
// x in the low lane (the high lane zero): an operand whose high lane is not read.
inline V2 low(double x) {
  return _mm_set_sd(x);
}
// Writes the pair to slot[0], slot[1] (first) or adds it there.
template <bool first>
inline void put_pair(double* slot, V2 share) {
  if constexpr (first)
    _mm_storeu_pd(slot, share);
  else
    _mm_storeu_pd(slot, _mm_add_pd(_mm_loadu_pd(slot), share));
}
inline void store(double* slot, V2 v) {
  _mm_storeu_pd(slot, v);
}
// Stores the lanes to two places.
inline void store_lanes(V2 v, double& lo_slot, double& hi_slot) {
  _mm_storel_pd(&lo_slot, v);
  _mm_storeh_pd(&hi_slot, v);
}

}  // namespace kanesens::math::two_lane
#endif
