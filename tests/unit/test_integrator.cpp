// Tests of solve/integrator against hand-written OdeProblems:
// - damped oscillator sensitivities against the closed form,
//   for every sensitivity method, exact and DQ sensitivity RHS;
// - failures are statuses with messages (throwing, NaN, too much work), not crashes;
// - method/Jacobian variants agree; one Integrator reused equals fresh ones.
#include <cvodes/cvodes.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "closed_forms.hpp"
#include "sim/solve/integrator.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::sim;
namespace kt = kanesens::testing;

namespace {

// m ẍ + c ẋ + k x = 0, y = (x, v). Sensitivity parameters (x0, v0, m, c, k).
// p_ holds (x0-dummy, v0-dummy, m, c, k) so CVODES's DQ sensitivities can perturb m, c, k.
class Oscillator : public ks::OdeProblem {
 public:
  Oscillator(double x0 = 1, double v0 = 0, double m = 1, double c = 0.4, double k = 4)
      : x0_(x0), v0_(v0), p_{0, 0, m, c, k} {}

  int size() const override { return 2; }
  void initial_state(double* y0) const override {
    y0[0] = x0_;
    y0[1] = v0_;
  }
  void rhs(double /*t*/, const double* y, double* ydot) override {
    ++rhs_calls;
    const double m = p_[2], c = p_[3], k = p_[4];
    ydot[0] = y[1];
    ydot[1] = -(c * y[1] + k * y[0]) / m;
  }
  bool has_jacobian() const override { return true; }
  void jacobian(double, const double*, const double*, double* J) override {
    const double m = p_[2], c = p_[3], k = p_[4];
    J[0 + 0 * 2] = 0;
    J[0 + 1 * 2] = 1;
    J[1 + 0 * 2] = -k / m;
    J[1 + 1 * 2] = -c / m;
  }
  bool has_jacobian_times() const override { return true; }
  void jacobian_times(double, const double*, const double*, const double* v, double* Jv) override {
    ++jtimes_calls;
    const double m = p_[2], c = p_[3], k = p_[4];
    Jv[0] = v[1];
    Jv[1] = -(k * v[0] + c * v[1]) / m;
  }
  int num_sensitivities() const override { return with_sens ? 5 : 0; }
  void initial_sensitivity(int i, double* s0) const override {
    s0[0] = i == 0 ? 1 : 0;
    s0[1] = i == 1 ? 1 : 0;
  }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double, const double* y, const double*, int i, const double* s,
                       double* sdot) override {
    const double m = p_[2], c = p_[3], k = p_[4];
    sdot[0] = s[1];
    sdot[1] = -(c * s[1] + k * s[0]) / m;
    if (i == 2) sdot[1] += (c * y[1] + k * y[0]) / (m * m);
    if (i == 3) sdot[1] += -y[1] / m;
    if (i == 4) sdot[1] += -y[0] / m;
  }
  std::vector<double> sensitivity_scales() const override { return {1, 1, p_[2], p_[3], p_[4]}; }
  double* dq_parameters() override { return p_; }
  std::vector<int> dq_parameter_list() const override { return {0, 1, 2, 3, 4}; }

  const double* parameters() const { return p_; }
  bool with_sens = true;
  long rhs_calls = 0;
  long jtimes_calls = 0;

 private:
  double x0_, v0_;
  double p_[5];
};

struct Trajectory {
  std::vector<double> t;
  std::vector<std::vector<double>> y;               // [k][state]
  std::vector<std::vector<std::vector<double>>> s;  // [k][sens][state]
  ks::IntegrationResult result;
};

Trajectory run(ks::Integrator& integ, ks::OdeProblem& problem, const std::vector<double>& times) {
  Trajectory tr;
  const int n = problem.size(), ns = problem.num_sensitivities();
  tr.result = integ.integrate(problem, times,
                              [&](int k, double t, const double* y, const double* const* s) {
                                EXPECT_EQ(k, static_cast<int>(tr.t.size()));
                                tr.t.push_back(t);
                                tr.y.emplace_back(y, y + n);
                                tr.s.emplace_back();
                                for (int i = 0; i < ns; ++i)
                                  tr.s.back().emplace_back(s[i], s[i] + n);
                              });
  return tr;
}

Trajectory run(const ks::SolverOptions& o, ks::OdeProblem& problem,
               const std::vector<double>& times) {
  ks::Integrator integ(o);
  return run(integ, problem, times);
}

struct ReferenceRow {
  double t;
  double v[6];  // x, dx/dx0, dx/dv0, dx/dm, dx/dc, dx/dk
};

// The closed form at t = 0.5, 1, 2, 5, 10 for m = 1, c = 0.4, k = 4 (ωn = 2, ζ = 0.1), x0 = 1,
// v0 = 0 (tests/support/closed_forms.hpp; checked below by complex-step differentiation).
std::vector<ReferenceRow> closed_form_reference() {
  std::vector<ReferenceRow> rows;
  for (double t : {0.5, 1.0, 2.0, 5.0, 10.0}) {
    const kt::OscillatorSolution s = kt::damped_oscillator(t, 1, 0, 1, 0.4, 4);
    ReferenceRow r{t, {s.x, s.dx[0], s.dx[1], s.dx[2], s.dx[3], s.dx[4]}};
    rows.push_back(r);
  }
  return rows;
}

// Max over the reference rows of |computed − reference| / max(|reference|, 1e-2)
// for x (index 0) and the five sensitivities (1..5).
double max_rel_error(const Trajectory& tr, const std::vector<ReferenceRow>& ref) {
  double worst = 0;
  for (std::size_t r = 0; r < ref.size(); ++r) {
    const std::size_t k = r + 1;  // times = {0, ref t...}
    for (int j = 0; j < 6; ++j) {
      const double got = j == 0 ? tr.y[k][0] : tr.s[k][static_cast<std::size_t>(j - 1)][0];
      worst = std::max(worst, std::abs(got - ref[r].v[j]) / std::max(std::abs(ref[r].v[j]), 1e-2));
    }
  }
  return worst;
}

std::vector<double> reference_times(const std::vector<ReferenceRow>& ref) {
  std::vector<double> times{0.0};
  for (const auto& r : ref) times.push_back(r.t);
  return times;
}

double max_abs_diff(const Trajectory& a, const Trajectory& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.y.size(); ++k) {
    for (std::size_t j = 0; j < a.y[k].size(); ++j)
      d = std::max(d, std::abs(a.y[k][j] - b.y[k][j]));
    for (std::size_t i = 0; i < a.s[k].size(); ++i) {
      for (std::size_t j = 0; j < a.s[k][i].size(); ++j) {
        d = std::max(d, std::abs(a.s[k][i][j] - b.s[k][i][j]));
      }
    }
  }
  return d;
}

ks::SolverOptions tight() {
  ks::SolverOptions o;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  return o;
}

}  // namespace

// ---------- 1. analytic sensitivities ----------

