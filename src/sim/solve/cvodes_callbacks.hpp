// The C callbacks CVODES calls (Integrator's implementation, sim/solve/integrator.cpp): nothrow
// trampolines into an OdeProblem, and the data they share with the integrator. Exceptions never
// cross into C: a callback that throws keeps its message and returns −1 (CVODES stops); a
// non-finite output returns +1 (CVODES retries with a smaller step).
#pragma once
#include <cvodes/cvodes.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <exception>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/solve/ode_problem.hpp"

namespace kanesens::sim::detail {

// "%.10g" of t, for messages.
std::string format_time(double t);

// What the trampolines share with the integrator (CVodeSetUserData). Lives inside
// the integrator, whose address is stable.
struct CallbackData {
  OdeProblem* problem = nullptr;
  OdeQuadrature* quadrature = nullptr;  // integrals computed alongside, or none
  OdeEvents* events = nullptr;          // event functions (CVodeRootInit), or none
  int nquad = 0;
  std::vector<const double*> quadrature_s;  // the quadrature sensitivity call's pointers (ns each)
  std::vector<double*> quadrature_sdot;
  int n = 0;
  long recoverable = 0;          // callbacks that returned +1
  std::string callback_message;  // last callback failure (exception or non-finite output)
  std::string solver_message;    // last error reported by CVODES's error handler
  std::vector<const double*> s_in;  // sens_rhs_all_trampoline's pointers into yS and ySdot (ns each)
  std::vector<double*> s_out;
  // Set when the simultaneous corrector tests the sensitivities' error and the state's error
  // estimate is projected (proj_trampoline then restores the sensitivities' part of the error
  // norm): CVODES's memory, and scratch for the state's and the ns sensitivities' error weights.
  // Null otherwise.
  void* sens_error_mem = nullptr;
  N_Vector state_weights = nullptr;
  N_Vector* sens_weights = nullptr;
  int ns = 0;
  // Sensitivities stacked after the state in one CVODES vector (stacked_rhs_trampoline): how
  // many; 0 when CVODES's sensitivity module carries them.
  int stacked_ns = 0;

  void reset(OdeProblem* p, int size) {
    problem = p;
    n = size;
    recoverable = 0;
    callback_message.clear();
    solver_message.clear();
  }

  // An exception escaped a callback: keep its message, tell CVODES to stop (−1).
  int fail(const char* where, double t, const char* what) noexcept {
    try {
      callback_message = std::string(where) + " threw at t = " + format_time(t) + ": " + what;
    } catch (...) {  // out of memory: the status still says what happened
    }
    return -1;
  }

  // The callback could not evaluate at this trial state (RecoverableError): +1, CVODES retries
  // with a smaller step; the message is reported if it gives up.
  int recover(const char* where, double t, const char* what) noexcept {
    ++recoverable;
    try {
      callback_message = std::string(where) + " failed at t = " + format_time(t) + ": " + what;
    } catch (...) {
    }
    return 1;
  }

