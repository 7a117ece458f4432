// Cholesky factorisation A = Uᵀ U (U upper triangular) of the small dense symmetric positive
// definite matrices of Kane's equations — M (solve_accelerations), NᵀN of redundant
// multipliers (solve_constrained_accelerations), Cᵀ M C of the embedding — and the solve, on
// any scalar: on Dual the derivatives flow through the factorisation exactly. Column-major
// storage with a leading dimension, so a factor can live in a block of a workspace matrix; no
// allocation (these run inside the right-hand side).
//
// U(j, i) = (A(j, i) − Σ_{k<j} U(k, j) U(k, i)) / U(j, j) (Golub & Van Loan 2013, Alg. 4.2.1,
// transposed): every sum is a dot product down two contiguous columns of U. On double, rows
// j and j + 1 are formed together in blocks of 2 rows × 4 columns, each block's eight dot
// products in one sweep with explicit 2-wide vector operations: for a few tens of rows most of
// the cost of a lone short dot product is fixed (set-up, reduction), not the sums.
//
// Hand-written rather than Eigen's LLT on a Ref (in place, no allocation): for these matrices
// (a few to a few tens of rows, double and Dual) it takes measurably fewer instructions and less
// time per right-hand side (`kanesens bench rhs`); Eigen's dynamic-size LLT also computes the
// matrix's l1 norm on every factorisation.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "math/dual.hpp"

