// The solvers' Jacobian and sensitivity right-hand sides come from multi-tangent passes (blocks
// of 2 to 16 directions; one sensitivity from a single-tangent pass). They must equal,
// direction by direction, what one single-tangent Dual pass per direction gives (the form the
// finite-difference and closed-form tests validate), and the matrix-free product J v the
// assembled J times v and the differences of the RHS, on
// scenes that take every path: planar and 3-D trees, quaternions, multipliers with projection,
// the embedding, rolling with Baumgarte terms; and they must not allocate.
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

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;

struct Case {
  std::string scene;
  std::vector<std::string> sensitivities;
  ConstraintOptions constraints;
};

ConstraintOptions with(ConstraintOptions::Formulation f, ConstraintOptions::Stabilization s) {
  ConstraintOptions c;
  c.formulation = f;
  c.stabilization = s;
  return c;
}

std::vector<Case> cases() {
  using F = ConstraintOptions::Formulation;
  using St = ConstraintOptions::Stabilization;
  return {
      {"nlink_chain_4.yaml", {"m", "L", "c", "j1.q0", "j2.u0"}, {}},
      {"arm_3d.yaml", {"m1", "m2", "m3", "k_tele", "c_tele", "L1", "wrist.q0[0]", "L2", "shoulder.u0"}, {}},
      {"spinning_top.yaml", {"m", "l", "tip.q0[1]"}, {}},
      {"four_bar.yaml", {"r", "c", "b", "m1", "m2", "m3"}, with(F::multipliers, St::projection)},
      {"four_bar.yaml", {"r", "c", "b", "m1", "m2", "m3"}, with(F::embedding, St::projection)},
      {"rolling_disc.yaml", {"m", "r", "base.u0[0]"}, with(F::multipliers, St::baumgarte)},
      {"andrews.yaml", {"m1", "c0", "xa", "I7"}, with(F::multipliers, St::projection)},
      // One sensitivity: a single-tangent pass (KaneProblem::kSingleTangentPasses); two: a block
      // of width 2.
      {"arm_3d.yaml", {"k_tele"}, {}},
      {"four_bar.yaml", {"c", "m2"}, with(F::embedding, St::projection)},
      {"nlink_chain_4.yaml", {"m", "j2.u0"}, {}},
  };
}

// A state near the problem's initial state (inside the embedding's chart), with random speeds.
std::vector<double> test_state(KaneProblem& p, std::mt19937& rng) {
  std::vector<double> y(static_cast<std::size_t>(p.size()));
  p.initial_state(y.data());
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (double& v : y) v += u(rng);
  return y;
}

