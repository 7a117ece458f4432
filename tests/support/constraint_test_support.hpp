// Helpers for the constraint tests (tests/regression/test_constraints*.cpp): run one trajectory
// of a constrained scene with chosen stabilization and tolerances, a fixed-step RK4 for the
// 1-DOF reductions (written here, independent of src/), and the Workspace-level evaluation of
// multipliers and constraint rank at a state.
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "dynamics/equations.hpp"
#include "kane_test_support.hpp"
#include "sim/simulate.hpp"
#include "layers.hpp"

namespace kanesens::testing {

using Stab = ConstraintOptions::Stabilization;

// A rod on a planar joint pinned at its top end to the ground (2 coincident rows), released at
// theta0 with angular rate w0: the scene of the multiplier- and projection-sensitivity tests
// (parameters m, L, theta0 and the initial rate base.u0[2] to differentiate with respect to).
inline constexpr const char* kSpinningPinnedPendulum = R"yaml(
kanesens: 1
scene:
  name: constrained_pendulum_sens
  gravity: [0, -9.81, 0]
  parameters: {m: 1.3, L: 0.8, theta0: 0.5, w0: 0.7}
  bodies:
    - {name: rod, mass: m, inertia: {shape: rod, length: L, axis: y}}
  joints:
    - {name: base, type: planar, parent: ground, child: rod, axis: [0, 0, 1],
       q0: ["L/2*sin(theta0)", "-L/2*cos(theta0)", theta0],
       u0: ["L/2*cos(theta0)*w0", "L/2*sin(theta0)*w0", w0]}
  constraints:
    - {name: pin, type: coincident, body_a: rod, point_a: [0, "L/2", 0], body_b: ground, point_b: [0, 0, 0]}
)yaml";

inline ConstraintOptions constraint_options(Stab s) {
  ConstraintOptions c;
  c.stabilization = s;
  return c;
}

inline sim::SolverOptions tolerances(double rtol, double atol) {
  sim::SolverOptions o;
  o.rtol = rtol;
  o.atol = atol;
  return o;
}

inline std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> t;
  for (int k = 0; k < n; ++k) t.push_back(k == n - 1 ? b : a + (b - a) * k / (n - 1));
  return t;
}

struct TrajRun {
  Trajectory tr;
  std::vector<double> times;
  int n = 0, m = 0, ns = 0;
  double y(int k, int r) const { return tr.states[static_cast<std::size_t>(k * n + r)]; }
  double lambda(int k, int r) const { return tr.multipliers[static_cast<std::size_t>(k * m + r)]; }
  double s(int k, int r, int i) const { return tr.sensitivities[static_cast<std::size_t>((k * n + r) * ns + i)]; }
  double dlambda(int k, int r, int i) const {
    return tr.multiplier_sensitivities[static_cast<std::size_t>((k * m + r) * ns + i)];
  }
};

// One trajectory with multipliers, residuals and (if `sens` is not empty) sensitivities.
inline TrajRun run(const Model& model, const std::vector<double>& times, ConstraintOptions copt,
               const sim::SolverOptions& sopt, const std::vector<std::string>& sens = {},
               const std::vector<std::pair<std::string, double>>& set = {}) {
  std::vector<InputRef> refs;
  for (const auto& name : sens) refs.push_back(resolve_input(model, name, "test"));
  KaneProblem problem(model, refs, copt);
  SampleInputs in(model);
  for (const auto& [name, v] : set) in.set(resolve_input(model, name, "test"), v);
  problem.set_sample(in);
  sim::Integrator integ(sopt);
  RecordFlags flags;
  flags.sensitivities = !refs.empty();
  flags.multipliers = model.nconstraint_rows > 0;
  flags.constraint_residual = model.nconstraint_rows > 0;
  TrajRun r;
  simulate(problem, integ, times, flags, r.tr);
  r.times = times;
  r.n = model.nstate();
  r.m = model.nconstraint_rows;
  r.ns = static_cast<int>(refs.size());
  return r;
}

// Multipliers, rank and u̇ at one state, straight from the dynamics/ functions.
struct Evaluation {
  std::vector<double> lambda, ydot;
  int rank = 0;
};
inline Evaluation evaluate_at(const Model& m, const std::vector<double>& y, double t = 0) {
  Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  Evaluation e;
  e.ydot.resize(static_cast<std::size_t>(m.nstate()));
  evaluate_rhs(m, ws, t, y.data(), e.ydot.data());
  e.lambda.assign(ws.multipliers.data(), ws.multipliers.data() + m.nconstraint_rows);
  e.rank = ws.constraint_rank;
  return e;
}

// Classical fixed-step RK4 for x' = f(x) (x = [θ, θ̇] etc.), returning x at each of `times`
// (which must be multiples of h from times[0]).
template <std::size_t N>
std::vector<std::array<double, N>> rk4(const std::function<std::array<double, N>(const std::array<double, N>&)>& f,
                                       std::array<double, N> x, const std::vector<double>& times, double h) {
  std::vector<std::array<double, N>> out;
  double t = times.front();
  auto axpy = [](const std::array<double, N>& a, double s, const std::array<double, N>& b) {
    std::array<double, N> r;
    for (std::size_t i = 0; i < N; ++i) r[i] = a[i] + s * b[i];
    return r;
  };
  for (double target : times) {
    const long steps = std::lround((target - t) / h);
    for (long k = 0; k < steps; ++k) {
      const auto k1 = f(x), k2 = f(axpy(x, h / 2, k1)), k3 = f(axpy(x, h / 2, k2)), k4 = f(axpy(x, h, k3));
      for (std::size_t i = 0; i < N; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    t += static_cast<double>(steps) * h;
    out.push_back(x);
  }
  return out;
}

}  // namespace kanesens::testing
