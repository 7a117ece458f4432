// Newton's dense linear solver (sim/solve/dense_lu_solver.hpp), through SUNDIALS's generic calls
// as CVODES makes them: its solves agree with Eigen's full-pivoting LU on random matrices and on
// ones whose diagonal vanishes (pivoting needed), in place and not; a zero or non-finite pivot
// (or one whose reciprocal overflows) is a recoverable SUNLS_LUFACT_FAIL; a matrix of another
// size is refused; a stacked vector of several blocks of n is solved block by block.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "sim/solve/sundials_handles.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;

// One solver of size n with its matrix and vectors.
struct Solver {
  explicit Solver(int size)
      : n(size),
        ctx(make_context()),
        ls(make_dense_solver(n, ctx.get())),
        A(make_dense_matrix(n, ctx.get())),
        x(make_serial_vector(n, ctx.get())),
        b(make_serial_vector(n, ctx.get())) {}
  int setup(const Eigen::MatrixXd& M) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) SM_ELEMENT_D(A.get(), i, j) = M(i, j);
    return SUNLinSolSetup(ls.get(), A.get());
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs, bool in_place = false) {
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(b.get()), n) = rhs;
    N_Vector out = in_place ? b.get() : x.get();
    EXPECT_EQ(SUNLinSolSolve(ls.get(), A.get(), out, b.get(), 0.0), SUNLS_SUCCESS);
    if (!in_place) {
      EXPECT_EQ(Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(b.get()), n), rhs) << "b kept";
    }
    return Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(out), n);
  }
  int n;
  ContextPtr ctx;
  LinearSolverPtr ls;
  MatrixPtr A;
  NVectorPtr x, b;
};

TEST(DenseLuSolver, SolvesAsEigensFullPivotingLu) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  // Every size with its own unrolled substitutions (1 to 16), and larger ones.
  for (int n : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 32, 57}) {
    SCOPED_TRACE(n);
    Solver s(n);
    EXPECT_EQ(SUNLinSolGetType(s.ls.get()), SUNLINEARSOLVER_DIRECT);
    EXPECT_EQ(SUNLinSolInitialize(s.ls.get()), SUNLS_SUCCESS);
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::MatrixXd M(n, n);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) M(i, j) = u(rng);
      // Half the trials: I − γJ as CVODES forms it (diagonally dominant); half: no structure.
      if (trial % 2 == 0) M = Eigen::MatrixXd::Identity(n, n) - 0.1 * M;
      Eigen::VectorXd rhs(n);
      for (int i = 0; i < n; ++i) rhs[i] = u(rng);
      ASSERT_EQ(s.setup(M), SUNLS_SUCCESS);
      const Eigen::FullPivLU<Eigen::MatrixXd> full(M);
      const Eigen::VectorXd ref = full.solve(rhs);
      const double tol = 1e-14 / full.rcond() * ref.norm();  // rcond: 1 / (an estimate of) the condition number
      EXPECT_LE((s.solve(rhs) - ref).norm(), tol) << "trial " << trial;
      EXPECT_LE((s.solve(rhs, true) - ref).norm(), tol) << "trial " << trial << ", in place";
      EXPECT_EQ(SUNLinSolLastFlag(s.ls.get()), SUNLS_SUCCESS);
    }
  }
}

TEST(DenseLuSolver, PivotsWhereTheDiagonalVanishes) {
  // A permutation times a scaling: every diagonal entry is 0, so each step must swap rows.
  const int n = 6;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) M(i, (i + 2) % n) = 1.0 + i;
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) rhs[i] = std::sin(1.0 + i);
  Solver s(n);
  ASSERT_EQ(s.setup(M), SUNLS_SUCCESS);
  EXPECT_LE((M * s.solve(rhs) - rhs).norm(), 1e-15);
}

