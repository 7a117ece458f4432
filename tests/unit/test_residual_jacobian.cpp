// The Jacobian by inverse dynamics (KaneProblem::DerivativeMethod::residual: one
// multi-tangent pass of Kane's equations as a residual at the accelerations of ydot, solved with
// M's and A M⁻¹ Aᵀ's value factors, dynamics/inverse_dynamics.hpp) must equal the whole right-hand
// side's multi-tangent passes to round-off, and the central differences of the right-hand side to
// their truncation error, on planar and 3-D trees (chain and branched: dense and tree factor),
// quaternions, multipliers with projection and with Baumgarte terms, rolling, general
// constraints; and the method must actually be taken there. Where it does not apply — the
// embedding, redundant constraint rows, a ydot that is not f(t, y) — jacobian() must take the
// whole right-hand side and say so. The sensitivity right-hand sides by the same residual passes
// (J s_i + ∂f/∂p_i with parameter tangents) must equal the whole passes' likewise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/equations.hpp"
#include "dynamics/inverse_dynamics.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"
#include "kane_test_support.hpp"
#include "jacobian_checks.hpp"
#include "test_scenes.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;
using Method = KaneProblem::DerivativeMethod;

ConstraintOptions with(ConstraintOptions::Formulation f, ConstraintOptions::Stabilization s) {
  ConstraintOptions c;
  c.formulation = f;
  c.stabilization = s;
  return c;
}

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
    const Model m = model_from_source_file(c.scene);
    KaneProblem p(m, {}, c.constraints);
    p.set_sample(SampleInputs(m));
    const int n = p.size();
    const std::vector<double> y = test_state(p, rng, 0.05);
    std::vector<double> ydot(static_cast<std::size_t>(n));
    p.rhs(0.1, y.data(), ydot.data());

    std::vector<double> J(static_cast<std::size_t>(n) * n), Jw(J.size());
    p.set_jacobian_method(Method::residual);  // not the closed form where it applies
    p.jacobian(0.1, y.data(), ydot.data(), J.data());
    EXPECT_EQ(p.last_jacobian_method(), Method::residual);
    p.set_jacobian_method(Method::whole_rhs);
    p.jacobian(0.1, y.data(), ydot.data(), Jw.data());
    EXPECT_EQ(p.last_jacobian_method(), Method::whole_rhs);
    double err = 0;
    for (std::size_t k = 0; k < J.size(); ++k) err = std::max(err, std::abs(J[k] - Jw[k]));
    const double scale = std::max(1.0, max_abs(Jw));
    // The whole passes of unconstrained planar chains take the articulated-body recursion, not M:
    // a different algorithm, agreeing to its round-off (as on double, test_articulated_body).
    EXPECT_LT(err / scale, 1e-11) << "residual vs whole right-hand side";

    // Central differences, column by column, relative to J's size.
    const double efd = central_difference_error(p, 0.1, y, J, scale);
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
    const Model m = model_from_source_file("configs/four_bar.yaml");
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
      const Model m = model_from_source_file(scene);
      KaneProblem p(m, {});
      p.set_sample(SampleInputs(m));
      p.set_jacobian_method(Method::residual);  // (the closed form's fallback: test_closed_form_jacobian)
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
    const Model m = model_from_source_file("configs/parallelogram_four_bar.yaml");
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

// The sensitivity right-hand sides s_i ↦ J s_i + ∂f/∂p_i: as CVODES asks (ydot given), or as
// DOP853's stages do (ydot null: f comes out in *f).
std::vector<std::vector<double>> sensitivity_rhs(KaneProblem& p, const std::vector<double>& y,
                                                 const std::vector<double>* ydot,
                                                 const std::vector<std::vector<double>>& s, std::vector<double>* f) {
  std::vector<std::vector<double>> out(s.size(), std::vector<double>(y.size()));
  std::vector<const double*> in;
  std::vector<double*> outp;
  for (std::size_t i = 0; i < s.size(); ++i) {
    in.push_back(s[i].data());
    outp.push_back(out[i].data());
  }
  const int ns = static_cast<int>(s.size());
  if (ydot) p.sensitivity_rhs_all(0.1, y.data(), ydot->data(), ns, in.data(), outp.data());
  else p.rhs_with_sensitivities(0.1, y.data(), ns, in.data(), f->data(), outp.data());
  return out;
}

