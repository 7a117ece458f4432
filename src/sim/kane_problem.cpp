#include "sim/kane_problem.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "dynamics/equations.hpp"
#include "model/parameters.hpp"
#include "sim/outputs.hpp"

namespace kanesens::sim {

using dynamics::Workspace;
using math::Dual;

KaneProblem::KaneProblem(const model::Model& model, std::vector<InputRef> sensitivities, ConstraintOptions constraints,
                         double t0)
    : model_(model),
      sens_(std::move(sensitivities)),
      options_(constraints),
      t0_(t0),
      workspaces_(model, sens_),
      holonomic_(model),
      projector_(model, holonomic_),
      y_dual_(model.nstate()),
      ydot_dual_(model.nstate()) {
  embedded_ = model.nconstraint_rows > 0 && options_.formulation == ConstraintOptions::Formulation::embedding;
  if (options_.stabilization == ConstraintOptions::Stabilization::baumgarte) {
    dynamics_.baumgarte_alpha = options_.alpha;
    dynamics_.baumgarte_beta = options_.beta;
  }
  try {
    set_sample(SampleInputs(model));
  } catch (const InputError&) {
    // Kept in failure_: initial_state() reports it unless another sample is loaded.
  }
}

void KaneProblem::set_sample(const SampleInputs& inputs) {
  try {
    failure_.reset();
    const std::string why = model::check_parameters(model_, inputs.parameters.data());
    if (!why.empty()) throw InputError({}, "parameters", why);
    workspaces_.set_parameters(inputs.parameters);
    holonomic_.set_parameters(inputs.parameters);
    initial_ = consistent_initial_state(model_, inputs, sens_, options_, t0_, workspaces_, holonomic_);
    if (embedded_) {
      // Independent speeds from A at the (consistent) initial state.
      Workspace<double>& ws = workspaces_.values();
      const std::vector<double> zero(static_cast<std::size_t>(model_.nu), 0.0);
      dynamics::evaluate_constraints(model_, ws, t0_, initial_.y.data(), zero.data());
      sets_ = dynamics::choose_embedding(ws.constraint_matrix);
      sc_ = std::make_unique<dynamics::EmbeddingScratch<double>>(model_, sets_);
      sc_dual_ = std::make_unique<dynamics::EmbeddingScratch<Dual>>(model_, sets_);
    }
  } catch (const InputError& e) {
    failure_ = e;
    throw;
  }
}

void KaneProblem::check_initial_state() const {
  if (failure_) throw *failure_;
}

void KaneProblem::initial_state(double* y0) const {
  check_initial_state();
  const int nq = model_.nq;
  std::copy(initial_.y.begin(), initial_.y.begin() + nq, y0);
  if (!embedded_) {
    std::copy(initial_.y.begin() + nq, initial_.y.end(), y0 + nq);
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c)
    y0[nq + static_cast<int>(c)] = initial_.y[static_cast<std::size_t>(nq + sets_.independent[c])];
}

void KaneProblem::initial_sensitivity(int i, double* s0) const {
  check_initial_state();
  const int nq = model_.nq;
  const std::vector<double>& s = initial_.s[static_cast<std::size_t>(i)];
  std::copy(s.begin(), s.begin() + nq, s0);
  if (!embedded_) {
    std::copy(s.begin() + nq, s.end(), s0 + nq);
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c)
    s0[nq + static_cast<int>(c)] = s[static_cast<std::size_t>(nq + sets_.independent[c])];
}

template <class S>
void KaneProblem::evaluate(Workspace<S>& ws, const S& t, const S* y, S* ydot) {
  if (!embedded_) {
    dynamics::RhsFailure why = dynamics::RhsFailure::none;
    if (!dynamics::evaluate_rhs(model_, ws, t, y, ydot, dynamics_, &why)) throw RecoverableError(dynamics::describe(why));
    return;
  }
  bool ok = false;
  if constexpr (std::is_same_v<S, double>) {
    ok = dynamics::embedded_rhs(model_, ws, *sc_, sets_, t, y, ydot, dynamics_);
  } else {
    ok = dynamics::embedded_rhs(model_, ws, *sc_dual_, sets_, t, y, ydot, dynamics_);
  }
  if (!ok) throw RecoverableError("embedding: singular mass matrix or dependent-speed matrix");
}

void KaneProblem::rhs(double t, const double* y, double* ydot) {
  evaluate(workspaces_.values(), t, y, ydot);
  if (embedded_ && sc_->conditioning > 1e10)
    throw std::runtime_error("embedding: the independent speeds chosen at t0 no longer parameterise the motion at t = " +
                             std::to_string(t) + " (dependent-speed matrix conditioning " +
                             std::to_string(sc_->conditioning) + "); use formulation: multipliers");
}

void KaneProblem::jacobian(double t, const double* y, const double*, double* J) {
  const int n = size();
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], r == c ? 1.0 : 0.0);
    evaluate(workspaces_.jacobian(), Dual(t), y_dual_.data(), ydot_dual_.data());
    for (int r = 0; r < n; ++r) J[r + c * n] = ydot_dual_[r].d;
  }
}

