// The velocity-level constraint matrix A must be the derivative of the position residual g:
// ġ = G q̇ = G N(q) u for holonomic rows, so G N = A, checked here against central differences of
// g (not against the code that forms A). KaneProblem::project relies on it: for scenes without
// quaternions (N = I) it takes G = A instead of differentiating g with nq dual evaluations.
// Also MinNormSolver, the minimum-norm solve of those projections, against Eigen's complete
// orthogonal decomposition, and its fallback on rank-deficient (redundant) rows.
#include <gtest/gtest.h>

#include <random>

#include "dynamics/equations.hpp"
#include "kane_test_support.hpp"
#include "math/min_norm_solver.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;
using kanesens::testing::qdot_of;

namespace {

struct Evaluated {
  Eigen::VectorXd g;  // all rows (0 for nonholonomic ones)
  Eigen::MatrixXd A;
};

Evaluated constraints_at(const Model& m, Workspace<double>& ws, const std::vector<double>& q) {
  const std::vector<double> u(m.nu, 0.0);
  evaluate_state_expressions(m, ws, 0.0, q.data(), u.data());
  compute_position(m, ws, q.data());
  compute_velocity(m, ws, u.data());
  compute_kinematic_derivatives(m, ws, q.data(), u.data());
  compute_constraints(m, ws, q.data(), u.data());
  return {ws.position_residual, ws.constraint_matrix};
}

// A free rod (quaternion coordinates, q̇ = N(q) u with N ≠ I) held at one end by a coincident
// constraint to the ground: a spherical pendulum closed by 3 holonomic rows.
const char* const kFreeRodOnAPoint = R"(kanesens: 1
scene:
  name: free_rod_on_a_point
  gravity: [0, -9.81, 0]
  bodies:
    - {name: rod, mass: 1.0, inertia: {shape: rod, length: 1.0, axis: x}}
  joints:
    - {name: base, type: free, parent: ground, child: rod}
  constraints:
    - {name: tip, type: coincident, body_a: rod, point_a: [-0.5, 0, 0], body_b: ground, point_b: [0.2, 0.1, 0]}
)";

Model scene_model(const std::string& which) {
  if (which == "free_rod_on_a_point") return kanesens::testing::model_from_text(kFreeRodOnAPoint);
  return build_model(parse_scene_file(std::string(KANESENS_SOURCE_DIR) + "/configs/" + which));
}

class ConstraintJacobian : public ::testing::TestWithParam<const char*> {};

TEST_P(ConstraintJacobian, HolonomicRowsOfAAreTheDerivativeOfG) {
  const Model m = scene_model(GetParam());
  ASSERT_GT(m.nconstraint_rows, 0);
  Workspace<double> ws(m);
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  int holonomic_rows = 0;
  double worst = 0;
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> q(m.nq);
    for (double& v : q) v = uni(rng);
    for (const Joint& J : m.joints)
      if (J.quaternion_offset >= 0) {
        double* e = q.data() + J.quaternion_offset;
        const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
        for (int k = 0; k < 4; ++k) e[k] /= n;
      }
    const Evaluated at = constraints_at(m, ws, q);
    // G by 4th-order central differences of g; N(q) column by column from unit speeds.
    const double h = 1e-3;
    Eigen::MatrixXd G(m.nconstraint_rows, m.nq);
    for (int i = 0; i < m.nq; ++i) {
      auto g_at = [&](double dx) {
        std::vector<double> qs = q;
        qs[i] += dx;
        return constraints_at(m, ws, qs).g;
      };
      G.col(i) = (8 * (g_at(h) - g_at(-h)) - (g_at(2 * h) - g_at(-2 * h))) / (12 * h);
    }
    Eigen::MatrixXd N(m.nq, m.nu);
    for (int k = 0; k < m.nu; ++k) {
      std::vector<double> u(m.nu, 0.0);
      u[k] = 1;
      const std::vector<double> qd = qdot_of(m, q.data(), u.data());
      for (int i = 0; i < m.nq; ++i) N(i, k) = qd[i];
    }
    const Eigen::MatrixXd GN = G * N;
    holonomic_rows = 0;
    for (const Constraint& c : m.constraints)
      for (int r = 0; r < c.nrows; ++r) {
        if (!c.holonomic[r]) continue;
        ++holonomic_rows;
        const int row = c.row_offset + r;
        const double scale = std::max(1.0, at.A.row(row).lpNorm<Eigen::Infinity>());
        const double diff = (GN.row(row) - at.A.row(row)).lpNorm<Eigen::Infinity>() / scale;
        worst = std::max(worst, diff);
        EXPECT_LT(diff, 1e-9) << GetParam() << " row " << row << "\nG N = " << GN.row(row) << "\nA   = " << at.A.row(row);
      }
  }
  EXPECT_GT(holonomic_rows, 0) << GetParam() << " has no holonomic rows: the test checks nothing";
  std::cout << GetParam() << ": worst |G N − A| / max(1, |A|) = " << worst << "\n";
}

