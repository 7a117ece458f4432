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

 private:
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
};

}  // namespace kanesens::sim
