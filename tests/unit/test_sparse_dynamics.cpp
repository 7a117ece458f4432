// The tree-sparse mass-matrix factor and the sparse constraint solve give the dense path's
// numbers to round-off: on the IFToMM N four-bar (planar and 3-D evaluation, random, consistent
// and exactly singular configurations) and on a branched 3-D tree, on double and on Dual and
// MultiDual tangents. The dense path is itself checked against SymPy and closed forms
// (test_kane_golden, test_kane_closed_forms).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "dynamics/embedding.hpp"
#include "dynamics/equations.hpp"
#include "math/multi_dual.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "test_scenes.hpp"

namespace kanesens {
namespace {

using dynamics::Workspace;
using math::Dual;
using math::MultiDual;
using model::Model;

Model build(const std::string& text) { return model::build_model(model::parse_scene_text(text, "scene.yaml")); }

// A 3-D tree with three branches on a ball-jointed torso, closed by a distance between two branch
// tips and a coincident of the third tip with a ground point.
const char* kBranchedTree = R"yaml(kanesens: 1
scene:
  name: branched
  gravity: [0, 0, -9.81]
  bodies:
    - {name: torso, mass: 4, inertia: {shape: box, size: [0.3, 0.2, 0.6]}}
    - {name: a1, mass: 1, inertia: {shape: rod, length: 0.5, axis: x}}
    - {name: a2, mass: 0.8, inertia: {shape: rod, length: 0.4, axis: x}}
    - {name: a3, mass: 0.3, inertia: {shape: sphere, radius: 0.05}}
    - {name: b1, mass: 1.2, inertia: {shape: rod, length: 0.5, axis: y}}
    - {name: b2, mass: 0.7, inertia: {shape: box, size: [0.1, 0.4, 0.1]}}
    - {name: c1, mass: 1.5, inertia: {shape: cylinder, radius: 0.05, length: 0.6, axis: z}}
    - {name: c2, mass: 0.9, inertia: {shape: rod, length: 0.5, axis: z}}
  joints:
    - {name: waist, type: spherical, parent: ground, child: torso, parent_point: [0, 0, 1], child_point: [0, 0, -0.3]}
    - {name: sa, type: revolute, parent: torso, child: a1, axis: [0, 1, 0], parent_point: [0.15, 0, 0.3], child_point: [-0.25, 0, 0]}
    - {name: ea, type: universal, parent: a1, child: a2, axes: [[0, 0, 1], [0, 1, 0]], parent_point: [0.25, 0, 0], child_point: [-0.2, 0, 0]}
    - {name: wa, type: revolute, parent: a2, child: a3, axis: [1, 0.3, 0], parent_point: [0.2, 0, 0]}
    - {name: sb, type: revolute, parent: torso, child: b1, axis: [1, 0, 0], parent_point: [0, 0.1, 0.3], child_point: [0, -0.25, 0]}
    - {name: eb, type: prismatic, parent: b1, child: b2, axis: [0, 1, 0], parent_point: [0, 0.25, 0], child_point: [0, -0.2, 0]}
    - {name: hc, type: revolute, parent: torso, child: c1, axis: [1, 0, 0], parent_point: [0, 0, -0.3], child_point: [0, 0, 0.3]}
    - {name: kc, type: revolute, parent: c1, child: c2, axis: [0, 1, 0.2], parent_point: [0, 0, -0.3], child_point: [0, 0, 0.25]}
  constraints:
    - {name: grip, type: distance, body_a: a3, body_b: b2, point_b: [0, 0.2, 0], length: 0.7}
    - {name: foot, type: coincident, body_a: c2, point_a: [0, 0, -0.25], body_b: ground, point_b: [0.1, 0, 0.2]}
)yaml";

struct Paths {
  bool tree_factor, sparse_constraints;
};

template <class S>
std::vector<S> rhs(const Model& m, const std::vector<S>& y, Paths paths, int* rank = nullptr, std::vector<S>* lambda = nullptr) {
  Workspace<S> ws(m);
  ws.tree_factor = paths.tree_factor;
  ws.sparse_constraints = paths.sparse_constraints;
  const std::vector<double> p0 = m.nominal_parameters();
  const std::vector<S> p(p0.begin(), p0.end());
  dynamics::set_parameters(m, ws, p.data());
  std::vector<S> ydot(y.size());
  EXPECT_TRUE(dynamics::evaluate_rhs(m, ws, S(0.3), y.data(), ydot.data()));
  if (rank) *rank = ws.constraint_rank;
  if (lambda) lambda->assign(ws.multipliers.data(), ws.multipliers.data() + m.nconstraint_rows);
  return ydot;
}

// Largest |a − b| over values and tangents, relative to the largest |b|.
template <class S>
double relative_difference(const std::vector<S>& a, const std::vector<S>& b) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if constexpr (std::is_same_v<S, double>) {
      diff = std::max(diff, std::abs(a[i] - b[i]));
      scale = std::max(scale, std::abs(b[i]));
    } else if constexpr (std::is_same_v<S, Dual>) {
      diff = std::max({diff, std::abs(a[i].v - b[i].v), std::abs(a[i].d - b[i].d)});
      scale = std::max({scale, std::abs(b[i].v), std::abs(b[i].d)});
    } else {
      diff = std::max(diff, std::abs(a[i].v - b[i].v));
      scale = std::max(scale, std::abs(b[i].v));
      for (int t = 0; t < S::tangents; ++t) {
        diff = std::max(diff, std::abs(a[i].d(t) - b[i].d(t)));
        scale = std::max(scale, std::abs(b[i].d(t)));
      }
    }
  }
  return diff / std::max(scale, 1.0);
}

