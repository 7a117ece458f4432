// The abstract initial-value problem the CVODES integrator solves:
//
//     ẏ = f(t, y; p),   y(t0) = y0(p),   y ∈ ℝⁿ,
//
// with optional forward sensitivities s_i = ∂y/∂p_i (i = 0..ns-1) that obey
//
//     ṡ_i = J s_i + ∂f/∂p_i,   s_i(t0) = ∂y0/∂p_i,   J = ∂f/∂y (n×n).
//
// A "parameter" p_i may be a parameter of f or an initial condition (then ∂f/∂p_i = 0 and
// s_i(t0) is a unit vector). The integrator knows nothing about multibody systems; the Kane model
// implements this interface (one OdeProblem object per sample, or one re-pointed per sample).
//
// Hot path: rhs, jacobian, jacobian_times, sensitivity_rhs and project are called with raw
// pointers into CVODES's own vectors and must neither allocate nor keep the pointers. They may throw: the
// integrator's nothrow trampolines catch the exception, keep its message, and make CVODES stop
// (return −1). A non-finite value written into ydot, J, Jv or sdot is caught by the trampoline too
// and reported to CVODES as a recoverable failure (+1: it retries with a smaller step), and so
// is a RecoverableError: the state of a trial step where the equations cannot be solved (a
// singular mass matrix), which a smaller step may avoid.
#pragma once
#include <stdexcept>
#include <vector>

namespace kanesens::sim {

// Thrown by rhs, jacobian or sensitivity_rhs when f cannot be evaluated at this (t, y) but may
// be at a nearby one: the integrator retries the step with a smaller one (CVODES's recoverable
// +1; DOP853 likewise), and reports this message if that does not help.
class RecoverableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OdeProblem {
 public:
  virtual ~OdeProblem() = default;

  // n, the number of states. Constant for the lifetime of the object.
  virtual int size() const = 0;

  // y0 (n): the initial state at t0 = output_times[0].
  virtual void initial_state(double* y0) const = 0;

  // ydot (n) = f(t, y). y (n) is read-only.
  virtual void rhs(double t, const double* y, double* ydot) = 0;

  // Exact Jacobian J = ∂f/∂y, column-major n×n: J[i + j*n] = ∂ydot_i/∂y_j. ydot = f(t, y) is
  // the current value (free to use). All n² entries must be written (CVODES zeroes J before the
  // call, but do not rely on it). Only called when has_jacobian() and the options ask for it.
  virtual bool has_jacobian() const { return false; }
  virtual void jacobian(double /*t*/, const double* /*y*/, const double* /*ydot*/, double* /*J*/) {}

  // Exact Jacobian–vector product Jv (n) = J v for v (n) at (t, y), ydot = f(t, y) (matrix-free
  // Newton–Krylov: CVODES's GMRES calls it once per Krylov iteration). Only called when
  // has_jacobian_times() and the options ask for an exact Jacobian with the krylov solver.
  virtual bool has_jacobian_times() const { return false; }
  // Whether one exact J v costs about as much as a few right-hand sides, as the krylov solver's
  // automatic choice assumes; false where rhs() takes a cheaper algorithm than J v's pass can
  // (linear_solver: auto then keeps dense when J v is exact).
  virtual bool jacobian_times_cheap() const { return true; }
  virtual void jacobian_times(double /*t*/, const double* /*y*/, const double* /*ydot*/, const double* /*v*/,
                              double* /*Jv*/) {}

  // ns, the number of sensitivity parameters. 0 = no sensitivities are computed.
  virtual int num_sensitivities() const { return 0; }
  // s0 (n) = ∂y0/∂p_i, 0 ≤ i < ns.
  virtual void initial_sensitivity(int /*i*/, double* s0) const { (void)s0; }

  // Exact sensitivity right-hand side sdot (n) = J s + ∂f/∂p_i for the sensitivity s (n) of
  // parameter i. Only called when has_sensitivity_rhs() and the options ask for it.
  virtual bool has_sensitivity_rhs() const { return false; }
  virtual void sensitivity_rhs(double /*t*/, const double* /*y*/, const double* /*ydot*/, int /*i*/,
                               const double* /*s*/, double* /*sdot*/) {}

  // All sensitivity right-hand sides at once: sdot[i] (n) = J s[i] + ∂f/∂p_i for i < ns (CVODES's
  // CVodeSensInit; DOP853). The default calls sensitivity_rhs for each i; a problem that shares
  // work between directions overrides it.
  virtual void sensitivity_rhs_all(double t, const double* y, const double* ydot, int ns, const double* const* s,
                                   double* const* sdot) {
    for (int i = 0; i < ns; ++i) sensitivity_rhs(t, y, ydot, i, s[i], sdot[i]);
  }
  // ydot = f(t, y) and all sensitivity right-hand sides together (DOP853's stages). The default
  // calls rhs, then sensitivity_rhs_all; a problem whose sensitivity pass yields f as a by-product
  // overrides it (f may then differ from rhs() in the last bits: the order of operations).
  virtual void rhs_with_sensitivities(double t, const double* y, int ns, const double* const* s, double* ydot,
                                      double* const* sdot) {
    rhs(t, y, ydot);
    if (ns > 0) sensitivity_rhs_all(t, y, ydot, ns, s, sdot);
  }

