// The serial N_Vector's operations compiled with the project (sim/solve/serial_vector_ops.hpp).
// Each computes what SUNDIALS 6.4's nvector_serial computes, entry by entry: the same special
// cases where they change the rounding (c (x + y) for a = b, c (x − y) for a = −b, x − y for
// a = 1, b = −1) and the same order of every sum. The in-place forms (y ← a x + y, ...) give the
// same bits as the general form, so they need no case of their own.
#include "sim/solve/serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <utility>
#include <stdexcept>

namespace kanesens::sim {

namespace {

using Real = realtype;
using Index = sunindextype;

Real* data(N_Vector v) { return NV_DATA_S(v); }
Index length(N_Vector v) { return NV_LENGTH_S(v); }

// z = a x + b y on n entries, case by case as N_VLinearSum_Serial.
void linear_sum(Real a, const Real* x, Real b, const Real* y, Real* z, Index n) {
  if (a == 1 && b == 1) {
    for (Index i = 0; i < n; ++i) z[i] = x[i] + y[i];
  } else if (a == 1 && b == -1) {
    for (Index i = 0; i < n; ++i) z[i] = x[i] - y[i];
  } else if (a == -1 && b == 1) {
    for (Index i = 0; i < n; ++i) z[i] = y[i] - x[i];
  } else if (a == 1) {
    for (Index i = 0; i < n; ++i) z[i] = b * y[i] + x[i];
  } else if (b == 1) {
    for (Index i = 0; i < n; ++i) z[i] = a * x[i] + y[i];
  } else if (a == -1) {
    for (Index i = 0; i < n; ++i) z[i] = b * y[i] - x[i];
  } else if (b == -1) {
    for (Index i = 0; i < n; ++i) z[i] = a * x[i] - y[i];
  } else if (a == b) {
    for (Index i = 0; i < n; ++i) z[i] = a * (x[i] + y[i]);
  } else if (a == -b) {
    for (Index i = 0; i < n; ++i) z[i] = a * (x[i] - y[i]);
  } else {
    for (Index i = 0; i < n; ++i) z[i] = a * x[i] + b * y[i];
  }
}

void scale(Real c, const Real* x, Real* z, Index n) {
  for (Index i = 0; i < n; ++i) z[i] = c * x[i];
}

// z = c0 x0 + c1 x1 + … (k ≥ 3 terms), summed in that order.
template <class Term>
void combination(int k, const Real* c, Term term, Real* z, Index n) {
  const Real* x0 = term(0);
  for (Index i = 0; i < n; ++i) z[i] = c[0] * x0[i];
  for (int j = 1; j < k; ++j) {
    const Real* xj = term(j);
    for (Index i = 0; i < n; ++i) z[i] += c[j] * xj[i];
  }
}

Real weighted_square_sum(const Real* x, const Real* w, Index n) {
  Real sum = 0;
  for (Index i = 0; i < n; ++i) {
    const Real p = x[i] * w[i];
    sum += p * p;
  }
  return sum;
}

Real weighted_square_sum_mask(const Real* x, const Real* w, const Real* id, Index n) {
  Real sum = 0;
  for (Index i = 0; i < n; ++i)
    if (id[i] > 0) {
      const Real p = x[i] * w[i];
      sum += p * p;
    }
  return sum;
}

Real dot(const Real* x, const Real* y, Index n) {
  Real sum = 0;
  for (Index i = 0; i < n; ++i) sum += x[i] * y[i];
  return sum;
}

// Standard operations.
void op_linear_sum(Real a, N_Vector x, Real b, N_Vector y, N_Vector z) {
  linear_sum(a, data(x), b, data(y), data(z), length(x));
}
void op_const(Real c, N_Vector z) {
  Real* zd = data(z);
  const Index n = length(z);
  for (Index i = 0; i < n; ++i) zd[i] = c;
}
void op_prod(N_Vector x, N_Vector y, N_Vector z) {
  const Real *xd = data(x), *yd = data(y);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = xd[i] * yd[i];
}
void op_div(N_Vector x, N_Vector y, N_Vector z) {
  const Real *xd = data(x), *yd = data(y);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = xd[i] / yd[i];
}
void op_scale(Real c, N_Vector x, N_Vector z) { scale(c, data(x), data(z), length(x)); }
void op_abs(N_Vector x, N_Vector z) {
  const Real* xd = data(x);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = std::abs(xd[i]);
}
void op_inv(N_Vector x, N_Vector z) {
  const Real* xd = data(x);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = 1 / xd[i];
}
void op_add_const(N_Vector x, Real b, N_Vector z) {
  const Real* xd = data(x);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = xd[i] + b;
}
Real op_dot_prod(N_Vector x, N_Vector y) { return dot(data(x), data(y), length(x)); }
Real op_max_norm(N_Vector x) {
  const Real* xd = data(x);
  const Index n = length(x);
  Real max = 0;
  for (Index i = 0; i < n; ++i)
    if (std::abs(xd[i]) > max) max = std::abs(xd[i]);
  return max;
}
Real op_wsqrsum(N_Vector x, N_Vector w) { return weighted_square_sum(data(x), data(w), length(x)); }
Real op_wsqrsum_mask(N_Vector x, N_Vector w, N_Vector id) {
  return weighted_square_sum_mask(data(x), data(w), data(id), length(x));
}
Real op_wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(op_wsqrsum(x, w) / static_cast<Real>(length(x)));
}
Real op_wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(op_wsqrsum_mask(x, w, id) / static_cast<Real>(length(x)));
}
Real op_min(N_Vector x) {
  const Real* xd = data(x);
  const Index n = length(x);
  Real min = xd[0];
  for (Index i = 1; i < n; ++i)
    if (xd[i] < min) min = xd[i];
  return min;
}
Real op_wl2_norm(N_Vector x, N_Vector w) { return std::sqrt(op_wsqrsum(x, w)); }
Real op_l1_norm(N_Vector x) {
  const Real* xd = data(x);
  const Index n = length(x);
  Real sum = 0;
  for (Index i = 0; i < n; ++i) sum += std::abs(xd[i]);
  return sum;
}
void op_compare(Real c, N_Vector x, N_Vector z) {
  const Real* xd = data(x);
  Real* zd = data(z);
  const Index n = length(x);
  for (Index i = 0; i < n; ++i) zd[i] = std::abs(xd[i]) >= c ? 1 : 0;
}
booleantype op_inv_test(N_Vector x, N_Vector z) {
  const Real* xd = data(x);
  Real* zd = data(z);
  const Index n = length(x);
  booleantype no_zero = SUNTRUE;
  for (Index i = 0; i < n; ++i) {
    if (xd[i] == 0) no_zero = SUNFALSE;
    else zd[i] = 1 / xd[i];
  }
  return no_zero;
}
booleantype op_constr_mask(N_Vector c, N_Vector x, N_Vector m) {
  const Real *cd = data(c), *xd = data(x);
  Real* md = data(m);
  const Index n = length(x);
  bool violated = false;
  for (Index i = 0; i < n; ++i) {
    md[i] = 0;
    if (cd[i] == 0) continue;
    if ((std::abs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0) || (std::abs(cd[i]) > 0.5 && xd[i] * cd[i] < 0)) {
      md[i] = 1;
      violated = true;
    }
  }
  return violated ? SUNFALSE : SUNTRUE;
}
Real op_min_quotient(N_Vector num, N_Vector denom) {
  const Real *nd = data(num), *dd = data(denom);
  const Index n = length(num);
  bool first = true;
  Real min = BIG_REAL;
  for (Index i = 0; i < n; ++i) {
    if (dd[i] == 0) continue;
    const Real q = nd[i] / dd[i];
    min = first ? q : (min < q ? min : q);  // SUNMIN's form (a NaN quotient wins, as there)
    first = false;
  }
  return min;
}