namespace kanesens::math {

namespace detail {
// Σ a_k b_k over contiguous entries (Eigen's vectorised dot).
template <class S>
S dot(const S* a, const S* b, int n) {
  if (n == 0) return S(0);
  using V = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  return Eigen::Map<const V>(a, n).dot(Eigen::Map<const V>(b, n));
}

// s[c] = Σ_{k<n} a_k b_c[k] for C columns b_c = b + c ldb in one sweep of a, two terms at a time
// (explicit 2-wide vectors: the compiler keeps a loop's order of additions and would not pair
// them itself). For the short columns of these factors the fixed cost of a dot product is a
// large part of it; C at once divide it by C and share a's loads.
template <int C>
EIGEN_ALWAYS_INLINE void dots(const double* a, const double* b, std::ptrdiff_t ldb, int n, double* s) {
  using P = Eigen::Matrix<double, 2, 1>;
  P acc[C];
  for (int c = 0; c < C; ++c) acc[c].setZero();
  int k = 0;
  for (; k + 2 <= n; k += 2) {
    const P x = Eigen::Map<const P>(a + k);
    for (int c = 0; c < C; ++c) acc[c] += x.cwiseProduct(Eigen::Map<const P>(b + c * ldb + k));
  }
  for (int c = 0; c < C; ++c) {
    s[c] = acc[c][0] + acc[c][1];
    if (k < n) s[c] += a[k] * b[c * ldb + k];
  }
}

// The same for two rows a0, a1 at once: s0[c] = Σ a0_k b_c[k], s1[c] = Σ a1_k b_c[k].
template <int C>
EIGEN_ALWAYS_INLINE void dots2(const double* a0, const double* a1, const double* b, std::ptrdiff_t ldb, int n,
                               double* s0, double* s1) {
  using P = Eigen::Matrix<double, 2, 1>;
  P acc0[C], acc1[C];
  for (int c = 0; c < C; ++c) {
    acc0[c].setZero();
    acc1[c].setZero();
  }
  int k = 0;
  for (; k + 2 <= n; k += 2) {
    const P x0 = Eigen::Map<const P>(a0 + k), x1 = Eigen::Map<const P>(a1 + k);
    for (int c = 0; c < C; ++c) {
      const P y = Eigen::Map<const P>(b + c * ldb + k);
      acc0[c] += x0.cwiseProduct(y);
      acc1[c] += x1.cwiseProduct(y);
    }
  }
  for (int c = 0; c < C; ++c) {
    s0[c] = acc0[c][0] + acc0[c][1];
    s1[c] = acc1[c][0] + acc1[c][1];
    if (k < n) {
      s0[c] += a0[k] * b[c * ldb + k];
      s1[c] += a1[k] * b[c * ldb + k];
    }
  }
}

// Rows j and j + 1 of U (double): the 2×2 diagonal block, then C columns at a time with dots2.
// False if a pivot is not positive. inverse_pivots (if not null) gets 1/U(j, j), 1/U(j+1, j+1).
inline bool cholesky_two_rows(const double* A, std::ptrdiff_t lda, double* U, std::ptrdiff_t ldu, int n, int j,
                              double* inverse_pivots) {
  double* U0 = U + j * ldu;
  double* U1 = U0 + ldu;
  double s[2];
  dots<2>(U0, U0, ldu, j, s);  // U0·U0, U0·U1 (column j + 1 down to row j − 1)
  const double d0 = A[j * lda + j] - s[0];
  if (!(d0 > 0)) return false;
  U0[j] = std::sqrt(d0);
  const double inv0 = 1.0 / U0[j];
  const double a01 = A[(j + 1) * lda + j];
  U1[j] = (a01 - s[1]) * inv0;
  double t[1];
  dots<1>(U1, U1, 0, j, t);
  const double d1 = A[(j + 1) * lda + j + 1] - t[0] - U1[j] * U1[j];
  if (!(d1 > 0)) return false;
  U1[j + 1] = std::sqrt(d1);
  const double inv1 = 1.0 / U1[j + 1];
  if (inverse_pivots) {
    inverse_pivots[j] = inv0;
    inverse_pivots[j + 1] = inv1;
  }
  const double u01 = U1[j];
  auto finish = [&](int i, int C, const double* s0, const double* s1) {
    for (int c = 0; c < C; ++c) {
      double* Ui = U + (i + c) * ldu;
      const double* Ai = A + (i + c) * lda;
      const double a0 = Ai[j], a1 = Ai[j + 1];
      const double x = (a0 - s0[c]) * inv0;
      Ui[j] = x;
      Ui[j + 1] = (a1 - s1[c] - u01 * x) * inv1;
    }
  };
  int i = j + 2;
  double s0[4], s1[4];
  for (; i + 4 <= n; i += 4) {
    dots2<4>(U0, U1, U + i * ldu, ldu, j, s0, s1);
    finish(i, 4, s0, s1);
  }
  switch (n - i) {
    case 3: dots2<3>(U0, U1, U + i * ldu, ldu, j, s0, s1); finish(i, 3, s0, s1); break;
    case 2: dots2<2>(U0, U1, U + i * ldu, ldu, j, s0, s1); finish(i, 2, s0, s1); break;
    case 1: dots2<1>(U0, U1, U + i * ldu, ldu, j, s0, s1); finish(i, 1, s0, s1); break;
    default: break;
  }
  return true;
}

// Rows of U one at a time (every scalar; on double after the pairs, the last row of an odd n).
template <class S>
bool cholesky_factor(const S* A, std::ptrdiff_t lda, S* U, std::ptrdiff_t ldu, int n, double* inverse_pivots) {
  using std::sqrt;
  int j0 = 0;
  if constexpr (std::is_same_v<S, double>) {
    // Two rows at a time: each column's entries of both rows from one sweep of the column.
    for (; j0 + 2 <= n; j0 += 2)
      if (!cholesky_two_rows(A, lda, U, ldu, n, j0, inverse_pivots)) return false;
  }
  for (int j = j0; j < n; ++j) {  // every row on other scalars; on double the last of an odd n
    S* Uj = U + j * ldu;
    const S d = A[j * lda + j] - dot(Uj, Uj, j);
    if (!(value_of(d) > 0)) return false;
    Uj[j] = sqrt(d);
    const S inv = S(1) / Uj[j];
    if constexpr (std::is_same_v<S, double>)
      if (inverse_pivots) inverse_pivots[j] = inv;
    for (int i = j + 1; i < n; ++i) {
      S* Ui = U + i * ldu;
      Ui[j] = (A[i * lda + j] - dot(Uj, Ui, j)) * inv;
    }
  }
  return true;
}
}  // namespace detail

// Reads the upper triangle of the n×n matrix A (leading dimension lda) and writes U into the
// upper triangle of U (ldu); U may be A. False if A is not positive definite (a pivot ≤ 0).
template <class S>
bool cholesky_factor(const S* A, std::ptrdiff_t lda, S* U, std::ptrdiff_t ldu, int n) {
  return detail::cholesky_factor(A, lda, U, ldu, n, nullptr);
}

// The same on double, also writing the pivots' reciprocals 1/U(j, j) to inverse_pivots (n), for
// the solve below: it then multiplies where it would divide, and a division's latency lies on
// the critical path of each substitution (every unknown waits for the one before).
inline bool cholesky_factor(const double* A, std::ptrdiff_t lda, double* U, std::ptrdiff_t ldu, int n,
                            double* inverse_pivots) {
  return detail::cholesky_factor(A, lda, U, ldu, n, inverse_pivots);
}

// x ← (Uᵀ U)⁻¹ x: Uᵀ y = x by dot products down the columns, then U x = y by column axpys.
template <class S>
void cholesky_solve(const S* U, std::ptrdiff_t ldu, int n, S* x) {
  using detail::dot;
  using V = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  if constexpr (std::is_same_v<S, double>) {
    for (int i = 0; i < n; ++i) {
      const double* Ui = U + i * ldu;
      double s[1];
      detail::dots<1>(Ui, x, 0, i, s);
      x[i] = (x[i] - s[0]) / Ui[i];
    }
    for (int i = n - 1; i >= 0; --i) {
      const double* Ui = U + i * ldu;
      const double xi = x[i] / Ui[i];
      x[i] = xi;
      for (int k = 0; k < i; ++k) x[k] -= xi * Ui[k];
    }
    return;
  }
  for (int i = 0; i < n; ++i) {
    const S* Ui = U + i * ldu;
    x[i] = (x[i] - dot(Ui, x, i)) / Ui[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const S* Ui = U + i * ldu;
    x[i] /= Ui[i];
    const S xi = x[i];
    Eigen::Map<V>(x, i) -= xi * Eigen::Map<const V>(Ui, i);
  }
}

namespace detail {
// C columns of a column-major X (leading dimension ldx) solved together: each row's C dot
// products in one sweep of U's column (dots<C>), so the columns' substitutions, each a chain of
// dependent steps, run side by side.
template <int C>
void cholesky_solve_columns(const double* U, std::ptrdiff_t ldu, int n, const double* inverse_pivots, double* X,
                            std::ptrdiff_t ldx) {
  double s[C];
  for (int i = 0; i < n; ++i) {
    dots<C>(U + i * ldu, X, ldx, i, s);
    for (int c = 0; c < C; ++c) X[c * ldx + i] = (X[c * ldx + i] - s[c]) * inverse_pivots[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const double* Ui = U + i * ldu;
    for (int c = 0; c < C; ++c) {
      double* x = X + c * ldx;
      const double xi = x[i] * inverse_pivots[i];
      x[i] = xi;
      for (int k = 0; k < i; ++k) x[k] -= xi * Ui[k];
    }
  }
}
}  // namespace detail

// x ← (Uᵀ U)⁻¹ x on double with the reciprocal pivots of cholesky_factor (the same sums; each
// quotient a product with the reciprocal).
inline void cholesky_solve(const double* U, std::ptrdiff_t ldu, int n, const double* inverse_pivots, double* x) {
  detail::cholesky_solve_columns<1>(U, ldu, n, inverse_pivots, x, n);
}

// X ← (Uᵀ U)⁻¹ X for an n×ncols column-major X (leading dimension ldx), with the reciprocal
// pivots of cholesky_factor: cholesky_solve's sums for every column (the same bits), up to four
// columns at a time.
inline void cholesky_solve_columns(const double* U, std::ptrdiff_t ldu, int n, const double* inverse_pivots,
                                   double* X, std::ptrdiff_t ldx, int ncols) {
  int c = 0;
  for (; c + 4 <= ncols; c += 4) detail::cholesky_solve_columns<4>(U, ldu, n, inverse_pivots, X + c * ldx, ldx);
  switch (ncols - c) {
    case 3: detail::cholesky_solve_columns<3>(U, ldu, n, inverse_pivots, X + c * ldx, ldx); break;
    case 2: detail::cholesky_solve_columns<2>(U, ldu, n, inverse_pivots, X + c * ldx, ldx); break;
    case 1: detail::cholesky_solve_columns<1>(U, ldu, n, inverse_pivots, X + c * ldx, ldx); break;
    default: break;
  }
}

// X ← (Uᵀ U)⁻¹ X for an n×ncols row-major X (leading dimension ldx), with the reciprocal pivots
// of cholesky_factor: cholesky_solve's substitutions applied to whole rows, so that the work on
// the columns is vector operations along each row.
inline void cholesky_solve_rows(const double* U, std::ptrdiff_t ldu, int n, const double* inverse_pivots, double* X,
                                std::ptrdiff_t ldx, int ncols) {
  using Row = Eigen::Map<Eigen::RowVectorXd>;
  for (int i = 0; i < n; ++i) {
    Row xi(X + i * ldx, ncols);
    const double* Ui = U + i * ldu;
    for (int k = 0; k < i; ++k) xi -= Ui[k] * Row(X + k * ldx, ncols);
    xi *= inverse_pivots[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    Row xi(X + i * ldx, ncols);
    xi *= inverse_pivots[i];
    const double* Ui = U + i * ldu;
    for (int k = 0; k < i; ++k) Row(X + k * ldx, ncols) -= Ui[k] * xi;
  }
}

// x ← (Uᵀ U)⁻¹ x with a factor U on doubles and x on any scalar S: the tangents of x are solved
// with the value factor (each operation scales S by a double, half the cost of S × S). Given the
// reciprocal pivots of cholesky_factor, each quotient is a product with the reciprocal, off the
// critical path of the substitutions as in cholesky_solve.
template <class S>
void cholesky_solve_with_value_factor(const double* U, std::ptrdiff_t ldu, int n, S* x,
                                      const double* inverse_pivots = nullptr) {
  const auto over_pivot = [&](const S& y, int i) -> S {
    return inverse_pivots ? S(y * inverse_pivots[i]) : S(y / U[i * ldu + i]);
  };
  for (int i = 0; i < n; ++i) {
    const double* Ui = U + i * ldu;
    S s = x[i];
    for (int k = 0; k < i; ++k) s -= Ui[k] * x[k];
    x[i] = over_pivot(s, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    const double* Ui = U + i * ldu;
    x[i] = over_pivot(x[i], i);
    const S xi = x[i];
    for (int k = 0; k < i; ++k) x[k] -= Ui[k] * xi;
  }
}

}  // namespace kanesens::math