TEST(DenseLuSolver, ReportsAZeroOrNonFinitePivotAndAWrongSize) {
  Solver s(3);
  Eigen::MatrixXd zero_column = Eigen::Matrix3d::Identity();
  zero_column.col(1).setZero();
  EXPECT_EQ(s.setup(zero_column), SUNLS_LUFACT_FAIL);
  EXPECT_EQ(SUNLinSolLastFlag(s.ls.get()), SUNLS_LUFACT_FAIL);
  Eigen::MatrixXd with_nan = Eigen::Matrix3d::Identity();
  with_nan(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(s.setup(with_nan), SUNLS_LUFACT_FAIL);
  Eigen::MatrixXd with_inf = Eigen::Matrix3d::Identity();
  with_inf(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(s.setup(with_inf), SUNLS_LUFACT_FAIL);
  Eigen::MatrixXd subnormal = Eigen::Matrix3d::Identity();
  subnormal(1, 1) = 1e-310;  // its reciprocal overflows
  EXPECT_EQ(s.setup(subnormal), SUNLS_LUFACT_FAIL);
  // Recovers on the next good matrix.
  EXPECT_EQ(s.setup(Eigen::Matrix3d::Identity() * 2), SUNLS_SUCCESS);
  EXPECT_EQ(s.solve(Eigen::Vector3d(2, 4, 6)), Eigen::VectorXd(Eigen::Vector3d(1, 2, 3)));

  MatrixPtr other = make_dense_matrix(4, s.ctx.get());
  EXPECT_EQ(SUNLinSolSetup(s.ls.get(), other.get()), SUNLS_ILL_INPUT);
  long lenrw = 0, leniw = 0;
  EXPECT_EQ(SUNLinSolSpace(s.ls.get(), &lenrw, &leniw), SUNLS_SUCCESS);
  EXPECT_EQ(lenrw, 18);  // the factors and the inverse for stacked right-hand sides
}

// A state stacked with its sensitivities, [y; s_0; …]: each block of n solved with the one
// factorisation, as one solve of it would be; a length that is no multiple of n is refused.
TEST(DenseLuSolver, SolvesEveryBlockOfAStackedVector) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {1, 5, 10, 17}) {
    SCOPED_TRACE(n);
    Solver s(n);
    Eigen::MatrixXd M(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) M(i, j) = u(rng);
    M = Eigen::MatrixXd::Identity(n, n) - 0.1 * M;
    ASSERT_EQ(s.setup(M), SUNLS_SUCCESS);
    const int blocks = 7;
    NVectorPtr b = make_serial_vector(n * blocks, s.ctx.get()), x = make_serial_vector(n * blocks, s.ctx.get());
    Eigen::Map<Eigen::VectorXd> bd(N_VGetArrayPointer(b.get()), n * blocks), xd(N_VGetArrayPointer(x.get()), n * blocks);
    for (int i = 0; i < n * blocks; ++i) bd[i] = u(rng);
    const Eigen::VectorXd rhs = bd;
    ASSERT_EQ(SUNLinSolSolve(s.ls.get(), s.A.get(), x.get(), b.get(), 0.0), SUNLS_SUCCESS);
    const Eigen::FullPivLU<Eigen::MatrixXd> full(M);
    for (int k = 0; k < blocks; ++k) {
      const Eigen::VectorXd ref = full.solve(rhs.segment(k * n, n));
      EXPECT_LE((xd.segment(k * n, n) - ref).norm(), 1e-14 / full.rcond() * ref.norm()) << "block " << k;
    }
    const Eigen::VectorXd first = xd;
    ASSERT_EQ(SUNLinSolSolve(s.ls.get(), s.A.get(), b.get(), b.get(), 0.0), SUNLS_SUCCESS);  // in place
    EXPECT_EQ(Eigen::VectorXd(bd), first);
    // A new factorisation is used from the next solve on (the inverse is not stale).
    ASSERT_EQ(s.setup(2 * M), SUNLS_SUCCESS);
    bd = rhs;
    ASSERT_EQ(SUNLinSolSolve(s.ls.get(), s.A.get(), x.get(), b.get(), 0.0), SUNLS_SUCCESS);
    EXPECT_LE((xd - first / 2).norm(), 1e-13 / full.rcond() * first.norm());
  }
  Solver s(3);
  ASSERT_EQ(s.setup(Eigen::Matrix3d::Identity()), SUNLS_SUCCESS);
  NVectorPtr odd = make_serial_vector(7, s.ctx.get());
  EXPECT_EQ(SUNLinSolSolve(s.ls.get(), s.A.get(), odd.get(), odd.get(), 0.0), SUNLS_ILL_INPUT);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
