// The recorded constraint residuals (KaneProblem::constraint_residuals: max |g| over the holonomic
// rows, max |A u + a0| over all rows) come from the constraints' own stages: they must be those
// of the whole right-hand side's workspace to the bit — planar and 3-D, loop, rolling and
// coupler rows, Baumgarte terms (which change the bias, not the residuals) — and NaN when a
// residual is not finite, never the largest of the finite ones.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/holonomic.hpp"
#include "sim/kane_problem.hpp"
#include "../support/layers.hpp"
#include "kane_test_support.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;

ConstraintOptions baumgarte() {
  ConstraintOptions c;
  c.formulation = ConstraintOptions::Formulation::multipliers;
  c.stabilization = ConstraintOptions::Stabilization::baumgarte;
  return c;
}

TEST(ConstraintResiduals, AreTheRightHandSidesAndNaNWhenNotFinite) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-0.05, 0.05);
  for (const char* scene : {"configs/four_bar.yaml", "configs/slider_crank.yaml", "configs/andrews.yaml",
                            "configs/rolling_disc.yaml", "configs/whipple_bicycle.yaml", "configs/knife_edge.yaml"}) {
    SCOPED_TRACE(scene);
    const Model m = model_from_source_file(scene);
    KaneProblem p(m, {}, baumgarte());
    p.set_sample(SampleInputs(m));
    Workspace<double> ws(m);
    const std::vector<double> params = m.nominal_parameters();
    set_parameters(m, ws, params.data());
    const std::vector<int> holonomic = HolonomicConstraints(m).rows();
    std::vector<double> y(static_cast<std::size_t>(p.size())), ydot(y.size());
    p.initial_state(y.data());
    for (double& v : y) v += uni(rng);  // off the constraints at both levels
    double position = 0, velocity = 0;
    p.constraint_residuals(0.2, y.data(), position, velocity);
    ASSERT_TRUE(evaluate_rhs(m, ws, 0.2, y.data(), ydot.data(), p.dynamics_options()));
    double pos = 0, vel = 0;
    for (int r : holonomic) pos = std::max(pos, std::abs(ws.position_residual[r]));
    for (int r = 0; r < m.nconstraint_rows; ++r) vel = std::max(vel, std::abs(ws.velocity_residual[r]));
    EXPECT_EQ(position, pos);
    EXPECT_EQ(velocity, vel);
    EXPECT_GT(velocity, 0);
    if (!holonomic.empty()) {
      EXPECT_GT(position, 0);
    }
    // A speed that is not finite, one the first row reads: the velocity residual (and the position
    // one, reported together) is NaN, whatever the other rows give.
    int k = 0;
    while (k + 1 < m.nu && ws.constraint_matrix(0, k) == 0) ++k;
    y[static_cast<std::size_t>(m.nq + k)] = std::numeric_limits<double>::quiet_NaN();
    p.constraint_residuals(0.2, y.data(), position, velocity);
    EXPECT_TRUE(std::isnan(velocity));
    EXPECT_TRUE(std::isnan(position));
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
