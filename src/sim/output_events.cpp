// The parts of OutputEvaluator the integrator drives through its event functions: the study's
// events (times, counts, values at events) and the extrema of series outputs, located as the
// roots of their rates on the solver's continuous solution, with their sensitivities.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "sim/output_evaluator.hpp"

#include "dynamics/equations.hpp"
#include "math/dual2.hpp"

namespace kanesens::sim {

using math::Dual;
using math::Dual2;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

void OutputEvaluator::rates(const OutputProgram& program, double t, const double* y) {
  const std::size_t n = static_cast<std::size_t>(problem_.size());
  const std::size_t nfull = static_cast<std::size_t>(model_.nstate());
  ydot_.resize(n);
  ydot_full_.resize(nfull);
  problem_.rhs(t, y, ydot_.data());
  problem_.full_state(t, y, y_full_.data());
  problem_.full_rate(t, y, ydot_.data(), ydot_full_.data());
  for (std::size_t r = 0; r < nfull; ++r) y_dual_[r] = Dual(y_full_[r], ydot_full_[r]);
  if (!evaluate_series(plan_, program, model_, problem_.workspaces().jacobian(), problem_.dynamics_options(),
                       Dual(t, 1.0), y_dual_.data(), dual_values_.data(), scratch_dual_))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
}

void OutputEvaluator::full_at(double t, const double* y, const double* const* s) {
  problem_.full_state(t, y, y_full_.data());
  for (int k = 0; s && k < ns_; ++k) problem_.full_sensitivity(t, y, k, s[k], s_full_[static_cast<std::size_t>(k)].data());
}

void OutputEvaluator::event_time_tangents(const OutputNode& node, double t, const double* y, const double* const* s) {
  const int slot = plan_.nodes[static_cast<std::size_t>(node.of)].slot;
  rates(plan_.events, t, y);
  const double dgdt = dual_values_[static_cast<std::size_t>(slot)].d;
  full_at(t, y, s);
  evaluate(plan_.events, t, y_full_.data(), s_full_ptr_.data());
  for (int k = 0; k < ns_; ++k)
    dtau_[static_cast<std::size_t>(k)] = dgdt != 0 ? -tangent(slot, k) / dgdt : kNaN;
}

void OutputEvaluator::take_at_event_values(int event_node, long count, double t, const double* y,
                                           const double* const* s) {
  bool any = false;
  for (int v : plan_.at_event_nodes) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(v)];
    any = any || (n.event == event_node && n.occurrence == count);
  }
  if (!any) return;
  const bool sens = ns_ > 0 && s;
  if (sens) event_time_tangents(plan_.nodes[static_cast<std::size_t>(event_node)], t, y, s);
  // y_out(τ) + ẏ_out(τ)·dτ/dp: the value moves with the event.
  rates(plan_.at_event, t, y);
  std::vector<double> rate;
  for (int v : plan_.at_event_nodes)
    rate.push_back(dual_values_[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(v)].of)].slot)].d);
  full_at(t, y, s);
  evaluate(plan_.at_event, t, y_full_.data(), sens ? s_full_ptr_.data() : nullptr);
  for (std::size_t j = 0; j < plan_.at_event_nodes.size(); ++j) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.at_event_nodes[j])];
    if (n.event != event_node || n.occurrence != count) continue;
    const int of = plan_.nodes[static_cast<std::size_t>(n.of)].slot;
    values_[static_cast<std::size_t>(n.slot)] = value(of);
    for (int k = 0; sens && k < ns_; ++k)
      tangents_[static_cast<std::size_t>(n.slot * ns_ + k)] = tangent(of, k) + rate[j] * dtau_[static_cast<std::size_t>(k)];
  }
}

namespace {
bool beyond(Reduction r, double v, double best) {
  if (std::isnan(v)) return false;
  if (std::isnan(best)) return true;
  return (r == Reduction::max || r == Reduction::argmax) ? v > best : v < best;
}
}  // namespace

