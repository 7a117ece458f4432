#include <cmath>
#include <cstdio>

#include "workprecision.hpp"

namespace kanesens::bench {

void write_row(JsonWriter& j, const Row& r) {
  j.begin_object();
  j.key("method").value(r.method);
  j.key("tol").value(r.tol);
  j.key("rtol").value(r.rtol);
  j.key("atol").value(r.atol);
  j.key("h").value(r.h);
  j.key("with_sens").value(r.with_sens);
  j.key("ok").value(r.ok);
  j.key("skipped").value(r.skipped);
  j.key("status").value(r.status);
  j.key("message").value(r.message);
  j.key("t_fail").value(r.t_fail);
  j.key("wall_seconds").value(r.wall_median);
  j.key("wall_seconds_min").value(r.wall_min);
  j.key("repeats").value(r.repeats);
  j.key("timed_with_recording").value(r.timed_with_recording);
  j.key("steps").value(static_cast<long long>(r.stats.steps));
  j.key("rhs_evals").value(static_cast<long long>(r.stats.rhs_evals));
  j.key("rhs_evals_total").value(static_cast<long long>(r.stats.rhs_evals + r.stats.lin_rhs_evals + r.stats.rhs_evals_for_sens));
  j.key("jac_evals").value(static_cast<long long>(r.stats.jac_evals));
  j.key("lin_rhs_evals").value(static_cast<long long>(r.stats.lin_rhs_evals));
  j.key("sens_rhs_evals").value(static_cast<long long>(r.stats.sens_rhs_evals));
  j.key("rhs_evals_for_sens").value(static_cast<long long>(r.stats.rhs_evals_for_sens));
  j.key("error_test_fails").value(static_cast<long long>(r.stats.error_test_fails));
  j.key("nonlin_conv_fails").value(static_cast<long long>(r.stats.nonlin_conv_fails));
  j.key("final_rel_error").value(r.err.final_rel);
  j.key("final_rel_error_component").value(r.err.worst_component);
  j.key("final_abs_error").value(r.err.final_abs);
  j.key("l2_error").value(r.err.l2);
  j.key("linf_error").value(r.err.linf);
  j.key("sens_final_rel_error").value(r.err.sens_final_rel);
  j.key("sens_l2_error").value(r.err.sens_l2);
  j.key("energy_error").value(r.err.energy_error);
  j.key("energy_drift").value(r.diag.energy_drift);
  j.key("energy_drift_final").value(r.diag.energy_drift_final);
  j.key("quaternion_norm_drift").value(r.diag.quaternion_drift);
  j.key("constraint_position_residual").value(r.diag.position_residual);
  j.key("constraint_velocity_residual").value(r.diag.velocity_residual);
  j.key("sens_norm_final").value(r.diag.sens_norm_final);
  j.key("sens_growth_rate").value(r.diag.sens_rate);
  j.key("sens_growth_slope").value(r.diag.sens_slope);
  j.end_object();
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace kanesens::bench
