// A study's outputs over one sample of a KaneProblem (sim/output_plan.hpp): values and exact
// sensitivities of the series at given states, the `at:` values, the integrands of
// integral/mean/rms as the solver's quadratures (an OdeQuadrature), and the final scalars.
// One per thread; reused across samples (start() resets it). simulate() drives it.
#pragma once
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

  // The study's events (plan.event_nodes) as the integrator's event functions, or nullptr if
  // there are none. At each occurrence (up to max_count) NAME.count grows; at the first,
  // NAME.time = τ and its sensitivities dτ/dp_i = −(∂g/∂y·s_i + ∂g/∂p_i)/(∂g/∂y·ẏ + ∂g/∂t),
  // both through dual numbers.
  OdeEvents* events() { return plan_.event_nodes.empty() ? nullptr : &events_; }

 private:
  class Events final : public OdeEvents {
   public:
    explicit Events(OutputEvaluator& e) : e_(e) {}
    int size() const override { return static_cast<int>(e_.plan_.event_nodes.size()); }
    int direction(int i) const override;
    void g(double t, const double* y, double* gout) override;
    bool occurred(int i, double t, const double* y, const double* const* s) override;

   private:
    OutputEvaluator& e_;
  };
  // dg/dt along the solution at (t, y) for the series slot `slot` of `program` (values_ there):
  // y_full_dot the full state's derivative. Exact, by two dual passes (∂/∂p_0 cancels).
  double time_derivative(const OutputProgram& program, int slot, double t, const double* y_full,
                         const double* y_full_dot);

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
};

}  // namespace kanesens::sim
