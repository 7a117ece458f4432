// Newton's linear solvers on closed loops and chains: matrix-free GMRES (linear_solver krylov,
// exact J v from one Dual pass) reaches the dense solver's trajectory on the IFToMM A02 N four-bar
// mechanism (multipliers + projection; its exact motion is a 1-DOF pendulum, φ̈ = −(G/J) cos φ)
// and on a spring chain; and the Jacobians of both are dense in their u̇ rows (M⁻¹ and the
// Schur complement couple every speed), which is why no sparse direct solver is offered
// (docs/explanation/solvers.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../support/kane_test_support.hpp"
#include "sim/simulate.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::testing;
using namespace kanesens::testing;

namespace {

// bench/n_four_bar.py's scene: N windows of unit rods, cranks on ground pivots L apart, couplers
// closed onto the next crank's tip by coincident constraints.
std::string n_four_bar(int n) {
  std::string s = "kanesens: 1\nscene:\n  name: n_four_bar\n  gravity: [0, -9.81, 0]\n"
                  "  parameters: {L: 1.0, m: 1.0, phi0: \"pi/4\", w0: \"-1/(L*sin(phi0))\"}\n  bodies:\n";
  for (int i = 0; i <= n; ++i)
    s += "    - {name: crank" + std::to_string(i) + ", mass: m, inertia: {shape: rod, length: L, axis: x}}\n";
  for (int i = 0; i < n; ++i)
    s += "    - {name: coupler" + std::to_string(i) + ", mass: m, inertia: {shape: rod, length: L, axis: x}}\n";
  s += "  joints:\n";
  for (int i = 0; i <= n; ++i)
    s += "    - {name: crank" + std::to_string(i) + ", type: revolute, parent: ground, child: crank" +
         std::to_string(i) + ", axis: [0, 0, 1], parent_point: [\"" + std::to_string(i) +
         "*L\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: phi0, u0: w0}\n";
  for (int i = 0; i < n; ++i)
    s += "    - {name: coupler" + std::to_string(i) + ", type: revolute, parent: crank" + std::to_string(i) +
         ", child: coupler" + std::to_string(i) +
         ", axis: [0, 0, 1], parent_point: [\"L/2\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: \"-phi0\", "
         "u0: \"-w0\"}\n";
  s += "  constraints:\n";
  for (int i = 0; i < n; ++i)
    s += "    - {name: loop" + std::to_string(i) + ", type: coincident, body_a: coupler" + std::to_string(i) +
         ", point_a: [\"L/2\", 0, 0], body_b: crank" + std::to_string(i + 1) + ", point_b: [\"L/2\", 0, 0]}\n";
  return s;
}

// A planar chain of n rods with joint springs and dampers, hanging from the origin.
// axes_zx: joint axes alternate z, x (a chain moving in 3-D) instead of all z (planar).
std::string chain(int n, double k = 20, double c = 0.2, bool axes_zx = false) {
  std::string s = "kanesens: 1\nscene:\n  name: chain\n  gravity: [0, -9.81, 0]\n"
                  "  parameters: {m: 1.0, L: 1.0, k: " + std::to_string(k) + ", c: " + std::to_string(c) +
                  "}\n  bodies:\n";
  for (int i = 1; i <= n; ++i)
    s += "    - {name: link" + std::to_string(i) + ", mass: m, inertia: {shape: rod, length: L, axis: y}}\n";
  s += "  joints:\n";
  for (int i = 1; i <= n; ++i)
    s += "    - {name: j" + std::to_string(i) + ", type: revolute, parent: " +
         (i == 1 ? std::string("ground") : "link" + std::to_string(i - 1)) + ", child: link" + std::to_string(i) +
         ", axis: " + (axes_zx && i % 2 == 0 ? "[1, 0, 0]" : "[0, 0, 1]") + ", parent_point: [0, " +
         (i == 1 ? "0" : "\"-L/2\"") + ", 0], child_point: [0, \"L/2\", 0]," +
         " q0: " + (i == 1 ? "0.5" : "0") + ", u0: 0, spring: {k: k, rest: 0}, damper: {c: c}}\n";
  return s;
}

// φ(t) of the N four-bar: its 1-DOF equation integrated by the same CVODES at rtol 1e-12.
class Crank : public ks::OdeProblem {
 public:
  explicit Crank(int n) : ratio_(((n + 1) / 2.0 + n) * 9.81 / ((n + 1) / 3.0 + n)) {}
  int size() const override { return 2; }
  void initial_state(double* y0) const override {
    y0[0] = M_PI / 4;
    y0[1] = -1 / std::sin(M_PI / 4);
  }
  void rhs(double, const double* y, double* ydot) override {
    ydot[0] = y[1];
    ydot[1] = -ratio_ * std::cos(y[0]);
  }