  // Scale of each sensitivity parameter, |p̄_i| > 0 (ns entries; empty = all 1). CVODES uses
  // it (CVodeSetSensParams pbar) for the default sensitivity tolerances, atol_S = atol/|p̄_i|
  // (CVodeSensEEtolerances), and for the size of its difference-quotient increments. Usually
  // the nominal value of the parameter, or 1 when that is 0 or the parameter is an initial
  // condition.
  virtual std::vector<double> sensitivity_scales() const { return {}; }

  // For CVODES's internal difference-quotient sensitivities (options.sens_rhs = dq): an array
  // that the RHS reads its parameter values from. CVODES perturbs dq_parameters()[plist[i]] in
  // place between RHS calls (the integrator restores the values after every run, including a
  // failed one). plist = dq_parameter_list() has ns entries; entries for initial-condition
  // sensitivities point at dummies that the RHS ignores (∂f/∂dummy = 0).
  virtual double* dq_parameters() { return nullptr; }
  virtual std::vector<int> dq_parameter_list() const { return {}; }

  // Projection onto a constraint manifold after each step (CVodeSetProjFn with BDF; DOP853 calls
  // it after every accepted step, err = nullptr). Given
  // the step's solution y (n), write the correction corr (n) so that y + corr is the projected
  // state (‖corr‖ within the weighted tolerance eps_proj). err (n, may be nullptr) is CVODES's
  // local error estimate; when not null, overwrite it with its projection (P err). Return 0 on
  // success, > 0 for a recoverable failure (CVODES retries with a smaller step), < 0 fatal.
  // NOTE: combining projection with sensitivities is experimental; see docs/solve.md.
  // Coordinates that change between steps (the embedding re-choosing its independent speeds,
  // docs/explanation/constraints.md). When has_step_check(), the integrator calls after_step after every
  // accepted step (and projection) that does not end the integration, with the step's state y
  // (n) and sensitivities s[i] (n each; s == nullptr when ns = 0). A problem that changes the
  // meaning of its state rewrites y and s in place (same n) and returns true; the integrator
  // then restarts from (t, y, s) (CVodeReInit and CVodeSensReInit; DOP853 re-evaluates its first
  // stage) and counts it (SolverStats::repartitions). Outputs are recorded in the coordinates
  // of the moment (CVODES records those it interpolates before t first). An exception fails the
  // integration with its message.
  virtual bool has_step_check() const { return false; }
  virtual bool after_step(double /*t*/, double* /*y*/, double* const* /*s*/) { return false; }

  virtual bool has_projection() const { return false; }
  virtual int project(double /*t*/, const double* /*y*/, double* /*corr*/, double /*eps_proj*/,
                      double* /*err*/) {
    return 0;
  }
};

// Integrals computed alongside an OdeProblem (quadratures): Q(t) = ∫_{t0}^{t} g(τ, y(τ)) dτ with
// nq = size() components, and, when the problem has forward sensitivities, their sensitivities
// QS_i(t) = ∫ (∂g/∂y s_i + ∂g/∂p_i) dτ. CVODES integrates them as quadratures (CVodeQuadInit,
// CVodeQuadSensInit), DOP853 as extra components stacked after [y; s]; both include them in the
// local error test with the solver's rtol and atol (QS: the sensitivity tolerances and
// error-control setting). Q(t0) = 0, QS_i(t0) = 0. The hot-path rules of OdeProblem apply: rhs
// and sensitivity_rhs neither allocate nor keep the pointers; they may throw (the sample fails).
class OdeQuadrature {
 public:
  virtual ~OdeQuadrature() = default;
  virtual int size() const = 0;
  // qdot (size()) = g(t, y); y is the problem's state (problem.size()).
  virtual void rhs(double t, const double* y, double* qdot) = 0;
  // qsdot[i] (size()) = ∂g/∂y s[i] + ∂g/∂p_i for i < ns (s[i]: the problem's sensitivity i).
  virtual void sensitivity_rhs(double t, const double* y, int ns, const double* const* s, double* const* qsdot) = 0;
  // At output k (the same calls as the RecordFn, after it): Q(t) and QS_i(t) (qs = nullptr when
  // there are no sensitivities). The pointers are valid only during the call.
  virtual void record(int k, double t, const double* q, const double* const* qs) = 0;
};

// Event functions located by the integrator on its continuous solution: an event i happens where
// g_i(t, y) crosses zero in direction(i) (+1 rising, −1 falling, 0 both). CVODES locates the
// crossings with its rootfinding (CVodeRootInit), DOP853 on its continuous extension; both look
// for a sign change of g_i over each step, so two crossings of one function within a step (a
// grazing touch) are not seen, and a g_i that is zero at the start is not an event there. At each
// crossing τ (in time order; several at the same τ in index order), occurred(i, τ, y(τ), s(τ))
// is called (s == nullptr without sensitivities; the pointers are valid during the call only);
// it returns true to stop the integration at τ (IntegrationResult::stopped_at). The outputs
// before τ are recorded first; the output times after a stop are not recorded. g may throw (the
// integration fails with its message).
class OdeEvents {
 public:
  virtual ~OdeEvents() = default;
  virtual int size() const = 0;
  virtual int direction(int i) const = 0;
  // gout (size()) = g(t, y); y is the problem's state (problem.size()).
  virtual void g(double t, const double* y, double* gout) = 0;
  virtual bool occurred(int i, double t, const double* y, const double* const* s) = 0;
};

}  // namespace kanesens::sim