TEST(TangentPasses, JacobianAndSensitivitiesMatchSingleTangentPasses) {
  std::mt19937 rng(5);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.scene + (c.constraints.formulation == ConstraintOptions::Formulation::embedding ? " (embedding)" : ""));
    const Model m = build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/" + c.scene));
    std::vector<InputRef> refs;
    for (const auto& s : c.sensitivities) refs.push_back(resolve_input(m, s, "test"));
    KaneProblem p(m, refs, c.constraints);
    p.set_sample(SampleInputs(m));
    const int n = p.size(), ns = static_cast<int>(refs.size());
    const std::vector<double> y = test_state(p, rng);
    std::vector<double> ydot(static_cast<std::size_t>(n));
    p.rhs(0.1, y.data(), ydot.data());

    // Jacobian: blocks vs columns e_j through sensitivity_rhs of an initial-condition-free
    // direction, i.e. J e_j — computed here from Dual passes on the single-direction path.
    std::vector<double> J(static_cast<std::size_t>(n) * n), Jd(J.size());
    p.jacobian(0.1, y.data(), ydot.data(), J.data());
    {
      // One Dual pass per column: the sensitivity RHS of a direction with no parameter tangent.
      std::vector<InputRef> ic;
      for (int j = 0; j < n; ++j) ic.push_back({InputRef::Kind::initial_condition, 0, "y0"});
      KaneProblem cols(m, ic, c.constraints);
      cols.set_sample(SampleInputs(m));
      std::vector<double> e(static_cast<std::size_t>(n));
      for (int j = 0; j < n; ++j) {
        std::fill(e.begin(), e.end(), 0.0);
        e[static_cast<std::size_t>(j)] = 1;
        cols.sensitivity_rhs(0.1, y.data(), ydot.data(), j, e.data(), Jd.data() + static_cast<std::ptrdiff_t>(j) * n);
      }
    }
    double scale = 1, err = 0;
    for (double v : Jd) scale = std::max(scale, std::abs(v));
    for (std::size_t k = 0; k < J.size(); ++k) err = std::max(err, std::abs(J[k] - Jd[k]));
    EXPECT_LT(err / scale, 1e-12) << "Jacobian";
    std::printf("%s: Jacobian max rel diff %.2e (n = %d)\n", c.scene.c_str(), err / scale, n);

    // Matrix-free products: J v from one Dual pass equals the assembled J times v to round-off,
    // and the central difference of the right-hand side along v to its truncation error.
    std::uniform_real_distribution<double> u(-1, 1);
    {
      std::vector<double> v(static_cast<std::size_t>(n)), Jv(v.size()), JvJ(v.size(), 0.0);
      for (double& x : v) x = u(rng);
      p.jacobian_times(0.1, y.data(), ydot.data(), v.data(), Jv.data());
      for (int j = 0; j < n; ++j)
        for (int r = 0; r < n; ++r)
          JvJ[static_cast<std::size_t>(r)] += J[static_cast<std::size_t>(j) * n + r] * v[static_cast<std::size_t>(j)];
      double sc = 1, e = 0, efd = 0;
      for (double x : JvJ) sc = std::max(sc, std::abs(x));
      for (int r = 0; r < n; ++r) e = std::max(e, std::abs(Jv[static_cast<std::size_t>(r)] - JvJ[static_cast<std::size_t>(r)]));
      EXPECT_LT(e / sc, 1e-12) << "J v vs the assembled J";
      const double h = 1e-6;
      std::vector<double> yp(y), ym(y), fp(v.size()), fm(v.size());
      for (int r = 0; r < n; ++r) {
        yp[static_cast<std::size_t>(r)] += h * v[static_cast<std::size_t>(r)];
        ym[static_cast<std::size_t>(r)] -= h * v[static_cast<std::size_t>(r)];
      }
      p.rhs(0.1, yp.data(), fp.data());
      p.rhs(0.1, ym.data(), fm.data());
      for (int r = 0; r < n; ++r)
        efd = std::max(efd, std::abs((fp[static_cast<std::size_t>(r)] - fm[static_cast<std::size_t>(r)]) / (2 * h) -
                                     Jv[static_cast<std::size_t>(r)]));
      EXPECT_LT(efd / sc, 1e-6) << "J v vs central differences of the right-hand side";
      std::printf("%s: J v max rel diff %.2e vs J, %.2e vs differences\n", c.scene.c_str(), e / sc, efd / sc);
    }

    // Sensitivities: all at once vs one at a time, random s_i.
    std::vector<std::vector<double>> s(static_cast<std::size_t>(ns), std::vector<double>(static_cast<std::size_t>(n)));
    std::vector<std::vector<double>> all(s), one(s);
    std::vector<const double*> sp;
    std::vector<double*> ap;
    for (int i = 0; i < ns; ++i) {
      for (double& v : s[static_cast<std::size_t>(i)]) v = u(rng);
      sp.push_back(s[static_cast<std::size_t>(i)].data());
      ap.push_back(all[static_cast<std::size_t>(i)].data());
    }
    p.sensitivity_rhs_all(0.1, y.data(), ydot.data(), ns, sp.data(), ap.data());
    for (int i = 0; i < ns; ++i) {
      p.sensitivity_rhs(0.1, y.data(), ydot.data(), i, sp[static_cast<std::size_t>(i)], one[static_cast<std::size_t>(i)].data());
      double sc = 1, e2 = 0;
      for (double v : one[static_cast<std::size_t>(i)]) sc = std::max(sc, std::abs(v));
      for (int r = 0; r < n; ++r)
        e2 = std::max(e2, std::abs(all[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)] -
                                   one[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)]));
      EXPECT_LT(e2 / sc, 1e-12) << "sensitivity " << c.sensitivities[static_cast<std::size_t>(i)];
    }
    // f and the sensitivities from one call (DOP853's stages): f as rhs() gives it.
    std::vector<double> f(static_cast<std::size_t>(n));
    std::vector<std::vector<double>> both(s);
    std::vector<double*> bp;
    for (auto& v : both) bp.push_back(v.data());
    p.rhs_with_sensitivities(0.1, y.data(), ns, sp.data(), f.data(), bp.data());
    double fscale = 1, ferr = 0, serr = 0;
    for (int r = 0; r < n; ++r) {
      fscale = std::max(fscale, std::abs(ydot[static_cast<std::size_t>(r)]));
      ferr = std::max(ferr, std::abs(f[static_cast<std::size_t>(r)] - ydot[static_cast<std::size_t>(r)]));
      for (int i = 0; i < ns; ++i)
        serr = std::max(serr, std::abs(both[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)] -
                                       all[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)]));
    }
    EXPECT_LT(ferr / fscale, 1e-13) << "f of rhs_with_sensitivities";
    // On the 3-D path with the residual method, f comes from the same pass (at u̇ = 0, then moved
    // to u̇): the sensitivities agree to round-off, no longer bit for bit.
    double sscale = 1;
    for (const auto& v : all)
      for (double x : v) sscale = std::max(sscale, std::abs(x));
    EXPECT_LT(serr / sscale, 1e-13) << "sensitivities of rhs_with_sensitivities";
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
