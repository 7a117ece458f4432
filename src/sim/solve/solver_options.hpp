// CVODES settings (the study file's `solver:` section). Plain struct with defaults; validate()
// checks it against the problem size and throws std::invalid_argument naming the field.
#pragma once
#include <optional>
#include <string_view>
#include <vector>

#include "util/enum_names.hpp"

namespace kanesens::sim {

// CV_BDF (stiff) | CV_ADAMS (non-stiff) | explicit Runge–Kutta 8(5,3) (non-stiff, tight
// tolerances; solve/dop853.hpp: no Jacobian, iteration or max_order)
enum class Method { bdf, adams, dop853 };
enum class Iteration { newton, functional };  // Newton + dense LU | fixed point (no Jacobian)
enum class JacobianKind { exact, dq };        // OdeProblem::jacobian | CVODES difference quotient
// How Newton's linear systems (I − γJ) x = b are solved: dense LU of the n×n Jacobian (rebuilt only
// every few steps), matrix-free GMRES with Jacobian–vector products (OdeProblem::jacobian_times, or
// CVODES's difference quotient with jacobian = dq), or chosen by the problem's size
// (resolve_linear_solver).
enum class LinearSolver { dense, krylov, automatic };
// CVODES's sensitivity corrector: CV_SIMULTANEOUS, CV_STAGGERED, CV_STAGGERED1 (CVODES's
// sensitivity module), stacked (the simultaneous corrector's iteration and error test with the
// sensitivities stacked after the state in one CVODES vector), or chosen by the problem
// (resolve_sensitivity_method).
enum class SensitivityMethod { simultaneous, staggered, staggered1, stacked, automatic };
enum class SensitivityRhs { exact, dq };  // OdeProblem::sensitivity_rhs | CVODES internal DQ

struct SolverOptions {
  Method method = Method::bdf;
  Iteration iteration = Iteration::newton;
  double rtol = 1e-8;                  // relative tolerance (all states)
  double atol = 1e-10;                 // absolute tolerance, used when atol_per_state is empty
  std::vector<double> atol_per_state;  // n entries (CVodeSVtolerances); empty = scalar atol
  long max_steps = 100000;  // TOTAL steps allowed over the whole integration (not per output
                            // interval as CVODES's mxstep: the integrator sets mxstep to what
                            // is left before every output). Exceeding it: CV_TOO_MUCH_WORK.
  int max_order = 0;        // 0 = CVODES default (BDF 5, Adams 12)
  double initial_step = 0;  // 0 = CVODES estimates it
  double max_step = 0;      // 0 = unbounded
  JacobianKind jacobian = JacobianKind::exact;  // only with iteration = newton
  LinearSolver linear_solver = LinearSolver::automatic;  // only with iteration = newton
  SensitivityMethod sensitivity_method = SensitivityMethod::automatic;
  bool sens_error_control = true;  // sensitivities take part in the local error test
  SensitivityRhs sens_rhs = SensitivityRhs::exact;
  // Absolute tolerance of every sensitivity (CVodeSensSStolerances with rtol). Unset: CVODES
  // derives it from the state tolerances and the parameter scales, atol_i/|p̄_j|
  // (CVodeSensEEtolerances).
  std::optional<double> sens_atol;
  // Projection (only when the problem has_projection()): CVodeSetProjErrEst and
  // CVodeSetProjFrequency (steps between projections; 0 disables projection).
  bool projection_error_estimate = true;
  long projection_frequency = 1;

  bool operator==(const SolverOptions&) const = default;

  // Throws std::invalid_argument("solver.rtol: must be > 0, got -1") etc. n = problem size
  // (checks atol_per_state); pass -1 to skip size-dependent checks.
  void validate(int n = -1) const;
};

// Every value of each option with its name in the study file (`solver:`) and in the outputs
// (util/enum_names.hpp): the study parser and to_string read these tables.
inline constexpr EnumName<Method> kMethodNames[] = {
    {"bdf", Method::bdf}, {"adams", Method::adams}, {"dop853", Method::dop853}};
inline constexpr EnumName<Iteration> kIterationNames[] = {
    {"newton", Iteration::newton}, {"functional", Iteration::functional}};
inline constexpr EnumName<JacobianKind> kJacobianKindNames[] = {
    {"exact", JacobianKind::exact}, {"dq", JacobianKind::dq}};
inline constexpr EnumName<LinearSolver> kLinearSolverNames[] = {
    {"dense", LinearSolver::dense}, {"krylov", LinearSolver::krylov}, {"auto", LinearSolver::automatic}};
inline constexpr EnumName<SensitivityMethod> kSensitivityMethodNames[] = {
    {"simultaneous", SensitivityMethod::simultaneous},
    {"staggered", SensitivityMethod::staggered},
    {"staggered1", SensitivityMethod::staggered1},
    {"stacked", SensitivityMethod::stacked},
    {"auto", SensitivityMethod::automatic}};
inline constexpr EnumName<SensitivityRhs> kSensitivityRhsNames[] = {
    {"exact", SensitivityRhs::exact}, {"dq", SensitivityRhs::dq}};

std::string_view to_string(Method m);
std::string_view to_string(Iteration it);
std::string_view to_string(JacobianKind j);
std::string_view to_string(LinearSolver l);  // "dense", "krylov", "auto"

// `automatic` takes krylov for problems of at least kKrylovMinStates states whose Jacobian's
// spectral radius at the initial state is at most kKrylovMaxRate (1/s): there one J v costs far
// less than a dense Jacobian and unpreconditioned GMRES converges in about one iteration per
// Newton iteration; stiff problems (a larger radius) need the dense LU. Measured:
// docs/explanation/solvers.md, bench/newton_sweep.py.
inline constexpr int kKrylovMinStates = 120;
inline constexpr double kKrylovMaxRate = 1e3;
// The linear solver a Newton integration of n states uses: the option itself unless automatic;
// jacobian_rate: the estimated spectral radius of J (needed only when n >= kKrylovMinStates).
LinearSolver resolve_linear_solver(LinearSolver option, int n, double jacobian_rate = 0);
// automatic: stacked where the problem allows it (`stackable`, Integrator: the fastest,
// docs/benchmarks.md), else staggered with projection (the two module correctors are as accurate
// and as fast there) and simultaneous without (as fast or faster); an explicit choice is kept.
SensitivityMethod resolve_sensitivity_method(SensitivityMethod option, bool with_projection, bool stackable);
std::string_view to_string(SensitivityMethod s);
std::string_view to_string(SensitivityRhs s);

}  // namespace kanesens::sim
