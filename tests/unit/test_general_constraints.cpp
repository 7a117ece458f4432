// General constraints read their coordinates and parameters through dual copies. Those copies
// used to be fixed arrays of 64 entries: parameters beyond the 64th read as 0 (and beyond the
// array) and more than 64 coordinates overflowed the stack. Scenes with 70 parameters and 70
// coordinates check that g, A, the bias and the velocity residual see all of them.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "math/dual.hpp"
#include "dynamics/equations.hpp"
#include "kane_test_support.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {
// n prismatic joints along x in a chain, n parameters p0..p{n-1} = 0.01 (i + 1), and one general
// position constraint on the last coordinate and the last parameter.
std::string scene(int n, const std::string& constraint) {
  // std::ostringstream: GCC 12's -Wrestrict misfires on chains of std::string operator+.
  std::ostringstream s;
  s << "kanesens: 1\nscene:\n  name: many\n  parameters:\n";
  for (int i = 0; i < n; ++i) s << "    p" << i << ": " << 0.01 * (i + 1) << "\n";
  s << "  bodies:\n";
  for (int i = 0; i < n; ++i) s << "    - {name: b" << i << ", mass: 1, inertia: {shape: point}}\n";
  s << "  joints:\n";
  for (int i = 0; i < n; ++i) {
    s << "    - {name: j" << i << ", type: prismatic, parent: ";
    if (i) s << "b" << i - 1;
    else s << "ground";
    s << ", child: b" << i << ", axis: [1, 0, 0]}\n";
  }
  s << "  constraints:\n    - " << constraint << "\n";
  return s.str();
}

template <class S>
void evaluate(const Model& m, Workspace<S>& ws, const std::vector<S>& y) {
  std::vector<S> p(m.nparam());
  for (int i = 0; i < m.nparam(); ++i) p[i] = S(m.parameters[i].nominal);
  set_parameters(m, ws, p.data());
  std::vector<S> ydot(y.size());
  ASSERT_TRUE(evaluate_rhs(m, ws, S(0.0), y.data(), ydot.data()));
}
}  // namespace

TEST(GeneralConstraints, PositionFormSeesEveryCoordinateAndParameter) {
  const int n = 70;
  const Model m = kanesens::testing::model_from_text(
      scene(n, "{name: g, type: general, position: \"j69.q^2 - p69 + p0*t\"}"));
  ASSERT_EQ(m.nq, n);
  ASSERT_EQ(m.nparam(), n);
  Workspace<double> ws(m);
  std::vector<double> y(2 * n, 0.0);
  y[n - 1] = 0.3;          // j69.q
  y[2 * n - 1] = 2.0;      // j69.u
  evaluate(m, ws, y);
  EXPECT_NEAR(ws.position_residual[0], 0.09 - 0.70, 1e-15);
  EXPECT_NEAR(ws.constraint_matrix(0, n - 1), 0.6, 1e-15);
  EXPECT_NEAR(ws.velocity_residual[0], 0.6 * 2.0 + 0.01, 1e-15);
  EXPECT_NEAR(ws.constraint_bias[0], -2 * 2.0 * 2.0, 1e-14);  // −d²g/dt² at u̇ = 0: −2 u²
  for (int k = 0; k < n - 1; ++k) EXPECT_EQ(ws.constraint_matrix(0, k), 0.0);
  // Same on Dual (Jacobian / sensitivity path), tangent on j69.q.
  Workspace<Dual> wd(m);
  std::vector<Dual> yd(y.begin(), y.end());
  yd[n - 1].d = 1;
  evaluate(m, wd, yd);
  EXPECT_NEAR(wd.position_residual[0].v, 0.09 - 0.70, 1e-15);
  EXPECT_NEAR(wd.position_residual[0].d, 0.6, 1e-15);
}

TEST(GeneralConstraints, VelocityFormSeesEveryCoordinateAndParameter) {
  const int n = 70;
  const Model m = kanesens::testing::model_from_text(
      scene(n, "{name: v, type: general, a: {j69.u: \"p69*j69.q\", j0.u: 1}, a0: \"-p68\"}"));
  Workspace<double> ws(m);
  std::vector<double> y(2 * n, 0.0);
  y[n - 1] = 0.5;
  y[2 * n - 1] = 3.0;
  y[n] = 0.25;  // j0.u
  evaluate(m, ws, y);
  EXPECT_NEAR(ws.constraint_matrix(0, n - 1), 0.70 * 0.5, 1e-15);
  EXPECT_NEAR(ws.velocity_residual[0], 0.70 * 0.5 * 3.0 + 0.25 - 0.69, 1e-15);
  EXPECT_NEAR(ws.constraint_bias[0], -(0.70 * 3.0 * 3.0), 1e-14);  // −(ȧ u) with ȧ = p69 q̇
}

// A constraint row that vanishes at a state gives no multiplier there: evaluate_rhs says so
// (and why) instead of returning λ = 0 as if the constraint held.
TEST(GeneralConstraints, AVanishingRowIsAReportedFailureNotAZeroMultiplier) {
  const Model m = kanesens::testing::model_from_text(scene(2, "{name: g, type: general, position: \"j1.q^2 - p1\"}"));
  Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  std::vector<double> y(4, 0.0), ydot(4);
  RhsFailure why = RhsFailure::none;
  EXPECT_FALSE(evaluate_rhs(m, ws, 0.0, y.data(), ydot.data(), {}, &why));  // A = 2 j1.q = 0
  EXPECT_EQ(why, RhsFailure::constraints_degenerate);
  EXPECT_EQ(ws.constraint_rank, 0);
  y[1] = 0.2;
  EXPECT_TRUE(evaluate_rhs(m, ws, 0.0, y.data(), ydot.data(), {}, &why));
  EXPECT_EQ(why, RhsFailure::none);
  EXPECT_EQ(ws.constraint_rank, 1);
}

}  // namespace KANESENS_UNITY_ID
