// Integrator's choice of Newton's linear solver (solver.linear_solver: auto): dense LU or
// matrix-free GMRES, by the problem's size and the stiffness its Jacobian shows at t0.
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <utility>
#include <vector>

#include "sim/solve/integrator_impl.hpp"

namespace kanesens::sim {

// Power iteration on J at the initial state: (‖J²⁰v‖/‖J¹⁰v‖)^(1/10) tends to the spectral radius
// (an order of magnitude is all the choice needs). J v exact when the problem has it, else a
// difference quotient of the RHS.
double Integrator::Impl::jacobian_rate(OdeProblem& problem, double t0) const {
  const int size = problem.size();
  std::vector<double> y0(static_cast<std::size_t>(size)), f0(y0.size()), v(y0.size()), w(y0.size()),
      yp(y0.size()), fp(y0.size());
  problem.initial_state(y0.data());
  problem.rhs(t0, y0.data(), f0.data());
  const bool exact = options.jacobian == JacobianKind::exact && problem.has_jacobian_times();
  auto norm = [](const std::vector<double>& x) {
    double s = 0;
    for (double e : x) s += e * e;
    return std::sqrt(s);
  };
  for (int i = 0; i < size; ++i) v[static_cast<std::size_t>(i)] = 1.0 + 0.5 * std::sin(1.0 + i);  // generic, fixed
  double growth = 0;
  for (int k = 1; k <= 20; ++k) {
    const double nv = norm(v);
    if (!std::isfinite(nv)) return std::numeric_limits<double>::infinity();  // dense: the safe choice
    if (nv == 0) return 0;                                                       // J v = 0: nothing stiff
    for (double& e : v) e /= nv;
    if (exact) {
      problem.jacobian_times(t0, y0.data(), f0.data(), v.data(), w.data());
    } else {
      const double eps = 1e-7 * std::max(1.0, norm(y0));
      for (std::size_t i = 0; i < y0.size(); ++i) yp[i] = y0[i] + eps * v[i];
      problem.rhs(t0, yp.data(), fp.data());
      for (std::size_t i = 0; i < y0.size(); ++i) w[i] = (fp[i] - f0[i]) / eps;
    }
    if (k > 10) growth += std::log(std::max(norm(w), 1e-300));
    std::swap(v, w);
  }
  return std::exp(growth / 10);
}

LinearSolver Integrator::Impl::choose_linear_solver(OdeProblem& problem, double t0) const {
  const LinearSolver option = options.linear_solver;
  if (options.iteration != Iteration::newton || option != LinearSolver::automatic) return option;
  const int size = problem.size();
  if (options.jacobian == JacobianKind::exact) {
    if (!problem.has_jacobian_times()) return LinearSolver::dense;
    if (!problem.has_jacobian()) return LinearSolver::krylov;
    if (!problem.jacobian_times_cheap()) return LinearSolver::dense;
  }
  if (size < kKrylovMinStates) return LinearSolver::dense;
  double rate = std::numeric_limits<double>::infinity();
  try {
    rate = jacobian_rate(problem, t0);
  } catch (const std::exception&) {
    // The run itself will meet and report whatever failed here; dense is the safe choice.
  }
  return resolve_linear_solver(option, size, rate);
}

}  // namespace kanesens::sim
