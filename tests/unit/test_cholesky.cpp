// math/cholesky.hpp against Eigen's LLT: the factor on every size the right-hand side meets
// (even and odd: the double path forms rows in pairs), the solve with divisions and the solve
// with the reciprocal pivots, and a matrix that is not positive definite.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "math/cholesky.hpp"
#include "math/dual.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {
using Eigen::MatrixXd;
using Eigen::VectorXd;

// A random symmetric positive definite n×n matrix with condition number of a few hundred.
MatrixXd random_spd(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  MatrixXd B(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) B(i, j) = uni(rng);
  return B * B.transpose() + 0.05 * MatrixXd::Identity(n, n);
}

TEST(Cholesky, FactorAndBothSolvesMatchEigen) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int n = 1; n <= 33; ++n) {
    const MatrixXd A = random_spd(n, rng);
    VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = uni(rng);
    const Eigen::LLT<MatrixXd> llt(A);
    ASSERT_EQ(llt.info(), Eigen::Success);
    const VectorXd x_ref = llt.solve(b);
    const MatrixXd U_ref = llt.matrixU();

    MatrixXd U = MatrixXd::Zero(n, n);
    VectorXd inverse_pivots(n);
    ASSERT_TRUE(kanesens::math::cholesky_factor(A.data(), n, U.data(), n, n, inverse_pivots.data())) << n;
    const double scale = U_ref.cwiseAbs().maxCoeff();
    for (int j = 0; j < n; ++j) {
      EXPECT_DOUBLE_EQ(inverse_pivots[j], 1.0 / U(j, j)) << n << " " << j;
      for (int i = 0; i <= j; ++i) EXPECT_NEAR(U(i, j), U_ref(i, j), 1e-13 * scale) << n << " " << i << " " << j;
    }
    VectorXd x_div = b, x_mul = b;
    kanesens::math::cholesky_solve(U.data(), n, n, x_div.data());
    kanesens::math::cholesky_solve(U.data(), n, n, inverse_pivots.data(), x_mul.data());
    const double xs = x_ref.cwiseAbs().maxCoeff();
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(x_div[i], x_ref[i], 1e-10 * xs) << n << " " << i;
      EXPECT_NEAR(x_mul[i], x_ref[i], 1e-10 * xs) << n << " " << i;
      EXPECT_NEAR(x_mul[i], x_div[i], 1e-12 * xs) << n << " " << i;
    }
    // In place (U = A), as the embedding's solve uses it; the same factor.
    MatrixXd W = A;
    ASSERT_TRUE(kanesens::math::cholesky_factor(W.data(), n, W.data(), n, n));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= j; ++i) EXPECT_EQ(W(i, j), U(i, j)) << n << " " << i << " " << j;
  }
}

// The solve of many right-hand sides at once (rows of a row-major block, with a leading
// dimension wider than the block) gives each column's solve to round-off (its sums are paired
// differently), and leaves the columns beyond the block alone.
TEST(Cholesky, RowSolveEqualsTheSolveOfEachColumn) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int n : {1, 2, 3, 8, 10, 17}) {
    const MatrixXd A = random_spd(n, rng);
    MatrixXd U(n, n);
    VectorXd inverse_pivots(n);
    ASSERT_TRUE(kanesens::math::cholesky_factor(A.data(), n, U.data(), n, n, inverse_pivots.data()));
    const int ncols = 2 * n + 1, ldx = ncols + 3;
    std::vector<double> X(static_cast<std::size_t>(n * ldx));
    for (double& x : X) x = uni(rng);
    const std::vector<double> B = X;
    kanesens::math::cholesky_solve_rows(U.data(), n, n, inverse_pivots.data(), X.data(), ldx, ncols);
    for (int c = 0; c < ldx; ++c) {
      VectorXd x(n);
      for (int i = 0; i < n; ++i) x[i] = B[static_cast<std::size_t>(i * ldx + c)];
      if (c < ncols) kanesens::math::cholesky_solve(U.data(), n, n, inverse_pivots.data(), x.data());
      const double tol = c < ncols ? 1e-12 * std::max(1.0, x.cwiseAbs().maxCoeff()) : 0.0;
      for (int i = 0; i < n; ++i) EXPECT_LE(std::abs(X[static_cast<std::size_t>(i * ldx + c)] - x[i]), tol) << n << " " << c;
    }
  }
}

TEST(Cholesky, RejectsMatrixThatIsNotPositiveDefinite) {
  std::mt19937 rng(3);
  for (int n : {1, 2, 5, 8}) {
    MatrixXd A = random_spd(n, rng);
    A(n - 1, n - 1) = -1.0;  // the last pivot is negative whatever the rest
    MatrixXd U(n, n);
    VectorXd inverse_pivots(n);
    EXPECT_FALSE(kanesens::math::cholesky_factor(A.data(), n, U.data(), n, n, inverse_pivots.data())) << n;
    EXPECT_FALSE(kanesens::math::cholesky_factor(A.data(), n, U.data(), n, n)) << n;
  }
}

TEST(Cholesky, DualFactorCarriesTheDerivative) {
  // d/de of the solution of (A + e E) x = b at e = 0 is −A⁻¹ E x: the Dual path against it.
  std::mt19937 rng(11);
  const int n = 6;
  const MatrixXd A = random_spd(n, rng), E = random_spd(n, rng);
  VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = 0.1 * (i + 1);
  using kanesens::math::Dual;
  std::vector<Dual> Ad(n * n), U(n * n), x(n);
  for (int k = 0; k < n * n; ++k) Ad[k] = Dual(A.data()[k], E.data()[k]);
  for (int i = 0; i < n; ++i) x[i] = Dual(b[i]);
  ASSERT_TRUE(kanesens::math::cholesky_factor(Ad.data(), n, U.data(), n, n));
  kanesens::math::cholesky_solve(U.data(), n, n, x.data());
  const Eigen::LLT<MatrixXd> llt(A);
  const VectorXd x0 = llt.solve(b);
  const VectorXd dx = -llt.solve(E * x0);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(x[i].v, x0[i], 1e-12 * x0.cwiseAbs().maxCoeff());
    EXPECT_NEAR(x[i].d, dx[i], 1e-10 * dx.cwiseAbs().maxCoeff());
  }
}
}  // namespace

}  // namespace KANESENS_UNITY_ID