void KaneProblem::sensitivity_rhs(double t, const double* y, const double*, int i, const double* s, double* sdot) {
  const int n = size();
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  evaluate(workspaces_.tangent(i), Dual(t), y_dual_.data(), ydot_dual_.data());
  for (int r = 0; r < n; ++r) sdot[r] = ydot_dual_[r].d;
}

std::vector<double> KaneProblem::sensitivity_scales() const {
  std::vector<double> scales;
  for (const auto& s : sens_) {
    double v = 1;
    if (s.kind == InputRef::Kind::parameter) v = std::abs(workspaces_.parameters()[static_cast<std::size_t>(s.index)]);
    scales.push_back(v > 0 ? v : 1.0);
  }
  return scales;
}

int KaneProblem::project(double t, const double* y, double* corr, double, double* err) {
  return projector_.project(workspaces_.values(), t, y, size(), !embedded_, corr, err);
}

void KaneProblem::project_sensitivity(double t, const double* y, int i, double* s) {
  projector_.project_sensitivity(workspaces_.tangent(i), dynamics_, t, y, s);
}

void KaneProblem::full_state(double t, const double* y, double* y_full) {
  const int nq = model_.nq;
  std::copy(y, y + nq, y_full);
  if (!embedded_) {
    std::copy(y + nq, y + model_.nstate(), y_full + nq);
    return;
  }
  if (!dynamics::reconstruct_speeds(model_, workspaces_.values(), *sc_, sets_, t, y, y + nq, y_full + nq))
    throw std::runtime_error("embedding: the dependent-speed matrix is singular at t = " + std::to_string(t));
}

void KaneProblem::full_sensitivity(double t, const double* y, int i, const double* s, double* s_full) {
  const int nq = model_.nq, n = size();
  std::copy(s, s + nq, s_full);
  if (!embedded_) {
    std::copy(s + nq, s + model_.nstate(), s_full + nq);
    return;
  }
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  std::vector<Dual> u(static_cast<std::size_t>(model_.nu));
  if (!dynamics::reconstruct_speeds(model_, workspaces_.tangent(i), *sc_dual_, sets_, Dual(t), y_dual_.data(),
                                    y_dual_.data() + nq, u.data()))
    throw std::runtime_error("embedding: the dependent-speed matrix is singular at t = " + std::to_string(t));
  for (int k = 0; k < model_.nu; ++k) s_full[nq + k] = u[static_cast<std::size_t>(k)].d;
}

double KaneProblem::energy(double t, const double* y) { return sim::energy(model_, workspaces_.values(), t, y); }

void KaneProblem::multipliers(double t, const double* y, double* lambda) {
  sim::multipliers(model_, workspaces_.values(), dynamics_, t, y, lambda);
}

void KaneProblem::multiplier_sensitivity(double t, const double* y, int i, const double* s, double* dlambda) {
  sim::multiplier_sensitivity(model_, workspaces_.tangent(i), dynamics_, t, y, s, dlambda);
}

void KaneProblem::constraint_residuals(double t, const double* y, double& position, double& velocity) {
  sim::constraint_residuals(model_, workspaces_.values(), dynamics_, holonomic_.rows(), t, y, position, velocity);
}

void KaneProblem::sensitivity_constraint_residuals(double t, const double* y, int i, const double* s,
                                                   double& position, double& velocity) {
  sim::sensitivity_constraint_residuals(model_, workspaces_.tangent(i), dynamics_, holonomic_.rows(), t, y, s,
                                        position, velocity);
}

}  // namespace kanesens::sim
