// A study's outputs over one sample of a KaneProblem (sim/output_plan.hpp): values and exact
// sensitivities of the series at given states, the `at:` values, the integrands of
// integral/mean/rms as the solver's quadratures (an OdeQuadrature), and the final scalars.
// One per thread; reused across samples (start() resets it). simulate() drives it.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "math/dual.hpp"
#include "sim/kane_problem.hpp"
#include "sim/output_eval.hpp"
#include "sim/output_plan.hpp"
#include "sim/solve/ode_problem.hpp"

namespace kanesens::sim {

class OutputEvaluator final : public OdeQuadrature {
 public:
  OutputEvaluator(const OutputPlan& plan, KaneProblem& problem);

  const OutputPlan& plan() const { return plan_; }
  int num_sensitivities() const { return ns_; }

  // Before a sample's integration: every scalar value NaN.
  void start();
  // Series of `program` at the full state y (nstate) and, if s is not null, its sensitivities
  // s[i] (nstate each, i < ns): values()[slot] and tangent(slot, i). Throws if the mass matrix is
  // not positive definite there.
  void evaluate(const OutputProgram& program, double t, const double* y, const double* const* s);
  double value(int slot) const { return values_[static_cast<std::size_t>(slot)]; }
  double tangent(int slot, int i) const { return tangents_[static_cast<std::size_t>(slot * ns_ + i)]; }
  // At the initial state (after start()): the outputs of type eigenvalues. Throws
  // std::runtime_error if the sample cannot be linearized there.
  void take_initial_eigenvalues();
  // At an `at:` time t (after evaluate(plan.at, ...) there): the reductions `at` t take their values.
  void take_at_values(double t);
  // After the integration (ok: it reached the end; span: its length t1 − t0): the quadrature
  // reductions from the last recorded integrals, then the scalar expressions. scalars: [nscalar_recorded], tangents
  // [nscalar_recorded × ns], in plan.scalar_slots order.
  void finish(bool ok, double span, double* scalars, double* scalar_tangents);

  // OdeQuadrature: the integrands of integral, mean (g) and rms (g²) at the integrator's state.
  int size() const override { return static_cast<int>(plan_.quadrature_nodes.size()); }
  void rhs(double t, const double* y, double* qdot) override;
  void sensitivity_rhs(double t, const double* y, int ns, const double* const* s, double* const* qsdot) override;
  void record(int k, double t, const double* q, const double* const* qs) override;

  // The study's events (plan.event_nodes) and the rates of the extrema's series
  // (plan.extremum_nodes) as the integrator's event functions, or nullptr if there are none. At
  // each occurrence of an event (up to max_count) NAME.count grows; at the first, NAME.time = τ
  // and its sensitivities dτ/dp_i = −(∂g/∂y·s_i + ∂g/∂p_i)/(∂g/∂y·ẏ + ∂g/∂t), both through dual
  // numbers; at the k-th, the at_event reductions of k take y_out(τ) and s_out(τ) + ẏ_out(τ)·dτ/dp.
  // At a root of an extremum's rate (sim/output_extrema.cpp) the extremum takes the value if it
  // is beyond the best so far.
  OdeEvents* events() { return events_.size() == 0 ? nullptr : &events_; }
  // At the first and last output times (the full state and its sensitivities; s may be null):
  // the extrema's end candidates. An event that stops the sample makes its time the last end.
  void take_end_values(double t, const double* y_full, const double* const* s_full);
  // After the integration: what the sample's user should know about NaN results ("" if nothing),
  // e.g. an at_event output whose event did not occur k times.
  std::string notes() const;
  // After the integration: every event's kept occurrence times (nevent × W, W =
  // plan.event_occurrences, NaN-padded), their sensitivities (nevent × W × ns) and counts (nevent).
  void event_records(double* times, double* time_tangents, double* counts) const;

 private:
  class Events final : public OdeEvents {
   public:
    explicit Events(OutputEvaluator& e) : e_(e) {}
    int size() const override {
      return static_cast<int>(e_.plan_.event_nodes.size() + e_.plan_.extremum_nodes.size());
    }
    int direction(int i) const override;
    void g(double t, const double* y, double* gout) override;
    bool occurred(int i, double t, const double* y, const double* const* s) override;

   private:
    OutputEvaluator& e_;
  };
  // The rates d/dt of `program`'s series at the integrator's (t, y) into dual_values_[slot].d
  // (one dual pass along (1, ẏ) with no parameter tangent); ydot_, ydot_full_, y_full_ hold ẏ,
  // its full-state image and the full state afterwards.
  void rates(const OutputProgram& program, double t, const double* y);
  // y_full_ and s_full_ (and s_full_ptr_) at the integrator's (t, y, s).
  void full_at(double t, const double* y, const double* const* s);
  // dτ/dp (ns, into dtau_) of event node `node` occurring at the integrator's (t, y, s).
  void event_time_tangents(const OutputNode& node, double t, const double* y, const double* const* s);
  // An event's occurrence number `count` at (t, y, s): the at_event reductions it completes.
  void take_at_event_values(int event_node, long count, double t, const double* y, const double* const* s);
  // At a root of extremum j's rate, or at an end (end: dτ/dp of a moving end, or null): a candidate.
  void take_extremum(std::size_t j, double t, const double* y, const double* const* s, bool root,
                     const double* end_dtau);
  // dt*/dp_i (ns, into dtau_) at a root t* of the rate r = ẏ_out of extremum j's series:
  // −(∂r/∂p_i)/(dr/dt), the event-time formula applied to r, from second-order dual numbers.
  void argextremum_tangents(std::size_t j, double t, const double* y, const double* const* s);
  // The derivative of the rate of the series in `slot` (at y_full_, t) along the direction
  // (dt, dy on the full state, the parameter tangents of `ws`): one pass of the equations of
  // motion on Dual for ẏ and its derivative, one of the extrema's program on Dual2.
  double rate_derivative(int slot, double t, double dt, const double* dy, dynamics::Workspace<math::Dual>& ws,
                         int parameter);

  // Tangent i of `program` into tangents_ (values_ must hold the values at the same state).
  void evaluate_tangent(const OutputProgram& program, int i, double t, const double* y, const double* s);

  const OutputPlan& plan_;
  KaneProblem& problem_;
  const model::Model& model_;
  int ns_ = 0;
  std::vector<double> values_, tangents_;  // nvalues, nvalues × ns
  std::vector<math::Dual> dual_values_, y_dual_;
  OutputScratch<double> scratch_;
  OutputScratch<math::Dual> scratch_dual_;
  std::vector<double> y_full_;                // nstate (quadrature integrands)
  std::vector<std::vector<double>> s_full_;   // ns × nstate
  std::vector<double> quadrature_, quadrature_tangents_;  // last recorded Q (nquad), QS (nquad × ns)
  Events events_{*this};
  std::vector<double> ydot_, ydot_full_, zero_;  // events: ẏ, its full-state image, zeros
  std::vector<const double*> s_full_ptr_;         // ns pointers into s_full_
  std::vector<double> dtau_;                      // ns: an event time's sensitivities
  std::vector<double> best_;                      // per extremum: its series' best value so far
  std::vector<double> occurrence_times_, occurrence_tangents_;  // nevent × W, nevent × W × ns
  // argextremum_tangents' Dual2 workspace and scratch (sim/output_events.cpp), made at the first
  // argextremum with sensitivities.
  struct SecondOrder;
  struct SecondOrderDeleter {
    void operator()(SecondOrder* p) const;
  };
  std::unique_ptr<SecondOrder, SecondOrderDeleter> second_;
};

}  // namespace kanesens::sim