// y with tangents: Dual seeds state `seed`, MultiDual<K> seeds states seed..seed+K−1.
template <class S>
std::vector<S> seeded(const std::vector<double>& y, int seed) {
  std::vector<S> out(y.begin(), y.end());
  if constexpr (std::is_same_v<S, Dual>) {
    out[static_cast<std::size_t>(seed) % y.size()].d = 1;
  } else if constexpr (!std::is_same_v<S, double>) {
    for (int t = 0; t < S::tangents; ++t) out[static_cast<std::size_t>(seed + t) % y.size()].set_d(t, 1.0);
  }
  return out;
}

template <class S>
void expect_paths_agree(const Model& m, const std::vector<double>& y, int seed, double tol, const std::string& what) {
  const std::vector<S> ys = seeded<S>(y, seed);
  int rank_sparse = 0, rank_dense = 0;
  std::vector<S> lam_sparse, lam_dense;
  const auto sparse = rhs<S>(m, ys, {true, true}, &rank_sparse, &lam_sparse);
  const auto dense = rhs<S>(m, ys, {false, false}, &rank_dense, &lam_dense);
  EXPECT_LE(relative_difference(sparse, dense), tol) << what;
  EXPECT_LE(relative_difference(lam_sparse, lam_dense), tol) << what << " (multipliers)";
  EXPECT_EQ(rank_sparse, rank_dense) << what;
  // The tree factor alone (dense constraint solve) agrees too.
  EXPECT_LE(relative_difference(rhs<S>(m, ys, {true, false}), dense), tol) << what << " (tree factor only)";
}

// Crank angles φ, coupler angles −φ (relative), speeds consistent with the loops, perturbed by
// `noise` (0: on the constraint manifold).
std::vector<double> four_bar_state(const Model& m, int n, double phi, double rate, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> uni(-1, 1);
  std::vector<double> y(static_cast<std::size_t>(m.nstate()));
  for (int i = 0; i <= n; ++i) {
    y[static_cast<std::size_t>(i)] = phi + noise * uni(rng);
    y[static_cast<std::size_t>(m.nq + i)] = rate + noise * uni(rng);
  }
  for (int i = 0; i < n; ++i) {
    y[static_cast<std::size_t>(n + 1 + i)] = -phi + noise * uni(rng);
    y[static_cast<std::size_t>(m.nq + n + 1 + i)] = -rate + noise * uni(rng);
  }
  return y;
}

TEST(SparseDynamics, ModelCarriesTheSpeedTree) {
  const Model m = build(test_scenes::n_four_bar(3));
  // Cranks 0..3 are speeds 0..3 (roots); coupler i (speed 4 + i) hangs from crank i.
  EXPECT_EQ(m.speed_parent, (std::vector<int>{-1, -1, -1, -1, 0, 1, 2}));
  ASSERT_EQ(m.speed_order.size(), 7u);
  for (std::size_t s = 0; s < m.speed_order.size(); ++s) {
    const int p = m.speed_parent[static_cast<std::size_t>(m.speed_order[s])];
    if (p >= 0) {
      EXPECT_LT(std::find(m.speed_order.begin(), m.speed_order.end(), p) - m.speed_order.begin(), static_cast<std::ptrdiff_t>(s));
    }
  }
  const Model tree = build(kBranchedTree);  // waist has 3 speeds, ea 2
  EXPECT_EQ(tree.speed_parent[0], -1);
  EXPECT_EQ(tree.speed_parent[1], 0);
  EXPECT_EQ(tree.speed_parent[2], 1);
  EXPECT_EQ(tree.speed_parent[3], 2);  // sa under the waist's last speed
}

