#include "sim/solve/dense_lu_solver.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/LU>
#include <cmath>
#include <utility>
#include <vector>

namespace kanesens::sim {

namespace {

struct Content {
  explicit Content(sunindextype size)
      : n(size), lu(size), inverse_pivots(size), source_rows(static_cast<std::size_t>(size)), scratch(size),
        inverse(size, size) {}
  sunindextype n;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // sized once: compute() and solves allocate nothing
  Eigen::VectorXd inverse_pivots;           // 1 / U(k, k)
  std::vector<int> source_rows;             // (P b)[k] = b[source_rows[k]]
  Eigen::VectorXd scratch;                  // b when the solve is in place (x = b)
  Eigen::MatrixXd inverse;                  // (P⁻¹ L U)⁻¹ for stacked right-hand sides, formed on demand
  bool inverse_current = false;
  sunindextype last_flag = SUNLS_SUCCESS;
};

// The sizes whose substitutions (and products with the inverse) are written out.
constexpr int kSizedSolves = 16;

Content& content(SUNLinearSolver S) { return *static_cast<Content*>(S->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver S) {
  content(S).last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
  Content& c = content(S);
  if (SUNMatGetID(A) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(A) != c.n || SUNDenseMatrix_Columns(A) != c.n)
    return static_cast<int>(c.last_flag = SUNLS_ILL_INPUT);
  c.lu.compute(Eigen::Map<const Eigen::MatrixXd>(SUNDenseMatrix_Data(A), c.n, c.n));
  // PartialPivLU does not stop at a zero pivot; U's diagonal tells.
  const auto pivots = c.lu.matrixLU().diagonal();
  for (Eigen::Index k = 0; k < pivots.size(); ++k) {
    if (!(pivots[k] != 0) || !std::isfinite(pivots[k])) return static_cast<int>(c.last_flag = SUNLS_LUFACT_FAIL);
    c.inverse_pivots[k] = 1.0 / pivots[k];
    // A pivot so small that its reciprocal overflows (subnormal) is singular in practice too.
    if (!std::isfinite(c.inverse_pivots[k])) return static_cast<int>(c.last_flag = SUNLS_LUFACT_FAIL);
  }
  c.inverse_current = false;
  const auto& rows = c.lu.permutationP().indices();  // (P b)[rows[i]] = b[i]
  for (Eigen::Index i = 0; i < c.n; ++i) c.source_rows[static_cast<std::size_t>(rows[i])] = static_cast<int>(i);
  return static_cast<int>(c.last_flag = SUNLS_SUCCESS);
}

// The substitutions by hand: Eigen's triangularView solves go through its blocked
// panel-and-GEMV path even at the sizes of a mechanism's state, several times slower there
// (bench/dense_lu_solve.cpp), and CVODES asks for one solve per Newton iteration and
// sensitivity.

// x = U⁻¹ L⁻¹ P b for n = N known at compile time, column by column on the column-major factor
// (L unit lower): the loops unroll and the vector stays in registers (b may be x: it is read
// whole before x is written).
template <int N>
void solve_sized(const Content& c, const double* b, double* x) {
  const double* lu = c.lu.matrixLU().data();
  const double* inverse_pivots = c.inverse_pivots.data();
  double v[N];
#pragma GCC unroll 16
  for (int k = 0; k < N; ++k) v[k] = b[c.source_rows[static_cast<std::size_t>(k)]];
#pragma GCC unroll 16
  for (int j = 0; j < N; ++j) {  // L y = P b
#pragma GCC unroll 16
    for (int i = j + 1; i < N; ++i) v[i] -= lu[j * N + i] * v[j];
  }
#pragma GCC unroll 16
  for (int j = N - 1; j >= 0; --j) {  // U x = y
    v[j] *= inverse_pivots[j];
#pragma GCC unroll 16
    for (int i = 0; i < j; ++i) v[i] -= lu[j * N + i] * v[j];
  }
#pragma GCC unroll 16
  for (int k = 0; k < N; ++k) x[k] = v[k];
}

// The same for any n, in x. (Written once for both would lose the registers: GCC keeps the
// local array in memory when the loops take n as an argument.)
void solve_any(Content& c, const double* b, double* x) {
  const Eigen::Index n = c.n;
  if (x == b) {
    c.scratch = Eigen::Map<const Eigen::VectorXd>(b, n);
    b = c.scratch.data();
  }
  for (Eigen::Index k = 0; k < n; ++k) x[k] = b[c.source_rows[static_cast<std::size_t>(k)]];
  const double* lu = c.lu.matrixLU().data();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double xj = x[j];
    for (Eigen::Index i = j + 1; i < n; ++i) x[i] -= lu[j * n + i] * xj;
  }
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    const double xj = x[j] *= c.inverse_pivots[j];
    for (Eigen::Index i = 0; i < j; ++i) x[i] -= lu[j * n + i] * xj;
  }
}

// c.inverse = (P⁻¹ L U)⁻¹ for n = N: solve_sized's substitutions applied to the permuted identity
// a whole row at a time (every column's entry gets the same operations in the same order, so
// each column is what solve_sized gives for that unit vector, to the bit), the rows' entries
// in vector operations.
template <int N>
void form_inverse_sized(Content& c) {
  const double* lu = c.lu.matrixLU().data();
  const double* inverse_pivots = c.inverse_pivots.data();
  alignas(64) double X[N][N] = {};
  for (int k = 0; k < N; ++k) X[k][c.source_rows[static_cast<std::size_t>(k)]] = 1;
  for (int j = 0; j < N; ++j)  // L Y = P
    for (int i = j + 1; i < N; ++i) {
      const double l = lu[j * N + i];
#pragma GCC unroll 16
      for (int k = 0; k < N; ++k) X[i][k] -= l * X[j][k];
    }
  for (int j = N - 1; j >= 0; --j) {  // U X = Y
#pragma GCC unroll 16
    for (int k = 0; k < N; ++k) X[j][k] *= inverse_pivots[j];
    for (int i = 0; i < j; ++i) {
      const double u = lu[j * N + i];
#pragma GCC unroll 16
      for (int k = 0; k < N; ++k) X[i][k] -= u * X[j][k];
    }
  }
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) c.inverse(i, j) = X[i][j];
}

