// Eigenvalues as study outputs (sim/eigenvalue_outputs.hpp) and their exact sensitivities, against
// what we did not write: the compound pendulum's closed form λ = ±i √(3g cos q0 / (2L)) and its
// derivatives in L, m and the initial angle; central finite differences of the Whipple bicycle's
// eigenvalues (each perturbed sample made consistent and linearized afresh), over the speed (an
// initial condition), geometry and masses; the first-order perturbation formula on matrices with
// known eigenvalue derivatives; and the upright rolling disc's closed form (below).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "../support/kane_test_support.hpp"
#include "../support/layers.hpp"
#include "sim/eigenvalue_outputs.hpp"
#include "sim/kane_problem.hpp"
#include "sim/linearize.hpp"
#include "sim/modes.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

Model config(const std::string& name) {
  return build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/" + name));
}

// One sample's eigenvalue outputs: values (re0, im0, ...) and tangents [component × ns].
struct Eig {
  std::vector<double> values, tangents;
};

// The node a study would build: the reduced states of the nominal sample, every eigenvalue.
OutputNode eigen_node(const Model& m, const SampleInputs& in, double t0 = 0) {
  KaneProblem p(m, {}, {}, t0);
  p.set_sample(in);
  std::vector<double> y0(static_cast<std::size_t>(p.size())), y(static_cast<std::size_t>(m.nstate()));
  p.initial_state(y0.data());
  p.full_state(t0, y0.data(), y.data());
  const Linearization lin = linearize(m, in.parameters, t0, y);
  OutputNode n;
  n.name = "modes";
  n.kind = OutputKind::eigenvalues;
  n.series = false;
  n.linear_coordinates = lin.coordinates;
  n.linear_speeds = lin.speeds;
  n.eigenvalue_count = static_cast<int>(lin.A.rows());
  return n;
}

Eig eigenvalues_of(const Model& m, const OutputNode& node, const SampleInputs& in, const std::vector<InputRef>& sens) {
  KaneProblem p(m, sens, {}, 0);
  p.set_sample(in);
  Eig e;
  e.values.assign(2 * static_cast<std::size_t>(node.eigenvalue_count), std::nan(""));
  e.tangents.assign(e.values.size() * sens.size(), std::nan(""));
  evaluate_eigenvalues(node, p, e.values.data(), e.tangents.data());
  return e;
}

InputRef input(const Model& m, const std::string& name) { return resolve_input(m, name, "test"); }

// ---------------------------------------------------------------------------------------------
// Compound pendulum (configs/simple_pendulum.yaml): q̈ = −(3g / 2L) sin q, so about the initial
// angle q0 the linearization has λ = ±i ω, ω = √(3g cos q0 / (2L)); dω/dL = −ω / (2L),
// dω/dm = 0, dω/dq0 = −ω tan(q0) / 2.
TEST(EigenvalueOutputs, PendulumMatchesClosedForm) {
  const Model m = config("simple_pendulum.yaml");
  SampleInputs in(m);
  const double L = 0.8, q0 = 0.4, g = 9.81;
  in.set(input(m, "L"), L);
  in.set(input(m, "pivot.q0"), q0);
  const std::vector<InputRef> sens = {input(m, "L"), input(m, "m"), input(m, "pivot.q0")};
  const OutputNode node = eigen_node(m, in);
  ASSERT_EQ(node.eigenvalue_count, 2);
  const Eig e = eigenvalues_of(m, node, in, sens);
  const double w = std::sqrt(3 * g * std::cos(q0) / (2 * L));
  // Sorted by real part (both 0), then +Im before −Im.
  EXPECT_NEAR(e.values[0], 0, 1e-14);
  EXPECT_NEAR(e.values[1], w, 1e-13 * w);
  EXPECT_NEAR(e.values[2], 0, 1e-14);
  EXPECT_NEAR(e.values[3], -w, 1e-13 * w);
  const double want[3] = {-w / (2 * L), 0, -w * std::tan(q0) / 2};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(e.tangents[1 * 3 + static_cast<std::size_t>(i)], want[i], 1e-12 * w) << "sensitivity " << i;
    EXPECT_NEAR(e.tangents[3 * 3 + static_cast<std::size_t>(i)], -want[i], 1e-12 * w) << "sensitivity " << i;
    EXPECT_NEAR(e.tangents[0 * 3 + static_cast<std::size_t>(i)], 0, 1e-12 * w);
  }
}

