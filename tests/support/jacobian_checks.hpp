// The largest difference between a Jacobian J (n×n, column-major) of ẏ = f(t, y) and the central
// differences of the problem's right-hand side at (t, y) with step h, relative to `scale`
// (shared by the Jacobian tests; the differences are written independently of the code checked).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/solve/ode_problem.hpp"

namespace kanesens::testing {

inline double central_difference_error(sim::OdeProblem& p, double t, const std::vector<double>& y,
                                       const std::vector<double>& J, double scale, double h = 1e-6) {
  const std::size_t n = y.size();
  double err = 0;
  std::vector<double> yp(y), fp(n), fm(n);
  for (std::size_t j = 0; j < n; ++j) {
    yp[j] = y[j] + h;
    p.rhs(t, yp.data(), fp.data());
    yp[j] = y[j] - h;
    p.rhs(t, yp.data(), fm.data());
    yp[j] = y[j];
    for (std::size_t r = 0; r < n; ++r) err = std::max(err, std::abs((fp[r] - fm[r]) / (2 * h) - J[j * n + r]) / scale);
  }
  return err;
}

}  // namespace kanesens::testing