void OutputEvaluator::take_end_values(double t, const double* y_full, const double* const* s_full) {
  if (plan_.extremum_nodes.empty()) return;
  evaluate(plan_.extrema, t, y_full, s_full);
  for (std::size_t j = 0; j < plan_.extremum_nodes.size(); ++j) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.extremum_nodes[j])];
    const int of = plan_.nodes[static_cast<std::size_t>(n.of)].slot;
    if (!beyond(n.reduce, value(of), best_[j])) continue;
    best_[j] = value(of);
    const bool arg = n.reduce == Reduction::argmax || n.reduce == Reduction::argmin;
    values_[static_cast<std::size_t>(n.slot)] = arg ? t : value(of);
    // A fixed end: the time does not move with the parameters.
    for (int k = 0; k < ns_; ++k)
      tangents_[static_cast<std::size_t>(n.slot * ns_ + k)] = !s_full ? kNaN : arg ? 0.0 : tangent(of, k);
  }
}

void OutputEvaluator::take_extremum(std::size_t j, double t, const double* y, const double* const* s, bool root,
                                    const double* end_dtau) {
  const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.extremum_nodes[j])];
  const int of = plan_.nodes[static_cast<std::size_t>(n.of)].slot;
  const bool sens = ns_ > 0 && s;
  double rate = 0;
  if (!root && end_dtau) {
    rates(plan_.extrema, t, y);
    rate = dual_values_[static_cast<std::size_t>(of)].d;
  }
  full_at(t, y, s);
  evaluate(plan_.extrema, t, y_full_.data(), sens ? s_full_ptr_.data() : nullptr);
  const double v = value(of);
  if (!beyond(n.reduce, v, best_[j])) return;
  best_[j] = v;
  const std::size_t slot = static_cast<std::size_t>(n.slot);
  if (n.reduce == Reduction::max || n.reduce == Reduction::min) {
    // Envelope rule: at a root of the rate, dt*/dp does not enter; at a moving end, ẏ_out·dτ/dp does.
    values_[slot] = v;
    for (int k = 0; sens && k < ns_; ++k)
      tangents_[slot * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(k)] =
          tangent(of, k) + (end_dtau ? rate * end_dtau[k] : 0.0);
    return;
  }
  values_[slot] = t;
  if (!sens) return;
  if (root) argextremum_tangents(j, t, y, s);
  for (int k = 0; k < ns_; ++k)
    tangents_[slot * static_cast<std::size_t>(ns_) + static_cast<std::size_t>(k)] =
        root ? dtau_[static_cast<std::size_t>(k)] : end_dtau ? end_dtau[k] : 0.0;
}

struct OutputEvaluator::SecondOrder {
  explicit SecondOrder(const model::Model& m, int nvalues)
      : ws(m), scratch(m), values(static_cast<std::size_t>(nvalues)), y(static_cast<std::size_t>(m.nstate())),
        p(static_cast<std::size_t>(m.nparam())), y1(y.size()), f1(y.size()) {}
  dynamics::Workspace<Dual2> ws;
  OutputScratch<Dual2> scratch;
  std::vector<Dual2> values, y, p;
  std::vector<Dual> y1, f1;
};

void OutputEvaluator::SecondOrderDeleter::operator()(SecondOrder* p) const { delete p; }

void OutputEvaluator::argextremum_tangents(std::size_t j, double t, const double* y, const double* const* s) {
  // t* is a root of r(t, p) = ġ_out = ∂g/∂t + ∂g/∂y·ẏ, so dt*/dp = −(∂r/∂p)/(dr/dt): the event-time
  // formula applied to r. Both are second derivatives of g along the solution. The solution in
  // full coordinates obeys ẏ = F(t, y, p), the equations of motion in multiplier form (also when
  // the embedding integrates it: they give the same u̇ where the speeds satisfy the constraints),
  // so r is a function of (t, y, p) and its derivative along a direction (δt, δy, δp) is exact on
  // Dual2 — the outer tangent (δt, δy, δp) and F's derivative along it, the inner (1, F).
  const OutputNode& n = plan_.nodes[static_cast<std::size_t>(plan_.extremum_nodes[j])];
  const int of = plan_.nodes[static_cast<std::size_t>(n.of)].slot;
  if (!second_) second_.reset(new SecondOrder(model_, plan_.nvalues));
  full_at(t, y, s);
  SampleWorkspaces& ws = problem_.workspaces();
  ydot_full_.resize(static_cast<std::size_t>(model_.nstate()));
  if (!dynamics::evaluate_rhs(model_, ws.values(), t, y_full_.data(), ydot_full_.data(), problem_.dynamics_options()))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
  const double rdot = rate_derivative(of, t, 1.0, ydot_full_.data(), ws.jacobian(), -1);
  for (int k = 0; k < ns_; ++k) {
    const InputRef& ref = problem_.sensitivities()[static_cast<std::size_t>(k)];
    const double drdp = rate_derivative(of, t, 0.0, s_full_[static_cast<std::size_t>(k)].data(), ws.tangent(k),
                                        ref.kind == InputRef::Kind::parameter ? ref.index : -1);
    dtau_[static_cast<std::size_t>(k)] = rdot != 0 ? -drdp / rdot : kNaN;
  }
}