 private:
  double ratio_;
};

ks::Trajectory simulate(const ks::Model& m, ks::LinearSolver ls, const std::vector<double>& times,
                        const std::vector<ks::InputRef>& sens = {}, ks::JacobianKind jacobian = ks::JacobianKind::exact) {
  SCOPED_TRACE(m.name);
  ks::KaneProblem problem(m, sens);
  ks::SolverOptions o;
  o.linear_solver = ls;
  o.jacobian = jacobian;
  ks::Integrator integ(o);
  ks::Trajectory tr;
  ks::RecordFlags flags;
  flags.energy = false;
  ks::simulate(problem, integ, times, flags, tr);
  EXPECT_TRUE(tr.result.ok()) << tr.result.message;
  return tr;
}

std::vector<double> times(double end, int outputs) {
  std::vector<double> t;
  for (int k = 0; k < outputs; ++k) t.push_back(end * k / (outputs - 1));
  return t;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace

TEST(NewtonKrylov, NFourBarMatchesDenseAndTheExactMotion) {
  for (int n : {5, 10}) {
    SCOPED_TRACE("N = " + std::to_string(n));
    const ks::Model m = model_from_text(n_four_bar(n));
    // 3 s: through two of the singular (all links horizontal) configurations.
    const std::vector<double> t = times(3.0, 61);
    const ks::Trajectory dense = simulate(m, ks::LinearSolver::dense, t);
    const ks::Trajectory krylov = simulate(m, ks::LinearSolver::krylov, t);
    ASSERT_TRUE(dense.result.ok() && krylov.result.ok());
    Crank crank(n);
    ks::SolverOptions tight;
    tight.rtol = 1e-12;
    tight.atol = 1e-14;
    std::vector<double> phi;
    tight.jacobian = ks::JacobianKind::dq;
    ks::integrate(crank, tight, t, [&](int, double, const double* y, const double* const*) { phi.push_back(y[0]); });
    const std::size_t ns = static_cast<std::size_t>(m.nstate());
    double err_dense = 0, err_krylov = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      err_dense = std::max(err_dense, std::abs(dense.states[k * ns] - phi[k]));
      err_krylov = std::max(err_krylov, std::abs(krylov.states[k * ns] - phi[k]));
    }
    const double d = max_diff(dense.states, krylov.states);
    std::printf("[ measure  ] N = %d: |dense - krylov| %.2e; crank0.q error dense %.2e, krylov %.2e; steps %ld / %ld, "
                "J %ld, J v %ld (GMRES iterations %ld)\n",
                n, d, err_dense, err_krylov, dense.result.stats.steps, krylov.result.stats.steps,
                dense.result.stats.jac_evals, krylov.result.stats.jtimes_evals, krylov.result.stats.lin_iters);
    EXPECT_LT(err_dense, 1e-5);
    EXPECT_LT(err_krylov, 1e-5);
    EXPECT_LT(d, 2e-5);
    EXPECT_EQ(krylov.result.stats.jac_evals, 0);
    EXPECT_GT(krylov.result.stats.jtimes_evals, 0);
  }
}

TEST(NewtonKrylov, ChainMatchesDenseWithSensitivities) {
  const ks::Model m = model_from_text(chain(12));
  std::vector<ks::InputRef> sens;
  for (const char* name : {"k", "m", "j1.q0"}) sens.push_back(ks::resolve_input(m, name, "test"));
  const std::vector<double> t = times(3.0, 31);
  const ks::Trajectory dense = simulate(m, ks::LinearSolver::dense, t, sens);
  const ks::Trajectory krylov = simulate(m, ks::LinearSolver::krylov, t, sens);
  ASSERT_TRUE(dense.result.ok() && krylov.result.ok());
  double peak = 0, peak_s = 0;
  for (double v : dense.states) peak = std::max(peak, std::abs(v));
  for (double v : dense.sensitivities) peak_s = std::max(peak_s, std::abs(v));
  const double d = max_diff(dense.states, krylov.states), ds = max_diff(dense.sensitivities, krylov.sensitivities);
  std::printf("[ measure  ] chain 12: |dense - krylov| states %.2e (peak %.2f), sensitivities %.2e (peak %.2f); "
              "J v %ld, sensitivity RHS %ld / %ld\n",
              d, peak, ds, peak_s, krylov.result.stats.jtimes_evals, dense.result.stats.sens_rhs_evals,
              krylov.result.stats.sens_rhs_evals);
  EXPECT_LT(d, 1e-6 * peak);
  EXPECT_LT(ds, 1e-5 * peak_s);
}

// The u̇ rows of J = ∂ẏ/∂y at a generic state: every entry is nonzero on both mechanisms, so a
// sparse LU would hold n²/2 entries at least and fill in the rest; the q̇ rows are the
// kinematic identity.
TEST(NewtonKrylov, JacobiansOfLoopsAndChainsAreDense) {
  for (const auto& [label, yaml] : {std::pair<std::string, std::string>{"N four-bar 10", n_four_bar(10)},
                                    std::pair<std::string, std::string>{"chain 24", chain(24)}}) {
    const ks::Model m = model_from_text(yaml);
    ks::KaneProblem p(m, {});
    p.set_sample(ks::SampleInputs(m));
    const int n = p.size(), nq = m.nq;
    std::vector<double> y(static_cast<std::size_t>(n)), ydot(y.size()), J(y.size() * y.size());
    p.initial_state(y.data());
    for (int r = 0; r < n; ++r) y[static_cast<std::size_t>(r)] += 0.01 * (r % 7);  // a generic state
    p.rhs(0.0, y.data(), ydot.data());
    p.jacobian(0.0, y.data(), ydot.data(), J.data());
    double scale = 0;
    for (double v : J) scale = std::max(scale, std::abs(v));
    long nonzero_q = 0, nonzero_u = 0;
    for (int c = 0; c < n; ++c)
      for (int r = nq; r < n; ++r)
        if (std::abs(J[static_cast<std::size_t>(c) * n + r]) > 1e-12 * scale) ++(c < nq ? nonzero_q : nonzero_u);
    const double rows = n - nq, fq = nonzero_q / (rows * nq), fu = nonzero_u / (rows * (n - nq));
    std::printf("[ measure  ] %s: %d states, nonzero in du/dq %.1f%%, in du/du %.1f%%\n", label.c_str(), n, 100 * fq,
                100 * fu);
    EXPECT_GT(fq, 0.5) << label;
    EXPECT_GT(fu, 0.9) << label;
  }
}

// linear_solver: auto takes krylov for a large mechanism whose Jacobian's spectral radius is
// small (the N four-bar, N = 30: 122 states; a planar 64-link chain), dense for a small one and
// for a large stiff one (a 64-link chain with stiff overdamped joints: radius ~5e4/s, where GMRES
// without a preconditioner needs many iterations, even with jacobian: dq). A 64-link chain moving
// in 3-D takes krylov too: its exact J v is the 3-D articulated-body recursion on duals, O(n) like
// the right-hand side (where J v would form M, tests/unit/test_integrator.cpp: dense).
TEST(NewtonKrylov, AutoChoosesBySizeAndStiffness) {
  const std::vector<double> t = times(0.02, 3);
  EXPECT_EQ(simulate(model_from_text(n_four_bar(30)), ks::LinearSolver::automatic, t).result.linear_solver,
            ks::LinearSolver::krylov);
  EXPECT_EQ(simulate(model_from_text(chain(64)), ks::LinearSolver::automatic, t).result.linear_solver,
            ks::LinearSolver::krylov);
  EXPECT_EQ(simulate(model_from_text(chain(64, 20, 0.2, true)), ks::LinearSolver::automatic, t).result.linear_solver,
            ks::LinearSolver::krylov);
  EXPECT_EQ(simulate(model_from_text(chain(64, 20, 0.2, true)), ks::LinearSolver::automatic, t, {}, ks::JacobianKind::dq)
                .result.linear_solver,
            ks::LinearSolver::krylov);
  EXPECT_EQ(simulate(model_from_text(n_four_bar(5)), ks::LinearSolver::automatic, t).result.linear_solver,
            ks::LinearSolver::dense);
  EXPECT_EQ(simulate(model_from_text(chain(64, 1e5, 1e3)), ks::LinearSolver::automatic, t, {}, ks::JacobianKind::dq)
                .result.linear_solver,
            ks::LinearSolver::dense);
}

}  // namespace KANESENS_UNITY_ID
