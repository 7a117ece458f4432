#include "sim/output_evaluator.hpp"

#include "sim/eigenvalue_outputs.hpp"
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>


namespace kanesens::sim {

using math::Dual;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

OutputEvaluator::OutputEvaluator(const OutputPlan& plan, KaneProblem& problem)
    : plan_(plan),
      problem_(problem),
      model_(problem.model()),
      ns_(problem.num_sensitivities()),
      values_(static_cast<std::size_t>(plan.nvalues), kNaN),
      tangents_(static_cast<std::size_t>(plan.nvalues * ns_), kNaN),
      dual_values_(static_cast<std::size_t>(plan.nvalues)),
      y_dual_(static_cast<std::size_t>(model_.nstate())),
      scratch_(model_),
      scratch_dual_(model_),
      y_full_(static_cast<std::size_t>(model_.nstate())),
      s_full_(static_cast<std::size_t>(ns_), std::vector<double>(static_cast<std::size_t>(model_.nstate()))),
      quadrature_(plan.quadrature_nodes.size(), kNaN),
      quadrature_tangents_(plan.quadrature_nodes.size() * static_cast<std::size_t>(ns_), kNaN) {}

void OutputEvaluator::start() {
  std::fill(values_.begin(), values_.end(), kNaN);
  std::fill(tangents_.begin(), tangents_.end(), kNaN);
  for (int v : plan_.event_nodes) {  // NAME.time NaN until it happens, NAME.count 0
    const std::size_t count = static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(v)].slot + 1);
    values_[count] = 0;
    for (int i = 0; i < ns_; ++i) tangents_[count * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(i)] = 0;
  }
  std::fill(quadrature_.begin(), quadrature_.end(), kNaN);
  std::fill(quadrature_tangents_.begin(), quadrature_tangents_.end(), kNaN);
}

void OutputEvaluator::evaluate(const OutputProgram& program, double t, const double* y, const double* const* s) {
  if (program.empty()) return;
  if (!evaluate_series(plan_, program, model_, problem_.workspaces().values(), problem_.dynamics_options(), t, y,
                       values_.data(), scratch_))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
  for (int i = 0; s && i < ns_; ++i) evaluate_tangent(program, i, t, y, s[i]);
}

void OutputEvaluator::evaluate_tangent(const OutputProgram& program, int i, double t, const double* y,
                                       const double* s) {
  for (int r = 0; r < model_.nstate(); ++r) y_dual_[static_cast<std::size_t>(r)] = Dual(y[r], s[r]);
  if (!evaluate_series(plan_, program, model_, problem_.workspaces().tangent(i), problem_.dynamics_options(), Dual(t),
                       y_dual_.data(), dual_values_.data(), scratch_dual_))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
  for (int v : program.nodes) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(v)];
    for (int c = 0; c < static_cast<int>(n.components.size()); ++c)
      tangents_[static_cast<std::size_t>((n.slot + c) * ns_ + i)] = dual_values_[static_cast<std::size_t>(n.slot + c)].d;
  }
}

void OutputEvaluator::take_initial_eigenvalues() {
  for (const OutputNode& n : plan_.nodes)
    if (n.kind == OutputKind::eigenvalues)
      evaluate_eigenvalues(n, problem_, values_.data() + n.slot, tangents_.data() + static_cast<std::ptrdiff_t>(n.slot) * ns_);
}

void OutputEvaluator::take_at_values(double t) {
  for (const OutputNode& n : plan_.nodes) {
    if (n.kind != OutputKind::reduction || n.reduce != Reduction::at || n.at != t) continue;
    const int from = plan_.nodes[static_cast<std::size_t>(n.of)].slot;
    values_[static_cast<std::size_t>(n.slot)] = values_[static_cast<std::size_t>(from)];
    for (int i = 0; i < ns_; ++i)
      tangents_[static_cast<std::size_t>(n.slot * ns_ + i)] = tangents_[static_cast<std::size_t>(from * ns_ + i)];
  }
}

