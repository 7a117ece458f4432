// Kane's equations as a CVODES problem: state y = [q; u], exact Jacobian and sensitivity
// right-hand sides from forward-mode dual numbers through the same templated code.
//
// Sensitivity i is with respect to a scene parameter or an initial condition (InputRef).
//   Jacobian column j:      evaluate_rhs on Dual with tangent e_j on y, 0 on parameters.
//   sensitivity rhs i:      evaluate_rhs on Dual with tangent s_i on y and e_p on parameter p
//                           (0 for an initial condition) = J s_i + ∂f/∂p.
//   initial sensitivity i:  the tangent of y0(p) — q0/u0 expressions of parameters, explicit
//                           initial values, and the normalisation of quaternions.
#pragma once
#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "ad/dual.hpp"
#include "model/workspace.hpp"
#include "sim/constraint_options.hpp"
#include "sim/embedding.hpp"
#include "sim/inputs.hpp"
#include "sim/min_norm_solver.hpp"
#include "solve/ode_problem.hpp"

namespace kanesens {

class KaneProblem final : public solve::OdeProblem {
 public:
  KaneProblem(const Model& model, std::vector<InputRef> sensitivities, ConstraintOptions constraints = {});

  // Loads one sample (parameters, initial conditions). Throws InputError if the parameters are
  // physically invalid (mass ≤ 0, ...).
  void set_sample(const SampleInputs& inputs);
  // The time t0 of the initial state (the study's time.start; default 0): time-dependent
  // constraints are made consistent, and the embedding's independent speeds chosen, at t0.
  void set_initial_time(double t0);

  // nq + nu, or with the embedding formulation nq + (number of independent speeds).
  int size() const override {
    return embedded_ ? model_.nq + static_cast<int>(sets_.independent.size()) : model_.nstate();
  }
  void initial_state(double* y0) const override;
  // Checks the current sample at t0 as validation does before a run (sim/initial_checks.cpp):
  // its consistent initial state exists (no constraint vanishes or is non-finite there, the
  // correction converges) and Kane's equations give finite values there with a positive
  // definite mass matrix. Throws InputError naming what is wrong and where it was written.
  void check_initial_state() const;
  void rhs(double t, const double* y, double* ydot) override;
  bool has_jacobian() const override { return true; }
  void jacobian(double t, const double* y, const double* ydot, double* J) override;
  int num_sensitivities() const override { return static_cast<int>(sens_.size()); }
  void initial_sensitivity(int i, double* s0) const override;
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double t, const double* y, const double* ydot, int i, const double* s,
                       double* sdot) override;
  std::vector<double> sensitivity_scales() const override;
  double* dq_parameters() override { return dq_parameters_.data(); }
  std::vector<int> dq_parameter_list() const override;

  bool has_projection() const override {
    return model_.nconstraint_rows > 0 && options_.stabilization == ConstraintOptions::Stabilization::projection;
  }
  bool embedded() const { return embedded_; }
  const EmbeddingSets& embedding_sets() const { return sets_; }
  // The full state [q; u] (nstate) from the integrator's state y (size()), and the full state
  // sensitivity from the integrator's s_i. Identity copies unless embedded.
  void full_state(double t, const double* y, double* y_full);
  void full_sensitivity(double t, const double* y, int i, const double* s, double* s_full);
  int project(double t, const double* y, double* corr, double eps_proj, double* err) override;
  // Whether simulate() projects the recorded sensitivities (projection + project_sensitivities).
  bool projects_sensitivities() const { return has_projection() && options_.project_sensitivities; }

  // Total mechanical energy T + V at (t, y) with the current parameters.
  double energy(double t, const double* y);
  // Multipliers λ (m) at (t, y), and their sensitivity dλ/dp_i (m) along the state sensitivity
  // s_i (n): the chain rule through the augmented solve, by one dual evaluation.
  void multipliers(double t, const double* y, double* lambda);
  void multiplier_sensitivity(double t, const double* y, int i, const double* s, double* dlambda);
  // Projects sensitivity i (s, n entries, in place) onto the tangent space of the constraints at
  // (t, y): the linearisation of project() — s_q ← s_q − G⁺(G s_q + ∂g/∂p), then
  // s_u ← s_u − A⁺ d(A u + a0)/dε along (s, e_p). CVODES's projection moves y only, so the
  // integrated sensitivities drift off this space (docs/constraints.md); simulate() applies this
  // to the recorded sensitivities when stabilization is projection.
  void project_sensitivity(double t, const double* y, int i, double* s);
  // Velocity-level and position-level constraint residuals of sensitivity i at (t, y):
  // max |G s_q + ∂g/∂p| (holonomic rows) and max |d(A u + a0)/dε| (should be 0).
  void sensitivity_constraint_residuals(double t, const double* y, int i, const double* s, double& position,
                                        double& velocity);
  // Constraint residuals at (t, y): max |g| over holonomic rows, max |A u + a0| over all rows.
  void constraint_residuals(double t, const double* y, double& position, double& velocity);
  // Size of the correction that made the last sample's initial state consistent (max norms).
  double initial_position_correction() const { return initial_dq_; }
  double initial_velocity_correction() const { return initial_du_; }
  const Model& model() const { return model_; }
  const std::vector<InputRef>& sensitivities() const { return sens_; }

 private:
  void sync_dq_parameters();
  void initial_state_dual(int i, std::vector<Dual>& y0) const;
  void make_consistent(std::vector<Dual>& y0, const Workspace<Dual>& ws_params) const;
  // Holonomic residual g (mh) and its Jacobian G = ∂g/∂q (mh × nq) at q (doubles).
  void position_constraints(double t, const double* q, Eigen::VectorXd& g, Eigen::MatrixXd* G) const;

  void initial_state_full(double* y0) const;
  // Holonomic residual (and G) at q into projection_.g (.G).
  void holonomic_residual(double t, const double* q, bool jacobian);

  // Storage of project(), allocated once.
  struct ProjectionScratch {
    Eigen::VectorXd q, dq, du, g, zero_u;
    Eigen::MatrixXd G;
    MinNormSolver position, velocity;
  };
  ProjectionScratch projection_;
  bool identity_kinematics_ = false;  // q̇ = u for every joint: G is the holonomic rows of A
  Workspace<Dual>& dual_workspace(int i) { return ws_sens_[i] ? *ws_sens_[i] : ws_jacobian_; }

  ConstraintOptions options_;
  bool embedded_ = false;
  EmbeddingSets sets_;
  std::unique_ptr<EmbeddingScratch<double>> sc_;
  std::unique_ptr<EmbeddingScratch<Dual>> sc_dual_;
  std::vector<int> holonomic_rows_;
  mutable double initial_dq_ = 0, initial_du_ = 0;
  double initial_time_ = 0;
  std::unique_ptr<Workspace<Dual>> ws_project_;

  const Model& model_;
  std::vector<InputRef> sens_;
  SampleInputs inputs_;
  Workspace<double> ws_;
  Workspace<Dual> ws_jacobian_;                           // zero parameter tangents
  std::vector<std::unique_ptr<Workspace<Dual>>> ws_sens_;  // one per parameter sensitivity
  std::vector<double> parameters_;                        // as set in ws_
  std::vector<double> dq_parameters_;                     // np + ns dummies, read by rhs()
  std::vector<Dual> y_dual_, ydot_dual_;
};

}  // namespace kanesens
