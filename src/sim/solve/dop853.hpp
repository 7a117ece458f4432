// The explicit Runge–Kutta method of Dormand and Prince of order 8 with adaptive steps (DOP853;
// Hairer, Nørsett & Wanner, Solving ODEs I, §II.10), on the same OdeProblem as CVODES:
// `solver.method: dop853`. For non-stiff problems at tight tolerances, where CVODES's Adams
// method runs out of accuracy (its global error on the four-bar stays ~1e-9 at rtol 1e-14,
// docs/peers.md) and BDF takes many small steps: DOP853's 12 stages buy an 8th-order step.
// No Jacobian, so a stiff problem makes it take tiny steps (docs/explanation/stability.md); use bdf there.
//
// Error control: the local error estimate of Hairer's dop853.f (its 5th- and 3rd-order
// embedded solutions), in the RMS norm over the controlled components with scale
// atol_i + rtol·max(|y_i|, |y_new_i|) (atol_per_state when given); the step factor is
// 0.9·err^−(1/8 − 0.2β)·err_old^β with β = 0.06 (control with memory, dop853.f's BETA),
// limited to [0.2, 6] (≤ 1 right after a rejection). Initial step: Hairer's estimate
// (ibid. §II.4) unless solver.initial_step is set; solver.max_step bounds it.
//
// Outputs: read from the order-7 continuous extension (dop853.f's CONTD8, three more
// evaluations in a step that holds output times); the steps follow the error control, only
// the last one is cut to land on the final time.
//
// Sensitivities (exact sensitivity_rhs only): integrated with the states by the same stages
// (internal differentiation, as integrate_rk4), so they are the exact derivatives of the
// discrete solution. With solver.sensitivity.error_control they take part in the error test
// with atol = sensitivity.atol, or atol_i/|p̄_j| as CVODES's CVodeSensEEtolerances.
//
// Quadratures (an OdeQuadrature): integrated as components stacked after [y; s] by the same
// stages, with error control (atol, rtol; their sensitivities like the state sensitivities).
//
// Events (an OdeEvents): g is evaluated at the end of every accepted step; where g_i changes
// sign in its direction, the crossing is located on the continuous extension (Illinois
// false position, to 100·ε·(|t| + |h|) in time, CVODES's rootfinding tolerance).
//
// Constraints: with a problem that has_projection() (stabilization: projection), the state is
// projected after every accepted step (every projection_frequency steps), and the first stage
// of the next step re-evaluated; the sensitivities are not projected during the integration
// (simulate() projects the recorded ones, as with CVODES).
//
// Result and statuses mirror the CVODES integrator (solve/integrator.hpp), with the CVODES
// flag numbers a study output already knows: −1 max_steps reached (CV_TOO_MUCH_WORK), −3 the
// step size fell below round-off of t after repeated error-test failures or non-finite
// stages (CV_ERR_FAILURE), −8 rhs or sensitivity_rhs threw (CV_RHSFUNC_FAIL). Non-finite
// stages reject the step (×0.25), as CVODES treats a recoverable callback failure.
#pragma once
#include <span>

#include "sim/solve/integrator.hpp"
#include "sim/solve/ode_problem.hpp"
#include "sim/solve/solver_options.hpp"

namespace kanesens::sim {

// Throws std::invalid_argument for bad output times, or sensitivities without an exact
// sensitivity_rhs. Stats: steps, rhs_evals, sens_rhs_evals, error_test_fails, projections,
// callback_recoverable (rejected non-finite steps), wall_seconds.
IntegrationResult integrate_dop853(OdeProblem& problem, const SolverOptions& options,
                                   std::span<const double> output_times, const RecordFn& record,
                                   OdeQuadrature* quadrature = nullptr, OdeEvents* events = nullptr);

}  // namespace kanesens::sim
