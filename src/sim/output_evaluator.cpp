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
      quadrature_tangents_(plan.quadrature_nodes.size() * static_cast<std::size_t>(ns_), kNaN),
      s_full_ptr_(static_cast<std::size_t>(ns_)),
      dtau_(static_cast<std::size_t>(ns_)),
      best_(plan.extremum_nodes.size(), kNaN),
      occurrence_times_(plan.event_nodes.size() * static_cast<std::size_t>(plan.event_occurrences), kNaN),
      occurrence_tangents_(occurrence_times_.size() * static_cast<std::size_t>(ns_), kNaN) {
  for (int i = 0; i < ns_; ++i) s_full_ptr_[static_cast<std::size_t>(i)] = s_full_[static_cast<std::size_t>(i)].data();
}

void OutputEvaluator::start() {
  std::fill(values_.begin(), values_.end(), kNaN);
  std::fill(tangents_.begin(), tangents_.end(), kNaN);
  std::fill(best_.begin(), best_.end(), kNaN);
  std::fill(occurrence_times_.begin(), occurrence_times_.end(), kNaN);
  std::fill(occurrence_tangents_.begin(), occurrence_tangents_.end(), kNaN);
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
  for (int v : plan_.extremum_nodes) {  // over part of the span only: not the sample's extremum
    if (ok) continue;
    const std::size_t slot = static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(v)].slot);
    values_[slot] = kNaN;
    for (int i = 0; i < ns_; ++i) tangents_[slot * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(i)] = kNaN;
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

}  // namespace kanesens::sim
