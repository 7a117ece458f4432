#include "math/min_norm_solver.hpp"

#include <algorithm>
#include <cmath>

namespace kanesens::math {

void MinNormSolver::compute(const Eigen::MatrixXd& J) {
  J_ = J;
  const Eigen::Index m = J.rows(), n = J.cols();
  gram_.resize(m, m);
  first_.resize(m);
  column_rows_.resize(m);
  Eigen::Index nnz = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    for (Eigen::Index i = 0; i < m; ++i) nnz += J_(i, k) != 0;
  if (4 * nnz > m * n) {
    gram_.noalias() = J_ * J_.transpose();
    first_.setZero();
  } else {
    // Upper triangle of J Jᵀ, column k of J adding J_ik J_jk for its nonzero rows i ≤ j.
    gram_.setZero();
    for (Eigen::Index i = 0; i < m; ++i) first_[i] = static_cast<int>(i);
    for (Eigen::Index k = 0; k < n; ++k) {
      int c = 0;
      for (Eigen::Index i = 0; i < m; ++i)
        if (J_(i, k) != 0) column_rows_[c++] = static_cast<int>(i);
      for (int b = 0; b < c; ++b) {
        const int j = column_rows_[b];
        first_[j] = std::min(first_[j], column_rows_[0]);
        for (int a = 0; a <= b; ++a) gram_(column_rows_[a], j) += J_(column_rows_[a], k) * J_(j, k);
      }
    }
  }
  // Envelope Cholesky J Jᵀ = Uᵀ U in place: U(k, i) = L(i, k), column i from row first_[i].
  cholesky_ = true;
  double dmax = 0, dmin = 0;
  for (Eigen::Index i = 0; i < m && cholesky_; ++i) {
    const int fi = first_[i];
    double* Ui = &gram_(0, i);
    for (Eigen::Index j = fi; j < i; ++j) {
      const int lo = std::max(fi, first_[j]);
      const double* Uj = &gram_(0, j);
      double s = Ui[j];
      for (Eigen::Index k = lo; k < j; ++k) s -= Uj[k] * Ui[k];
      Ui[j] = s / Uj[j];
    }
    double d = Ui[i];
    for (Eigen::Index k = fi; k < i; ++k) d -= Ui[k] * Ui[k];
    if (!(d > 0)) {
      cholesky_ = false;
      break;
    }
    Ui[i] = std::sqrt(d);
    dmax = i == 0 ? Ui[i] : std::max(dmax, Ui[i]);
    dmin = i == 0 ? Ui[i] : std::min(dmin, Ui[i]);
  }
  if (cholesky_ && m > 0) cholesky_ = dmin > 1e-4 * dmax;
  if (!cholesky_) cod_.compute(J_);
}

void MinNormSolver::solve(const Eigen::VectorXd& r, Eigen::VectorXd& x) {
  if (!cholesky_) {
    x = cod_.solve(r);
    return;
  }
  const Eigen::Index m = J_.rows();
  w_ = r;
  for (Eigen::Index i = 0; i < m; ++i) {  // Uᵀ y = r
    const double* Ui = &gram_(0, i);
    double s = w_[i];
    for (Eigen::Index k = first_[i]; k < i; ++k) s -= Ui[k] * w_[k];
    w_[i] = s / Ui[i];
  }
  for (Eigen::Index i = m - 1; i >= 0; --i) {  // U w = y
    const double* Ui = &gram_(0, i);
    w_[i] /= Ui[i];
    for (Eigen::Index k = first_[i]; k < i; ++k) w_[k] -= Ui[k] * w_[i];
  }
  x.resize(J_.cols());
  x.noalias() = J_.transpose() * w_;
}

void MinNormSolver::remove_normal_component(Eigen::Ref<Eigen::VectorXd> e) {
  Je_.resize(J_.rows());
  Je_.noalias() = J_ * e;
  solve(Je_, x_);
  e -= x_;
}

}  // namespace kanesens::math
