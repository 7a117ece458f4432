#include "math/min_norm_solver.hpp"

namespace kanesens::math {

void MinNormSolver::compute(const Eigen::MatrixXd& J) {
  J_ = J;
  gram_.resize(J.rows(), J.rows());
  gram_.noalias() = J_ * J_.transpose();
  llt_.compute(gram_);
  cholesky_ = llt_.info() == Eigen::Success;
  if (cholesky_) {
    const auto d = llt_.matrixLLT().diagonal();
    cholesky_ = d.minCoeff() > 1e-4 * d.maxCoeff();
  }
  if (!cholesky_) cod_.compute(J_);
}

void MinNormSolver::solve(const Eigen::VectorXd& r, Eigen::VectorXd& x) {
  if (!cholesky_) {
    x = cod_.solve(r);
    return;
  }
  w_ = r;
  llt_.solveInPlace(w_);
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