// The reference itself: the hand-derived sensitivities against complex-step derivatives of x(t)
// (Squire & Trapp 1998: ∂x/∂p = Im x(p + ih)/h, no cancellation, exact to round-off), and x(t)
// against the equation of motion and the initial conditions.
TEST(DampedOscillatorClosedForm, SensitivitiesAndEquationOfMotion) {
  using C = std::complex<double>;
  const double h = 1e-30;
  double worst_sens = 0, worst_residual = 0;
  for (const double t : {0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 17.3}) {
    for (const auto& p : {std::array<double, 5>{1, 0, 1, 0.4, 4},
                          std::array<double, 5>{0.3, -0.7, 1.7, 0.9, 5.5}}) {
      const kt::OscillatorSolution s = kt::damped_oscillator(t, p[0], p[1], p[2], p[3], p[4]);
      EXPECT_DOUBLE_EQ(s.x, kt::damped_oscillator_x(t, p[0], p[1], p[2], p[3], p[4]));
      for (int j = 0; j < 5; ++j) {
        C pc[5] = {p[0], p[1], p[2], p[3], p[4]};
        pc[j] += C(0, h);
        const double cs = kt::damped_oscillator_x(C(t), pc[0], pc[1], pc[2], pc[3], pc[4]).imag() / h;
        worst_sens = std::max(worst_sens, std::abs(s.dx[j] - cs) / std::max(std::abs(cs), 1e-2));
      }
      // ẋ by complex step in t, ẍ by a central difference of ẋ: m ẍ + c ẋ + k x = 0.
      auto xdot = [&](double tt) {
        return kt::damped_oscillator_x(C(tt, h), C(p[0]), C(p[1]), C(p[2]), C(p[3]), C(p[4])).imag() / h;
      };
      const double d = 1e-5, xdd = (xdot(t + d) - xdot(t - d)) / (2 * d);
      worst_residual = std::max(worst_residual, std::abs(p[2] * xdd + p[3] * xdot(t) + p[4] * s.x));
      if (t == 0) {
        EXPECT_DOUBLE_EQ(s.x, p[0]);
        EXPECT_NEAR(xdot(0), p[1], 1e-15);
      }
    }
  }
  std::printf("[ measure  ] oscillator closed form: hand vs complex-step sensitivities %.1e, "
              "|m x'' + c x' + k x| %.1e\n",
              worst_sens, worst_residual);
  EXPECT_LT(worst_sens, 1e-13);
  EXPECT_LT(worst_residual, 1e-8);
}

struct SensCase {
  ks::SensitivityMethod method;
  ks::SensitivityRhs rhs;
  ks::LinearSolver linear_solver = ks::LinearSolver::dense;
};

class OscillatorSensitivities : public ::testing::TestWithParam<SensCase> {};