// A clone whose data starts on a 64-byte boundary (a cache line, a 512-bit register): the
// loops above then never split a load across two lines. N_VDestroy_Serial frees it with free(),
// which takes aligned_alloc's memory.
N_Vector op_clone(N_Vector w) {
  N_Vector v = N_VCloneEmpty_Serial(w);
  if (v == nullptr) return nullptr;
  const std::size_t bytes = static_cast<std::size_t>(length(w)) * sizeof(Real);
  void* memory = std::aligned_alloc(64, std::max<std::size_t>(64, (bytes + 63) / 64 * 64));  // whole lines
  if (memory == nullptr) {
    N_VDestroy_Serial(v);
    return nullptr;
  }
  NV_DATA_S(v) = static_cast<Real*>(memory);
  NV_OWN_DATA_S(v) = SUNTRUE;
  return v;
}

// Fused operations.
int op_linear_combination(int k, Real* c, N_Vector* X, N_Vector z) {
  const Index n = length(z);
  if (k == 1) scale(c[0], data(X[0]), data(z), n);
  else if (k == 2) linear_sum(c[0], data(X[0]), c[1], data(X[1]), data(z), n);
  else combination(k, c, [&](int j) { return data(X[j]); }, data(z), n);
  return 0;
}
int op_scale_add_multi(int k, Real* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const Real* xd = data(x);
  const Index n = length(x);
  for (int j = 0; j < k; ++j) {
    const Real* yd = data(Y[j]);
    Real* zd = data(Z[j]);
    for (Index i = 0; i < n; ++i) zd[i] = a[j] * xd[i] + yd[i];
  }
  return 0;
}
int op_dot_prod_multi(int k, N_Vector x, N_Vector* Y, Real* dots) {
  for (int j = 0; j < k; ++j) dots[j] = dot(data(x), data(Y[j]), length(x));
  return 0;
}