// ---------------------------------------------------------------------------------------------
// The perturbation formula dλ = wᴴ dA v / wᴴ v on matrices whose eigenvalues are known in
// closed form: A(ε) = [[a, b], [c, d]] + ε E has λ = (tr ± √(tr² − 4 det)) / 2.
TEST(EigenvalueDerivatives, TwoByTwoClosedForm) {
  Eigen::Matrix2d A, E;
  A << 0.3, -2.0, 1.5, -0.7;  // complex pair
  E << 0.2, 0.1, -0.4, 0.9;
  auto lambda = [&](double eps, int sign) {
    const Eigen::Matrix2d B = A + eps * E;
    const double tr = B.trace(), det = B.determinant();
    return (tr + double(sign) * std::sqrt(std::complex<double>(tr * tr - 4.0 * det, 0.0))) / 2.0;
  };
  // d/dε of the closed form, by the quotient rule on its pieces.
  const double tr = A.trace(), det = A.determinant(), dtr = E.trace();
  const double ddet = A(0, 0) * E(1, 1) + E(0, 0) * A(1, 1) - A(0, 1) * E(1, 0) - E(0, 1) * A(1, 0);
  const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr - 4.0 * det, 0.0));
  const Modes md = modes(A);
  const Eigen::MatrixXcd d = eigenvalue_derivatives(md, {E});
  for (int k = 0; k < 2; ++k) {
    const int sign = md.values[k].imag() > 0 ? 1 : -1;
    ASSERT_LE(std::abs(md.values[k] - lambda(0, sign)), 1e-14);
    const std::complex<double> want = (dtr + double(sign) * (2.0 * tr * dtr - 4.0 * ddet) / (2.0 * disc)) / 2.0;
    EXPECT_LE(std::abs(d(k, 0) - want), 1e-14) << d(k, 0) << " vs " << want;
  }
}

