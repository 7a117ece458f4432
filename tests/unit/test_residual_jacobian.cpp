// The Jacobian by inverse dynamics (KaneProblem::JacobianMethod::residual: one
// multi-tangent pass of Kane's equations as a residual at the accelerations of ydot, solved with
// M's and A M⁻¹ Aᵀ's value factors, dynamics/inverse_dynamics.hpp) must equal the whole right-hand
// side's multi-tangent passes to round-off, and the central differences of the right-hand side to
// their truncation error, on planar and 3-D trees (chain and branched: dense and tree factor),
// quaternions, multipliers with projection and with Baumgarte terms, rolling, general
// constraints; and the method must actually be taken there. Where it does not apply — the
// embedding, redundant constraint rows, a ydot that is not f(t, y) — jacobian() must take the
// whole right-hand side and say so.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"

namespace {

using namespace kanesens::testing;
using Method = KaneProblem::JacobianMethod;

ConstraintOptions with(ConstraintOptions::Formulation f, ConstraintOptions::Stabilization s) {
  ConstraintOptions c;
  c.formulation = f;
  c.stabilization = s;
  return c;
}

Model load(const std::string& path) { return build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/" + path)); }

// A state near the problem's initial state, with random speeds; ydot = f(t, y).
std::vector<double> test_state(KaneProblem& p, std::mt19937& rng, double spread) {
  std::vector<double> y(static_cast<std::size_t>(p.size()));
  p.initial_state(y.data());
  std::uniform_real_distribution<double> u(-spread, spread);
  for (double& v : y) v += u(rng);
  return y;
}

double max_abs(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s = std::max(s, std::abs(x));
  return s;
}

struct Case {
  std::string scene;
  ConstraintOptions constraints;
};

TEST(ResidualJacobian, MatchesWholeRhsPassesAndDifferences) {
  using F = ConstraintOptions::Formulation;
  using St = ConstraintOptions::Stabilization;
  const std::vector<Case> cases = {
      {"configs/nlink_chain_4.yaml", {}},
      {"bench/configs/nlink_chain_16.yaml", {}},
      {"configs/arm_3d.yaml", {}},
      {"configs/spinning_top.yaml", {}},
      {"configs/free_body.yaml", {}},
      {"configs/cart_double_pendulum.yaml", {}},
      {"configs/four_bar.yaml", with(F::multipliers, St::projection)},
      {"configs/four_bar.yaml", with(F::multipliers, St::baumgarte)},
      {"configs/rolling_disc.yaml", with(F::multipliers, St::baumgarte)},
      {"configs/rolling_disc.yaml", with(F::multipliers, St::projection)},
      {"configs/andrews.yaml", with(F::multipliers, St::projection)},
      {"configs/whipple_bicycle.yaml", with(F::multipliers, St::projection)},
      {"configs/slider_crank.yaml", with(F::multipliers, St::baumgarte)},
  };
  std::mt19937 rng(17);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    const Model m = load(c.scene);
    KaneProblem p(m, {}, c.constraints);
    p.set_sample(SampleInputs(m));
    const int n = p.size();
    const std::vector<double> y = test_state(p, rng, 0.05);
    std::vector<double> ydot(static_cast<std::size_t>(n));
    p.rhs(0.1, y.data(), ydot.data());

    std::vector<double> J(static_cast<std::size_t>(n) * n), Jw(J.size());
    p.jacobian(0.1, y.data(), ydot.data(), J.data());
    EXPECT_EQ(p.last_jacobian_method(), Method::residual);
    p.set_jacobian_method(Method::whole_rhs);
    p.jacobian(0.1, y.data(), ydot.data(), Jw.data());
    EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs);
    double err = 0;
    for (std::size_t k = 0; k < J.size(); ++k) err = std::max(err, std::abs(J[k] - Jw[k]));
    const double scale = std::max(1.0, max_abs(Jw));
    EXPECT_LT(err / scale, 1e-12) << "residual vs whole right-hand side";

    // Central differences, column by column, relative to J's size.
    double efd = 0;
    const double h = 1e-6;
    std::vector<double> yp(y), fp(ydot), fm(ydot);
    for (int j = 0; j < n; ++j) {
      const std::size_t js = static_cast<std::size_t>(j);
      yp[js] = y[js] + h;
      p.rhs(0.1, yp.data(), fp.data());
      yp[js] = y[js] - h;
      p.rhs(0.1, yp.data(), fm.data());
      yp[js] = y[js];
      for (int r = 0; r < n; ++r) {
        const double Jrj = J[js * n + static_cast<std::size_t>(r)];
        efd = std::max(efd, std::abs((fp[static_cast<std::size_t>(r)] - fm[static_cast<std::size_t>(r)]) / (2 * h) - Jrj) / scale);
      }
    }
    EXPECT_LT(efd, 1e-6) << "residual Jacobian vs central differences";

    std::printf("%s: residual J vs whole %.2e, vs differences %.2e (n = %d)\n", c.scene.c_str(), err / scale, efd, n);
  }
}

