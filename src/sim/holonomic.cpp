#include "sim/holonomic.hpp"

#include <algorithm>

#include "dynamics/equations.hpp"

namespace kanesens::sim {

using math::Dual;

std::vector<int> choose_dependent_columns(const Eigen::MatrixXd& J, const std::vector<int>& order) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> full(J);
  full.setThreshold(1e-10);
  const Eigen::Index rank = full.rank();
  const double scale = J.colwise().norm().maxCoeff();
  std::vector<int> dep;
  for (std::size_t o = 0; o < order.size() && static_cast<Eigen::Index>(dep.size()) < rank; ++o) {
    const int i = order[o];
    if (!(J.col(i).norm() > 1e-10 * scale)) continue;
    std::vector<int> trial = dep;
    trial.push_back(i);
    Eigen::MatrixXd Jd(J.rows(), static_cast<Eigen::Index>(trial.size()));
    for (std::size_t c = 0; c < trial.size(); ++c) Jd.col(static_cast<Eigen::Index>(c)) = J.col(trial[c]);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jd);
    qr.setThreshold(1e-10);
    if (qr.rank() == static_cast<Eigen::Index>(trial.size())) dep = trial;
  }
  return dep;
}

HolonomicConstraints::HolonomicConstraints(const model::Model& model) : model_(model) {
  for (const model::Constraint& c : model.constraints)
    for (int r = 0; r < c.nrows; ++r)
      if (c.holonomic[r]) rows_.push_back(c.row_offset + r);
  identity_kinematics_ = std::all_of(model.joints.begin(), model.joints.end(),
                                     [](const model::Joint& j) { return j.quaternion_offset < 0; });
  if (model.nconstraint_rows > 0) ws_ = std::make_unique<dynamics::Workspace<Dual>>(model);
}

void HolonomicConstraints::set_parameters(const std::vector<double>& parameters) {
  if (!ws_) return;
  const std::vector<Dual> p(parameters.begin(), parameters.end());
  dynamics::set_parameters(model_, *ws_, p.data());
}

void HolonomicConstraints::evaluate(double t, const double* q, Eigen::VectorXd& g, Eigen::MatrixXd* G) {
  const int nq = model_.nq, nu = model_.nu, mh = size();
  std::vector<Dual> qd(q, q + nq), ud(nu, Dual(0));
  g.resize(mh);
  if (G) G->resize(mh, nq);
  const int columns = G ? nq : 1;
  for (int i = 0; i < columns; ++i) {
    if (G) qd[i].d = 1;
    dynamics::evaluate_constraints(model_, *ws_, Dual(t), qd.data(), ud.data());
    for (int r = 0; r < mh; ++r) {
      g[r] = ws_->position_residual[rows_[r]].v;
      if (G) (*G)(r, i) = ws_->position_residual[rows_[r]].d;
    }
    if (G) qd[i].d = 0;
  }
}

}  // namespace kanesens::sim