// Sensitivity right-hand sides by residual passes (parameter tangents set per sample, the state
// tangents s_i) against the whole right-hand side's passes, both as CVODES asks (ydot given) and
// as DOP853's stages do (f and the sensitivities from one call); and the default per path.
TEST(ResidualSensitivities, MatchWholeRhsPasses) {
  using F = ConstraintOptions::Formulation;
  using St = ConstraintOptions::Stabilization;
  struct SensCase {
    std::string scene;
    ConstraintOptions constraints;
    std::vector<std::string> sensitivities;
    Method default_method;
  };
  const std::vector<SensCase> cases = {
      {"configs/arm_3d.yaml", {}, {"m1", "m2", "m3", "k_tele", "c_tele", "wrist.q0[0]"}, Method::residual},
      {"configs/spinning_top.yaml", {}, {"m", "r", "h", "l", "tip.u0[2]", "tip.q0[1]"}, Method::residual},
      {"configs/rolling_disc.yaml", with(F::multipliers, St::baumgarte),
       {"m", "r", "base.u0[0]", "base.u0[4]", "base.u0[5]", "base.q0[4]"}, Method::residual},
      {"configs/four_bar.yaml", with(F::multipliers, St::projection), {"r", "c", "b", "m1", "m2", "m3"},
       Method::whole_rhs},
      {"configs/nlink_chain_4.yaml", {}, {"m", "L", "c", "j1.q0", "j2.q0", "j1.u0", "j3.u0", "j4.q0", "k"},
       Method::whole_rhs},
      // Two sensitivities: one block of width 2.
      {"configs/arm_3d.yaml", {}, {"m1", "wrist.q0[0]"}, Method::residual},
      {"configs/rolling_disc.yaml", with(F::multipliers, St::baumgarte), {"r", "base.u0[4]"}, Method::residual},
      {"configs/nlink_chain_4.yaml", {}, {"m", "L"}, Method::whole_rhs},
  };
  std::mt19937 rng(29);
  for (const SensCase& c : cases) {
    SCOPED_TRACE(c.scene);
    const Model m = model_from_source_file(c.scene);
    std::vector<InputRef> refs;
    for (const std::string& name : c.sensitivities) refs.push_back(resolve_input(m, name, "test"));
    KaneProblem p(m, refs, c.constraints);
    p.set_sample(SampleInputs(m));
    const int n = p.size(), ns = static_cast<int>(refs.size());
    const std::vector<double> y = test_state(p, rng, 0.05);
    std::vector<double> ydot(static_cast<std::size_t>(n));
    p.rhs(0.1, y.data(), ydot.data());
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<std::vector<double>> s(static_cast<std::size_t>(ns), std::vector<double>(static_cast<std::size_t>(n)));
    for (auto& si : s)
      for (double& v : si) v = u(rng);
    auto run = [&](bool with_f, std::vector<double>* f) { return sensitivity_rhs(p, y, with_f ? nullptr : &ydot, s, f); };
    p.set_sensitivity_method(Method::whole_rhs);
    std::vector<double> f_whole(ydot.size()), f_res(ydot.size());
    const auto whole = run(false, nullptr);
    EXPECT_EQ(p.last_sensitivity_method(), Method::whole_rhs);
    const auto whole_f = run(true, &f_whole);
    p.set_sensitivity_method(Method::residual);
    const auto res = run(false, nullptr);
    EXPECT_EQ(p.last_sensitivity_method(), Method::residual);
    const auto res_f = run(true, &f_res);
    EXPECT_EQ(p.last_sensitivity_method(), Method::residual);
    EXPECT_EQ(p.last_f_from_sensitivity_pass(), !m.evaluate_planar()) << "f from the residual pass on the 3-D path";
    // DOP853's f by the residual method comes from the pass's own f and M's value factor (not
    // from rhs()): the same to round-off.
    for (std::size_t r = 0; r < ydot.size(); ++r)
      EXPECT_NEAR(f_res[r], ydot[r], 1e-13 * std::max(1.0, max_abs(ydot))) << "DOP853's f, entry " << r;
    double err = 0, err_f = 0, scale = 1;
    for (std::size_t i = 0; i < s.size(); ++i) {
      scale = std::max(scale, max_abs(whole[i]));
      EXPECT_EQ(whole[i], whole_f[i]) << "the whole passes do not depend on how they are called";
      for (std::size_t r = 0; r < ydot.size(); ++r) {
        err = std::max(err, std::abs(res[i][r] - whole[i][r]));
        err_f = std::max(err_f, std::abs(res_f[i][r] - whole[i][r]));
      }
    }
    EXPECT_LT(err / scale, 1e-12);
    EXPECT_LT(err_f / scale, 1e-12);
    for (std::size_t r = 0; r < ydot.size(); ++r)
      EXPECT_NEAR(f_whole[r], ydot[r], 1e-12 * std::max(1.0, max_abs(ydot)));

    KaneProblem fresh(m, refs, c.constraints);
    fresh.set_sample(SampleInputs(m));
    std::vector<double> f(ydot.size());
    sensitivity_rhs(fresh, y, nullptr, s, &f);
    EXPECT_EQ(fresh.last_sensitivity_method(), c.default_method);
    std::printf("%s: residual sensitivity rhs vs whole %.2e (from DOP853's call %.2e), %d sensitivities\n",
                c.scene.c_str(), err / scale, err_f / scale, ns);
  }
}

