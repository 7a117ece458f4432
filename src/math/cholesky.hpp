// Cholesky factorisation A = Uᵀ U (U upper triangular) of the small dense symmetric positive
// definite matrices of Kane's equations — M (solve_accelerations), NᵀN of redundant
// multipliers (solve_constrained_accelerations), Cᵀ M C of the embedding — and the solve, on
// any scalar: on Dual the derivatives flow through the factorisation exactly. Column-major
// storage with a leading dimension, so a factor can live in a block of a workspace matrix; no
// allocation (these run inside the right-hand side).
//
// U(j, i) = (A(j, i) − Σ_{k<j} U(k, j) U(k, i)) / U(j, j) (Golub & Van Loan 2013, Alg. 4.2.1,
// transposed): every sum is a dot product down two contiguous columns of U.
//
// Hand-written rather than Eigen's LLT on a Ref (in place, no allocation): for these matrices
// (a few to a few tens of rows, double and Dual) it takes measurably fewer instructions and less
// time per right-hand side (`kanesens bench rhs`); Eigen's dynamic-size LLT also computes the
// matrix's l1 norm on every factorisation.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstddef>

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
}  // namespace detail

// Reads the upper triangle of the n×n matrix A (leading dimension lda) and writes U into the
// upper triangle of U (ldu); U may be A. False if A is not positive definite (a pivot ≤ 0).
template <class S>
bool cholesky_factor(const S* A, std::ptrdiff_t lda, S* U, std::ptrdiff_t ldu, int n) {
  using detail::dot;
  using std::sqrt;
  for (int j = 0; j < n; ++j) {
    S* Uj = U + j * ldu;
    const S d = A[j * lda + j] - dot(Uj, Uj, j);
    if (!(value_of(d) > 0)) return false;
    Uj[j] = sqrt(d);
    const S inv = S(1) / Uj[j];
    for (int i = j + 1; i < n; ++i) {
      S* Ui = U + i * ldu;
      Ui[j] = (A[i * lda + j] - dot(Uj, Ui, j)) * inv;
    }
  }
  return true;
}

// x ← (Uᵀ U)⁻¹ x: Uᵀ y = x by dot products down the columns, then U x = y by column axpys.
template <class S>
void cholesky_solve(const S* U, std::ptrdiff_t ldu, int n, S* x) {
  using detail::dot;
  using V = Eigen::Matrix<S, Eigen::Dynamic, 1>;
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

// x ← (Uᵀ U)⁻¹ x with a factor U on doubles and x on any scalar S: the tangents of x are solved
// with the value factor (each operation scales S by a double, half the cost of S × S).
template <class S>
void cholesky_solve_with_value_factor(const double* U, std::ptrdiff_t ldu, int n, S* x) {
  for (int i = 0; i < n; ++i) {
    const double* Ui = U + i * ldu;
    S s = x[i];
    for (int k = 0; k < i; ++k) s -= Ui[k] * x[k];
    x[i] = s / Ui[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const double* Ui = U + i * ldu;
    x[i] /= Ui[i];
    const S xi = x[i];
    for (int k = 0; k < i; ++k) x[k] -= Ui[k] * xi;
  }
}

}  // namespace kanesens::math