  // Scan a callback's output; a NaN or Inf makes the step fail recoverably (+1), so CVODES
  // retries with a smaller step; if that keeps happening it gives up with a flag < 0.
  int check_finite(const char* where, double t, const double* v, long count) noexcept {
    // One branch-free sweep first (a stacked state is several times the state): x · 0 is ±0
    // for a finite x and NaN otherwise, summed in eight lanes that vectorise; the first bad
    // entry is looked for only when there is one.
    double lanes[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    long i0 = 0;
    for (; i0 + 8 <= count; i0 += 8)
      for (int j = 0; j < 8; ++j) lanes[j] += v[i0 + j] * 0.0;
    double zero = 0;
    for (; i0 < count; ++i0) zero += v[i0] * 0.0;
    for (const double l : lanes) zero += l;
    if (zero == 0) return 0;
    for (long i = 0; i < count; ++i) {
      if (!std::isfinite(v[i])) {
        ++recoverable;
        try {
          char buf[160];
          std::snprintf(buf, sizeof buf,
                        "%s returned a non-finite value (%g at index %ld) at t = %.10g", where,
                        v[i], i, t);
          callback_message = buf;
        } catch (...) {
        }
        return 1;
      }
    }
    return 0;
  }
};

inline CallbackData& data_of(void* user_data) {
  return *static_cast<CallbackData*>(user_data);
}

// A callback's body, run so that no exception crosses into C: a RecoverableError asks CVODES
// for a smaller step (+1) where `recoverable`, any other exception stops it (−1) with its message.
template <class Body>
int guarded(CallbackData& cb, const char* where, double t, bool recoverable, Body&& body) noexcept {
  try {
    return body();
  } catch (const RecoverableError& e) {
    return recoverable ? cb.recover(where, t, e.what()) : cb.fail(where, t, e.what());
  } catch (const std::exception& e) {
    return cb.fail(where, t, e.what());
  } catch (...) {
    return cb.fail(where, t, "unknown exception");
  }
}

int rhs_trampoline(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept;
int jac_trampoline(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* user_data, N_Vector, N_Vector,
                   N_Vector) noexcept;
// CVodeSetJacTimes's Jv = J v (matrix-free Newton–Krylov): OdeProblem::jacobian_times.
int jtimes_trampoline(N_Vector v, N_Vector Jv, sunrealtype t, N_Vector y, N_Vector fy, void* user_data,
                      N_Vector tmp) noexcept;
// The identity preconditioner of the krylov solver (why: integrator.cpp): setup does nothing,
// solve copies r into z.
int identity_psetup(sunrealtype t, N_Vector y, N_Vector fy, sunbooleantype jok, sunbooleantype* jcur,
                    sunrealtype gamma, void* user_data) noexcept;
int identity_psolve(sunrealtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z, sunrealtype gamma,
                    sunrealtype delta, int lr, void* user_data) noexcept;
int sens_rhs_trampoline(int ns, sunrealtype t, N_Vector y, N_Vector ydot, int iS, N_Vector yS, N_Vector ySdot,
                        void* user_data, N_Vector, N_Vector) noexcept;
// All sensitivities in one call (CVodeSensInit): the problem evaluates every direction in one
// multi-tangent pass.
int sens_rhs_all_trampoline(int ns, sunrealtype t, N_Vector y, N_Vector ydot, N_Vector* yS, N_Vector* ySdot,
                            void* user_data, N_Vector, N_Vector) noexcept;
// The right-hand side of the state stacked with its stacked_ns sensitivities, [y; s_0; …] (n
// each): f and every sensitivity right-hand side in one pass (OdeProblem::rhs_with_sensitivities).
int stacked_rhs_trampoline(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept;
// CVodeRootInit's g: OdeEvents::g (an exception: −1, CVODES stops with CV_RTFUNC_FAIL).
int root_trampoline(sunrealtype t, N_Vector y, sunrealtype* gout, void* user_data) noexcept;
// CVodeSetProjFn's projection: OdeProblem::project; with sens_error_mem set, also scales the
// projected error estimate err so that its norm keeps the sensitivities' local error (see
// keep_sensitivity_error in the .cpp).
int proj_trampoline(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj, N_Vector err,
                    void* user_data) noexcept;
// The projection of a stacked system (stacked_rhs_trampoline): OdeProblem::project corrects the
// state block and its part of the error estimate; the sensitivities are left as they are (zero
// correction), so their error estimates stay in the error test.
int stacked_proj_trampoline(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj, N_Vector err,
                            void* user_data) noexcept;
// CVODES reports errors through this instead of printing them to stderr (thousands of failing
// samples would flood the terminal). Warnings (error_code > 0, e.g. "t + h = t") are dropped.
void error_handler(int error_code, const char* module, const char* function, char* msg, void* user_data) noexcept;

}  // namespace kanesens::sim::detail
