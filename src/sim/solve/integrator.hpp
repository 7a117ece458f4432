// CVODES integration of an OdeProblem with forward sensitivities, reusable across samples.
//
//   Integrator integ(options);                 // validates options; no SUNDIALS objects yet
//   for (each sample) {
//     problem.set_sample(...);
//     IntegrationResult r = integ.integrate(problem, times, record);
//     if (!r.ok()) log(r.message);             // a failed sample is a status, not an exception
//   }
//
// The first integrate() builds the CVODES objects (context, vectors, dense matrix and LU
// solver or matrix-free GMRES, cvode_mem, sensitivity vectors) in the documented order (cvsRoberts_FSA_dns.c):
// create → init → tolerances → linear solver → SensInit1 → sensitivity tolerances →
// SetSensParams → SetSensErrCon. With stacked sensitivities (SensitivityMethod::stacked, auto's
// choice where it applies) there is no sensitivity module: CVODES integrates [y; s_0; …] as one
// system (docs/solve.md, "Stacked sensitivities"). Later calls with a problem of the same shape
// (size, number of sensitivities, projection or not, corrector) only re-initialise them
// (CVodeReInit, CVodeSensReInit, CVodeSetSensParams; stacked: the tolerances); a different shape
// rebuilds them.
//
// Output: record(k, t, y, s) is called for k = 0..times.size()-1 with t = times[k], the state
// y (n) and s[i] (n) = ∂y/∂p_i for i < ns (s == nullptr when ns = 0). Output 0 is the initial
// state at t0 = times[0] (no integration). The pointers are valid only during the call.
// CVODES steps with its own step sizes and interpolates at each t (CV_NORMAL); it never
// evaluates the RHS past the last output time (CVodeSetStopTime). A problem that
// has_step_check() is stepped one step at a time (CV_ONE_STEP, outputs by CVodeGetDky and
// CVodeGetSensDky) and restarted where after_step() changes its coordinates.
//
// Errors: a solver failure (CVODES flag < 0, including a callback that threw) returns a result
// with status < 0. Exceptions thrown by initial_state, initial_sensitivity, sensitivity_scales,
// dq_parameter_list (called before integration) and by `record` propagate to the caller. Invalid
// options, a problem that lacks what the options ask for (exact Jacobian, exact sensitivity RHS, DQ
// parameters) or bad output times throw std::invalid_argument; a failing SUNDIALS setup call throws
// std::runtime_error. Not thread-safe: one Integrator per thread.
#pragma once
#include <limits>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "sim/solve/ode_problem.hpp"
#include "sim/solve/solver_options.hpp"

namespace kanesens::sim {

// Counters of one integration (CVodeGet*; reset by every integrate()).
struct SolverStats {
  long steps = 0;                  // CVodeGetNumSteps
  long rhs_evals = 0;              // CVodeGetNumRhsEvals (excludes DQ-Jacobian evals)
  long jac_evals = 0;              // CVodeGetNumJacEvals (exact or DQ)
  long lin_rhs_evals = 0;          // CVodeGetNumLinRhsEvals: RHS evals for the DQ Jacobian (or DQ J v)
  long jtimes_evals = 0;           // CVodeGetNumJtimesEvals: J v products, exact or DQ (krylov)
  long lin_iters = 0;              // CVodeGetNumLinIters: GMRES iterations (krylov)
  long lin_conv_fails = 0;         // CVodeGetNumLinConvFails: GMRES failures to converge (krylov)
  long nonlin_iters = 0;           // CVodeGetNumNonlinSolvIters
  long nonlin_conv_fails = 0;      // CVodeGetNumNonlinSolvConvFails
  long error_test_fails = 0;       // CVodeGetNumErrTestFails
  long sens_rhs_evals = 0;         // CVodeGetSensStats nfSevals: sensitivity RHS calls
  long rhs_evals_for_sens = 0;     // CVodeGetSensStats nfevalsS: RHS calls by DQ sensitivities
  long sens_error_test_fails = 0;  // CVodeGetSensStats netfS
  long sens_nonlin_iters = 0;      // CVodeGetSensNumNonlinSolvIters (staggered methods)
  long projections = 0;            // CVodeGetNumProjEvals
  long callback_recoverable = 0;   // callbacks that returned +1 (non-finite output)
  long repartitions = 0;           // restarts in new coordinates (OdeProblem::after_step)
  long dense_outputs = 0;          // DOP853: steps whose continuous extension was built (3 rhs each)
  double wall_seconds = 0;         // wall-clock time of integrate(), setup included

  // Adds the counters of another segment of the same integration (a restart resets CVODES's).
  SolverStats& operator+=(const SolverStats& o);
};

struct IntegrationResult {
  // 1 = all outputs reached; < 0 = the CVODES flag of the failure (CV_TOO_MUCH_WORK = −1,
  // CV_CONV_FAILURE = −4, CV_RHSFUNC_FAIL = −8, ...).
  int status = 0;
  // Empty on success. On failure: flag name, time, CVODES's own message and the last callback
  // message, e.g. "CV_RHSFUNC_FAIL at t = 0.5: CVode: At t = 0.5, the right-hand side routine
  // failed in an unrecoverable manner.; rhs threw: negative length in spring 'k1'".
  std::string message;
  double t_fail = 0;         // time reached when the integration failed (NaN on success)
  int outputs_recorded = 0;  // number of record() calls made
  // An event stopped the integration (OdeEvents::occurred returned true): its time, else NaN.
  // The status stays 1 (ok) and the message says it stopped.
  double stopped_at = std::numeric_limits<double>::quiet_NaN();
  SolverStats stats;
  // The linear solver of Newton's iteration (dense or krylov, as options.linear_solver resolved
  // for this problem); automatic when there was none (functional iteration, dop853).
  LinearSolver linear_solver = LinearSolver::automatic;
  // CVODES's sensitivity corrector (options.sensitivity_method resolved for this problem);
  // automatic when there were no sensitivities or no CVODES (dop853).
  SensitivityMethod sensitivity_method = SensitivityMethod::automatic;
  bool ok() const { return status == 1; }
};

using RecordFn = std::function<void(int k, double t, const double* y, const double* const* s)>;

class Integrator {
 public:
  explicit Integrator(SolverOptions options);  // throws std::invalid_argument
  ~Integrator();
  Integrator(Integrator&&) noexcept;
  Integrator& operator=(Integrator&&) noexcept;
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  // output_times: at least one, strictly increasing, finite. See the file comment. `quadrature`
  // (optional): integrals computed alongside (ode_problem.hpp), handed to its record() after each
  // record() call.
  // `events` (optional): event functions located on the way (ode_problem.hpp, OdeEvents).
  IntegrationResult integrate(OdeProblem& problem, std::span<const double> output_times,
                              const RecordFn& record, OdeQuadrature* quadrature = nullptr,
                              OdeEvents* events = nullptr);

  const SolverOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot convenience: Integrator(options).integrate(problem, output_times, record).
IntegrationResult integrate(OdeProblem& problem, const SolverOptions& options,
                            std::span<const double> output_times, const RecordFn& record,
                            OdeQuadrature* quadrature = nullptr, OdeEvents* events = nullptr);

// "6.4.1": the SUNDIALS this build links.
std::string sundials_version();

}  // namespace kanesens::sim