TEST(SparseDynamics, FourBarWorkspaceChoosesTheSparsePaths) {
  const Model m = build(test_scenes::n_four_bar(10));
  Workspace<double> ws(m);
  EXPECT_TRUE(ws.tree_factor);
  EXPECT_TRUE(ws.sparse_constraints);
  const Model m6 = build(test_scenes::n_four_bar(6));  // test_no_allocation's scene
  Workspace<double> w6(m6);
  EXPECT_TRUE(w6.sparse_constraints);
  // Loop i touches crank i, coupler i, crank i+1: the envelope is a band.
  const auto& sp = ws.constraint_sparsity;
  for (int i = 0; i < m.nconstraint_rows; ++i) {
    EXPECT_EQ(sp.closure_start[static_cast<std::size_t>(i) + 1] - sp.closure_start[static_cast<std::size_t>(i)], 3);
    // Below them: coupler i+1 too, except for the last loop (crank N carries no coupler).
    EXPECT_EQ(sp.support_start[static_cast<std::size_t>(i) + 1] - sp.support_start[static_cast<std::size_t>(i)], i / 2 == 9 ? 3 : 4);
    EXPECT_GE(sp.envelope_first[static_cast<std::size_t>(i)], std::max(0, 2 * (i / 2) - 2));
  }
  // A chain keeps the dense factor.
  const Model chain = build(
      "kanesens: 1\nscene:\n  name: c\n  bodies:\n    - {name: a, mass: 1, inertia: {shape: rod, length: 1, axis: x}}\n"
      "    - {name: b, mass: 1, inertia: {shape: rod, length: 1, axis: x}}\n  joints:\n"
      "    - {name: j1, type: revolute, parent: ground, child: a, axis: [0, 0, 1]}\n"
      "    - {name: j2, type: revolute, parent: a, child: b, axis: [0, 0, 1], parent_point: [0.5, 0, 0]}\n");
  Workspace<double> wc(chain);
  EXPECT_FALSE(wc.tree_factor);
  EXPECT_FALSE(wc.sparse_constraints);
}

class FourBarPaths : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(FourBarPaths, SparseEqualsDense) {
  const auto [n, general_3d] = GetParam();
  Model m = build(test_scenes::n_four_bar(n));
  m.force_general_3d = general_3d;
  std::mt19937 rng(static_cast<unsigned>(7 + n));
  struct Case {
    double phi, rate, noise;
    const char* what;
  };
  const Case cases[] = {{0.7, -1.4, 0.0, "consistent"},
                        {0.3, 0.8, 0.5, "random"},
                        {-2.1, 2.0, 1.0, "random, large"},
                        {0.0, 0.0, 0.0, "horizontal at rest (singular)"},
                        {0.0, -1.4, 0.0, "horizontal, moving (singular)"},
                        {1e-5, -1.4, 0.0, "near the singular configuration"}};
  int seed = 0;
  for (const Case& c : cases) {
    const std::vector<double> y = four_bar_state(m, n, c.phi, c.rate, c.noise, rng);
    const std::string what = std::string(c.what) + ", N = " + std::to_string(n) + (general_3d ? ", 3-D" : ", planar");
    // Near the singular configuration A M⁻¹ Aᵀ has a condition number ~1e10: round-off grows by it.
    const double tol = c.phi == 1e-5 ? 1e-5 : 1e-11;
    expect_paths_agree<double>(m, y, seed, tol, what);
    expect_paths_agree<Dual>(m, y, seed, tol, what + " (Dual)");
    expect_paths_agree<MultiDual<4>>(m, y, seed, tol, what + " (MultiDual<4>)");
    seed += 3;
  }
  // At the singular configuration the rank drops by N: the sparse path hands over to the dense
  // path's minimum-norm multipliers.
  int rank = 0;
  rhs<double>(m, four_bar_state(m, n, 0.0, -1.4, 0.0, rng), {true, true}, &rank);
  EXPECT_EQ(rank, n);
  rhs<double>(m, four_bar_state(m, n, 0.7, -1.4, 0.0, rng), {true, true}, &rank);
  EXPECT_EQ(rank, 2 * n);
}

INSTANTIATE_TEST_SUITE_P(SeveralN, FourBarPaths,
                         ::testing::Combine(::testing::Values(1, 2, 5, 12), ::testing::Values(false, true)));

// The embedding's banded LU of A_d: its band does not grow with N, it gives the dense LU's
// numbers (A_d's natural column order, full band) on double and Dual tangents, and on the
// constraint manifold its u̇_i equals the multiplier formulation's u̇ at the independent speeds.
template <class S>
std::vector<S> embedded(const Model& m, dynamics::EmbeddingScratch<S>& sc, const dynamics::EmbeddingSets& sets,
                        const std::vector<S>& reduced) {
  Workspace<S> ws(m);
  const std::vector<double> p0 = m.nominal_parameters();
  const std::vector<S> p(p0.begin(), p0.end());
  dynamics::set_parameters(m, ws, p.data());
  std::vector<S> ydot(reduced.size());
  EXPECT_TRUE(dynamics::embedded_rhs(m, ws, sc, sets, S(0.3), reduced.data(), ydot.data()));
  return ydot;
}