// Vector-array operations.
int op_linear_sum_array(int k, Real a, N_Vector* X, Real b, N_Vector* Y, N_Vector* Z) {
  for (int j = 0; j < k; ++j) linear_sum(a, data(X[j]), b, data(Y[j]), data(Z[j]), length(Z[j]));
  return 0;
}
int op_scale_array(int k, Real* c, N_Vector* X, N_Vector* Z) {
  for (int j = 0; j < k; ++j) scale(c[j], data(X[j]), data(Z[j]), length(Z[j]));
  return 0;
}
int op_const_array(int k, Real c, N_Vector* Z) {
  for (int j = 0; j < k; ++j) op_const(c, Z[j]);
  return 0;
}
int op_wrms_norm_array(int k, N_Vector* X, N_Vector* W, Real* norms) {
  for (int j = 0; j < k; ++j) norms[j] = op_wrms_norm(X[j], W[j]);
  return 0;
}
int op_wrms_norm_mask_array(int k, N_Vector* X, N_Vector* W, N_Vector id, Real* norms) {
  for (int j = 0; j < k; ++j) norms[j] = op_wrms_norm_mask(X[j], W[j], id);
  return 0;
}
// Z[s][j] = a[s] X[j] + Y[s][j].
int op_scale_add_multi_array(int k, int sums, Real* a, N_Vector* X, N_Vector** Y, N_Vector** Z) {
  for (int j = 0; j < k; ++j) {
    const Real* xd = data(X[j]);
    const Index n = length(X[j]);
    for (int s = 0; s < sums; ++s) {
      const Real* yd = data(Y[s][j]);
      Real* zd = data(Z[s][j]);
      for (Index i = 0; i < n; ++i) zd[i] = a[s] * xd[i] + yd[i];
    }
  }
  return 0;
}
// Z[j] = Σ_s c[s] X[s][j].
int op_linear_combination_array(int k, int sums, Real* c, N_Vector** X, N_Vector* Z) {
  for (int j = 0; j < k; ++j) {
    const Index n = length(Z[j]);
    if (sums == 1) scale(c[0], data(X[0][j]), data(Z[j]), n);
    else if (sums == 2) linear_sum(c[0], data(X[0][j]), c[1], data(X[1][j]), data(Z[j]), n);
    else combination(sums, c, [&](int s) { return data(X[s][j]); }, data(Z[j]), n);
  }
  return 0;
}

