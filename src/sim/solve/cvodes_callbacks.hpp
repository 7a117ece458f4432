// What the CVODES callbacks share with the integrator (internal to sim/solve): the problem, the
// last failure's message, and the nothrow checks every trampoline applies to its output.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/solve/ode_problem.hpp"

namespace kanesens::sim::detail {

inline std::string format_time(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", t);
  return buf;
}

// What the trampolines share with the integrator (CVodeSetUserData). Lives inside
// Integrator::Impl, whose address is stable.
struct CallbackData {
  OdeProblem* problem = nullptr;
  OdeQuadrature* quadrature = nullptr;  // integrals computed alongside, or none
  int nquad = 0;
  std::vector<const double*> quadrature_s;  // the quadrature sensitivity call's pointers (ns each)
  std::vector<double*> quadrature_sdot;
  int n = 0;
  long recoverable = 0;          // callbacks that returned +1
  std::string callback_message;  // last callback failure (exception or non-finite output)
  std::string solver_message;    // last error reported by CVODES's error handler

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

  // Scan a callback's output; a NaN or Inf makes the step fail recoverably (+1), so CVODES
  // retries with a smaller step; if that keeps happening it gives up with a flag < 0.
  int check_finite(const char* where, double t, const double* v, long count) noexcept {
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

}  // namespace kanesens::sim::detail