void OutputEvaluator::finish(bool ok, double span, double* scalars, double* scalar_tangents) {
  // integral = Q(t1), mean = Q/T, rms = sqrt(Q/T) with Q = ∫ g²; tangents by the chain rule.
  const double T = span;
  for (std::size_t j = 0; j < plan_.quadrature_nodes.size(); ++j) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.quadrature_nodes[j])];
    const double Q = ok ? quadrature_[j] : kNaN;
    double v = Q, scale = 1;
    if (n.reduce == Reduction::mean) {
      v = Q / T;
      scale = 1 / T;
    } else if (n.reduce == Reduction::rms) {
      v = std::sqrt(Q / T);
      scale = v > 0 ? 1 / (2 * T * v) : 0.0;  // d sqrt(Q/T) = dQ / (2 T rms)
    }
    values_[static_cast<std::size_t>(n.slot)] = v;
    for (int i = 0; i < ns_; ++i)
      tangents_[static_cast<std::size_t>(n.slot * ns_ + i)] =
          ok ? scale * quadrature_tangents_[j * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(i)] : kNaN;
  }
  if (!plan_.scalar_expressions.empty()) {
    evaluate_scalar_expressions(plan_, problem_.workspaces().values().parameters.data(), values_.data());
    for (int i = 0; i < ns_; ++i) {
      for (int k = 0; k < plan_.nvalues; ++k)
        dual_values_[static_cast<std::size_t>(k)] = Dual(values_[static_cast<std::size_t>(k)], tangents_[static_cast<std::size_t>(k * ns_ + i)]);
      evaluate_scalar_expressions(plan_, problem_.workspaces().tangent(i).parameters.data(), dual_values_.data());
      for (int v : plan_.scalar_expressions) {
        const int slot = plan_.nodes[static_cast<std::size_t>(v)].slot;
        tangents_[static_cast<std::size_t>(slot * ns_ + i)] = dual_values_[static_cast<std::size_t>(slot)].d;
      }
    }
  }
  for (std::size_t k = 0; k < plan_.scalar_slots.size(); ++k) {
    const int slot = plan_.scalar_slots[k];
    scalars[k] = values_[static_cast<std::size_t>(slot)];
    for (int i = 0; i < ns_; ++i)
      scalar_tangents[k * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(i)] =
          tangents_[static_cast<std::size_t>(slot * ns_ + i)];
  }
}

void OutputEvaluator::rhs(double t, const double* y, double* qdot) {
  problem_.full_state(t, y, y_full_.data());
  evaluate(plan_.integrands, t, y_full_.data(), nullptr);
  for (std::size_t j = 0; j < plan_.quadrature_nodes.size(); ++j) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.quadrature_nodes[j])];
    const double g = values_[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(n.of)].slot)];
    qdot[j] = n.reduce == Reduction::rms ? g * g : g;
  }
}

void OutputEvaluator::sensitivity_rhs(double t, const double* y, int ns, const double* const* s,
                                      double* const* qsdot) {
  problem_.full_state(t, y, y_full_.data());
  for (int i = 0; i < ns; ++i) {
    double* sf = s_full_[static_cast<std::size_t>(i)].data();
    problem_.full_sensitivity(t, y, i, s[i], sf);
    for (int r = 0; r < model_.nstate(); ++r) y_dual_[static_cast<std::size_t>(r)] = Dual(y_full_[static_cast<std::size_t>(r)], sf[r]);
    if (!evaluate_series(plan_, plan_.integrands, model_, problem_.workspaces().tangent(i), problem_.dynamics_options(),
                         Dual(t), y_dual_.data(), dual_values_.data(), scratch_dual_))
      throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
    for (std::size_t j = 0; j < plan_.quadrature_nodes.size(); ++j) {
      const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.quadrature_nodes[j])];
      const Dual g = dual_values_[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(n.of)].slot)];
      qsdot[i][j] = n.reduce == Reduction::rms ? 2 * g.v * g.d : g.d;
    }
  }
}

void OutputEvaluator::record(int, double, const double* q, const double* const* qs) {
  const std::size_t nq = quadrature_.size();
  std::copy(q, q + nq, quadrature_.begin());
  for (std::size_t j = 0; j < nq; ++j)
    for (int i = 0; i < ns_; ++i)
      quadrature_tangents_[j * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(i)] = qs ? qs[i][j] : kNaN;
}