// DOP853's stages take f from the residual pass itself: the stages at u̇ = 0
// (evaluate_residual_at_rest), f on values from them (forcing_values), then the residual at u̇
// (residual_from_rest). That must be evaluate_residual at u̇ to round-off; f must be
// evaluate_mass_matrix_and_forcing's, and f − r must be M u̇ with M from the composite-rigid-body
// recursion (trees, quaternions, rolling, general and loop constraints with Baumgarte terms).
TEST(ResidualFromRest, IsTheResidualAtUdot) {
  const std::vector<std::pair<std::string, Model>> scenes = {
      {"arm_3d", model_from_source_file("configs/arm_3d.yaml")},
      {"spinning_top", model_from_source_file("configs/spinning_top.yaml")},
      {"rolling_disc", model_from_source_file("configs/rolling_disc.yaml")},
      {"andrews", model_from_source_file("configs/andrews.yaml")},
      {"four_bar", model_from_source_file("configs/four_bar.yaml")},
      {"tilted chain of 8", build_model(parse_scene_text(test_scenes::chain_scene(8, 0.1), "chain.yaml"))}};
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> uni(-1, 1);
  DynamicsOptions options;
  options.baumgarte_alpha = 3, options.baumgarte_beta = 2;
  for (const auto& [name, model] : scenes) {
    SCOPED_TRACE(name);
    Model m = model;
    m.force_general_3d = true;  // the 3-D path, which the fused pass takes
    const int nq = m.nq, nu = m.nu, nc = m.nconstraint_rows;
    Workspace<double> ws(m), wd(m);
    const std::vector<double> p = m.nominal_parameters();
    set_parameters(m, ws, p.data());
    for (int trial = 0; trial < 3; ++trial) {
      std::vector<double> y(static_cast<std::size_t>(m.nstate())), udot(static_cast<std::size_t>(nu));
      for (double& v : y) v = uni(rng);
      for (double& v : udot) v = 3 * uni(rng);
      std::vector<double> at(y.size()), moved(y.size()), c_at(static_cast<std::size_t>(nc)), c_moved(c_at);
      std::vector<double> f(static_cast<std::size_t>(nu));
      evaluate_residual(m, ws, 0.2, y.data(), udot.data(), nullptr, options, at.data(), c_at.data());
      evaluate_residual_at_rest(m, ws, 0.2, y.data(), options, moved.data(), c_moved.data());
      const std::vector<double> minus_b = c_moved;
      ASSERT_TRUE(factor_mass_matrix_values(m, ws, wd));
      forcing_values(m, ws, wd, f.data());
      residual_from_rest(m, ws, udot.data(), moved.data() + nq, c_moved.data());
      evaluate_mass_matrix_and_forcing(m, ws, 0.2, y.data(), y.data() + nq);
      double scale = 1;
      for (double v : at) scale = std::max(scale, std::abs(v));
      for (double v : f) scale = std::max(scale, std::abs(v));
      for (int k = 0; k < nq; ++k) EXPECT_EQ(moved[k], at[k]) << "q̇ " << k;
      for (int k = 0; k < nu; ++k) {
        double Mu = 0;
        for (int l = 0; l < nu; ++l) {
          Mu += ws.mass_matrix(k, l) * udot[static_cast<std::size_t>(l)];
          scale = std::max(scale, std::abs(ws.mass_matrix(k, l) * udot[static_cast<std::size_t>(l)]));
        }
        EXPECT_NEAR(moved[nq + k], at[nq + k], 1e-13 * scale) << "r " << k;
        EXPECT_NEAR(f[k] - moved[nq + k], Mu, 1e-13 * scale) << "M u̇ " << k;
        EXPECT_NEAR(f[k], ws.forcing[k], 1e-13 * scale) << "f " << k;
      }
      for (int j = 0; j < nc; ++j) {
        double cscale = std::abs(minus_b[j]);
        for (int k = 0; k < nu; ++k) cscale = std::max(cscale, std::abs(ws.constraint_matrix(j, k) * udot[static_cast<std::size_t>(k)]));
        EXPECT_NEAR(c_moved[j], c_at[j], 1e-13 * std::max(1.0, cscale)) << "c " << j;
      }
    }
  }
}

