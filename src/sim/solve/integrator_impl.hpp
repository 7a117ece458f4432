// Integrator's state (internal to sim/solve): the CVODES objects of one problem shape, reused
// across integrations, and the data its callbacks share. integrator.cpp builds and drives it;
// integrator_stepwise.cpp holds the step-by-step path (re-partitioning restarts),
// integrator_linear_solver.cpp the choice of Newton's linear solver.
#pragma once
#include <cvodes/cvodes.h>

#include <span>
#include <string>
#include <vector>

#include "sim/solve/cvodes_callbacks.hpp"
#include "sim/solve/cvodes_quadrature.hpp"
#include "sim/solve/integrator.hpp"
#include "sim/solve/sundials_handles.hpp"

namespace kanesens::sim {

namespace detail {
// CV_SIMULTANEOUS, CV_STAGGERED or CV_STAGGERED1.
int sensitivity_method_flag(SensitivityMethod m);
}  // namespace detail

struct Integrator::Impl {
  explicit Impl(SolverOptions o) : options(std::move(o)) {}

  SolverOptions options;
  detail::CallbackData cb;

  // Shape of the CVODES objects below (built = false: none yet).
  bool built = false;
  int n = 0;
  int ns = 0;
  int nquad = 0;
  bool projection = false;
  LinearSolver linear_solver = LinearSolver::dense;  // Newton's, resolved (automatic: no Newton)
  SensitivityMethod sensitivity_method = SensitivityMethod::simultaneous;  // resolved
  // The sensitivities ride in the state's vector, [y; s_0; …; s_ns−1], instead of CVODES's
  // sensitivity module (stacking_obstacle).
  bool stacked() const { return ns > 0 && sensitivity_method == SensitivityMethod::stacked; }

  // Declared in creation order; release() frees them in reverse (cvode_mem first).
  ContextPtr ctx;
  NVectorPtr y;
  NVectorPtr atol_vector;
  MatrixPtr A;
  LinearSolverPtr LS;
  NonlinearSolverPtr NLS;
  NVectorArray yS;
  NonlinearSolverPtr NLS_sens;
  NVectorPtr state_weights;   // scratch of proj_trampoline (CallbackData::sens_error_mem)
  NVectorArray sens_weights;
  CvodeMemPtr mem;
  detail::CvodesQuadrature quadrature;  // after mem: its vectors are only CVODES's templates

  NVectorPtr y_out;                       // output interpolated between steps (step-by-step runs)
  NVectorArray yS_out;
  std::vector<const double*> s_pointers;  // ns pointers into yS, for record()
  std::vector<const double*> s_out_pointers;  // ns pointers into yS_out
  std::vector<double*> s_step_pointers;   // ns pointers into yS, for after_step()
  std::vector<double> pbar;               // sensitivity scales of the current problem
  std::vector<int> plist;                 // DQ parameter list of the current problem
  double* dq_p = nullptr;                 // DQ parameter array of the current problem
  std::vector<double> dq_p_saved;         // its values at the start of the run
  std::vector<int> root_directions, roots_found;  // per event function (CVodeRootInit)

  // After CV_ROOT_RETURN at t (y, s: the state and sensitivities there): calls occurred() for
  // every function CVODES found crossing, in index order. True if one asked to stop.
  bool handle_roots(double t, const double* yv, const double* const* s) {
    check_flag(CVodeGetRootInfo(mem.get(), roots_found.data()), "CVodeGetRootInfo");
    bool stop = false;
    event_error.clear();
    try {
      for (std::size_t i = 0; i < roots_found.size(); ++i)
        if (roots_found[i] != 0) stop = cb.events->occurred(static_cast<int>(i), t, yv, s) || stop;
    } catch (const std::exception& e) {
      event_error = e.what();
      return true;
    }
    return stop;
  }
  std::string event_error;  // handle_roots: an event handler threw (the run fails)
  // The integration ends at t: stopped by an event, or failed if its handler threw.
  void stop_at(IntegrationResult& result, double t) const {
    if (!event_error.empty()) {
      result.status = CV_RHSFUNC_FAIL;
      result.t_fail = t;
      result.message = cvode_flag_name(CV_RHSFUNC_FAIL) + " at t = " + detail::format_time(t) + ": event handler threw: " + event_error;
      return;
    }
    result.stopped_at = t;
    result.message = "stopped by an event at t = " + detail::format_time(t);
  }

  void release() noexcept {
    quadrature.release();
    mem.reset();
    yS_out = NVectorArray();
    y_out.reset();
    cb.sens_error_mem = nullptr;
    cb.state_weights = nullptr;
    cb.sens_weights = nullptr;
    sens_weights = NVectorArray();
    state_weights.reset();
    NLS_sens.reset();
    yS = NVectorArray();
    NLS.reset();
    LS.reset();
    A.reset();
    atol_vector.reset();
    y.reset();
    ctx.reset();
    built = false;
  }

  void check_problem(OdeProblem& problem, std::span<const double> times) const;
  // options.linear_solver, or for automatic the choice for this problem (resolve_linear_solver
  // with the estimated spectral radius of J at t0); automatic when there is no Newton iteration.
  LinearSolver choose_linear_solver(OdeProblem& problem, double t0) const;
  double jacobian_rate(OdeProblem& problem, double t0) const;
  // Steps one at a time, records the outputs each step passes and restarts where the problem
  // changes its coordinates (OdeProblem::after_step). Outputs 1.. into `result`.
  void integrate_stepwise(OdeProblem& problem, std::span<const double> times, const RecordFn& record,
                          OdeQuadrature* quad, IntegrationResult& result);
  void fail(IntegrationResult& result, int flag, double t) const {
    result.status = flag;
    result.t_fail = t;
    result.message = cvode_flag_name(flag) + " at t = " + detail::format_time(t);
    if (!cb.solver_message.empty()) result.message += ": " + cb.solver_message;
    if (!cb.callback_message.empty()) result.message += "; " + cb.callback_message;
  }
  // Stacked or not: sensitivity_method (resolved) with n_sens > 0.
  void build(int n_states, int n_sens, bool with_projection, int n_quad, double t0);
  // Why this problem's sensitivities cannot ride in the state's vector (SensitivityMethod::stacked),
  // nullptr when they can. linear_solver: the resolved one.
  const char* stacking_obstacle(OdeProblem& problem, int n_quad, LinearSolver linear_solver) const;
  void reinit(OdeProblem& problem, OdeQuadrature* quad, OdeEvents* events, double t0, double t_end);
  void restore_dq_parameters() noexcept {
    for (std::size_t i = 0; i < dq_p_saved.size(); ++i) dq_p[plist[i]] = dq_p_saved[i];
  }
  SolverStats collect_stats() const;
};

}  // namespace kanesens::sim
