#include "sim/solve/cvodes_callbacks.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

namespace kanesens::sim::detail {

std::string format_time(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", t);
  return buf;
}

int rhs_trampoline(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "rhs", t, true, [&] {
    double* f = N_VGetArrayPointer(ydot);
    cb.problem->rhs(t, N_VGetArrayPointer(y), f);
    return cb.check_finite("rhs", t, f, cb.n);
  });
}

int stacked_rhs_trampoline(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "rhs", t, true, [&] {
    const double* yd = N_VGetArrayPointer(y);
    double* f = N_VGetArrayPointer(ydot);
    const int ns = cb.stacked_ns;
    for (int i = 0; i < ns; ++i) {
      const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(cb.n) * (i + 1);
      cb.s_in[static_cast<std::size_t>(i)] = yd + offset;
      cb.s_out[static_cast<std::size_t>(i)] = f + offset;
    }
    cb.problem->rhs_with_sensitivities(t, yd, ns, cb.s_in.data(), f, cb.s_out.data());
    return cb.check_finite("rhs", t, f, static_cast<long>(cb.n) * (ns + 1));
  });
}

int root_trampoline(sunrealtype t, N_Vector y, sunrealtype* gout, void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "event function", t, false, [&] {
    cb.events->g(t, N_VGetArrayPointer(y), gout);
    return 0;
  });
}

int jac_trampoline(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* user_data, N_Vector,
                   N_Vector, N_Vector) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "jacobian", t, true, [&] {
    // SUNDenseMatrix storage is column-major and contiguous (leading dimension n).
    double* jac = SUNDenseMatrix_Data(J);
    cb.problem->jacobian(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy), jac);
    return cb.check_finite("jacobian", t, jac, static_cast<long>(cb.n) * cb.n);
  });
}

int jtimes_trampoline(N_Vector v, N_Vector Jv, sunrealtype t, N_Vector y, N_Vector fy, void* user_data,
                      N_Vector) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "jacobian_times", t, true, [&] {
    double* jv = N_VGetArrayPointer(Jv);
    cb.problem->jacobian_times(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy), N_VGetArrayPointer(v), jv);
    return cb.check_finite("jacobian_times", t, jv, cb.n);
  });
}

int identity_psetup(sunrealtype, N_Vector, N_Vector, sunbooleantype, sunbooleantype* jcur, sunrealtype,
                    void*) noexcept {
  *jcur = SUNTRUE;  // J v is exact at every iterate: a fresh setup would change nothing
  return 0;
}

int identity_psolve(sunrealtype, N_Vector, N_Vector, N_Vector r, N_Vector z, sunrealtype, sunrealtype, int,
                    void*) noexcept {
  N_VScale(1.0, r, z);
  return 0;
}

int sens_rhs_trampoline(int /*Ns*/, sunrealtype t, N_Vector y, N_Vector ydot, int iS, N_Vector yS,
                        N_Vector ySdot, void* user_data, N_Vector, N_Vector) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "sensitivity_rhs", t, true, [&] {
    double* sdot = N_VGetArrayPointer(ySdot);
    cb.problem->sensitivity_rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), iS,
                                N_VGetArrayPointer(yS), sdot);
    return cb.check_finite("sensitivity_rhs", t, sdot, cb.n);
  });
}

int sens_rhs_all_trampoline(int Ns, sunrealtype t, N_Vector y, N_Vector ydot, N_Vector* yS, N_Vector* ySdot,
                            void* user_data, N_Vector, N_Vector) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "sensitivity_rhs", t, true, [&] {
    for (int i = 0; i < Ns; ++i) {
      cb.s_in[static_cast<std::size_t>(i)] = N_VGetArrayPointer(yS[i]);
      cb.s_out[static_cast<std::size_t>(i)] = N_VGetArrayPointer(ySdot[i]);
    }
    cb.problem->sensitivity_rhs_all(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), Ns, cb.s_in.data(),
                                    cb.s_out.data());
    for (int i = 0; i < Ns; ++i) {
      const int flag = cb.check_finite("sensitivity_rhs", t, cb.s_out[static_cast<std::size_t>(i)], cb.n);
      if (flag != 0) return flag;
    }
    return 0;
  });
}