// The krylov solver's premise (OdeProblem::jacobian_times_cheap) fails where the right-hand side
// is the 3-D articulated-body recursion (on double only: J v's dual pass forms M); it holds where
// u̇ comes from M, and on the planar path, whose recursion runs on duals too.
TEST(JacobianTimes, CheapUnlessOnlyTheValuesTakeTheArticulatedBodyRecursion) {
  for (const auto& [scene, cheap] : std::vector<std::pair<std::string, bool>>{{"configs/nlink_chain_4.yaml", true},
                                                                             {"bench/configs/nlink_chain_16.yaml", true},
                                                                             {"configs/arm_3d.yaml", true},
                                                                             {"configs/four_bar.yaml", true}}) {
    const Model m = model_from_source_file(scene);
    KaneProblem p(m, {});
    EXPECT_EQ(p.jacobian_times_cheap(), cheap) << scene;
  }
  const Model spatial = build_model(parse_scene_text(test_scenes::chain_scene(8, 0.1), "chain.yaml"));
  EXPECT_TRUE(KaneProblem(spatial, {}).jacobian_times_cheap()) << "the tilted chain: the recursion on duals too";
  // Spherical joints from kArticulatedBodyMinSpeeds speeds: the recursion on double, M on duals.
  const Model balls = build_model(
      parse_scene_text(test_scenes::ball_chain((dynamics::kArticulatedBodyMinSpeeds + 2) / 3), "balls.yaml"));
  EXPECT_FALSE(KaneProblem(balls, {}).jacobian_times_cheap()) << "the ball chain";
}
}  // namespace