double OutputEvaluator::rate_derivative(int slot, double t, double dt, const double* dy,
                                        dynamics::Workspace<Dual>& ws, int parameter) {
  SecondOrder& so = *second_;
  const std::size_t nstate = static_cast<std::size_t>(model_.nstate());
  for (std::size_t r = 0; r < nstate; ++r) so.y1[r] = Dual(y_full_[r], dy[r]);
  if (!dynamics::evaluate_rhs(model_, ws, Dual(t, dt), so.y1.data(), so.f1.data(), problem_.dynamics_options()))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
  const std::vector<double>& p = problem_.workspaces().parameters();
  for (std::size_t i = 0; i < p.size(); ++i) so.p[i] = Dual2(Dual(p[i], static_cast<int>(i) == parameter ? 1.0 : 0.0));
  dynamics::set_parameters(model_, so.ws, so.p.data());
  for (std::size_t r = 0; r < nstate; ++r) so.y[r] = Dual2(so.y1[r], so.f1[r]);
  if (!evaluate_series(plan_, plan_.extrema, model_, so.ws, problem_.dynamics_options(), Dual2(Dual(t, dt), Dual(1.0)),
                       so.y.data(), so.values.data(), so.scratch))
    throw std::runtime_error("outputs: mass matrix is not positive definite at t = " + std::to_string(t));
  return so.values[static_cast<std::size_t>(slot)].d.d;
}

int OutputEvaluator::Events::direction(int i) const {
  const OutputPlan& plan = e_.plan_;
  const std::size_t ne = plan.event_nodes.size();
  if (static_cast<std::size_t>(i) < ne) return plan.nodes[static_cast<std::size_t>(plan.event_nodes[static_cast<std::size_t>(i)])].direction;
  // A maximum where the rate falls through zero, a minimum where it rises.
  const Reduction r = plan.nodes[static_cast<std::size_t>(plan.extremum_nodes[static_cast<std::size_t>(i) - ne])].reduce;
  return r == Reduction::max || r == Reduction::argmax ? -1 : 1;
}

void OutputEvaluator::Events::g(double t, const double* y, double* gout) {
  const OutputPlan& plan = e_.plan_;
  const std::size_t ne = plan.event_nodes.size();
  if (ne > 0) {
    e_.problem_.full_state(t, y, e_.y_full_.data());
    e_.evaluate(plan.events, t, e_.y_full_.data(), nullptr);
    for (std::size_t i = 0; i < ne; ++i) {
      const OutputNode& n = plan.nodes[static_cast<std::size_t>(plan.event_nodes[i])];
      gout[i] = e_.values_[static_cast<std::size_t>(plan.nodes[static_cast<std::size_t>(n.of)].slot)];
      // A NaN has no sign: the crossing could not be located. Say which event, and where.
      if (std::isnan(gout[i]))
        throw std::runtime_error("event '" + n.name + "': 'when' is not a number at t = " + std::to_string(t) +
                                 " (not defined there)");
    }
  }
  if (plan.extremum_nodes.empty()) return;
  e_.rates(plan.extrema, t, y);
  for (std::size_t j = 0; j < plan.extremum_nodes.size(); ++j) {
    const OutputNode& n = plan.nodes[static_cast<std::size_t>(plan.extremum_nodes[j])];
    gout[ne + j] = e_.dual_values_[static_cast<std::size_t>(plan.nodes[static_cast<std::size_t>(n.of)].slot)].d;
    if (std::isnan(gout[ne + j]))
      throw std::runtime_error("output '" + n.name + "': the rate of 'of' is not a number at t = " + std::to_string(t) +
                               " (not defined there)");
  }
}