TEST_P(OscillatorSensitivities, MatchAnalyticReference) {
  const auto ref = closed_form_reference();
  ASSERT_EQ(ref.size(), 5u);
  // CVODES's DQ sensitivities perturb y by about the local error tolerance, so their roundoff
  // is ~ eps/rtol relative: they break down below rtol ~ 1e-9 (docs/solve.md). Exact: rtol
  // 1e-10; DQ: rtol 1e-8.
  const bool dq = GetParam().rhs == ks::SensitivityRhs::dq;
  ks::SolverOptions o = tight();
  if (dq) {
    o.rtol = 1e-8;
    o.atol = 1e-10;
  }
  const double tolerance = dq ? 2e-6 : 3e-8;  // measured max: DQ 5.2e-7, exact 7.1e-9
  o.sensitivity_method = GetParam().method;
  o.sens_rhs = GetParam().rhs;
  o.linear_solver = GetParam().linear_solver;
  Oscillator osc;
  const Trajectory tr = run(o, osc, reference_times(ref));
  ASSERT_TRUE(tr.result.ok()) << tr.result.message;
  ASSERT_EQ(tr.y.size(), ref.size() + 1);
  const double err = max_rel_error(tr, ref);
  std::printf(
      "[ measure  ] %s/%s rtol %.0e: max rel error %.3e, steps %ld, rhs %ld, sens rhs %ld, "
      "rhs for sens %ld\n",
      std::string(ks::to_string(o.sensitivity_method)).c_str(),
      std::string(ks::to_string(o.sens_rhs)).c_str(), o.rtol, err, tr.result.stats.steps,
      tr.result.stats.rhs_evals, tr.result.stats.sens_rhs_evals,
      tr.result.stats.rhs_evals_for_sens);
  EXPECT_LT(err, tolerance);
  // Output 0 is the initial state and the initial sensitivities, exactly.
  EXPECT_EQ(tr.t[0], 0.0);
  EXPECT_EQ(tr.y[0], (std::vector<double>{1, 0}));
  EXPECT_EQ(tr.s[0][0], (std::vector<double>{1, 0}));
  EXPECT_EQ(tr.s[0][1], (std::vector<double>{0, 1}));
  EXPECT_EQ(tr.s[0][4], (std::vector<double>{0, 0}));
  if (o.sens_rhs == ks::SensitivityRhs::exact) {
    EXPECT_GT(tr.result.stats.sens_rhs_evals, 0);
    EXPECT_EQ(tr.result.stats.rhs_evals_for_sens, 0);
  } else {
    EXPECT_GT(tr.result.stats.rhs_evals_for_sens, 0);
  }
  // CVODES's DQ perturbations of p are undone.
  EXPECT_EQ(osc.parameters()[3], 0.4);
  // The sensitivities' Newton systems go through the same linear solver: GMRES on J v only.
  if (o.linear_solver == ks::LinearSolver::krylov) {
    EXPECT_EQ(tr.result.stats.jac_evals, 0);
    EXPECT_GT(tr.result.stats.jtimes_evals, 0);
    EXPECT_EQ(tr.result.stats.jtimes_evals, osc.jtimes_calls);
  } else {
    EXPECT_GT(tr.result.stats.jac_evals, 0);
    EXPECT_EQ(osc.jtimes_calls, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllMethods, OscillatorSensitivities,
    ::testing::Values(SensCase{ks::SensitivityMethod::stacked, ks::SensitivityRhs::exact},
                      SensCase{ks::SensitivityMethod::simultaneous, ks::SensitivityRhs::exact},
                      SensCase{ks::SensitivityMethod::staggered, ks::SensitivityRhs::exact},
                      SensCase{ks::SensitivityMethod::staggered1, ks::SensitivityRhs::exact},
                      SensCase{ks::SensitivityMethod::simultaneous, ks::SensitivityRhs::dq},
                      SensCase{ks::SensitivityMethod::staggered, ks::SensitivityRhs::dq},
                      SensCase{ks::SensitivityMethod::staggered1, ks::SensitivityRhs::dq},
                      SensCase{ks::SensitivityMethod::simultaneous, ks::SensitivityRhs::exact, ks::LinearSolver::krylov},
                      SensCase{ks::SensitivityMethod::staggered, ks::SensitivityRhs::exact, ks::LinearSolver::krylov},
                      SensCase{ks::SensitivityMethod::staggered1, ks::SensitivityRhs::exact, ks::LinearSolver::krylov},
                      SensCase{ks::SensitivityMethod::staggered, ks::SensitivityRhs::dq, ks::LinearSolver::krylov}),
    [](const auto& info) {
      return std::string(ks::to_string(info.param.method)) + "_" + std::string(ks::to_string(info.param.rhs)) +
             (info.param.linear_solver == ks::LinearSolver::krylov ? "_krylov" : "");
    });

TEST(Integrator, ErrorShrinksWithTolerance) {
  const auto ref = closed_form_reference();
  double previous = 1;
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    ks::SolverOptions o;
    o.rtol = rtol;
    o.atol = rtol * 1e-2;
    Oscillator osc;
    const Trajectory tr = run(o, osc, reference_times(ref));
    ASSERT_TRUE(tr.result.ok()) << tr.result.message;
    const double err = max_rel_error(tr, ref);
    std::printf("[ measure  ] auto (%s)/exact rtol %.0e: max rel error %.3e\n",
                std::string(ks::to_string(tr.result.sensitivity_method)).c_str(), rtol, err);
    EXPECT_LT(err, previous);
    EXPECT_LT(err, 1000 * rtol);
    previous = err;
  }
}

TEST(Integrator, SensitivitySSTolerances) {
  const auto ref = closed_form_reference();
  ks::SolverOptions o = tight();
  o.sens_atol = 1e-12;
  Oscillator osc;
  const Trajectory tr = run(o, osc, reference_times(ref));
  ASSERT_TRUE(tr.result.ok()) << tr.result.message;
  EXPECT_LT(max_rel_error(tr, ref), 3e-8);
}

// ---------- 5. variants agree ----------

// The stacked system against CVODES's simultaneous corrector and the closed form: BDF, Adams–Newton
// and Adams with fixed-point iteration, with and without the sensitivities in the error test
// (without: the stacked norm is the state's alone, so the steps are about the plain solve's).
TEST(Integrator, StackedAgreesWithTheModule) {
  const auto ref = closed_form_reference();
  const auto times = reference_times(ref);
  struct Case {
    ks::Method method;
    ks::Iteration iteration;
  };
  for (const Case c : {Case{ks::Method::bdf, ks::Iteration::newton}, Case{ks::Method::adams, ks::Iteration::newton},
                       Case{ks::Method::adams, ks::Iteration::functional}})
    for (const bool error_control : {true, false}) {
      ks::SolverOptions o = tight();
      o.method = c.method;
      o.iteration = c.iteration;
      o.sens_error_control = error_control;
      Oscillator a, b, plain;
      plain.with_sens = false;
      o.sensitivity_method = ks::SensitivityMethod::stacked;
      const Trajectory stacked = run(o, a, times);
      o.sensitivity_method = ks::SensitivityMethod::simultaneous;
      const Trajectory module = run(o, b, times);
      const Trajectory state_only = run(o, plain, times);
      ASSERT_TRUE(stacked.result.ok() && module.result.ok() && state_only.result.ok()) << stacked.result.message;
      EXPECT_EQ(stacked.result.sensitivity_method, ks::SensitivityMethod::stacked);
      const double e_stacked = max_rel_error(stacked, ref), e_module = max_rel_error(module, ref);
      std::printf("[ measure  ] %s/%s, error control %d: max rel error stacked %.3e (%ld steps), module %.3e (%ld), "
                  "plain solve %ld steps\n",
                  std::string(ks::to_string(c.method)).c_str(), std::string(ks::to_string(c.iteration)).c_str(),
                  error_control, e_stacked, stacked.result.stats.steps, e_module, module.result.stats.steps,
                  state_only.result.stats.steps);
      EXPECT_LT(e_stacked, error_control ? 3e-8 : 3e-7);
      // With the sensitivities in the error test both take the same steps (the same test); without,
      // neither controls the sensitivities' error, and the stacked system steps as the plain solve.
      if (error_control) {
        EXPECT_LT(e_stacked, 1.01 * e_module);
      }
      EXPECT_EQ(stacked.result.stats.sens_rhs_evals, stacked.result.stats.rhs_evals);
      if (!error_control) {
        EXPECT_NEAR(stacked.result.stats.steps, state_only.result.stats.steps, 5);
      }
      if (c.iteration == ks::Iteration::functional) {
        EXPECT_EQ(stacked.result.stats.jac_evals, 0);
      }
    }
}

TEST(Integrator, AdamsAndBdfAgree) {
  const auto ref = closed_form_reference();
  const auto times = reference_times(ref);
  Oscillator a, b, c;
  const Trajectory bdf = run(tight(), a, times);
  ks::SolverOptions o = tight();
  o.method = ks::Method::adams;
  const Trajectory adams = run(o, b, times);
  o.iteration = ks::Iteration::functional;
  const Trajectory adams_fp = run(o, c, times);
  ASSERT_TRUE(bdf.result.ok() && adams.result.ok() && adams_fp.result.ok())
      << adams_fp.result.message;
  const double d1 = max_abs_diff(bdf, adams), d2 = max_abs_diff(bdf, adams_fp);
  std::printf(
      "[ measure  ] |bdf - adams/newton| = %.3e, |bdf - adams/functional| = %.3e; steps bdf %ld "
      "adams %ld adams/fp %ld\n",
      d1, d2, bdf.result.stats.steps, adams.result.stats.steps, adams_fp.result.stats.steps);
  EXPECT_LT(d1, 2e-8);
  EXPECT_LT(d2, 2e-8);
  EXPECT_EQ(adams_fp.result.stats.jac_evals, 0);
  EXPECT_LT(max_rel_error(adams, ref), 3e-8);
  EXPECT_LT(max_rel_error(adams_fp, ref), 3e-8);
}

TEST(Integrator, ExactAndDqJacobianAgree) {
  const auto times = reference_times(closed_form_reference());
  Oscillator a, b;
  const Trajectory exact = run(tight(), a, times);
  ks::SolverOptions o = tight();
  o.jacobian = ks::JacobianKind::dq;
  const Trajectory dq = run(o, b, times);
  ASSERT_TRUE(exact.result.ok() && dq.result.ok());
  const double d = max_abs_diff(exact, dq);
  std::printf(
      "[ measure  ] |exact J - DQ J| trajectories = %.3e; lin_rhs_evals exact %ld, dq %ld\n", d,
      exact.result.stats.lin_rhs_evals, dq.result.stats.lin_rhs_evals);
  EXPECT_LT(d, 1e-9);
  EXPECT_EQ(exact.result.stats.lin_rhs_evals, 0);
  EXPECT_GT(dq.result.stats.lin_rhs_evals, 0);
  EXPECT_GT(exact.result.stats.jac_evals, 0);
}

// Matrix-free Newton (GMRES on exact J v, or on CVODES's difference quotients J v) reaches the
// dense solver's trajectory and sensitivities; the automatic choice takes dense for 2 states.
TEST(Integrator, KrylovAndDenseAgree) {
  const auto times = reference_times(closed_form_reference());
  Oscillator a, b, c;
  const Trajectory dense = run(tight(), a, times);
  ks::SolverOptions o = tight();
  o.linear_solver = ks::LinearSolver::krylov;
  const Trajectory krylov = run(o, b, times);
  o.jacobian = ks::JacobianKind::dq;
  const Trajectory krylov_dq = run(o, c, times);
  ASSERT_TRUE(dense.result.ok() && krylov.result.ok() && krylov_dq.result.ok()) << krylov.result.message;
  const double d = max_abs_diff(dense, krylov), d_dq = max_abs_diff(dense, krylov_dq);
  std::printf("[ measure  ] |dense - krylov| = %.3e, |dense - krylov dq| = %.3e; J v %ld, GMRES iterations %ld\n", d,
              d_dq, krylov.result.stats.jtimes_evals, krylov.result.stats.lin_iters);
  EXPECT_LT(d, 1e-8);
  EXPECT_LT(d_dq, 1e-8);
  EXPECT_GT(krylov.result.stats.jtimes_evals, 0);
  EXPECT_EQ(krylov.result.stats.jtimes_evals, b.jtimes_calls);
  EXPECT_EQ(krylov.result.stats.lin_rhs_evals, 0);
  EXPECT_GT(krylov_dq.result.stats.lin_rhs_evals, 0);  // one RHS per difference-quotient J v
  EXPECT_EQ(c.jtimes_calls, 0);
  EXPECT_EQ(krylov.result.stats.jac_evals, 0);
  EXPECT_EQ(dense.result.stats.jtimes_evals, 0);
  EXPECT_EQ(ks::resolve_linear_solver(ks::LinearSolver::automatic, 2), ks::LinearSolver::dense);
  EXPECT_EQ(ks::resolve_linear_solver(ks::LinearSolver::automatic, ks::kKrylovMinStates), ks::LinearSolver::krylov);
  EXPECT_EQ(ks::resolve_linear_solver(ks::LinearSolver::automatic, ks::kKrylovMinStates, 10 * ks::kKrylovMaxRate),
            ks::LinearSolver::dense);  // stiff
  EXPECT_EQ(dense.result.linear_solver, ks::LinearSolver::dense);  // auto, 2 states
  EXPECT_EQ(krylov.result.linear_solver, ks::LinearSolver::krylov);
  EXPECT_EQ(ks::resolve_linear_solver(ks::LinearSolver::dense, 100000), ks::LinearSolver::dense);
  EXPECT_EQ(ks::resolve_linear_solver(ks::LinearSolver::krylov, 1), ks::LinearSolver::krylov);
}

namespace {
// n decoupled decays ẏ_i = −a_i y_i, a_i from 1 to a_max /s (log-spaced): J's spectral radius is
// a_max.
class Decays : public ks::OdeProblem {
 public:
  Decays(int n, double a_max) : a_(static_cast<std::size_t>(n)) {
    for (int i = 0; i < n; ++i) a_[static_cast<std::size_t>(i)] = std::pow(a_max, i / (n - 1.0));
  }
  int size() const override { return static_cast<int>(a_.size()); }
  void initial_state(double* y0) const override { std::fill(y0, y0 + size(), 1.0); }
  void rhs(double, const double* y, double* ydot) override {
    for (int i = 0; i < size(); ++i) ydot[i] = -a_[static_cast<std::size_t>(i)] * y[i];
  }
  bool has_jacobian() const override { return true; }
  void jacobian(double, const double*, const double*, double* J) override {
    std::fill(J, J + size() * size(), 0.0);
    for (int i = 0; i < size(); ++i) J[i + i * size()] = -a_[static_cast<std::size_t>(i)];
  }
  bool has_jacobian_times() const override { return true; }
  void jacobian_times(double, const double*, const double*, const double* v, double* Jv) override {
    for (int i = 0; i < size(); ++i) Jv[i] = -a_[static_cast<std::size_t>(i)] * v[i];
  }
  bool jacobian_times_cheap() const override { return cheap_; }
  bool cheap_ = true;

 private:
  std::vector<double> a_;
};
}  // namespace

// auto: krylov for a large problem whose Jacobian has a small spectral radius, dense for a small
// or a stiff one (the radius estimated by power iteration at t0, exact J v or differences), and
// dense for one whose exact J v costs far more than its right-hand side unless J v is a
// difference quotient.
TEST(Integrator, AutoLinearSolverBySizeAndStiffness) {
  const std::vector<double> times{0, 0.1};
  auto noop = [](int, double, const double*, const double* const*) {};
  ks::SolverOptions o;
  for (const ks::JacobianKind j : {ks::JacobianKind::exact, ks::JacobianKind::dq}) {
    o.jacobian = j;
    Decays slow(ks::kKrylovMinStates, 0.1 * ks::kKrylovMaxRate), stiff(ks::kKrylovMinStates, 10 * ks::kKrylovMaxRate),
        small(ks::kKrylovMinStates - 1, 1.0);
    const ks::IntegrationResult a = ks::integrate(slow, o, times, noop), b = ks::integrate(stiff, o, times, noop),
                                c = ks::integrate(small, o, times, noop);
    ASSERT_TRUE(a.ok() && b.ok() && c.ok()) << a.message << b.message << c.message;
    EXPECT_EQ(a.linear_solver, ks::LinearSolver::krylov);
    EXPECT_EQ(b.linear_solver, ks::LinearSolver::dense);
    EXPECT_EQ(c.linear_solver, ks::LinearSolver::dense);
    slow.cheap_ = false;
    const ks::IntegrationResult d = ks::integrate(slow, o, times, noop);
    ASSERT_TRUE(d.ok()) << d.message;
    EXPECT_EQ(d.linear_solver, j == ks::JacobianKind::exact ? ks::LinearSolver::dense : ks::LinearSolver::krylov);
  }
  o.method = ks::Method::dop853;
  Decays slow(ks::kKrylovMinStates, 1.0);
  EXPECT_EQ(ks::integrate(slow, o, times, noop).linear_solver, ks::LinearSolver::automatic);  // no Newton
}

// sensitivity.method auto: stacked where the problem allows it, else staggered with projection and
// simultaneous without; explicit choices kept.
TEST(Integrator, AutoSensitivityMethod) {
  using SM = ks::SensitivityMethod;
  for (const bool projection : {false, true})
    EXPECT_EQ(ks::resolve_sensitivity_method(SM::automatic, projection, true), SM::stacked);
  EXPECT_EQ(ks::resolve_sensitivity_method(SM::automatic, true, false), SM::staggered);
  EXPECT_EQ(ks::resolve_sensitivity_method(SM::automatic, false, false), SM::simultaneous);
  for (const SM m : {SM::simultaneous, SM::staggered, SM::staggered1, SM::stacked})
    for (const bool projection : {false, true})
      for (const bool stackable : {false, true})
        EXPECT_EQ(ks::resolve_sensitivity_method(m, projection, stackable), m);
  EXPECT_EQ(ks::SolverOptions{}.sensitivity_method, SM::automatic);

  const std::vector<double> times{0, 0.5, 1};
  auto noop = [](int, double, const double*, const double* const*) {};
  ks::SolverOptions o;
  Oscillator a(1, 0, 1, 0.4, 4);
  EXPECT_EQ(ks::integrate(a, o, times, noop).sensitivity_method, SM::stacked);
  o.sensitivity_method = SM::staggered1;
  EXPECT_EQ(ks::integrate(a, o, times, noop).sensitivity_method, SM::staggered1);
  // What stacking needs and this configuration lacks: auto takes the module, an explicit choice is an error.
  for (const auto& [what, configure] :
       std::vector<std::pair<std::string, std::function<void(ks::SolverOptions&)>>>{
           {"exact Jacobian", [](ks::SolverOptions& p) { p.jacobian = ks::JacobianKind::dq; }},
           {"exact sensitivity", [](ks::SolverOptions& p) { p.sens_rhs = ks::SensitivityRhs::dq; }},
           {"linear_solver dense", [](ks::SolverOptions& p) { p.linear_solver = ks::LinearSolver::krylov; }}}) {
    ks::SolverOptions lacking;
    configure(lacking);
    EXPECT_EQ(ks::integrate(a, lacking, times, noop).sensitivity_method, SM::simultaneous) << what;
    lacking.sensitivity_method = SM::stacked;
    try {
      ks::integrate(a, lacking, times, noop);
      ADD_FAILURE() << "stacked without the " << what << " was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("solver.sensitivity.method = stacked"), std::string::npos) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  }
}

// ---------- 2, 3, 4. failures are statuses ----------

namespace {
// The oscillator with a failure injected into one of its callbacks.
class Faulty : public Oscillator {
 public:
  enum class Fault {
    none,
    throw_rhs_after_t1,
    throw_sens_rhs_after_t1,
    throw_jacobian,
    nan_after_t1,
    nan_at_t0,
    nan_on_calls_20_to_22,
    throw_when_perturbed,
    recoverable_on_calls_20_to_22,  // e.g. a mass matrix that is singular at a trial state
    recoverable_after_t1,
    recoverable_at_t0
  };
  explicit Faulty(Fault f) : fault(f) {}
  void rhs(double t, const double* y, double* ydot) override {
    Oscillator::rhs(t, y, ydot);
    if (fault == Fault::throw_rhs_after_t1 && t > 1) throw std::runtime_error("spring 'k1' broke");
    if (fault == Fault::nan_after_t1 && t > 1) ydot[1] = std::numeric_limits<double>::quiet_NaN();
    if (fault == Fault::nan_at_t0) ydot[0] = std::numeric_limits<double>::quiet_NaN();
    if (fault == Fault::nan_on_calls_20_to_22 && rhs_calls >= 20 && rhs_calls <= 22) {
      ydot[1] = std::numeric_limits<double>::infinity();
    }
    if (fault == Fault::throw_when_perturbed && t > 1 && parameters()[3] != 0.4) {
      throw std::runtime_error("perturbed c");
    }
    if ((fault == Fault::recoverable_on_calls_20_to_22 && rhs_calls >= 20 && rhs_calls <= 22) ||
        (fault == Fault::recoverable_after_t1 && t > 1) || (fault == Fault::recoverable_at_t0 && t == 0))
      throw ks::RecoverableError("mass matrix is not positive definite");
  }
  void sensitivity_rhs(double t, const double* y, const double* ydot, int i, const double* s,
                       double* sdot) override {
    if (fault == Fault::throw_sens_rhs_after_t1 && t > 1)
      throw std::logic_error("dual number overflow");
    Oscillator::sensitivity_rhs(t, y, ydot, i, s, sdot);
  }
  void jacobian(double t, const double* y, const double* ydot, double* J) override {
    if (fault == Fault::throw_jacobian) throw 42;  // not even a std::exception
    Oscillator::jacobian(t, y, ydot, J);
  }
  void jacobian_times(double t, const double* y, const double* ydot, const double* v, double* Jv) override {
    if (fault == Fault::throw_jacobian) throw std::runtime_error("tangent lost");
    Oscillator::jacobian_times(t, y, ydot, v, Jv);
  }
  Fault fault;
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}
const std::vector<double> kTimes{0, 0.5, 1, 2, 5, 10};

// A run expected to fail; its message goes to the log so that a reader sees what a user would.
Trajectory run_showing_message(const ks::SolverOptions& o, ks::OdeProblem& problem,
                               const std::vector<double>& times = kTimes) {
  Trajectory tr = run(o, problem, times);
  std::printf("[ message  ] %s\n", tr.result.message.c_str());
  return tr;
}

// `fault` spoils calls 20–22 only: CVODES retries those steps smaller (three recoverable
// callbacks) and ends where the fault-free run does. *message is the faulty run's message.
void expect_recovered_like_fault_free(Faulty::Fault fault, std::string* message = nullptr) {
  Faulty f(fault);
  f.with_sens = false;
  Oscillator clean;
  clean.with_sens = false;
  const Trajectory tr = run(tight(), f, kTimes);
  const Trajectory ref = run(tight(), clean, kTimes);
  ASSERT_TRUE(tr.result.ok()) << tr.result.message;
  if (message) *message = tr.result.message;
  EXPECT_EQ(tr.result.stats.callback_recoverable, 3);
  EXPECT_LT(max_abs_diff(tr, ref), 1e-8);
}
}  // namespace

TEST(IntegratorFailure, ThrowingRhsIsAStatusWithTheMessage) {
  Faulty f(Faulty::Fault::throw_rhs_after_t1);
  const Trajectory tr = run_showing_message(tight(), f);
  EXPECT_EQ(tr.result.status, CV_RHSFUNC_FAIL);
  EXPECT_TRUE(contains(tr.result.message, "CV_RHSFUNC_FAIL")) << tr.result.message;
  EXPECT_TRUE(contains(tr.result.message, "spring 'k1' broke")) << tr.result.message;
  // CVODES steps past an output time and interpolates back, so the step that crosses t = 1
  // (while integrating towards the output t = 1) fails: t = 1 itself is not recorded.
  EXPECT_EQ(tr.result.outputs_recorded, 2);  // t = 0, 0.5
  EXPECT_EQ(tr.y.size(), 2u);
  EXPECT_GT(tr.result.t_fail, 0.9);
  EXPECT_LT(tr.result.t_fail, 1.0);
  EXPECT_GT(tr.result.stats.steps, 0);
}

TEST(IntegratorFailure, ThrowingSensitivityRhs) {
  // CVODES's sensitivity module calls the sensitivity RHS on its own; stacked, it is part of the RHS.
  for (const auto& [method, status] : {std::pair{ks::SensitivityMethod::simultaneous, CV_SRHSFUNC_FAIL},
                                       std::pair{ks::SensitivityMethod::stacked, CV_RHSFUNC_FAIL}}) {
    Faulty f(Faulty::Fault::throw_sens_rhs_after_t1);
    ks::SolverOptions o = tight();
    o.sensitivity_method = method;
    const Trajectory tr = run_showing_message(o, f);
    EXPECT_EQ(tr.result.status, status);
    EXPECT_TRUE(contains(tr.result.message, "dual number overflow")) << tr.result.message;
  }
}

TEST(IntegratorFailure, ThrowingJacobianNonStdException) {
  Faulty f(Faulty::Fault::throw_jacobian);
  const Trajectory tr = run_showing_message(tight(), f);
  EXPECT_EQ(tr.result.status, CV_LSETUP_FAIL);
  EXPECT_TRUE(contains(tr.result.message, "jacobian threw")) << tr.result.message;
  EXPECT_TRUE(contains(tr.result.message, "unknown exception")) << tr.result.message;
}

TEST(IntegratorFailure, ThrowingJacobianTimesWithKrylov) {
  Faulty f(Faulty::Fault::throw_jacobian);
  ks::SolverOptions o = tight();
  o.linear_solver = ks::LinearSolver::krylov;
  const Trajectory tr = run_showing_message(o, f);
  EXPECT_LT(tr.result.status, 0);
  EXPECT_TRUE(contains(tr.result.message, "jacobian_times threw")) << tr.result.message;
  EXPECT_TRUE(contains(tr.result.message, "tangent lost")) << tr.result.message;
}

TEST(IntegratorFailure, TransientNanIsRecovered) {
  std::string message;
  ASSERT_NO_FATAL_FAILURE(expect_recovered_like_fault_free(Faulty::Fault::nan_on_calls_20_to_22, &message));
  EXPECT_TRUE(message.empty());
}

TEST(IntegratorFailure, PersistentNanFailsWithMessage) {
  // CVODES shrinks the step after each recoverable failure and keeps taking the ever shorter
  // steps that end before t = 1 (a Zeno approach), until the step budget runs out.
  Faulty f(Faulty::Fault::nan_after_t1);
  ks::SolverOptions o = tight();
  o.max_steps = 5000;
  const Trajectory tr = run(o, f, kTimes);
  std::printf("[ message  ] %s (recoverable callbacks: %ld)\n", tr.result.message.c_str(),
              tr.result.stats.callback_recoverable);
  EXPECT_LT(tr.result.status, 0);
  EXPECT_TRUE(contains(tr.result.message, "rhs returned a non-finite value")) << tr.result.message;
  EXPECT_GT(tr.result.stats.callback_recoverable, 1);
  EXPECT_EQ(tr.result.status, CV_TOO_MUCH_WORK);
  EXPECT_GE(tr.result.outputs_recorded, 2);  // t = 0, 0.5 and (when the approach reaches
  EXPECT_LE(tr.result.outputs_recorded, 3);  // t = 1 to the last bit) t = 1
  EXPECT_GT(tr.result.t_fail, 0.9);
  EXPECT_LE(tr.result.t_fail, 1.0);
}

TEST(IntegratorFailure, NanAtInitialTime) {
  Faulty f(Faulty::Fault::nan_at_t0);
  const Trajectory tr = run_showing_message(tight(), f);
  EXPECT_EQ(tr.result.status, CV_FIRST_RHSFUNC_ERR);
  EXPECT_TRUE(contains(tr.result.message, "non-finite")) << tr.result.message;
  EXPECT_EQ(tr.result.outputs_recorded, 1);  // the initial state is still recorded
}

// A state where f cannot be evaluated (RecoverableError, e.g. a singular mass matrix at a trial
// state) is CVODES's recoverable +1: the step is retried smaller and the integration goes on.
TEST(IntegratorFailure, RecoverableErrorRetriesTheStep) {
  expect_recovered_like_fault_free(Faulty::Fault::recoverable_on_calls_20_to_22);
}

namespace {
// ∫ x² dt alongside the oscillator; calls 20–22 cannot be evaluated (RecoverableError) when
// `faulty`, as an integral output of a trial state where u̇ is undefined would.
class SquareIntegral : public ks::OdeQuadrature {
 public:
  explicit SquareIntegral(bool faulty) : faulty_(faulty) {}
  int size() const override { return 1; }
  void rhs(double, const double* y, double* qdot) override {
    ++calls_;
    if (faulty_ && calls_ >= 20 && calls_ <= 22) throw ks::RecoverableError("integrand undefined");
    qdot[0] = y[0] * y[0];
  }
  void sensitivity_rhs(double, const double*, int, const double* const*, double* const*) override {}
  void record(int, double, const double* q, const double* const*) override { last = q[0]; }
  double last = 0;

 private:
  bool faulty_;
  long calls_ = 0;
};
}  // namespace

// The same holds for an integral output: its RecoverableError is +1 (a smaller step), not a failure.
TEST(IntegratorFailure, RecoverableErrorInAQuadratureRetriesTheStep) {
  Oscillator osc, clean;
  osc.with_sens = clean.with_sens = false;
  SquareIntegral faulty(true), ok(false);
  ks::Integrator a(tight()), b(tight());
  const auto noop = [](int, double, const double*, const double* const*) {};
  const ks::IntegrationResult r = a.integrate(osc, kTimes, noop, &faulty);
  const ks::IntegrationResult ref = b.integrate(clean, kTimes, noop, &ok);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_TRUE(ref.ok()) << ref.message;
  EXPECT_EQ(r.stats.callback_recoverable, 3);
  EXPECT_NEAR(faulty.last, ok.last, 1e-7 * std::abs(ok.last));
}

// Only when smaller steps do not help does the sample fail, with the reason in its message.
TEST(IntegratorFailure, PersistentRecoverableErrorFailsWithItsMessage) {
  Faulty f(Faulty::Fault::recoverable_after_t1);
  ks::SolverOptions o = tight();
  o.max_steps = 5000;
  const Trajectory tr = run_showing_message(o, f);
  EXPECT_LT(tr.result.status, 0);
  EXPECT_GT(tr.result.stats.callback_recoverable, 1);
  EXPECT_TRUE(contains(tr.result.message, "rhs failed at t = 1")) << tr.result.message;
  EXPECT_TRUE(contains(tr.result.message, "mass matrix is not positive definite")) << tr.result.message;
  Faulty at_t0(Faulty::Fault::recoverable_at_t0);
  const Trajectory tr0 = run(tight(), at_t0, kTimes);
  EXPECT_EQ(tr0.result.status, CV_FIRST_RHSFUNC_ERR);
  EXPECT_TRUE(contains(tr0.result.message, "mass matrix is not positive definite")) << tr0.result.message;
}

TEST(IntegratorFailure, MaxStepsIsATotalBudget) {
  ks::SolverOptions o = tight();
  o.max_steps = 50;
  // Many outputs: CVODES's own mxstep counts per output interval and would never trigger.
  std::vector<double> times;
  for (int k = 0; k <= 1000; ++k) times.push_back(0.01 * k);
  Oscillator osc;
  const Trajectory tr = run_showing_message(o, osc, times);
  EXPECT_EQ(tr.result.status, CV_TOO_MUCH_WORK);
  EXPECT_TRUE(contains(tr.result.message, "CV_TOO_MUCH_WORK")) << tr.result.message;
  EXPECT_EQ(tr.result.stats.steps, 50);
  EXPECT_GT(tr.result.outputs_recorded, 1);
  EXPECT_LT(tr.result.outputs_recorded, 1001);
  EXPECT_GE(tr.result.t_fail, tr.t.back());         // failed between the last recorded output
  EXPECT_LT(tr.result.t_fail, times[tr.t.size()]);  // and the next one
}

TEST(IntegratorFailure, MaxStepsInOneInterval) {
  ks::SolverOptions o = tight();
  o.max_steps = 20;
  Oscillator osc;
  const Trajectory tr = run_showing_message(o, osc, {0, 10});
  EXPECT_EQ(tr.result.status, CV_TOO_MUCH_WORK);
  EXPECT_TRUE(contains(tr.result.message, "mxstep")) << tr.result.message;
  EXPECT_EQ(tr.result.stats.steps, 20);
}

TEST(IntegratorFailure, DqParametersRestoredAfterFailure) {
  ks::SolverOptions o = tight();
  o.sens_rhs = ks::SensitivityRhs::dq;
  o.rtol = 1e-8;
  Faulty f(Faulty::Fault::throw_when_perturbed);
  const Trajectory tr = run_showing_message(o, f);
  EXPECT_EQ(tr.result.status, CV_SRHSFUNC_FAIL);
  EXPECT_TRUE(contains(tr.result.message, "perturbed c")) << tr.result.message;
  EXPECT_EQ(f.parameters()[2], 1.0);
  EXPECT_EQ(f.parameters()[3], 0.4);
  EXPECT_EQ(f.parameters()[4], 4.0);
}

// ---------- 6. reuse ----------

TEST(Integrator, ReuseEqualsFreshBitForBit) {
  const std::vector<double> times{0, 0.5, 1, 2, 5, 10};
  for (auto method : {ks::SensitivityMethod::simultaneous, ks::SensitivityMethod::staggered,
                      ks::SensitivityMethod::staggered1, ks::SensitivityMethod::stacked}) {
    for (auto rhs : {ks::SensitivityRhs::exact, ks::SensitivityRhs::dq}) {
      if (method == ks::SensitivityMethod::stacked && rhs == ks::SensitivityRhs::dq) continue;  // not offered
      ks::SolverOptions o = tight();
      o.sensitivity_method = method;
      o.sens_rhs = rhs;
      if (rhs == ks::SensitivityRhs::dq) o.rtol = 1e-8;
      Oscillator a1(1, 0, 1, 0.4, 4), b1(0.5, -0.3, 1.3, 0.9, 2.5), a2 = a1, b2 = b1;
      Faulty bad(Faulty::Fault::throw_rhs_after_t1);
      ks::Integrator reused(o);
      const Trajectory ra = run(reused, a1, times);
      const Trajectory rbad = run(reused, bad, times);  // a failed sample in between
      const Trajectory rb = run(reused, b1, times);
      const Trajectory ra_again = run(reused, a1, times);
      const Trajectory fa = run(o, a2, times);
      const Trajectory fb = run(o, b2, times);
      ASSERT_TRUE(ra.result.ok() && rb.result.ok() && fa.result.ok() && fb.result.ok());
      EXPECT_LT(rbad.result.status, 0);
      EXPECT_EQ(max_abs_diff(ra, fa), 0.0);
      EXPECT_EQ(max_abs_diff(rb, fb), 0.0);
      EXPECT_EQ(max_abs_diff(ra_again, fa), 0.0);
      EXPECT_EQ(rb.result.stats.steps, fb.result.stats.steps);
      EXPECT_EQ(rb.result.stats.rhs_evals, fb.result.stats.rhs_evals);
      EXPECT_EQ(rb.result.stats.sens_rhs_evals, fb.result.stats.sens_rhs_evals);
      EXPECT_EQ(rb.result.stats.jac_evals, fb.result.stats.jac_evals);
      EXPECT_GT(max_abs_diff(ra, rb), 0.1);  // the two samples really differ
    }
  }
}

TEST(Integrator, ReuseAcrossShapesRebuilds) {
  const std::vector<double> times{0, 1, 2};
  ks::Integrator integ(tight());
  Oscillator with, without, without_fresh;
  without.with_sens = false;
  without_fresh.with_sens = false;
  const Trajectory a = run(integ, with, times);
  const Trajectory b = run(integ, without, times);
  const Trajectory c = run(tight(), without_fresh, times);
  ASSERT_TRUE(a.result.ok() && b.result.ok());
  EXPECT_EQ(a.s[1].size(), 5u);
  EXPECT_TRUE(b.s[1].empty());
  EXPECT_EQ(max_abs_diff(b, c), 0.0);
}

// ---------- configuration errors throw ----------

namespace {
class NoDerivatives : public ks::OdeProblem {
 public:
  int size() const override { return 1; }
  void initial_state(double* y0) const override { y0[0] = 1; }
  void rhs(double, const double* y, double* ydot) override { ydot[0] = -y[0]; }
  int num_sensitivities() const override { return 1; }
  void initial_sensitivity(int, double* s0) const override { s0[0] = 1; }
};
}  // namespace

TEST(IntegratorConfig, InvalidOptionsAndMissingCapabilitiesThrow) {
  ks::SolverOptions bad;
  bad.rtol = -1;
  EXPECT_THROW(ks::Integrator{bad}, std::invalid_argument);
  bad = {};
  bad.max_order = 6;  // BDF max is 5
  EXPECT_THROW(ks::Integrator{bad}, std::invalid_argument);

  NoDerivatives p;
  const std::vector<double> times{0, 1};
  auto noop = [](int, double, const double*, const double* const*) {};
  try {
    ks::integrate(p, ks::SolverOptions{}, times, noop);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "jacobian")) << e.what();
  }
  ks::SolverOptions o;
  o.jacobian = ks::JacobianKind::dq;
  ks::SolverOptions krylov;
  krylov.linear_solver = ks::LinearSolver::krylov;
  try {
    ks::integrate(p, krylov, times, noop);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "Jacobian-vector product")) << e.what();
  }
  EXPECT_THROW(ks::integrate(p, o, times, noop), std::invalid_argument);  // exact sens RHS missing
  o.sens_rhs = ks::SensitivityRhs::dq;
  EXPECT_THROW(ks::integrate(p, o, times, noop), std::invalid_argument);  // no dq_parameters()
  o.sens_rhs = ks::SensitivityRhs::exact;
  const std::vector<double> not_increasing{0, 1, 1};
  Oscillator osc;
  EXPECT_THROW(ks::integrate(osc, ks::SolverOptions{}, not_increasing, noop),
               std::invalid_argument);
  EXPECT_THROW(ks::integrate(osc, ks::SolverOptions{}, std::vector<double>{}, noop),
               std::invalid_argument);
  ks::SolverOptions wrong_atol;
  wrong_atol.atol_per_state = {1e-10, 1e-10, 1e-10};
  EXPECT_THROW(ks::integrate(osc, wrong_atol, times, noop), std::invalid_argument);
}