template <int... N>
void form_inverse_dispatch(Content& c, std::integer_sequence<int, N...>) {
  (void)((c.n == N + 1 && (form_inverse_sized<N + 1>(c), true)) || ...);
}

template <int... N>
void solve_dispatch(Content& c, const double* b, double* x, std::integer_sequence<int, N...>) {
  if (!((c.n == N + 1 && (solve_sized<N + 1>(c, b, x), true)) || ...)) solve_any(c, b, x);
}

// x = A⁻¹ b for each of `blocks` right-hand sides of N: products with the inverse formed once
// from the factors, whose entries are independent (the substitutions are a chain of dependent
// operations per right-hand side).
template <int N>
void apply_inverse_sized(const Content& c, const double* b, double* x, int blocks) {
  const double* inverse = c.inverse.data();
  for (int k = 0; k < blocks; ++k) {
    const double* bk = b + static_cast<std::ptrdiff_t>(k) * N;
    double acc[N] = {};
#pragma GCC unroll 16
    for (int j = 0; j < N; ++j) {
      const double bj = bk[j];
#pragma GCC unroll 16
      for (int i = 0; i < N; ++i) acc[i] += inverse[j * N + i] * bj;
    }
    double* xk = x + static_cast<std::ptrdiff_t>(k) * N;
#pragma GCC unroll 16
    for (int i = 0; i < N; ++i) xk[i] = acc[i];
  }
}

template <int... N>
bool apply_inverse_dispatch(Content& c, const double* b, double* x, int blocks, std::integer_sequence<int, N...>) {
  return ((c.n == N + 1 && (apply_inverse_sized<N + 1>(c, b, x, blocks), true)) || ...);
}

int solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  Content& c = content(S);
  double* xd = N_VGetArrayPointer(x);
  const double* bd = N_VGetArrayPointer(b);
  if (xd == nullptr || bd == nullptr) return static_cast<int>(c.last_flag = SUNLS_MEM_FAIL);
  // A vector of several blocks of n (a state stacked with its sensitivities) is solved block
  // by block with the one factorisation: the block-diagonal Newton matrix of CVODES's
  // simultaneous corrector.
  const sunindextype length = N_VGetLength(b);
  if (length % c.n != 0 || N_VGetLength(x) != length) return static_cast<int>(c.last_flag = SUNLS_ILL_INPUT);
  // Several blocks (a state stacked with its sensitivities), at the sizes written out: by the
  // inverse, formed once per factorisation (n solves) and applied to every block of every
  // Newton iteration until the next one.
  if (length > c.n && c.n <= kSizedSolves) {
    if (!c.inverse_current) {
      form_inverse_dispatch(c, std::make_integer_sequence<int, kSizedSolves>{});
      c.inverse_current = true;
    }
    apply_inverse_dispatch(c, bd, xd, static_cast<int>(length / c.n), std::make_integer_sequence<int, kSizedSolves>{});
    return static_cast<int>(c.last_flag = SUNLS_SUCCESS);
  }
  for (sunindextype k = 0; k < length; k += c.n)
    solve_dispatch(c, bd + k, xd + k, std::make_integer_sequence<int, kSizedSolves>{});
  return static_cast<int>(c.last_flag = SUNLS_SUCCESS);
}

sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

int space(SUNLinearSolver S, long int* lenrw, long int* leniw) {
  const long int n = static_cast<long int>(content(S).n);
  *lenrw = 2 * n * n;  // the factors and the inverse
  *leniw = 2 * n;
  return SUNLS_SUCCESS;
}

int free_solver(SUNLinearSolver S) {
  if (S == nullptr) return SUNLS_SUCCESS;
  delete static_cast<Content*>(S->content);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver make_dense_lu_solver(sunindextype n, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == nullptr) return nullptr;
  try {
    S->content = new Content(n);
  } catch (...) {
    SUNLinSolFreeEmpty(S);
    return nullptr;
  }
  S->ops->gettype = get_type;
  S->ops->getid = get_id;
  S->ops->initialize = initialize;
  S->ops->setup = setup;
  S->ops->solve = solve;
  S->ops->lastflag = last_flag;
  S->ops->space = space;
  S->ops->free = free_solver;
  return S;
}

}  // namespace kanesens::sim
