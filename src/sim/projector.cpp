#include "sim/projector.hpp"

#include <stdexcept>
#include <string>

#include "dynamics/equations.hpp"

namespace kanesens::sim {

using dynamics::Workspace;
using math::Dual;

Projector::Projector(const model::Model& model, HolonomicConstraints& holonomic)
    : model_(model), holonomic_(holonomic) {
  zero_u_ = Eigen::VectorXd::Zero(model.nu);
  g_.resize(holonomic.size());
  G_.resize(holonomic.size(), model.nq);
}

void Projector::holonomic_residual(Workspace<double>& ws, double t, const double* q, bool jacobian) {
  if (!holonomic_.identity_kinematics()) {
    holonomic_.evaluate(t, q, g_, jacobian ? &G_ : nullptr);
    return;
  }
  dynamics::evaluate_constraints(model_, ws, t, q, zero_u_.data());
  const std::vector<int>& rows = holonomic_.rows();
  for (int r = 0; r < holonomic_.size(); ++r) {
    g_[r] = ws.position_residual[rows[static_cast<std::size_t>(r)]];
    if (jacobian) G_.row(r) = ws.constraint_matrix.row(rows[static_cast<std::size_t>(r)]);
  }
}

int Projector::project(Workspace<double>& ws, double t, const double* y, int n, bool speeds_are_states, double* corr,
                       double* err) {
  const int nq = model_.nq, nu = model_.nu, mh = holonomic_.size();
  q_ = Eigen::Map<const Eigen::VectorXd>(y, nq);
  if (mh > 0) {
    holonomic_residual(ws, t, q_.data(), true);
    position_.compute(G_);
    for (int iter = 0; iter < 4 && g_.lpNorm<Eigen::Infinity>() > 1e-14; ++iter) {
      position_.solve(g_, dq_);
      q_ -= dq_;
      holonomic_residual(ws, t, q_.data(), false);
    }
    if (!g_.allFinite()) return 1;
  }
  for (int i = 0; i < nq; ++i) corr[i] = q_[i] - y[i];
  if (!speeds_are_states) {
    // Velocities satisfy the constraints by construction; only positions drift.
    for (int k = nq; k < n; ++k) corr[k] = 0;
    if (err && mh > 0) position_.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err, nq));
    return 0;
  }
  dynamics::evaluate_constraints(model_, ws, t, q_.data(), y + nq);
  velocity_.compute(ws.constraint_matrix);
  velocity_.solve(ws.velocity_residual, du_);
  for (int k = 0; k < nu; ++k) corr[nq + k] = -du_[k];
  if (!du_.allFinite()) return 1;
  if (err) {
    // e ← e − G⁺G e (positions), e_u ← e_u − A⁺A e_u (speeds).
    if (mh > 0) position_.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err, nq));
    velocity_.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err + nq, nu));
  }
  return 0;
}

void Projector::project_sensitivity(Workspace<Dual>& ws, const dynamics::DynamicsOptions& options, double t,
                                    const double* y, double* s) {
  const int nu = model_.nu, n = model_.nstate(), m = model_.nconstraint_rows;
  const int mh = holonomic_.size();
  if (m == 0) return;
  std::vector<Dual> yd(static_cast<std::size_t>(n)), ydot(static_cast<std::size_t>(n));
  auto evaluate = [&] {
    for (int r = 0; r < n; ++r) yd[static_cast<std::size_t>(r)] = Dual(y[r], s[r]);
    check_evaluated(dynamics::evaluate_rhs(model_, ws, Dual(t), yd.data(), ydot.data(), options), t);
  };
  double* const columns[] = {s};
  evaluate();
  if (mh > 0) {
    Eigen::MatrixXd rt(mh, 1);
    for (int r = 0; r < mh; ++r) rt(r, 0) = ws.position_residual[holonomic_.rows()[static_cast<std::size_t>(r)]].d;
    correct_sensitivity_positions(t, y, rt, columns);
    evaluate();
  }
  Eigen::MatrixXd A(m, nu), rv(m, 1);
  for (int r = 0; r < m; ++r) {
    for (int k = 0; k < nu; ++k) A(r, k) = ws.constraint_matrix(r, k).v;
    rv(r, 0) = ws.velocity_residual[r].d;
  }
  correct_sensitivity_speeds(A, rv, columns);
}

void Projector::check_evaluated(bool ok, double t) {
  if (!ok)
    throw std::runtime_error("sensitivity projection: mass matrix is not positive definite at t = " + std::to_string(t));
}

void Projector::correct_sensitivity_positions(double t, const double* y, const Eigen::MatrixXd& r, double* const* s) {
  Eigen::VectorXd g;
  Eigen::MatrixXd G;
  holonomic_.evaluate(t, y, g, &G);
  const Eigen::MatrixXd dq = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(G).solve(r);
  for (Eigen::Index i = 0; i < dq.cols(); ++i)
    for (int k = 0; k < model_.nq; ++k) s[i][k] -= dq(k, i);
}

void Projector::correct_sensitivity_speeds(const Eigen::MatrixXd& A, const Eigen::MatrixXd& v, double* const* s) {
  const Eigen::MatrixXd du = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(v);
  for (Eigen::Index i = 0; i < du.cols(); ++i)
    for (int k = 0; k < model_.nu; ++k) s[i][model_.nq + k] -= du(k, i);
}

}  // namespace kanesens::sim