TEST(IntegratorConfig, PerStateAtolAndSingleOutput) {
  ks::SolverOptions o = tight();
  o.atol_per_state = {1e-12, 1e-11};
  Oscillator osc;
  const Trajectory one = run(o, osc, {0.0});
  ASSERT_TRUE(one.result.ok());
  EXPECT_EQ(one.result.outputs_recorded, 1);
  const auto ref = closed_form_reference();
  const Trajectory tr = run(o, osc, reference_times(ref));
  ASSERT_TRUE(tr.result.ok());
  EXPECT_LT(max_rel_error(tr, ref), 3e-8);
}

// ---------- projection (CVodeSetProjFn) ----------

namespace {
// The planar pendulum of cvsPendulum_dns.c in Cartesian coordinates y = (x, y, ẋ, ẏ), unit
// length, gravity g along −y, with its projection onto x² + y² = 1, x ẋ + y ẏ = 0.
// One sensitivity, to g.
class CartesianPendulum : public ks::OdeProblem {
 public:
  double g = 13.75;
  int size() const override { return 4; }
  void initial_state(double* y) const override {
    y[0] = 1;
    y[1] = y[2] = y[3] = 0;
  }
  void rhs(double, const double* s, double* f) override {
    const double tension = s[2] * s[2] + s[3] * s[3] - g * s[1];
    f[0] = s[2];
    f[1] = s[3];
    f[2] = -s[0] * tension;
    f[3] = -s[1] * tension - g;
  }
  int num_sensitivities() const override { return with_sens ? 1 : 0; }
  void initial_sensitivity(int, double* s0) const override { s0[0] = s0[1] = s0[2] = s0[3] = 0; }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double, const double* y, const double*, int, const double* s,
                       double* sdot) override {
    const double tension = y[2] * y[2] + y[3] * y[3] - g * y[1];
    const double dtension = 2 * y[2] * s[2] + 2 * y[3] * s[3] - g * s[1] - y[1];  // incl. ∂/∂g
    sdot[0] = s[2];
    sdot[1] = s[3];
    sdot[2] = -s[0] * tension - y[0] * dtension;
    sdot[3] = -s[1] * tension - y[1] * dtension - 1;
  }
  std::vector<double> sensitivity_scales() const override { return {g}; }
  bool has_projection() const override { return true; }
  int project(double, const double* s, double* corr, double, double* err) override {
    const double r = std::hypot(s[0], s[1]), x = s[0] / r, y = s[1] / r;
    corr[0] = x - s[0];
    corr[1] = y - s[1];
    corr[2] = s[2] * y * y - s[3] * x * y - s[2];  // velocity projected on the tangent
    corr[3] = -s[2] * x * y + s[3] * x * x - s[3];
    if (err != nullptr) {  // P err
      const double e[4] = {err[0], err[1], err[2], err[3]};
      err[0] = y * y * e[0] - x * y * e[1];
      err[1] = -x * y * e[0] + x * x * e[1];
      err[2] = y * y * e[2] - x * y * e[3];
      err[3] = -x * y * e[2] + x * x * e[3];
    }
    return 0;
  }
  bool with_sens = true;
};

