#include "sim/kane_problem.hpp"

#include <cmath>
#include <stdexcept>

#include "kane/equations.hpp"
#include "model/build_model.hpp"
#include "util/error.hpp"

namespace kanesens {

KaneProblem::KaneProblem(const Model& model, std::vector<InputRef> sensitivities)
    : model_(model),
      sens_(std::move(sensitivities)),
      inputs_(model),
      ws_(model),
      ws_jacobian_(model),
      ws_sens_(sens_.size()),
      parameters_(model.nparam()),
      dq_parameters_(model.nparam() + sens_.size()),
      y_dual_(model.nstate()),
      ydot_dual_(model.nstate()) {
  for (std::size_t i = 0; i < sens_.size(); ++i)
    if (sens_[i].kind == InputRef::Kind::parameter) ws_sens_[i] = std::make_unique<Workspace<Dual>>(model);
  set_sample(inputs_);
}

void KaneProblem::set_sample(const SampleInputs& inputs) {
  const std::string why = check_parameters(model_, inputs.parameters.data());
  if (!why.empty()) throw InputError({}, "parameters", why);
  inputs_ = inputs;
  parameters_ = inputs.parameters;
  set_parameters(model_, ws_, parameters_.data());
  std::vector<Dual> p(parameters_.begin(), parameters_.end());
  set_parameters(model_, ws_jacobian_, p.data());
  for (std::size_t i = 0; i < sens_.size(); ++i) {
    if (!ws_sens_[i]) continue;
    p[sens_[i].index].d = 1;
    set_parameters(model_, *ws_sens_[i], p.data());
    p[sens_[i].index].d = 0;
  }
  std::copy(parameters_.begin(), parameters_.end(), dq_parameters_.begin());
  for (std::size_t i = 0; i < sens_.size(); ++i)
    dq_parameters_[model_.nparam() + i] = sens_[i].kind == InputRef::Kind::parameter ? 0.0 : 1.0;
}

// y0 as duals: tangent of sensitivity i (i < 0: no tangent).
void KaneProblem::initial_state_dual(int i, std::vector<Dual>& y0) const {
  const bool param = i >= 0 && sens_[i].kind == InputRef::Kind::parameter;
  const Workspace<Dual>& ws = param ? *ws_sens_[i] : ws_jacobian_;
  int k = 0;
  for (const Joint& j : model_.joints)
    for (Slot s : j.q0) y0[k++] = ws.values[s];
  for (const Joint& j : model_.joints)
    for (Slot s : j.u0) y0[k++] = ws.values[s];
  for (int s = 0; s < model_.nstate(); ++s)
    if (inputs_.initial_set[s]) y0[s] = Dual(inputs_.initial_values[s], 0);
  if (i >= 0 && sens_[i].kind == InputRef::Kind::initial_condition) y0[sens_[i].index].d = 1;
  for (const Joint& j : model_.joints) {
    if (j.quaternion_offset < 0) continue;
    Dual* e = y0.data() + j.quaternion_offset;
    const Dual n = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    if (!(n.v > 0)) throw InputError({}, j.name + ".q0", "the initial quaternion of joint '" + j.name + "' is zero");
    for (int c = 0; c < 4; ++c) e[c] = e[c] / n;
  }
}

void KaneProblem::initial_state(double* y0) const {
  std::vector<Dual> y(model_.nstate());
  initial_state_dual(-1, y);
  for (int s = 0; s < model_.nstate(); ++s) y0[s] = y[s].v;
}

void KaneProblem::initial_sensitivity(int i, double* s0) const {
  std::vector<Dual> y(model_.nstate());
  initial_state_dual(i, y);
  for (int s = 0; s < model_.nstate(); ++s) s0[s] = y[s].d;
}

void KaneProblem::sync_dq_parameters() {
  // CVODES's difference-quotient sensitivities perturb dq_parameters_ in place.
  for (int k = 0; k < model_.nparam(); ++k) {
    if (dq_parameters_[k] != parameters_[k]) {
      std::copy(dq_parameters_.begin(), dq_parameters_.begin() + model_.nparam(), parameters_.begin());
      set_parameters(model_, ws_, parameters_.data());
      return;
    }
  }
}

void KaneProblem::rhs(double t, const double* y, double* ydot) {
  sync_dq_parameters();
  if (!evaluate_rhs(model_, ws_, t, y, ydot))
    throw std::runtime_error("mass matrix is not positive definite at t = " + std::to_string(t));
}

void KaneProblem::jacobian(double t, const double* y, const double*, double* J) {
  const int n = model_.nstate();
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], r == c ? 1.0 : 0.0);
    if (!evaluate_rhs(model_, ws_jacobian_, Dual(t), y_dual_.data(), ydot_dual_.data()))
      throw std::runtime_error("mass matrix is not positive definite at t = " + std::to_string(t));
    for (int r = 0; r < n; ++r) J[r + c * n] = ydot_dual_[r].d;
  }
}

void KaneProblem::sensitivity_rhs(double t, const double* y, const double*, int i, const double* s,
                                  double* sdot) {
  const int n = model_.nstate();
  Workspace<Dual>& ws = ws_sens_[i] ? *ws_sens_[i] : ws_jacobian_;
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  if (!evaluate_rhs(model_, ws, Dual(t), y_dual_.data(), ydot_dual_.data()))
    throw std::runtime_error("mass matrix is not positive definite at t = " + std::to_string(t));
  for (int r = 0; r < n; ++r) sdot[r] = ydot_dual_[r].d;
}

std::vector<double> KaneProblem::sensitivity_scales() const {
  std::vector<double> scales;
  for (const auto& s : sens_) {
    double v = 1;
    if (s.kind == InputRef::Kind::parameter) v = std::abs(parameters_[s.index]);
    scales.push_back(v > 0 ? v : 1.0);
  }
  return scales;
}

std::vector<int> KaneProblem::dq_parameter_list() const {
  std::vector<int> plist;
  for (std::size_t i = 0; i < sens_.size(); ++i)
    plist.push_back(sens_[i].kind == InputRef::Kind::parameter ? sens_[i].index
                                                               : model_.nparam() + static_cast<int>(i));
  return plist;
}

double KaneProblem::energy(double t, const double* y) {
  const double* q = y;
  const double* u = y + model_.nq;
  evaluate_state_expressions(model_, ws_, t, q, u);
  compute_position(model_, ws_, q);
  compute_velocity(model_, ws_, u);
  return kinetic_energy(model_, ws_) + potential_energy(model_, ws_, q);
}

}  // namespace kanesens