namespace {

// CVODES's simultaneous corrector, with sensitivity error control, tests one local error norm for
// the state and the sensitivities together: max(‖e‖, maxᵢ ‖eᵢ‖), eᵢ = the correction of
// sensitivity i from its predictor. When the error estimate is projected, CVODES recomputes that
// norm after the projection from the projected state error alone, so the sensitivities drop out
// of the error test and of the step size (the staggered corrector tests them separately, after
// the projection). The projected estimate is used only through that norm, so scaling it to
// max(‖P e‖, maxᵢ ‖eᵢ‖) restores the test CVODES makes without projection (and the staggered one).
int keep_sensitivity_error(CallbackData& cb, double t, N_Vector err) {
  sunrealtype tcur = 0, gamma = 0, rl1 = 0;
  N_Vector *ys_pred = nullptr, *ys = nullptr, *zn1 = nullptr;
  void* user_data = nullptr;
  if (CVodeGetNonlinearSystemDataSens(cb.sens_error_mem, &tcur, &ys_pred, &ys, &gamma, &rl1, &zn1, &user_data) !=
          CV_SUCCESS ||
      CVodeGetSensErrWeights(cb.sens_error_mem, cb.sens_weights) != CV_SUCCESS ||
      CVodeGetErrWeights(cb.sens_error_mem, cb.state_weights) != CV_SUCCESS)
    return cb.fail("project", t, "cannot read the sensitivities' local error");
  double sens = 0;
  for (int i = 0; i < cb.ns; ++i) {
    const double* s = N_VGetArrayPointer(ys[i]);
    const double* p = N_VGetArrayPointer(ys_pred[i]);
    const double* w = N_VGetArrayPointer(cb.sens_weights[i]);
    double sum = 0;
    for (int k = 0; k < cb.n; ++k) sum += ((s[k] - p[k]) * w[k]) * ((s[k] - p[k]) * w[k]);
    sens = std::max(sens, std::sqrt(sum / cb.n));
  }
  const double state = N_VWrmsNorm(err, cb.state_weights);
  if (!(sens > state)) return 0;
  if (state > 0) {
    N_VScale(sens / state, err, err);
  } else {  // e_k = sens / w_k has norm sens
    N_VInv(cb.state_weights, err);
    N_VScale(sens, err, err);
  }
  return 0;
}

// OdeProblem::project on the state (the first n entries of ycur, corr and err): its flag, else
// whether the correction is finite.
int project_state(CallbackData& cb, double t, N_Vector ycur, double* c, double eps_proj, N_Vector err) {
  const int flag =
      cb.problem->project(t, N_VGetArrayPointer(ycur), c, eps_proj, err != nullptr ? N_VGetArrayPointer(err) : nullptr);
  if (flag != 0) {
    try {
      cb.callback_message = "project returned " + std::to_string(flag) + " at t = " + format_time(t);
    } catch (...) {
    }
    if (flag > 0) ++cb.recoverable;
    return flag;
  }
  return cb.check_finite("project", t, c, cb.n);
}

}  // namespace

int proj_trampoline(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj, N_Vector err,
                    void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "project", t, false, [&] {
    const int flag = project_state(cb, t, ycur, N_VGetArrayPointer(corr), eps_proj, err);
    if (flag != 0 || err == nullptr || cb.sens_error_mem == nullptr) return flag;
    return keep_sensitivity_error(cb, t, err);
  });
}

int stacked_proj_trampoline(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj, N_Vector err,
                            void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "project", t, false, [&] {
    double* c = N_VGetArrayPointer(corr);
    std::fill(c + cb.n, c + static_cast<std::ptrdiff_t>(cb.n) * (cb.stacked_ns + 1), 0.0);
    return project_state(cb, t, ycur, c, eps_proj, err);
  });
}

void error_handler(int error_code, const char* /*module*/, const char* function, char* msg,
                   void* user_data) noexcept {
  if (error_code >= 0) return;
  try {
    data_of(user_data).solver_message = std::string(function) + ": " + msg;
  } catch (...) {
  }
}

}  // namespace kanesens::sim::detail