// The same pendulum as an ODE in the angle θ from −y: θ̈ = −g sin θ, x = sin θ, y = −cos θ.
class AnglePendulum : public ks::OdeProblem {
 public:
  double g = 13.75;
  int size() const override { return 2; }
  void initial_state(double* y) const override {
    y[0] = std::acos(0.0);  // π/2: x = 1, y = 0
    y[1] = 0;
  }
  void rhs(double, const double* y, double* f) override {
    f[0] = y[1];
    f[1] = -g * std::sin(y[0]);
  }
  bool has_jacobian() const override { return true; }
  void jacobian(double, const double* y, const double*, double* J) override {
    J[0] = 0;
    J[1] = -g * std::cos(y[0]);
    J[2] = 1;
    J[3] = 0;
  }
  int num_sensitivities() const override { return 1; }
  void initial_sensitivity(int, double* s0) const override { s0[0] = s0[1] = 0; }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double, const double* y, const double*, int, const double* s,
                       double* sdot) override {
    sdot[0] = s[1];
    sdot[1] = -g * std::cos(y[0]) * s[0] - std::sin(y[0]);
  }
  std::vector<double> sensitivity_scales() const override { return {g}; }
};
}  // namespace

// Projection keeps the state on the constraint manifold. CVODES 6.4 accepts projection together
// with forward sensitivities (no error), but projects only y: the sensitivities are integrated
// unprojected and drift off the tangent space (docs/solve.md has the measured figures).
TEST(IntegratorProjection, KeepsConstraintAndRunsWithSensitivities) {
  std::vector<double> times;
  for (int k = 0; k <= 81; ++k) times.push_back(0.37 * k);  // 30 s, ~15 periods
  ks::SolverOptions ref_options;
  ref_options.rtol = 1e-12;
  ref_options.atol = 1e-14;
  AnglePendulum angle;
  const Trajectory ref = run(ref_options, angle, times);
  ASSERT_TRUE(ref.result.ok()) << ref.result.message;

  ks::SolverOptions o;  // rtol 1e-8, atol 1e-10
  o.jacobian = ks::JacobianKind::dq;
  for (bool with_sens : {false, true}) {
    CartesianPendulum pendulum;
    pendulum.with_sens = with_sens;
    const Trajectory tr = run(o, pendulum, times);
    ASSERT_TRUE(tr.result.ok()) << tr.result.message;
    EXPECT_GT(tr.result.stats.projections, 0);
    double drift = 0, x_err = 0, s_err = 0, s_max = 0, tangent = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const auto& y = tr.y[k];
      drift = std::max(drift, std::abs(y[0] * y[0] + y[1] * y[1] - 1));
      x_err = std::max(x_err, std::abs(y[0] - std::sin(ref.y[k][0])));
      if (!with_sens) continue;
      const double dx_dg = std::cos(ref.y[k][0]) * ref.s[k][0][0];
      s_err = std::max(s_err, std::abs(tr.s[k][0][0] - dx_dg));
      s_max = std::max(s_max, std::abs(dx_dg));
      tangent = std::max(tangent, std::abs(y[0] * tr.s[k][0][0] + y[1] * tr.s[k][0][1]));
    }
    std::printf(
        "[ measure  ] projection, sens %d: |g(y)| %.2e, |x - ref| %.2e, |dx/dg - ref| %.2e "
        "(max |dx/dg| %.2f), |G s| %.2e\n",
        with_sens, drift, x_err, s_err, s_max, tangent);
    EXPECT_LT(drift, 1e-8);
    EXPECT_LT(x_err, 1e-3);
    if (with_sens) {
      EXPECT_LT(s_err, 1e-2 * s_max);
    }
  }
}

TEST(IntegratorProjection, AdamsIsRejected) {
  ks::SolverOptions o;
  o.method = ks::Method::adams;
  CartesianPendulum pendulum;
  EXPECT_THROW(run(o, pendulum, {0, 1}), std::invalid_argument);
}

}  // namespace KANESENS_UNITY_ID