// Where the residual form does not apply, jacobian() takes the whole right-hand side.
TEST(ResidualJacobian, FallsBackWhereItDoesNotApply) {
  std::mt19937 rng(3);
  auto jacobian_of = [&](KaneProblem& p, const std::vector<double>& y, const std::vector<double>& ydot) {
    std::vector<double> J(y.size() * y.size());
    p.jacobian(0.1, y.data(), ydot.data(), J.data());
    return J;
  };
  {
    SCOPED_TRACE("embedding");
    const Model m = load("configs/four_bar.yaml");
    KaneProblem p(m, {}, with(ConstraintOptions::Formulation::embedding, ConstraintOptions::Stabilization::projection));
    p.set_sample(SampleInputs(m));
    const std::vector<double> y = test_state(p, rng, 0.01);
    std::vector<double> ydot(y.size());
    p.rhs(0.1, y.data(), ydot.data());
    jacobian_of(p, y, ydot);
    EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs);
  }
  {
    // A ydot that is not f(t, y): the residual's value does not vanish, so the result must be the
    // whole right-hand side's (which does not use ydot), not a Jacobian at other accelerations.
    SCOPED_TRACE("inconsistent ydot");
    for (const char* scene : {"configs/arm_3d.yaml", "configs/four_bar.yaml"}) {
      const Model m = load(scene);
      KaneProblem p(m, {});
      p.set_sample(SampleInputs(m));
      const std::vector<double> y = test_state(p, rng, 0.05);
      std::vector<double> ydot(y.size());
      p.rhs(0.1, y.data(), ydot.data());
      const std::vector<double> J = jacobian_of(p, y, ydot);
      EXPECT_EQ(p.last_jacobian_method(), Method::residual);
      std::vector<double> wrong(ydot);
      wrong.back() += 1e-3 * (1 + std::abs(wrong.back()));
      const std::vector<double> Jw = jacobian_of(p, y, wrong);
      EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs) << scene;
      double err = 0;
      for (std::size_t k = 0; k < J.size(); ++k) err = std::max(err, std::abs(J[k] - Jw[k]));
      EXPECT_LT(err / std::max(1.0, max_abs(J)), 1e-12) << scene;
    }
  }
  {
    // The parallelogram four-bar with all links collinear (every angle 0): the loop's x row
    // vanishes, A M⁻¹ Aᵀ loses rank and λ is the minimum-norm one, whose derivative is not the
    // residual solve.
    SCOPED_TRACE("redundant rows");
    const Model m = load("configs/parallelogram_four_bar.yaml");
    KaneProblem p(m, {});
    p.set_sample(SampleInputs(m));
    std::vector<double> y(static_cast<std::size_t>(p.size())), ydot(y.size());
    p.initial_state(y.data());
    for (int i = 0; i < m.nq; ++i) y[static_cast<std::size_t>(i)] = 0;
    p.rhs(0.1, y.data(), ydot.data());
    std::vector<double> J = jacobian_of(p, y, ydot);
    EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs);
    p.set_jacobian_method(Method::whole_rhs);
    const std::vector<double> Jw = jacobian_of(p, y, ydot);
    EXPECT_EQ(J, Jw);
  }
}

}  // namespace
