// The holonomic (position-level) constraint rows g(q, t) = 0 of a model on doubles, and their
// Jacobian G = ∂g/∂q: what the projection onto the constraints and the consistent initial state
// solve with.
#pragma once
#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "dynamics/workspace.hpp"
#include "math/dual.hpp"

namespace kanesens::sim {

// Dependent columns of a constraint Jacobian J (rank(J) of them), tried in the order `order`: a
// column is taken if it is not negligible against J's largest column and raises the rank of those
// taken. What the consistent initial state and the linearization solve for.
std::vector<int> choose_dependent_columns(const Eigen::MatrixXd& J, const std::vector<int>& order);

class HolonomicConstraints {
 public:
  explicit HolonomicConstraints(const model::Model& model);

  // The constraint rows with a position-level residual, in row order.
  const std::vector<int>& rows() const { return rows_; }
  int size() const { return static_cast<int>(rows_.size()); }
  // q̇ = u for every joint (no quaternions): G is then the holonomic rows of A.
  bool identity_kinematics() const { return identity_kinematics_; }

  void set_parameters(const std::vector<double>& parameters);
  // g (mh) and, when G is given, G (mh × nq) at (t, q): nq dual evaluations (any kinematics).
  void evaluate(double t, const double* q, Eigen::VectorXd& g, Eigen::MatrixXd* G);

 private:
  const model::Model& model_;
  std::vector<int> rows_;
  bool identity_kinematics_ = false;
  std::unique_ptr<dynamics::Workspace<math::Dual>> ws_;  // only for a model with constraints
};

}  // namespace kanesens::sim