TEST(EigenvalueDerivatives, RepeatedEigenvaluesAreNaN) {
  Eigen::Matrix3d A;
  A << -1, 1, 0, 0, -1, 0, 0, 0, -3;  // a Jordan block at −1 and a simple −3
  bool repeated = false;
  const Modes md = modes(A);
  const Eigen::MatrixXcd d = eigenvalue_derivatives(md, {Eigen::MatrixXd(Eigen::Matrix3d::Identity())}, &repeated);
  EXPECT_TRUE(repeated);
  EXPECT_TRUE(std::isnan(d(0, 0).real()));
  EXPECT_TRUE(std::isnan(d(1, 0).real()));
  EXPECT_NEAR(d(2, 0).real(), 1.0, 1e-12);  // λ = −3 + ε
  EXPECT_NEAR(d(2, 0).imag(), 0.0, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The Whipple bicycle (configs/whipple_bicycle.yaml) at 5 m/s: dλ/dp vs central differences of the
// eigenvalues of perturbed samples (each made consistent and linearized afresh), step h·max(1,|p|)
// for h = 1e-3, 1e-4, 1e-5: the smallest difference must be within 1e-7 of max(1, |dλ/dp|) —
// truncation error shrinks as h², rounding grows as 1/h, so one of the three steps is near the best.
TEST(EigenvalueOutputs, BicycleSensitivitiesMatchFiniteDifferences) {
  const Model m = config("whipple_bicycle.yaml");
  const SampleInputs nominal(m);
  const std::vector<std::string> names = {"v", "rR", "c", "w", "mB", "zB", "IBxz", "lam"};
  std::vector<InputRef> sens;
  for (const auto& n : names) sens.push_back(input(m, n));
  const OutputNode node = eigen_node(m, nominal);
  ASSERT_EQ(node.eigenvalue_count, 4);
  EXPECT_EQ(node.linear_coordinates, (std::vector<std::string>{"base.rx", "steer.q"}));
  const Eig e = eigenvalues_of(m, node, nominal, sens);
  const std::size_t ns = sens.size(), nc = e.values.size();
  double worst = 0;
  for (std::size_t i = 0; i < ns; ++i) {
    const double p0 = nominal.get(m, sens[i]);
    std::vector<double> best(nc, std::numeric_limits<double>::infinity());
    for (const double h : {1e-3, 1e-4, 1e-5}) {
      const double dp = h * std::max(1.0, std::abs(p0));
      SampleInputs plus = nominal, minus = nominal;
      plus.set(sens[i], p0 + dp);
      minus.set(sens[i], p0 - dp);
      const Eig ep = eigenvalues_of(m, node, plus, {}), em = eigenvalues_of(m, node, minus, {});
      for (std::size_t c = 0; c < nc; ++c) {
        const double fd = (ep.values[c] - em.values[c]) / (2 * dp);
        const double exact = e.tangents[c * ns + i];
        best[c] = std::min(best[c], std::abs(fd - exact) / std::max(1.0, std::abs(exact)));
      }
    }
    for (std::size_t c = 0; c < nc; ++c) {
      worst = std::max(worst, best[c]);
      EXPECT_LE(best[c], 1e-7) << "d(component " << c << ")/d" << names[i] << " = " << e.tangents[c * ns + i];
    }
  }
  std::printf("bicycle eigenvalue sensitivities vs central differences (8 inputs, 8 components): max rel. %.2e\n", worst);
  // The speed matters to every mode; the sorted order at 5 m/s is capsize, weave ±, castering.
  // Table 2 of Meijaard et al. (2007) at v = 5 (tests/data/whipple_benchmark.txt).
  EXPECT_NEAR(e.values[0], -0.32286642900409, 1e-12);
  EXPECT_NEAR(e.values[2], -0.77534188219585, 1e-12);
  EXPECT_NEAR(e.values[3], 4.46486771378823, 1e-12);
  EXPECT_NEAR(e.values[4], -0.77534188219585, 1e-12);
  EXPECT_NEAR(e.values[5], -4.46486771378823, 1e-12);
  EXPECT_NEAR(e.values[6], -14.07838969279820, 1e-11);
}

// ---------------------------------------------------------------------------------------------
// The upright rolling disc (configs/rolling_disc_upright.yaml: thin uniform disc, diametral
// inertia A = m r²/4 about its centre, axial C = m r²/2; lean φ and heading ψ as joint
// coordinates) rolling straight at speed v, spin Ω = v/r. The linearized equations (e.g. Neimark &
// Fufaev, Dynamics of Nonholonomic Systems, the rolling disc) are
//   (A + m r²) φ̈ + (C + m r²) Ω ψ̇ − m g r φ = 0,   A ψ̈ − C Ω φ̇ = 0,
// so ψ̇ − (CΩ/A) φ is conserved (a zero eigenvalue) and
//   λ² = −[(C + m r²) C Ω² / A − m g r] / (A + m r²) = −(4/5)(3Ω² − g/r),
// oscillatory above the critical speed v² = g r/3 and unstable below (SymPy's rolling-disc
// linearization test finds the same critical spin rate, 1/√3 with g = r = 1).
struct Disc {
  Model m = config("rolling_disc_upright.yaml");
  std::vector<double> p = m.nominal_parameters();
  Disc(double mass, double radius) {
    p[static_cast<std::size_t>(m.find_parameter("m"))] = mass;
    p[static_cast<std::size_t>(m.find_parameter("r"))] = radius;
  }
  Linearization at(double v) const {
    const double r = p[static_cast<std::size_t>(m.find_parameter("r"))];
    // q: contact point x, y, heading, lean, spin angle; u: their rates (spin v/r: rolling).
    const std::vector<double> y = {0, 0, 0, 0, 0, v, 0, 0, 0, v / r};
    return linearize(m, p, 0, y);
  }
};

TEST(LinearizeRollingDisc, UprightMatchesClosedForm) {
  const double g = 9.81;
  double worst = 0;
  for (const auto& [mass, r] : {std::pair{1.0, 1.0}, std::pair{2.5, 0.3}}) {
    const Disc disc(mass, r);
    const double vc = std::sqrt(g * r / 3);
    for (const double v : {0.0, 0.5 * vc, 0.9 * vc, 1.1 * vc, 2 * vc, 5.0}) {
      const Linearization lin = disc.at(v);
      EXPECT_EQ(lin.coordinates, (std::vector<std::string>{"lean.q"}));
      EXPECT_LE(lin.rates.cwiseAbs().maxCoeff(), 1e-12) << "steady straight rolling";
      const Modes md = modes(lin.A);
      const double Om = v / r;
      const std::complex<double> lam = std::sqrt(std::complex<double>(-0.8 * (3 * Om * Om - g / r)));
      // The pair ±λ, the rest zero.
      int matched_plus = 0, matched_minus = 0;
      for (Eigen::Index k = 0; k < md.values.size(); ++k) {
        const std::complex<double> z = md.values[k];
        const double dp = std::abs(z - lam), dm = std::abs(z + lam), d0 = std::abs(z);
        const double d = std::min({dp, dm, d0});
        worst = std::max(worst, d);
        EXPECT_LE(d, 1e-10 * std::max(1.0, std::abs(lam))) << "v = " << v << ": eigenvalue " << z << ", closed form ±" << lam;
        if (dp <= 1e-10 * std::max(1.0, std::abs(lam)) && d0 > 1e-8) ++matched_plus;
        if (dm <= 1e-10 * std::max(1.0, std::abs(lam)) && d0 > 1e-8) ++matched_minus;
      }
      if (v > 0) {
        EXPECT_TRUE(matched_plus == 1 && matched_minus == 1) << "v = " << v;
      }
      // Unstable below the critical speed (a positive real eigenvalue), not above.
      const double max_re = md.values.real().maxCoeff();
      if (v < vc) {
        EXPECT_GT(max_re, 0.1 * std::sqrt(g / r) * (1 - v / vc)) << "v = " << v;
      } else {
        EXPECT_LE(max_re, 1e-10) << "v = " << v;
      }
    }
  }
  std::printf("upright rolling disc vs closed form λ² = −(4/5)(3Ω² − g/r): max |difference| %.2e\n", worst);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