bool OutputEvaluator::Events::occurred(int i, double t, const double* y, const double* const* s) {
  const OutputPlan& plan = e_.plan_;
  const std::size_t ne = plan.event_nodes.size();
  if (static_cast<std::size_t>(i) >= ne) {
    e_.take_extremum(static_cast<std::size_t>(i) - ne, t, y, s, true, nullptr);
    return false;
  }
  const int node = plan.event_nodes[static_cast<std::size_t>(i)];
  const OutputNode& n = plan.nodes[static_cast<std::size_t>(node)];
  const std::size_t time = static_cast<std::size_t>(n.slot), count = time + 1;
  if (e_.values_[count] >= static_cast<double>(n.max_count)) return false;
  e_.values_[count] += 1;
  const long c = static_cast<long>(e_.values_[count]);
  const int ns = e_.ns_;
  const bool keep = c <= n.recorded_times;  // kept for /events/NAME/time
  if (ns > 0 && s && (keep || c == 1)) e_.event_time_tangents(n, t, y, s);
  if (keep) {
    const std::size_t at = static_cast<std::size_t>(i) * static_cast<std::size_t>(plan.event_occurrences) + static_cast<std::size_t>(c - 1);
    e_.occurrence_times_[at] = t;
    for (int k = 0; ns > 0 && s && k < ns; ++k)
      e_.occurrence_tangents_[at * static_cast<std::size_t>(ns) + static_cast<std::size_t>(k)] = e_.dtau_[static_cast<std::size_t>(k)];
  }
  if (c == 1) {
    e_.values_[time] = t;
    for (int k = 0; ns > 0 && s && k < ns; ++k)
      e_.tangents_[time * static_cast<std::size_t>(ns) + static_cast<std::size_t>(k)] = e_.dtau_[static_cast<std::size_t>(k)];
  }
  e_.take_at_event_values(node, c, t, y, s);
  if (c != 1 || !n.stop) return false;
  // The sample ends here: τ is the extrema's last end, and it moves with the parameters.
  std::vector<double> dtau(static_cast<std::size_t>(ns));
  for (int k = 0; k < ns; ++k) dtau[static_cast<std::size_t>(k)] = e_.tangent(n.slot, k);
  for (std::size_t j = 0; j < plan.extremum_nodes.size(); ++j) e_.take_extremum(j, t, y, s, false, dtau.data());
  return true;
}

std::string OutputEvaluator::notes() const {
  std::string out;
  for (int v : plan_.at_event_nodes) {
    const OutputNode& n = plan_.nodes[static_cast<std::size_t>(v)];
    const OutputNode& ev = plan_.nodes[static_cast<std::size_t>(n.event)];
    const double count = values_[static_cast<std::size_t>(ev.slot + 1)];
    if (count >= static_cast<double>(n.occurrence)) continue;
    out += (out.empty() ? "" : "; ") + n.name + " is NaN: event '" + ev.name + "' occurred " +
           std::to_string(static_cast<long>(count)) + " time" + (count == 1 ? "" : "s") + ", not " +
           std::to_string(n.occurrence);
  }
  return out;
}

}  // namespace kanesens::sim

namespace kanesens::sim {

void OutputEvaluator::event_records(double* times, double* time_tangents, double* counts) const {
  std::copy(occurrence_times_.begin(), occurrence_times_.end(), times);
  std::copy(occurrence_tangents_.begin(), occurrence_tangents_.end(), time_tangents);
  for (std::size_t i = 0; i < plan_.event_nodes.size(); ++i)
    counts[i] = values_[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(plan_.event_nodes[i])].slot + 1)];
}

}  // namespace kanesens::sim