INSTANTIATE_TEST_SUITE_P(Scenes, ConstraintJacobian,
                         ::testing::Values("four_bar.yaml", "andrews.yaml", "slider_crank.yaml",
                                           "constrained_pendulum.yaml", "parallelogram_four_bar.yaml",
                                           "free_rod_on_a_point"));

TEST(MinNormSolver, MatchesCompleteOrthogonalDecomposition) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  MinNormSolver s;
  for (const auto& [rows, cols] : {std::pair{1, 3}, std::pair{2, 3}, std::pair{5, 7}, std::pair{3, 3}}) {
    Eigen::MatrixXd J(rows, cols);
    Eigen::VectorXd r(rows), x;
    for (auto& v : J.reshaped()) v = normal(rng);
    for (auto& v : r) v = normal(rng);
    s.compute(J);
    EXPECT_TRUE(s.used_cholesky());
    s.solve(r, x);
    const Eigen::VectorXd expected = J.completeOrthogonalDecomposition().solve(r);
    EXPECT_LT((x - expected).norm(), 1e-12 * expected.norm()) << rows << "×" << cols;
    Eigen::VectorXd e(cols);
    for (auto& v : e) v = normal(rng);
    const Eigen::VectorXd e0 = e;
    s.remove_normal_component(e);
    EXPECT_LT((J * e).norm(), 1e-12 * e0.norm());                               // tangent
    EXPECT_LT(((e0 - e) - J.transpose() * (J * J.transpose()).ldlt().solve(J * e0)).norm(), 1e-12 * e0.norm());
  }
}

TEST(MinNormSolver, SparseJacobianMatchesCompleteOrthogonalDecomposition) {
  // The N four-bar's pattern (loop i: crank i, coupler i, crank i+1, two rows each) with random
  // entries: J Jᵀ is summed from J's nonzeros and factored in its envelope.
  const int n = 12, rows = 2 * n, cols = 2 * n + 1;
  std::mt19937 rng(9);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, cols);
  for (int i = 0; i < n; ++i)
    for (int r = 2 * i; r < 2 * i + 2; ++r)
      for (int k : {i, n + 1 + i, i + 1}) J(r, k) = normal(rng);
  Eigen::VectorXd r(rows), x;
  for (auto& v : r) v = normal(rng);
  MinNormSolver s;
  s.compute(J);
  EXPECT_TRUE(s.used_cholesky());
  s.solve(r, x);
  // The dense normal equations agree to round-off; the orthogonal decomposition to round-off
  // times J's condition number.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J);
  const double cond = svd.singularValues()(0) / svd.singularValues()(rows - 1);
  const Eigen::VectorXd dense = J.transpose() * (J * J.transpose()).llt().solve(r);
  EXPECT_LT((x - dense).norm(), 1e-15 * cond * cond * dense.norm()) << "cond(J) = " << cond;
  const Eigen::VectorXd expected = J.completeOrthogonalDecomposition().solve(r);
  EXPECT_LT((x - expected).norm(), 1e-14 * cond * cond * expected.norm()) << "cond(J) = " << cond;
  EXPECT_LT((J * x - r).norm(), 1e-12 * cond * r.norm());
  Eigen::VectorXd e(cols);
  for (auto& v : e) v = normal(rng);
  const Eigen::VectorXd e0 = e;
  s.remove_normal_component(e);
  EXPECT_LT((J * e).norm(), 1e-12 * cond * e0.norm());
  // A redundant (repeated) row still goes the careful way.
  J.row(5) = J.row(4);
  s.compute(J);
  EXPECT_FALSE(s.used_cholesky());
}

TEST(MinNormSolver, RedundantRowsFallBackToTheOrthogonalDecomposition) {
  // A repeated constraint row (a redundant closure): J Jᵀ is singular, the Cholesky path must not
  // be used, and the solution is still the minimum-norm one of the consistent system.
  Eigen::MatrixXd J(3, 4);
  J << 1, 2, 0, -1,  //
      0, 1, 3, 1,    //
      1, 2, 0, -1;
  const Eigen::VectorXd r = Eigen::Vector3d(0.5, -0.2, 0.5);
  MinNormSolver s;
  s.compute(J);
  EXPECT_FALSE(s.used_cholesky());
  Eigen::VectorXd x;
  s.solve(r, x);
  EXPECT_LT((J * x - r).norm(), 1e-14);
  const Eigen::MatrixXd J2 = J.topRows(2);
  const Eigen::VectorXd x2 = J2.transpose() * (J2 * J2.transpose()).ldlt().solve(r.head(2));
  EXPECT_LT((x - x2).norm(), 1e-14);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