double OutputEvaluator::time_derivative(const OutputProgram& program, int slot, double t, const double* y_full,
                                        const double* y_full_dot) {
  // With the tangent workspace of p_0: (g_y·ẏ + g_t + g_p0) − g_p0.
  auto pass = [&](bool along) {
    for (int r = 0; r < model_.nstate(); ++r)
      y_dual_[static_cast<std::size_t>(r)] = Dual(y_full[r], along ? y_full_dot[r] : 0.0);
    if (!evaluate_series(plan_, program, model_, problem_.workspaces().tangent(0), problem_.dynamics_options(),
                         Dual(t, along ? 1.0 : 0.0), y_dual_.data(), dual_values_.data(), scratch_dual_))
      throw std::runtime_error("events: mass matrix is not positive definite at t = " + std::to_string(t));
    return dual_values_[static_cast<std::size_t>(slot)].d;
  };
  const double with = pass(true);
  return with - pass(false);
}

int OutputEvaluator::Events::direction(int i) const {
  return e_.plan_.nodes[static_cast<std::size_t>(e_.plan_.event_nodes[static_cast<std::size_t>(i)])].direction;
}

void OutputEvaluator::Events::g(double t, const double* y, double* gout) {
  const OutputPlan& plan = e_.plan_;
  e_.problem_.full_state(t, y, e_.y_full_.data());
  e_.evaluate(plan.events, t, e_.y_full_.data(), nullptr);
  for (std::size_t i = 0; i < plan.event_nodes.size(); ++i) {
    const OutputNode& n = plan.nodes[static_cast<std::size_t>(plan.event_nodes[i])];
    gout[i] = e_.values_[static_cast<std::size_t>(plan.nodes[static_cast<std::size_t>(n.of)].slot)];
  }
}

bool OutputEvaluator::Events::occurred(int i, double t, const double* y, const double* const* s) {
  const OutputPlan& plan = e_.plan_;
  const OutputNode& n = plan.nodes[static_cast<std::size_t>(plan.event_nodes[static_cast<std::size_t>(i)])];
  const std::size_t time = static_cast<std::size_t>(n.slot), count = time + 1;
  if (e_.values_[count] >= static_cast<double>(n.max_count)) return false;
  e_.values_[count] += 1;
  if (e_.values_[count] > 1) return false;
  e_.values_[time] = t;
  const int ns = e_.ns_;
  if (ns > 0 && s) {
    const int slot = plan.nodes[static_cast<std::size_t>(n.of)].slot;
    const std::size_t nstate = static_cast<std::size_t>(e_.problem_.size());
    const std::size_t nfull = static_cast<std::size_t>(e_.model_.nstate());
    e_.ydot_.resize(nstate);
    e_.ydot_full_.resize(nfull);
    e_.zero_.assign(nstate, 0.0);
    // ẏ in the full state: the full-state map's linear part applied to the integrator's ẏ.
    e_.problem_.rhs(t, y, e_.ydot_.data());
    std::vector<double>& a = e_.s_full_[0];
    e_.problem_.full_sensitivity(t, y, 0, e_.ydot_.data(), e_.ydot_full_.data());
    e_.problem_.full_sensitivity(t, y, 0, e_.zero_.data(), a.data());
    for (std::size_t r = 0; r < nfull; ++r) e_.ydot_full_[r] -= a[r];
    e_.problem_.full_state(t, y, e_.y_full_.data());
    e_.evaluate(plan.events, t, e_.y_full_.data(), nullptr);
    const double dgdt = e_.time_derivative(plan.events, slot, t, e_.y_full_.data(), e_.ydot_full_.data());
    for (int k = 0; k < ns; ++k) {
      double* sf = e_.s_full_[static_cast<std::size_t>(k)].data();
      e_.problem_.full_sensitivity(t, y, k, s[k], sf);
      e_.evaluate_tangent(plan.events, k, t, e_.y_full_.data(), sf);
      const double dgdp = e_.tangents_[static_cast<std::size_t>(slot * ns + k)];
      e_.tangents_[time * static_cast<std::size_t>(ns) + static_cast<std::size_t>(k)] = dgdt != 0 ? -dgdp / dgdt : kNaN;
    }
  }
  return n.stop;
}

}  // namespace kanesens::sim