template <class S>
void expect_embedding_agrees(const Model& m, const std::vector<double>& y, int seed, const std::string& what) {
  Workspace<double> w0(m);
  const std::vector<double> p0 = m.nominal_parameters();
  dynamics::set_parameters(m, w0, p0.data());
  dynamics::evaluate_constraints(m, w0, 0.3, y.data(), y.data() + m.nq);
  const Eigen::MatrixXd A = w0.constraint_matrix;
  const dynamics::EmbeddingSets sets = dynamics::choose_embedding(A);
  dynamics::EmbeddingScratch<S> banded(m, sets), dense(m, sets);
  EXPECT_LE(banded.lower_band, 3) << what;
  EXPECT_LE(banded.upper_band, 3) << what;
  dense.dependent_speed = sets.dependent;
  dense.lower_band = dense.upper_band = std::max(0, static_cast<int>(sets.dependent.size()) - 1);
  const std::vector<S> full = seeded<S>(y, seed);
  std::vector<S> reduced(full.begin(), full.begin() + m.nq);
  for (int k : sets.independent) reduced.push_back(full[static_cast<std::size_t>(m.nq + k)]);
  const std::vector<S> ydot = embedded(m, banded, sets, reduced);
  EXPECT_LE(relative_difference(ydot, embedded(m, dense, sets, reduced)), 1e-11) << what << " (dense LU)";
  if constexpr (std::is_same_v<S, double>) {
    const std::vector<S> ref = rhs<S>(m, full, {false, false});
    std::vector<S> expected(ref.begin(), ref.begin() + m.nq);
    for (int k : sets.independent) expected.push_back(ref[static_cast<std::size_t>(m.nq + k)]);
    EXPECT_LE(relative_difference(ydot, expected), 1e-9) << what << " (multipliers)";
  }
}

TEST(SparseDynamics, EmbeddingBandedLuAgreesWithMultipliers) {
  for (int n : {1, 3, 12}) {
    const Model m = build(test_scenes::n_four_bar(n));
    std::mt19937 rng(5);
    const std::vector<double> y = four_bar_state(m, n, 0.7, -1.4, 0.0, rng);
    expect_embedding_agrees<double>(m, y, 0, "N = " + std::to_string(n));
    expect_embedding_agrees<Dual>(m, y, 1, "N = " + std::to_string(n) + " (Dual)");
  }
}

TEST(SparseDynamics, BranchedTreeSparseEqualsDense) {
  const Model m = build(kBranchedTree);
  ASSERT_FALSE(m.planar);
  Workspace<double> ws(m);
  EXPECT_TRUE(ws.tree_factor);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1, 1);
  for (int s = 0; s < 4; ++s) {
    std::vector<double> y(static_cast<std::size_t>(m.nstate()));
    for (double& v : y) v = uni(rng);
    // Unit quaternion of the waist (its 4 coordinates come first).
    const double norm = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]);
    for (int i = 0; i < 4; ++i) y[static_cast<std::size_t>(i)] /= norm;
    // The tangents of u̇ go through M⁻¹ twice (u̇' = M⁻¹(f' − M' u̇)), so their round-off is
    // larger than the values'.
    const std::string what = "branched tree, state " + std::to_string(s);
    // Two factorisations of M (tree and dense) agree to round-off amplified by M's condition
    // number (about 2e4 at these states): allow 10 κ(M) ε, which the ordering of the vectorised
    // sums of a build for AVX-512 approaches (3 κ ε at one state).
    Workspace<double> w(m);
    std::vector<double> ydot(y.size());
    dynamics::set_parameters(m, w, m.nominal_parameters().data());
    ASSERT_TRUE(dynamics::evaluate_rhs(m, w, 0.3, y.data(), ydot.data()));
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(w.mass_matrix).eigenvalues();
    const double condition = eig.maxCoeff() / eig.minCoeff();
    ASSERT_LT(condition, 1e6) << what;
    const double tol = 10 * condition * std::numeric_limits<double>::epsilon();
    expect_paths_agree<double>(m, y, s, tol, what);
    expect_paths_agree<Dual>(m, y, s, 1e-10, what + " (Dual)");
    expect_paths_agree<MultiDual<8>>(m, y, s, 1e-10, what + " (MultiDual<8>)");
  }
}

}  // namespace
}  // namespace kanesens
