#include "sim/solve/integrator.hpp"

#include "sim/solve/dop853.hpp"
#include "sim/solve/output_times.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <cvodes/cvodes_proj.h>
#include <sundials/sundials_config.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/solve/cvodes_callbacks.hpp"
#include "sim/solve/cvodes_quadrature.hpp"
#include "sim/solve/integrator_impl.hpp"
#include "sim/solve/serial_vector_ops.hpp"
#include "sim/solve/sundials_handles.hpp"

namespace kanesens::sim {

int detail::sensitivity_method_flag(SensitivityMethod m) {
  switch (m) {
    case SensitivityMethod::simultaneous:
      return CV_SIMULTANEOUS;
    case SensitivityMethod::staggered:
      return CV_STAGGERED;
    case SensitivityMethod::staggered1:
      return CV_STAGGERED1;
    case SensitivityMethod::stacked:
    case SensitivityMethod::automatic:
      break;  // not CVODES's (stacked), or resolved before CVODES sees it
  }
  return CV_STAGGERED;
}

namespace {

using namespace detail;

[[noreturn]] void invalid(const std::string& what) {
  throw std::invalid_argument(what);
}

}  // namespace


void Integrator::Impl::check_problem(OdeProblem& problem, std::span<const double> times) const {
  const int n_states = problem.size();
  if (n_states <= 0)
    invalid("integrate: problem size must be > 0, got " + std::to_string(n_states));
  options.validate(n_states);
  const int n_sens = problem.num_sensitivities();
  if (n_sens < 0) invalid("integrate: num_sensitivities() < 0");

  check_output_times(times, "integrate");

  if (options.iteration == Iteration::newton && options.jacobian == JacobianKind::exact) {
    if (options.linear_solver == LinearSolver::krylov && !problem.has_jacobian_times())
      invalid("solver.jacobian = exact with linear_solver krylov, but the problem has no exact Jacobian-vector "
              "product (use dq)");
    if (options.linear_solver != LinearSolver::krylov && !problem.has_jacobian() &&
        !(options.linear_solver == LinearSolver::automatic && problem.has_jacobian_times()))
      invalid("solver.jacobian = exact, but the problem has no exact Jacobian (use dq)");
  }
  if (problem.has_projection() && options.method != Method::bdf) {
    invalid("solver.method = adams: CVODES supports projection only with bdf");
  }
  if (n_sens == 0) return;
  if (options.sens_rhs == SensitivityRhs::exact && !problem.has_sensitivity_rhs()) {
    invalid(
        "solver.sensitivity.rhs = exact, but the problem has no exact sensitivity RHS (use dq)");
  }
  const std::vector<double> scales = problem.sensitivity_scales();
  if (!scales.empty() && static_cast<int>(scales.size()) != n_sens) {
    invalid("integrate: sensitivity_scales() has " + std::to_string(scales.size()) +
            " entries, expected num_sensitivities() = " + std::to_string(n_sens));
  }
  for (double s : scales) {
    if (!(std::isfinite(s) && s != 0))
      invalid("integrate: sensitivity scales must be finite and != 0");
  }
  if (options.sens_rhs == SensitivityRhs::dq) {
    if (problem.dq_parameters() == nullptr) {
      invalid("solver.sensitivity.rhs = dq, but the problem has no dq_parameters() array");
    }
    const std::vector<int> list = problem.dq_parameter_list();
    if (static_cast<int>(list.size()) != n_sens) {
      invalid("integrate: dq_parameter_list() has " + std::to_string(list.size()) +
              " entries, expected num_sensitivities() = " + std::to_string(n_sens));
    }
    for (int j : list) {
      if (j < 0) invalid("integrate: dq_parameter_list() entries must be >= 0");
    }
  }
}

// Why this problem's sensitivities cannot ride in the state's vector (nullptr: they can).
// Stacked, CVODES sees one system [y; s_0; …] and solves Newton's block-diagonal system with the
// state's factorisation, so it needs the dense solver and an exact n×n Jacobian (a difference
// quotient or J v would take the stacked system's); the quadratures' sensitivities and the
// re-partitioning restarts are CVODES's sensitivity module's.
const char* Integrator::Impl::stacking_obstacle(OdeProblem& problem, int n_quad, LinearSolver solver) const {
  const SolverOptions& o = options;
  if (o.iteration == Iteration::newton) {
    if (solver != LinearSolver::dense) return "it needs linear_solver dense";
    if (o.jacobian != JacobianKind::exact || !problem.has_jacobian()) return "it needs the exact Jacobian";
  }
  if (o.sens_rhs != SensitivityRhs::exact || !problem.has_sensitivity_rhs())
    return "it needs the exact sensitivity right-hand side (sensitivity.rhs: exact)";
  if (n_quad > 0) return "integral outputs (quadratures) need CVODES's sensitivity module";
  if (problem.has_step_check()) return "the embedding's re-partitioning restarts need CVODES's sensitivity module";
  if (problem.size() > kMaxErrorNormBlock) return "it takes at most 64 states";
  return nullptr;
}

void Integrator::Impl::build(int n_states, int n_sens, bool with_projection, int n_quad, double t0) {
  release();
  const SolverOptions& o = options;
  const bool stack = n_sens > 0 && sensitivity_method == SensitivityMethod::stacked;
  ctx = make_context();
  y = make_serial_vector(stack ? n_states * (1 + n_sens) : n_states, ctx.get());
  N_VConst(0.0, y.get());
  if (stack) {
    // The local error test and Newton's convergence test of the simultaneous corrector: the
    // largest of the blocks' norms with sensitivity error control, the state's alone without.
    if (!use_block_error_norm(y.get(), n_states, o.sens_error_control))
      throw std::logic_error("build: no stacked error norm for " + std::to_string(n_states) + " states");
    atol_vector = make_serial_vector(n_states * (1 + n_sens), ctx.get());
  }
  // y's operations are the compiled ones, fused and vector-array operations included
  // (make_serial_vector, sim/solve/serial_vector_ops.hpp): CVODES updates the Ns sensitivity
  // vectors with one call per operation instead of one per vector, and the clones below and
  // CVODES's own inherit them.

  // create → init
  mem = make_cvode(o.method == Method::bdf ? CV_BDF : CV_ADAMS, ctx.get());
  check_flag(CVodeInit(mem.get(), stack ? stacked_rhs_trampoline : rhs_trampoline, t0, y.get()), "CVodeInit");
  check_flag(CVodeSetUserData(mem.get(), &cb), "CVodeSetUserData");
  check_flag(CVodeSetErrHandlerFn(mem.get(), error_handler, &cb), "CVodeSetErrHandlerFn");

  // → tolerances (stacked: per problem, in reinit)
  if (stack || o.atol_per_state.empty()) {
    check_flag(CVodeSStolerances(mem.get(), o.rtol, o.atol), "CVodeSStolerances");
  } else {
    atol_vector = make_serial_vector(n_states, ctx.get());
    std::copy(o.atol_per_state.begin(), o.atol_per_state.end(),
              N_VGetArrayPointer(atol_vector.get()));
    check_flag(CVodeSVtolerances(mem.get(), o.rtol, atol_vector.get()), "CVodeSVtolerances");
  }

  // → linear solver (Newton) or fixed-point nonlinear solver (functional iteration)
  if (o.iteration == Iteration::newton && linear_solver == LinearSolver::krylov) {
    // Matrix-free: GMRES needs only products J v (without jacobian_times CVODES forms them by a
    // difference quotient of the RHS).
    LS = make_gmres_solver(y.get(), ctx.get());
    check_ls_flag(CVodeSetLinearSolver(mem.get(), LS.get(), nullptr), "CVodeSetLinearSolver");
    if (o.jacobian == JacobianKind::exact)
      check_ls_flag(CVodeSetJacTimes(mem.get(), nullptr, jtimes_trampoline), "CVodeSetJacTimes");
    // GMRES needs no preconditioning here (about one iteration per Newton iteration on stiff-free
    // mechanisms, docs/explanation/solvers.md), but CVODES keeps its estimate of the Newton
    // convergence rate across steps only when the linear solver has a setup phase; without one
    // it assumes a slow rate every step and iterates once more. Hence the identity.
    check_ls_flag(CVodeSetPreconditioner(mem.get(), identity_psetup, identity_psolve), "CVodeSetPreconditioner");
  } else if (o.iteration == Iteration::newton) {
    A = make_dense_matrix(n_states, ctx.get());
    LS = make_dense_solver(n_states, ctx.get());
    check_ls_flag(CVodeSetLinearSolver(mem.get(), LS.get(), A.get()), "CVodeSetLinearSolver");
    if (o.jacobian == JacobianKind::exact) {
      check_ls_flag(CVodeSetJacFn(mem.get(), jac_trampoline), "CVodeSetJacFn");
    }
  } else {
    NLS.reset(SUNNonlinSol_FixedPoint(y.get(), 0, ctx.get()));
    check_ptr(NLS.get(), "SUNNonlinSol_FixedPoint");
    check_flag(CVodeSetNonlinearSolver(mem.get(), NLS.get()), "CVodeSetNonlinearSolver");
  }

  // Optional inputs. max_steps is set before every output (a total budget, see SolverOptions).
  if (o.max_order > 0) check_flag(CVodeSetMaxOrd(mem.get(), o.max_order), "CVodeSetMaxOrd");
  if (o.initial_step > 0)
    check_flag(CVodeSetInitStep(mem.get(), o.initial_step), "CVodeSetInitStep");
  if (o.max_step > 0) check_flag(CVodeSetMaxStep(mem.get(), o.max_step), "CVodeSetMaxStep");

  // Projection (CVODES ≥ 5.3, BDF only). CVODES projects the state only; its interplay with
  // forward sensitivities is not documented by CVODES 6.4 and is tested with the constrained
  // models (docs/solve.md; the simultaneous corrector's error test: below).
  if (with_projection) {
    check_flag(CVodeSetProjFn(mem.get(), stack ? stacked_proj_trampoline : proj_trampoline), "CVodeSetProjFn");
    check_flag(CVodeSetProjErrEst(mem.get(), o.projection_error_estimate ? SUNTRUE : SUNFALSE),
               "CVodeSetProjErrEst");
    check_flag(CVodeSetProjFrequency(mem.get(), o.projection_frequency), "CVodeSetProjFrequency");
  }

  cb.stacked_ns = stack ? n_sens : 0;
  // The pointers the all-at-once sensitivity callbacks hand the problem (stacked or module).
  cb.s_in.assign(static_cast<std::size_t>(n_sens), nullptr);
  cb.s_out.assign(static_cast<std::size_t>(n_sens), nullptr);
  // → SensInit1 → sensitivity tolerances → SetSensParams (in reinit: per problem) → SensErrCon
  if (n_sens > 0 && !stack) {
    yS = NVectorArray(n_sens, y.get());
    for (int i = 0; i < n_sens; ++i) N_VConst(0.0, yS[i]);
    // Exact right-hand sides all at once (one multi-tangent pass), except for staggered1, which
    // CVODES runs only with the one-at-a-time form.
    if (o.sens_rhs == SensitivityRhs::exact && sensitivity_method != SensitivityMethod::staggered1) {
      check_flag(CVodeSensInit(mem.get(), n_sens, sensitivity_method_flag(sensitivity_method),
                               sens_rhs_all_trampoline, yS.get()),
                 "CVodeSensInit");
    } else {
      check_flag(CVodeSensInit1(mem.get(), n_sens, sensitivity_method_flag(sensitivity_method),
                                o.sens_rhs == SensitivityRhs::exact ? sens_rhs_trampoline : nullptr,
                                yS.get()),
                 "CVodeSensInit1");
    }
    if (o.sens_atol) {
      std::vector<double> abstol_s(static_cast<std::size_t>(n_sens), *o.sens_atol);  // copied
      check_flag(CVodeSensSStolerances(mem.get(), o.rtol, abstol_s.data()),
                 "CVodeSensSStolerances");
    } else {
      check_flag(CVodeSensEEtolerances(mem.get()), "CVodeSensEEtolerances");
    }
    check_flag(CVodeSetSensErrCon(mem.get(), o.sens_error_control ? SUNTRUE : SUNFALSE),
               "CVodeSetSensErrCon");
    // The simultaneous corrector's error test would lose the sensitivities when the state's
    // error estimate is projected; the projection callback keeps them (cvodes_callbacks.cpp).
    if (with_projection && o.projection_error_estimate && o.sens_error_control &&
        sensitivity_method == SensitivityMethod::simultaneous) {
      state_weights = make_serial_vector(n_states, ctx.get());
      sens_weights = NVectorArray(n_sens, y.get());
      cb.sens_error_mem = mem.get();
      cb.state_weights = state_weights.get();
      cb.sens_weights = sens_weights.get();
      cb.ns = n_sens;
    }
    if (o.iteration == Iteration::functional) {
      // CVodeSensInit1 attaches Newton solvers for the sensitivities; functional iteration
      // needs fixed-point ones of the matching kind (cvsAdvDiff_FSA_non.c).
      switch (sensitivity_method) {
        case SensitivityMethod::simultaneous:
          NLS_sens.reset(SUNNonlinSol_FixedPointSens(n_sens + 1, y.get(), 0, ctx.get()));
          check_ptr(NLS_sens.get(), "SUNNonlinSol_FixedPointSens");
          check_flag(CVodeSetNonlinearSolverSensSim(mem.get(), NLS_sens.get()),
                     "CVodeSetNonlinearSolverSensSim");
          break;
        case SensitivityMethod::staggered:
          NLS_sens.reset(SUNNonlinSol_FixedPointSens(n_sens, y.get(), 0, ctx.get()));
          check_ptr(NLS_sens.get(), "SUNNonlinSol_FixedPointSens");
          check_flag(CVodeSetNonlinearSolverSensStg(mem.get(), NLS_sens.get()),
                     "CVodeSetNonlinearSolverSensStg");
          break;
        case SensitivityMethod::staggered1:
          NLS_sens.reset(SUNNonlinSol_FixedPoint(y.get(), 0, ctx.get()));
          check_ptr(NLS_sens.get(), "SUNNonlinSol_FixedPoint");
          check_flag(CVodeSetNonlinearSolverSensStg1(mem.get(), NLS_sens.get()),
                     "CVodeSetNonlinearSolverSensStg1");
          break;
        case SensitivityMethod::stacked:
        case SensitivityMethod::automatic:
          break;  // not here (stacked), or resolved in integrate()
      }
    }
  }

  // → quadratures (and their sensitivities), after SensInit as CVodeQuadSensInit requires
  quadrature.build(mem.get(), ctx.get(), n_quad, n_sens, o, cb);

  y_out = make_serial_vector(n_states, ctx.get());
  N_VConst(0.0, y_out.get());
  if (n_sens > 0 && !stack) yS_out = NVectorArray(n_sens, y.get());
  s_pointers.assign(static_cast<std::size_t>(n_sens), nullptr);
  s_out_pointers.assign(static_cast<std::size_t>(n_sens), nullptr);
  s_step_pointers.assign(static_cast<std::size_t>(n_sens), nullptr);
  for (int i = 0; i < n_sens; ++i) {
    if (stack) {  // sensitivity i is block i + 1 of y
      s_pointers[static_cast<std::size_t>(i)] = N_VGetArrayPointer(y.get()) + static_cast<std::ptrdiff_t>(n_states) * (i + 1);
      continue;
    }
    s_pointers[static_cast<std::size_t>(i)] = yS.data(i);
    s_out_pointers[static_cast<std::size_t>(i)] = yS_out.data(i);
    s_step_pointers[static_cast<std::size_t>(i)] = yS.data(i);
  }
  n = n_states;
  ns = n_sens;
  nquad = n_quad;
  projection = with_projection;
  built = true;
}

void Integrator::Impl::reinit(OdeProblem& problem, OdeQuadrature* quad, OdeEvents* events, double t0,
                              double t_end) {
  cb.reset(&problem, n);
  cb.quadrature = quad;
  cb.nquad = nquad;
  problem.initial_state(N_VGetArrayPointer(y.get()));
  if (stacked()) {  // the sensitivities' initial values and tolerances, block by block
    double* yd = N_VGetArrayPointer(y.get());
    double* atol = N_VGetArrayPointer(atol_vector.get());
    const std::vector<double>& state_atol = options.atol_per_state;
    for (int k = 0; k < n; ++k) atol[k] = state_atol.empty() ? options.atol : state_atol[static_cast<std::size_t>(k)];
    pbar = problem.sensitivity_scales();
    for (int i = 0; i < ns; ++i) {
      const std::ptrdiff_t block = static_cast<std::ptrdiff_t>(n) * (i + 1);
      problem.initial_sensitivity(i, yd + block);
      // The module's sensitivity tolerances: sensitivity.atol, or atol / |p̄_i| (CVodeSensEEtolerances).
      const double scale = pbar.empty() ? 1.0 : std::abs(pbar[static_cast<std::size_t>(i)]);
      for (int k = 0; k < n; ++k) atol[block + k] = options.sens_atol ? *options.sens_atol : atol[k] / scale;
    }
    check_flag(CVodeSVtolerances(mem.get(), options.rtol, atol_vector.get()), "CVodeSVtolerances");
  }
  check_flag(CVodeReInit(mem.get(), t0, y.get()), "CVodeReInit");
  dq_p = nullptr;
  dq_p_saved.clear();
  if (ns > 0 && !stacked()) {
    for (int i = 0; i < ns; ++i) problem.initial_sensitivity(i, yS.data(i));
    check_flag(
        CVodeSensReInit(mem.get(), sensitivity_method_flag(sensitivity_method), yS.get()),
        "CVodeSensReInit");
    pbar = problem.sensitivity_scales();
    double* p = nullptr;
    plist.clear();
    if (options.sens_rhs == SensitivityRhs::dq) {
      p = problem.dq_parameters();
      plist = problem.dq_parameter_list();
      // CVODES perturbs p[plist[i]] in place; keep the values to restore after the run.
      dq_p = p;
      dq_p_saved.resize(plist.size());
      for (std::size_t i = 0; i < plist.size(); ++i) dq_p_saved[i] = p[plist[i]];
    }
    check_flag(CVodeSetSensParams(mem.get(), p, pbar.empty() ? nullptr : pbar.data(),
                                  plist.empty() ? nullptr : plist.data()),
               "CVodeSetSensParams");
  }
  quadrature.reinit(mem.get());
  cb.events = events;
  const int nev = events ? events->size() : 0;
  check_flag(CVodeRootInit(mem.get(), nev, nev > 0 ? root_trampoline : nullptr), "CVodeRootInit");
  root_directions.resize(static_cast<std::size_t>(nev));
  roots_found.resize(static_cast<std::size_t>(nev));
  if (nev > 0) {
    for (int i = 0; i < nev; ++i) root_directions[static_cast<std::size_t>(i)] = events->direction(i);
    check_flag(CVodeSetRootDirection(mem.get(), root_directions.data()), "CVodeSetRootDirection");
    // A function that is zero at the start is simply not an event there (ode_problem.hpp).
    check_flag(CVodeSetNoInactiveRootWarn(mem.get()), "CVodeSetNoInactiveRootWarn");
  }
  // Never step past the last output (a model's forcing may be defined only up to t_end).
  check_flag(CVodeSetStopTime(mem.get(), t_end), "CVodeSetStopTime");
}

SolverStats Integrator::Impl::collect_stats() const {
  SolverStats s;
  void* m = mem.get();
  check_flag(CVodeGetNumSteps(m, &s.steps), "CVodeGetNumSteps");
  check_flag(CVodeGetNumRhsEvals(m, &s.rhs_evals), "CVodeGetNumRhsEvals");
  check_flag(CVodeGetNumNonlinSolvIters(m, &s.nonlin_iters), "CVodeGetNumNonlinSolvIters");
  check_flag(CVodeGetNumNonlinSolvConvFails(m, &s.nonlin_conv_fails),
             "CVodeGetNumNonlinSolvConvFails");
  check_flag(CVodeGetNumErrTestFails(m, &s.error_test_fails), "CVodeGetNumErrTestFails");
  if (options.iteration == Iteration::newton) {
    check_ls_flag(CVodeGetNumJacEvals(m, &s.jac_evals), "CVodeGetNumJacEvals");
    check_ls_flag(CVodeGetNumLinRhsEvals(m, &s.lin_rhs_evals), "CVodeGetNumLinRhsEvals");
    check_ls_flag(CVodeGetNumJtimesEvals(m, &s.jtimes_evals), "CVodeGetNumJtimesEvals");
    check_ls_flag(CVodeGetNumLinIters(m, &s.lin_iters), "CVodeGetNumLinIters");
    check_ls_flag(CVodeGetNumLinConvFails(m, &s.lin_conv_fails), "CVodeGetNumLinConvFails");
  }
  if (stacked()) {
    s.sens_rhs_evals = s.rhs_evals;
  } else if (ns > 0) {
    long setups = 0;
    check_flag(CVodeGetSensStats(m, &s.sens_rhs_evals, &s.rhs_evals_for_sens,
                                 &s.sens_error_test_fails, &setups),
               "CVodeGetSensStats");
    if (sensitivity_method != SensitivityMethod::simultaneous) {
      check_flag(CVodeGetSensNumNonlinSolvIters(m, &s.sens_nonlin_iters),
                 "CVodeGetSensNumNonlinSolvIters");
    }
  }
  if (projection) check_flag(CVodeGetNumProjEvals(m, &s.projections), "CVodeGetNumProjEvals");
  s.callback_recoverable = cb.recoverable;
  return s;
}

Integrator::Integrator(SolverOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  impl_->options.validate();
}
Integrator::~Integrator() = default;
Integrator::Integrator(Integrator&&) noexcept = default;
Integrator& Integrator::operator=(Integrator&&) noexcept = default;

const SolverOptions& Integrator::options() const {
  return impl_->options;
}

IntegrationResult Integrator::integrate(OdeProblem& problem, std::span<const double> times,
                                        const RecordFn& record, OdeQuadrature* quad, OdeEvents* events) {
  // The explicit method has no CVODES objects; it shares the options, result and record().
  if (impl_->options.method == Method::dop853)
    return integrate_dop853(problem, impl_->options, times, record, quad, events);
  const auto start = std::chrono::steady_clock::now();
  Impl& im = *impl_;
  im.check_problem(problem, times);

  const int n_states = problem.size();
  const int n_sens = problem.num_sensitivities();
  const bool with_projection = problem.has_projection();
  const int n_quad = quad ? quad->size() : 0;
  const LinearSolver linear_solver = im.choose_linear_solver(problem, times.front());
  const char* stacking_obstacle = n_sens > 0 ? im.stacking_obstacle(problem, n_quad, linear_solver) : "";
  const SensitivityMethod sensitivity_method =
      resolve_sensitivity_method(im.options.sensitivity_method, with_projection, stacking_obstacle == nullptr);
  if (n_sens > 0 && sensitivity_method == SensitivityMethod::stacked && stacking_obstacle != nullptr)
    invalid(std::string("solver.sensitivity.method = stacked: ") + stacking_obstacle + " (use auto)");
  if (!im.built || im.n != n_states || im.ns != n_sens || im.projection != with_projection || im.nquad != n_quad ||
      im.linear_solver != linear_solver || im.sensitivity_method != sensitivity_method) {
    im.linear_solver = linear_solver;
    im.sensitivity_method = sensitivity_method;
    im.build(n_states, n_sens, with_projection, n_quad, times.front());
  }
  im.reinit(problem, quad, events, times.front(), times.back());

  // Restore CVODES's DQ perturbations of the problem's parameters however we leave.
  struct RestoreGuard {
    Impl& im;
    ~RestoreGuard() { im.restore_dq_parameters(); }
  } guard{im};

  IntegrationResult result;
  result.linear_solver = linear_solver;
  if (n_sens > 0) result.sensitivity_method = sensitivity_method;
  void* m = im.mem.get();
  double* y = N_VGetArrayPointer(im.y.get());
  const double* const* s = n_sens > 0 ? im.s_pointers.data() : nullptr;

  record(0, times[0], y, s);
  if (quad) im.quadrature.record(m, *quad, 0, times[0]);
  result.outputs_recorded = 1;
  result.status = 1;
  result.t_fail = std::numeric_limits<double>::quiet_NaN();

  if (problem.has_step_check()) {
    im.integrate_stepwise(problem, times, record, quad, result);
    const SolverStats earlier = result.stats;
    result.stats = im.collect_stats();
    result.stats += earlier;
    result.stats.callback_recoverable = im.cb.recoverable;  // ours: not reset by CVodeReInit
    result.stats.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
  for (std::size_t k = 1; k < times.size(); ++k) {
    const double tout = times[k];
    long steps = 0;
    check_flag(CVodeGetNumSteps(m, &steps), "CVodeGetNumSteps");
    const long remaining = im.options.max_steps - steps;
    double t_reached = times.front();
    if (remaining <= 0) {
      check_flag(CVodeGetCurrentTime(m, &t_reached), "CVodeGetCurrentTime");
      if (t_reached < tout) {  // another step would be needed
        result.status = CV_TOO_MUCH_WORK;
        result.t_fail = t_reached;
        result.message = "CV_TOO_MUCH_WORK at t = " + format_time(t_reached) +
                         ": max_steps = " + std::to_string(im.options.max_steps) +
                         " steps taken before reaching t = " + format_time(tout);
        break;
      }
    }
    check_flag(CVodeSetMaxNumSteps(m, remaining > 0 ? remaining : 1), "CVodeSetMaxNumSteps");
    int flag = CVode(m, tout, im.y.get(), &t_reached, CV_NORMAL);
    bool stopped = false;
    while (flag == CV_ROOT_RETURN && !stopped) {
      if (n_sens > 0 && !im.stacked()) check_flag(CVodeGetSens(m, &t_reached, im.yS.get()), "CVodeGetSens");
      stopped = im.handle_roots(t_reached, y, s);
      // A zero exactly at tout: y is y(tout) already. CVode(tout) again would search up to tout
      // once more and find g(tout) = 0 again, for ever.
      if (!stopped) flag = t_reached == tout ? CV_SUCCESS : CVode(m, tout, im.y.get(), &t_reached, CV_NORMAL);
    }
    if (stopped) {
      im.stop_at(result, t_reached);
      break;
    }
    if (flag < 0) {
      im.fail(result, flag, t_reached);
      break;
    }
    if (n_sens > 0 && !im.stacked()) check_flag(CVodeGetSens(m, &t_reached, im.yS.get()), "CVodeGetSens");
    record(static_cast<int>(k), tout, y, s);
    if (quad) im.quadrature.record(m, *quad, static_cast<int>(k), tout);
    ++result.outputs_recorded;
  }

  result.stats = im.collect_stats();
  result.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

SolverStats& SolverStats::operator+=(const SolverStats& o) {
  steps += o.steps;
  rhs_evals += o.rhs_evals;
  jac_evals += o.jac_evals;
  lin_rhs_evals += o.lin_rhs_evals;
  jtimes_evals += o.jtimes_evals;
  lin_iters += o.lin_iters;
  lin_conv_fails += o.lin_conv_fails;
  nonlin_iters += o.nonlin_iters;
  nonlin_conv_fails += o.nonlin_conv_fails;
  error_test_fails += o.error_test_fails;
  sens_rhs_evals += o.sens_rhs_evals;
  rhs_evals_for_sens += o.rhs_evals_for_sens;
  sens_error_test_fails += o.sens_error_test_fails;
  sens_nonlin_iters += o.sens_nonlin_iters;
  projections += o.projections;
  callback_recoverable += o.callback_recoverable;
  repartitions += o.repartitions;
  dense_outputs += o.dense_outputs;
  wall_seconds += o.wall_seconds;
  return *this;
}

IntegrationResult integrate(OdeProblem& problem, const SolverOptions& options,
                            std::span<const double> output_times, const RecordFn& record, OdeQuadrature* quad,
                            OdeEvents* events) {
  Integrator integrator(options);
  return integrator.integrate(problem, output_times, record, quad, events);
}

std::string sundials_version() {
  return SUNDIALS_VERSION;
}

}  // namespace kanesens::sim