// The norms of a state stacked with its sensitivities (use_block_error_norm): the largest WRMS
// norm of its blocks of Block entries, as CVODES's sensitivity module takes the largest of the
// state's and the sensitivities' norms with sensitivity error control; the first block's alone
// without it. The block size is a template argument so that the sums unroll as the plain norm's.
// Each block's sum in N_VWrmsNorm's order; one square root, of the largest sum: √(s/Block) is
// non-decreasing in s and correctly rounded, so it is the largest block's norm to the bit. A NaN
// in any block wins, as it would in one sum.
template <int Block>
Real op_wrms_norm_blocks(N_Vector x, N_Vector w) {
  const Real *xd = data(x), *wd = data(w);
  const Index n = length(x);
  Real largest = 0;
  bool nan = false;
  for (Index b = 0; b + Block <= n; b += Block) {
    const Real sum = weighted_square_sum(xd + b, wd + b, Block);
    nan |= std::isnan(sum);
    largest = std::max(largest, sum);
  }
  if (nan) return std::numeric_limits<Real>::quiet_NaN();
  return std::sqrt(largest / static_cast<Real>(Block));
}
template <int Block>
Real op_wrms_norm_first_block(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(data(x), data(w), Block) / static_cast<Real>(Block));
}

using NormOp = Real (*)(N_Vector, N_Vector);
template <int... B>
constexpr std::array<NormOp, sizeof...(B)> block_norms(std::integer_sequence<int, B...>) {
  return {&op_wrms_norm_blocks<B + 1>...};
}
template <int... B>
constexpr std::array<NormOp, sizeof...(B)> first_block_norms(std::integer_sequence<int, B...>) {
  return {&op_wrms_norm_first_block<B + 1>...};
}
constexpr auto kBlockNorms = block_norms(std::make_integer_sequence<int, kMaxErrorNormBlock>{});
constexpr auto kFirstBlockNorms = first_block_norms(std::make_integer_sequence<int, kMaxErrorNormBlock>{});

}  // namespace

bool use_block_error_norm(N_Vector v, int block, bool every_block) {
  if (v == nullptr || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL || block < 1 || block > kMaxErrorNormBlock ||
      length(v) % block != 0)
    return false;
  const auto index = static_cast<std::size_t>(block - 1);
  v->ops->nvwrmsnorm = every_block ? kBlockNorms[index] : kFirstBlockNorms[index];
  return true;
}

void use_compiled_serial_ops(N_Vector v) {
  if (v == nullptr || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL)
    throw std::invalid_argument("use_compiled_serial_ops: not a serial N_Vector");
  N_Vector_Ops ops = v->ops;
  ops->nvclone = op_clone;
  ops->nvlinearsum = op_linear_sum;
  ops->nvconst = op_const;
  ops->nvprod = op_prod;
  ops->nvdiv = op_div;
  ops->nvscale = op_scale;
  ops->nvabs = op_abs;
  ops->nvinv = op_inv;
  ops->nvaddconst = op_add_const;
  ops->nvdotprod = op_dot_prod;
  ops->nvmaxnorm = op_max_norm;
  ops->nvwrmsnorm = op_wrms_norm;
  ops->nvwrmsnormmask = op_wrms_norm_mask;
  ops->nvmin = op_min;
  ops->nvwl2norm = op_wl2_norm;
  ops->nvl1norm = op_l1_norm;
  ops->nvcompare = op_compare;
  ops->nvinvtest = op_inv_test;
  ops->nvconstrmask = op_constr_mask;
  ops->nvminquotient = op_min_quotient;
  ops->nvlinearcombination = op_linear_combination;
  ops->nvscaleaddmulti = op_scale_add_multi;
  ops->nvdotprodmulti = op_dot_prod_multi;
  ops->nvlinearsumvectorarray = op_linear_sum_array;
  ops->nvscalevectorarray = op_scale_array;
  ops->nvconstvectorarray = op_const_array;
  ops->nvwrmsnormvectorarray = op_wrms_norm_array;
  ops->nvwrmsnormmaskvectorarray = op_wrms_norm_mask_array;
  ops->nvscaleaddmultivectorarray = op_scale_add_multi_array;
  ops->nvlinearcombinationvectorarray = op_linear_combination_array;
  ops->nvdotprodlocal = op_dot_prod;
  ops->nvmaxnormlocal = op_max_norm;
  ops->nvminlocal = op_min;
  ops->nvl1normlocal = op_l1_norm;
  ops->nvinvtestlocal = op_inv_test;
  ops->nvconstrmasklocal = op_constr_mask;
  ops->nvminquotientlocal = op_min_quotient;
  ops->nvwsqrsumlocal = op_wsqrsum;
  ops->nvwsqrsummasklocal = op_wsqrsum_mask;
  ops->nvdotprodmultilocal = op_dot_prod_multi;
}

}  // namespace kanesens::sim
