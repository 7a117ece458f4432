// The classical fixed-step Runge–Kutta method of order 4, on the same OdeProblem as CVODES.
// A baseline for work-precision diagrams (`kanesens-workprecision`): no error control,
// no Jacobian, so it shows where an explicit method stops being usable (a stiff spring makes
// h·λ leave RK4's stability region, |hλ| ≲ 2.8 on the imaginary axis, and the solution grows
// without bound).
//
// Steps: each output interval [t_k, t_{k+1}] is divided into ceil((t_{k+1} − t_k)/h) equal
// steps, so every output time is hit exactly (with uniform outputs and h = (t_end − t0)/N,
// N a multiple of the number of intervals, all steps are h).
//
// Sensitivities (when the problem has them and has_sensitivity_rhs()): integrated by the same
// RK4 stages (internal differentiation: stage i of s_j uses sensitivity_rhs at stage i's state),
// so they are the exact derivatives of the discrete RK4 solution.
//
// Failure: a non-finite state, RHS or sensitivity stops the integration with status
// rk4_nonfinite; an exception thrown by rhs/sensitivity_rhs gives rk4_callback_failed. Outputs
// past the failure are not recorded. record() is called exactly as by Integrator
// (output 0 = initial state, no integration).
#pragma once
#include <span>

#include "sim/solve/integrator.hpp"
#include "sim/solve/ode_problem.hpp"

namespace kanesens::sim {

constexpr int rk4_nonfinite = -1001;        // a state or derivative became NaN/Inf
constexpr int rk4_callback_failed = -1002;  // rhs or sensitivity_rhs threw

struct Rk4Options {
  double h = 1e-3;            // nominal step; the actual steps are ≤ h (see above)
  bool sensitivities = true;  // integrate the problem's sensitivities (if it has any)
};

// Stats: steps, rhs_evals (4 per step), sens_rhs_evals, wall_seconds; the CVODES-only counters
// stay 0. Throws std::invalid_argument for h ≤ 0, bad output times or sensitivities without
// sensitivity_rhs.
IntegrationResult integrate_rk4(OdeProblem& problem, const Rk4Options& options,
                                std::span<const double> output_times, const RecordFn& record);

}  // namespace kanesens::sim