// rhs() on the 3-D multipliers path takes the value half of the fused pass (f from the stages
// at u̇ = 0, then u̇ and λ with M's and A M⁻¹ Aᵀ's factors): it must be the general right-hand
// side (evaluate_rhs) to round-off — rolling, loop, general and Baumgarte terms alike. With
// redundant rows (a rolling constraint given twice: A M⁻¹ Aᵀ singular) it must hand over to the
// general solve, whose minimum-norm λ it cannot give, with the same bits, for the rest of the
// sample.
TEST(ValueRhs, IsTheGeneralRightHandSideAndHandsOverOnRedundantRows) {
  using F = ConstraintOptions::Formulation;
  using St = ConstraintOptions::Stabilization;
  auto forced_3d = [](Model m) {
    m.force_general_3d = true;
    return m;
  };
  const std::vector<std::pair<std::string, std::pair<Model, ConstraintOptions>>> cases = {
      {"rolling disc, Baumgarte", {model_from_source_file("configs/rolling_disc.yaml"), with(F::multipliers, St::baumgarte)}},
      {"rolling disc, projection", {model_from_source_file("configs/rolling_disc.yaml"), with(F::multipliers, St::projection)}},
      {"whipple bicycle", {model_from_source_file("configs/whipple_bicycle.yaml"), with(F::multipliers, St::projection)}},
      {"two-wheeler, Baumgarte", {model_from_source_file("configs/two_wheeler.yaml"), with(F::multipliers, St::baumgarte)}},
      {"four-bar on the 3-D path", {forced_3d(model_from_source_file("configs/four_bar.yaml")), with(F::multipliers, St::baumgarte)}},
      {"knife edge (general velocity row) on the 3-D path",
       {forced_3d(model_from_source_file("configs/knife_edge.yaml")), with(F::multipliers, St::baumgarte)}},
      {"Andrews (general position rows) on the 3-D path",
       {forced_3d(model_from_source_file("configs/andrews.yaml")), with(F::multipliers, St::baumgarte)}},
  };
  std::mt19937 rng(29);
  for (const auto& [name, c] : cases) {
    SCOPED_TRACE(name);
    const Model& m = c.first;
    KaneProblem p(m, {}, c.second);
    p.set_sample(SampleInputs(m));
    EXPECT_TRUE(p.rhs_by_value_pass());
    Workspace<double> ws(m);
    const std::vector<double> params = m.nominal_parameters();
    set_parameters(m, ws, params.data());
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<double> y = test_state(p, rng, 0.05);
      std::vector<double> ydot(y.size()), general(y.size());
      p.rhs(0.3, y.data(), ydot.data());
      ASSERT_TRUE(evaluate_rhs(m, ws, 0.3, y.data(), general.data(), p.dynamics_options()));
      double err = 0;
      for (std::size_t k = 0; k < y.size(); ++k) err = std::max(err, std::abs(ydot[k] - general[k]));
      EXPECT_LT(err / std::max(1.0, max_abs(general)), 1e-12);
      EXPECT_TRUE(p.rhs_by_value_pass());
      std::printf("%s: rhs vs general %.2e\n", name.c_str(), err / std::max(1.0, max_abs(general)));
    }
  }
  {
    SCOPED_TRACE("redundant rows");
    std::ifstream file(std::string(KANESENS_SOURCE_DIR) + "/configs/rolling_disc.yaml");
    std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const std::string row = "    - {name: contact, type: rolling, body: disc, radius: r, axis: [0, 1, 0], normal: [0, 0, 1]}\n";
    ASSERT_NE(text.find(row), std::string::npos);
    text += "    - {name: again, type: rolling, body: disc, radius: r, axis: [0, 1, 0], normal: [0, 0, 1]}\n";
    const Model m = build_model(parse_scene_text(text, "twice.yaml"));
    KaneProblem p(m, {}, with(F::multipliers, St::baumgarte));
    p.set_sample(SampleInputs(m));
    EXPECT_TRUE(p.rhs_by_value_pass());
    Workspace<double> ws(m);
    const std::vector<double> params = m.nominal_parameters();
    set_parameters(m, ws, params.data());
    const std::vector<double> y = test_state(p, rng, 0.05);
    std::vector<double> ydot(y.size()), general(y.size());
    p.rhs(0.3, y.data(), ydot.data());
    EXPECT_FALSE(p.rhs_by_value_pass());
    ASSERT_TRUE(evaluate_rhs(m, ws, 0.3, y.data(), general.data(), p.dynamics_options()));
    EXPECT_EQ(ydot, general);
    p.set_sample(SampleInputs(m));
    EXPECT_TRUE(p.rhs_by_value_pass());
  }
}

}  // namespace KANESENS_UNITY_ID
