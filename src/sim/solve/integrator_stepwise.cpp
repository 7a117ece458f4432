// Integrator::Impl's step-by-step path (sim/solve/integrator_impl.hpp): for problems that check
// each accepted step (OdeProblem::after_step) and may change their coordinates there.
#include <cvodes/cvodes.h>

#include <string>

#include "sim/solve/integrator_impl.hpp"

namespace kanesens::sim {

using namespace detail;

void Integrator::Impl::integrate_stepwise(OdeProblem& problem, std::span<const double> times, const RecordFn& record,
                                          OdeQuadrature* quad, IntegrationResult& result) {
  void* m = mem.get();
  double* yv = N_VGetArrayPointer(y.get());
  const double* const* s_out = ns > 0 ? s_out_pointers.data() : nullptr;
  double* const* s_step = ns > 0 ? s_step_pointers.data() : nullptr;
  SolverStats before;  // counters of the segments before the last restart (CVodeReInit resets them)
  std::size_t k = 1;
  double t = times.front();
  while (k < times.size()) {
    long steps = 0;
    check_flag(CVodeGetNumSteps(m, &steps), "CVodeGetNumSteps");
    if (before.steps + steps >= options.max_steps) {
      result.status = CV_TOO_MUCH_WORK;
      result.t_fail = t;
      result.message = "CV_TOO_MUCH_WORK at t = " + format_time(t) + ": max_steps = " +
                       std::to_string(options.max_steps) + " steps taken before reaching t = " + format_time(times[k]);
      break;
    }
    const int flag = CVode(m, times.back(), y.get(), &t, CV_ONE_STEP);
    if (flag < 0) {
      fail(result, flag, t);
      break;
    }
    for (; k < times.size() && times[k] <= t; ++k) {
      check_flag(CVodeGetDky(m, times[k], 0, y_out.get()), "CVodeGetDky");
      for (int i = 0; i < ns; ++i) check_flag(CVodeGetSensDky1(m, times[k], 0, i, yS_out[i]), "CVodeGetSensDky1");
      record(static_cast<int>(k), times[k], N_VGetArrayPointer(y_out.get()), s_out);
      if (quad) quadrature.record_interpolated(m, *quad, static_cast<int>(k), times[k]);
      ++result.outputs_recorded;
    }
    if (ns > 0) {
      double ts = 0;
      check_flag(CVodeGetSens(m, &ts, yS.get()), "CVodeGetSens");
    }
    if (flag == CV_ROOT_RETURN) {  // t is the crossing, y and yS the state there
      if (handle_roots(t, yv, ns > 0 ? s_pointers.data() : nullptr)) {
        stop_at(result, t);
        break;
      }
      if (k == times.size()) break;  // a crossing at the final time: nothing left to integrate
      continue;
    }
    if (k == times.size()) break;
    bool changed = false;
    try {
      changed = problem.after_step(t, yv, s_step);
    } catch (const std::exception& e) {
      result.status = CV_RHSFUNC_FAIL;
      result.t_fail = t;
      result.message = cvode_flag_name(CV_RHSFUNC_FAIL) + " at t = " + format_time(t) + ": " + e.what();
      break;
    }
    if (!changed) continue;
    before += collect_stats();
    ++before.repartitions;
    if (quad) quadrature.save(m, t);
    check_flag(CVodeReInit(m, t, y.get()), "CVodeReInit");
    if (ns > 0)
      check_flag(CVodeSensReInit(m, sensitivity_method_flag(sensitivity_method), yS.get()), "CVodeSensReInit");
    if (quad) quadrature.restart(m);
    check_flag(CVodeSetStopTime(m, times.back()), "CVodeSetStopTime");
  }
  result.stats = before;
}

}  // namespace kanesens::sim
