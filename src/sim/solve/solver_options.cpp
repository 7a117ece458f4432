#include "sim/solve/solver_options.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace kanesens::sim {

namespace {
template <class T>
[[noreturn]] void invalid(const char* field, const char* expected, const T& got) {
  std::ostringstream os;
  os << "solver." << field << ": " << expected << ", got " << got;
  throw std::invalid_argument(os.str());
}
bool positive_finite(double x) {
  return std::isfinite(x) && x > 0;
}
}  // namespace

void SolverOptions::validate(int n) const {
  if (!positive_finite(rtol)) invalid("rtol", "must be a finite number > 0", rtol);
  if (!positive_finite(atol)) invalid("atol", "must be a finite number > 0", atol);
  for (double a : atol_per_state) {
    if (!(std::isfinite(a) && a >= 0)) invalid("atol_per_state", "entries must be >= 0", a);
  }
  if (n >= 0 && !atol_per_state.empty() && static_cast<int>(atol_per_state.size()) != n) {
    invalid("atol_per_state", ("must have one entry per state (" + std::to_string(n) + ")").c_str(),
            atol_per_state.size());
  }
  if (max_steps <= 0) invalid("max_steps", "must be > 0", max_steps);
  if (method == Method::dop853 && max_order != 0)
    invalid("max_order", "must be 0 (unused) for dop853, a method of fixed order 8", max_order);
  const int order_limit = method == Method::bdf ? 5 : 12;
  if (method != Method::dop853 && (max_order < 0 || max_order > order_limit)) {
    invalid("max_order",
            (std::string("must be 0 (default) or 1..") + std::to_string(order_limit) + " for " +
             std::string(to_string(method)))
                .c_str(),
            max_order);
  }
  if (!(std::isfinite(initial_step) && initial_step >= 0)) {
    invalid("initial_step", "must be >= 0 (0 = estimate)", initial_step);
  }
  if (!(std::isfinite(max_step) && max_step >= 0)) {
    invalid("max_step", "must be >= 0 (0 = unbounded)", max_step);
  }
  if (sens_atol && !positive_finite(*sens_atol)) {
    invalid("sensitivity.atol", "must be a finite number > 0", *sens_atol);
  }
  if (linear_solver != LinearSolver::automatic && (method == Method::dop853 || iteration == Iteration::functional))
    invalid("linear_solver", "must be auto (unused) without Newton iteration (dop853, or iteration: functional)",
            to_string(linear_solver));
  if (projection_frequency < 0)
    invalid("projection_frequency", "must be >= 0", projection_frequency);
}

std::string_view to_string(Method m) { return name_of(kMethodNames, m); }
std::string_view to_string(Iteration it) { return name_of(kIterationNames, it); }
std::string_view to_string(JacobianKind j) { return name_of(kJacobianKindNames, j); }
std::string_view to_string(LinearSolver l) { return name_of(kLinearSolverNames, l); }
std::string_view to_string(SensitivityMethod s) { return name_of(kSensitivityMethodNames, s); }
std::string_view to_string(SensitivityRhs s) { return name_of(kSensitivityRhsNames, s); }
LinearSolver resolve_linear_solver(LinearSolver option, int n, double jacobian_rate) {
  if (option != LinearSolver::automatic) return option;
  return n >= kKrylovMinStates && jacobian_rate <= kKrylovMaxRate ? LinearSolver::krylov : LinearSolver::dense;
}
SensitivityMethod resolve_sensitivity_method(SensitivityMethod option, bool with_projection, bool stackable) {
  if (option != SensitivityMethod::automatic) return option;
  if (stackable) return SensitivityMethod::stacked;
  return with_projection ? SensitivityMethod::staggered : SensitivityMethod::simultaneous;
}

}  // namespace kanesens::sim
