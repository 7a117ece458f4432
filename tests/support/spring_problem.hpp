// The undamped oscillator x'' = −(k/m) x, x(0) = x0, v(0) = 0, as a bare sim::OdeProblem with
// the sensitivity to k, and its closed form: x = x0 cos ωt, ω = √(k/m),
// ∂x/∂k = −x0 t sin(ωt) / (2 m ω). Shared by the integrator tests (test_rk4, test_dop853).
#pragma once
#include <cmath>
#include <stdexcept>

#include "sim/solve/ode_problem.hpp"
#include "layers.hpp"

namespace kanesens::testing {

class Spring : public sim::OdeProblem {
 public:
  explicit Spring(double k, double m = 1, double x0 = 1) : k_(k), m_(m), x0_(x0) {}
  int size() const override { return 2; }
  void initial_state(double* y0) const override {
    y0[0] = x0_;
    y0[1] = 0;
  }
  void rhs(double t, const double* y, double* ydot) override {
    if (t > throw_after) throw std::runtime_error("spring broke");
    ydot[0] = y[1];
    ydot[1] = -k_ / m_ * y[0];
  }
  int num_sensitivities() const override { return sensitivities ? 1 : 0; }
  void initial_sensitivity(int, double* s0) const override { s0[0] = s0[1] = 0; }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double, const double* y, const double*, int, const double* s, double* sdot) override {
    sdot[0] = s[1];
    sdot[1] = -k_ / m_ * s[0] - y[0] / m_;
  }
  double omega() const { return std::sqrt(k_ / m_); }
  double x(double t) const { return x0_ * std::cos(omega() * t); }
  double dx_dk(double t) const { return -x0_ * t * std::sin(omega() * t) / (2 * m_ * omega()); }
  double throw_after = 1e300;  // rhs throws for t beyond this (failure-path tests)
  bool sensitivities = true;   // whether ∂/∂k is integrated

 private:
  double k_, m_, x0_;
};

}  // namespace kanesens::testing
