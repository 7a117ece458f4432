// Samplers: LHS strata, Sobol' against Boost's engine and scipy's published-table points,
// scrambled nets, Halton radical inverses, grid order, Saltelli blocks, Morris steps, and
// order-independence of every design (what makes ensembles identical for any number of ranks).
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/random/sobol.hpp>
#include <cmath>
#include <set>
#include <vector>

#include "study/design.hpp"
#include "study/keyed_permutation.hpp"
#include "study/sobol_points.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::study;
using ks::SamplingMethod;

namespace {

constexpr double sobol_reference[][8] = {
#include "../fixtures/sobol_points.inc"
};

std::vector<ks::VariedInput> uniform_inputs(std::size_t P) {
  std::vector<ks::VariedInput> inputs;
  for (std::size_t k = 0; k < P; ++k) {
    std::string name = "x";  // (not "x" + to_string: GCC 12 -Wrestrict false positive)
    name += std::to_string(k);
    inputs.push_back({name, {ks::Uniform{0.0, 1.0}}});
  }
  return inputs;
}

ks::SamplingSpec spec_of(SamplingMethod m, std::int64_t samples, std::uint64_t seed = 7,
                         bool randomize = false) {
  ks::SamplingSpec s;
  s.method = m;
  s.samples = samples;
  s.seed = seed;
  s.randomize = randomize;
  return s;
}

std::vector<double> unit_row(const ks::Design& d, std::int64_t i) {
  std::vector<double> u(d.dimension());
  d.unit_sample(i, u);
  return u;
}

}  // namespace

TEST(KeyedPermutation, IsABijectionWithItsInverse) {
  for (std::uint64_t n : {1u, 2u, 3u, 5u, 16u, 97u, 1000u, 4097u}) {
    const ks::KeyedPermutation perm(n, 12345 + n);
    std::vector<bool> hit(n, false);
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint64_t j = perm(i);
      ASSERT_LT(j, n);
      EXPECT_FALSE(hit[j]) << "n = " << n << ": " << j << " hit twice";
      hit[j] = true;
      EXPECT_EQ(perm.inverse(j), i);
    }
  }
}

TEST(SobolPoints, RandomAccessEqualsBoostsSequentialEngine) {
  const std::size_t dim = 10;
  const ks::SobolPoints points(dim);
  boost::random::sobol engine(dim);
  for (std::uint64_t n = 0; n < 5000; ++n) {
    for (std::size_t d = 0; d < dim; ++d) {
      // Boost skips the origin: its output vector n is point n + 1.
      ASSERT_EQ(points.bits(n + 1, d), engine()) << "vector " << n << " dim " << d;
    }
  }
  EXPECT_EQ(points.bits(0, 3), 0u);  // the origin
}

TEST(SobolPoints, MatchesPublishedJoeKuoPoints) {
  // Gray-code order 2-D start (Boost's documentation; Joe & Kuo's tables after the origin).
  const ks::SobolPoints two(2);
  const double expected[][2] = {
      {0.5, 0.5}, {0.75, 0.25}, {0.25, 0.75}, {0.375, 0.375}, {0.875, 0.875}};
  for (std::size_t k = 0; k < std::size(expected); ++k) {
    EXPECT_EQ(two.coordinate(k + 1, 0), expected[k][0]);
    EXPECT_EQ(two.coordinate(k + 1, 1), expected[k][1]);
  }
  // 8-D against scipy.stats.qmc.Sobol(scramble=False) (tests/fixtures/gen_sobol_points.py).
  const ks::SobolPoints eight(8);
  for (std::size_t k = 0; k < std::size(sobol_reference); ++k) {
    for (std::size_t d = 0; d < 8; ++d) {
      EXPECT_EQ(eight.coordinate(k, d), sobol_reference[k][d]) << "point " << k << " dim " << d;
    }
  }
}

TEST(Design, SobolRunIIsPointIPlusOneAndNeverTouchesTheFaces) {
  const ks::Design design(spec_of(SamplingMethod::sobol, 63), uniform_inputs(8));
  ASSERT_EQ(design.size(), 63);
  for (std::int64_t i = 0; i < design.size(); ++i) {
    const auto u = unit_row(design, i);
    for (std::size_t d = 0; d < 8; ++d) {
      EXPECT_EQ(u[d], sobol_reference[i + 1][d]);
      EXPECT_GT(u[d], 0.0);
      EXPECT_LT(u[d], 1.0);
    }
  }
}

TEST(Design, ScrambledSobolKeepsTheNetProperty) {
  // The first 2^6 points of Sobol' dimensions 0 and 1 form a (0,6,2)-net: every elementary
  // box 2^-a × 2^-(6-a) holds exactly one point. Owen scrambling preserves this.
  const int m = 6, N = 1 << m;
  for (std::uint64_t seed : {1u, 2u, 99u}) {
    const ks::Design design(spec_of(SamplingMethod::sobol, N, seed, true), uniform_inputs(3));
    for (int a = 0; a <= m; ++a) {
      std::set<std::pair<int, int>> boxes;
      for (std::int64_t i = 0; i < N; ++i) {
        const auto u = unit_row(design, i);
        for (double x : u) {
          EXPECT_GT(x, 0.0);
          EXPECT_LT(x, 1.0);
        }
        boxes.insert({static_cast<int>(u[0] * (1 << a)), static_cast<int>(u[1] * (1 << (m - a)))});
      }
      EXPECT_EQ(boxes.size(), static_cast<std::size_t>(N)) << "seed " << seed << ", a = " << a;
    }
  }
  const ks::Design one(spec_of(SamplingMethod::sobol, N, 1, true), uniform_inputs(3));
  const ks::Design two(spec_of(SamplingMethod::sobol, N, 2, true), uniform_inputs(3));
  EXPECT_NE(unit_row(one, 5), unit_row(two, 5));
}

TEST(Design, LatinHypercubeHasOnePointPerStratum) {
  const std::int64_t N = 97;
  const std::size_t P = 5;
  const ks::Design design(spec_of(SamplingMethod::lhs, N, 2024), uniform_inputs(P));
  std::vector<std::vector<int>> count(P, std::vector<int>(N, 0));
  for (std::int64_t i = 0; i < N; ++i) {
    const auto u = unit_row(design, i);
    for (std::size_t d = 0; d < P; ++d) {
      ASSERT_GT(u[d], 0.0);
      ASSERT_LT(u[d], 1.0);
      ++count[d][static_cast<std::size_t>(u[d] * N)];
    }
  }
  for (std::size_t d = 0; d < P; ++d) {
    for (std::int64_t s = 0; s < N; ++s)
      EXPECT_EQ(count[d][s], 1) << "dim " << d << " stratum " << s;
  }
}

TEST(Design, MonteCarloIsUniformAndSeeded) {
  const std::int64_t N = 20000;
  const ks::Design design(spec_of(SamplingMethod::mc, N, 3), uniform_inputs(2));
  double sum = 0;
  for (std::int64_t i = 0; i < N; ++i) {
    const auto u = unit_row(design, i);
    EXPECT_GT(u[0], 0.0);
    EXPECT_LT(u[1], 1.0);
    sum += u[0];
  }
  // Mean of N uniforms: σ = 1/sqrt(12 N) ≈ 0.002; 6σ is a deterministic-seed sanity bound.
  EXPECT_NEAR(sum / N, 0.5, 0.012);
  const ks::Design other(spec_of(SamplingMethod::mc, N, 4), uniform_inputs(2));
  EXPECT_NE(unit_row(design, 0), unit_row(other, 0));
}

TEST(Design, HaltonIsTheRadicalInverseInPrimeBases) {
  const ks::Design design(spec_of(SamplingMethod::halton, 8), uniform_inputs(3));
  const double expected[][3] = {{1.0 / 2, 1.0 / 3, 1.0 / 5},
                                {1.0 / 4, 2.0 / 3, 2.0 / 5},
                                {3.0 / 4, 1.0 / 9, 3.0 / 5},
                                {1.0 / 8, 4.0 / 9, 4.0 / 5},
                                {5.0 / 8, 7.0 / 9, 1.0 / 25}};
  for (std::size_t i = 0; i < std::size(expected); ++i) {
    const auto u = unit_row(design, static_cast<std::int64_t>(i));
    for (std::size_t d = 0; d < 3; ++d) EXPECT_DOUBLE_EQ(u[d], expected[i][d]);
  }
  const ks::Design shifted(spec_of(SamplingMethod::halton, 500, 5, true), uniform_inputs(3));
  for (std::int64_t i = 0; i < shifted.size(); ++i) {
    for (double x : unit_row(shifted, i)) {
      EXPECT_GT(x, 0.0);
      EXPECT_LT(x, 1.0);
    }
  }
}

TEST(Design, GridIsRowMajorOverCellMidpoints) {
  ks::SamplingSpec spec = spec_of(SamplingMethod::grid, 0);
  spec.grid_levels = 3;
  spec.grid_levels_by_input = {{"b", 2, {}}};
  auto inputs = uniform_inputs(2);
  inputs[0].name = "a";
  inputs[1].name = "b";
  inputs.push_back({"c", ks::make_choice({10, 20, 30, 40})});  // defaults to its 4 values
  inputs.push_back({"d", {ks::Fixed{1.5}}});                   // defaults to 1 level
  const ks::Design design(spec, inputs);
  ASSERT_EQ(design.size(), 3 * 2 * 4 * 1);
  EXPECT_EQ(std::vector<std::int64_t>(design.grid_levels().begin(), design.grid_levels().end()),
            (std::vector<std::int64_t>{3, 2, 4, 1}));
  std::vector<double> v(4);
  std::int64_t i = 0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 2; ++b) {
      for (int c = 0; c < 4; ++c, ++i) {
        const auto u = unit_row(design, i);
        EXPECT_DOUBLE_EQ(u[0], (a + 0.5) / 3);
        EXPECT_DOUBLE_EQ(u[1], (b + 0.5) / 2);
        EXPECT_DOUBLE_EQ(u[2], (c + 0.5) / 4);
        design.sample(i, v);
        EXPECT_EQ(v[2], 10.0 * (c + 1));
        EXPECT_EQ(v[3], 1.5);
      }
    }
  }
  EXPECT_EQ(design.block_label(0), "");
}

TEST(Design, SaltelliBlocksMixAAndBColumnByColumn) {
  const std::size_t P = 3;
  const std::int64_t N = 16;
  const ks::Design design(spec_of(SamplingMethod::saltelli, N), uniform_inputs(P));
  ASSERT_EQ(design.size(), N * static_cast<std::int64_t>(P + 2));
  const ks::SobolPoints base(2 * P);
  for (std::int64_t j = 0; j < N; ++j) {
    const std::int64_t first = j * static_cast<std::int64_t>(P + 2);
    const auto A = unit_row(design, first);
    const auto B = unit_row(design, first + 1);
    EXPECT_EQ(design.block_label(first), "A");
    EXPECT_EQ(design.block_label(first + 1), "B");
    for (std::size_t k = 0; k < P; ++k) {
      // [A | B] is the 2P-dimensional Sobol' point j + 1.
      EXPECT_EQ(A[k], base.coordinate(static_cast<std::uint64_t>(j) + 1, k));
      EXPECT_EQ(B[k], base.coordinate(static_cast<std::uint64_t>(j) + 1, P + k));
    }
    // Columns may coincide (Sobol' point 1 is (½, …, ½), so A_0 = B_0), rows otherwise differ.
    if (j > 0) {
      EXPECT_NE(A, B) << "base point " << j;
    }
    for (std::size_t k = 0; k < P; ++k) {
      const std::int64_t run = first + 2 + static_cast<std::int64_t>(k);
      const auto AB = unit_row(design, run);
      for (std::size_t c = 0; c < P; ++c) EXPECT_EQ(AB[c], c == k ? B[c] : A[c]);
      const ks::SaltelliIndex s = design.saltelli_index(run);
      EXPECT_EQ(s.base, j);
      EXPECT_EQ(s.block, ks::SaltelliBlock::AB);
      EXPECT_EQ(s.input, k);
      EXPECT_EQ(design.block_label(run), "AB" + std::to_string(k));
    }
  }
  EXPECT_THROW(ks::Design(spec_of(SamplingMethod::mc, 4), uniform_inputs(2)).saltelli_index(0),
               std::logic_error);
}

TEST(Design, MorrisStepsChangeOneInputByDelta) {
  const std::size_t P = 4;
  for (std::int64_t p : {2, 4, 6}) {
    ks::SamplingSpec spec = spec_of(SamplingMethod::morris, 0, 11);
    spec.trajectories = 20;
    spec.morris_levels = p;
    const ks::Design design(spec, uniform_inputs(P));
    ASSERT_EQ(design.size(), 20 * static_cast<std::int64_t>(P + 1));
    const double delta = design.morris_delta();
    EXPECT_DOUBLE_EQ(delta, p / (2.0 * (p - 1)));
    const auto pd = static_cast<double>(p);
    for (std::int64_t t = 0; t < 20; ++t) {
      std::set<std::int64_t> changed;
      const std::int64_t first = t * static_cast<std::int64_t>(P + 1);
      EXPECT_EQ(design.morris_step(first).input, -1);
      EXPECT_EQ(design.block_label(first + 1), "traj" + std::to_string(t) + ".step1");
      for (std::int64_t s = 1; s <= static_cast<std::int64_t>(P); ++s) {
        const auto before = unit_row(design, first + s - 1);
        const auto after = unit_row(design, first + s);
        const ks::MorrisStep step = design.morris_step(first + s);
        EXPECT_EQ(step.trajectory, t);
        EXPECT_EQ(step.step, s);
        int differing = 0;
        for (std::size_t k = 0; k < P; ++k) {
          // Back to the classic grid x = (u·p − ½)/(p − 1) to compare with Δ.
          const double dx = (after[k] - before[k]) * pd / (pd - 1);
          if (after[k] != before[k]) {
            ++differing;
            EXPECT_EQ(static_cast<std::int64_t>(k), step.input);
            EXPECT_NEAR(dx, step.sign * delta, 1e-12);
          }
        }
        EXPECT_EQ(differing, 1) << "trajectory " << t << " step " << s;
        changed.insert(step.input);
      }
      EXPECT_EQ(changed.size(), P);  // every input moves once per trajectory
    }
  }
}

// The labels the run file records: checked against the unit points themselves (which
// columns a run shares with A_j and B_j, which one a Morris step changed), not the index maths.
TEST(Design, RunLabelsSayWhereEachRunSits) {
  const std::size_t P = 3;
  const ks::Design saltelli(spec_of(SamplingMethod::saltelli, 8, 3, true), uniform_inputs(P));
  ASSERT_TRUE(saltelli.has_run_labels());
  for (std::int64_t i = 0; i < saltelli.size(); ++i) {
    const ks::RunLabel label = saltelli.run_label(i);
    const std::int64_t first = label.block * static_cast<std::int64_t>(P + 2);
    ASSERT_EQ(first + label.row, i);
    const auto u = unit_row(saltelli, i), a = unit_row(saltelli, first),
               b = unit_row(saltelli, first + 1);
    for (std::size_t k = 0; k < P; ++k) {
      const bool from_b = label.row == 1 || static_cast<std::int64_t>(k) == label.input;
      EXPECT_EQ(u[k], from_b ? b[k] : a[k]) << "run " << i << " column " << k;
    }
    EXPECT_EQ(label.input, label.row >= 2 ? label.row - 2 : -1);
  }
  ks::SamplingSpec spec = spec_of(SamplingMethod::morris, 0, 5);
  spec.trajectories = 6;
  const ks::Design morris(spec, uniform_inputs(P));
  ASSERT_TRUE(morris.has_run_labels());
  for (std::int64_t i = 0; i < morris.size(); ++i) {
    const ks::RunLabel label = morris.run_label(i);
    EXPECT_EQ(label.block * static_cast<std::int64_t>(P + 1) + label.row, i);
    if (label.row == 0) {
      EXPECT_EQ(label.input, -1);
      continue;
    }
    const auto before = unit_row(morris, i - 1), after = unit_row(morris, i);
    for (std::size_t k = 0; k < P; ++k) {
      EXPECT_EQ(after[k] != before[k], static_cast<std::int64_t>(k) == label.input) << "run " << i;
    }
  }
  const ks::Design lhs(spec_of(SamplingMethod::lhs, 5), uniform_inputs(2));
  EXPECT_FALSE(lhs.has_run_labels());
  EXPECT_THROW(lhs.run_label(0), std::logic_error);
}

TEST(Design, SampleIsTheQuantileOfTheUnitSample) {
  std::vector<ks::VariedInput> inputs = {{"m", {ks::Normal{1.0, 0.1}}},
                                         {"k", {ks::LogNormal{0.0, 0.5}}}};
  const ks::Design design(spec_of(SamplingMethod::lhs, 10), inputs);
  std::vector<double> v(2);
  for (std::int64_t i = 0; i < 10; ++i) {
    const auto u = unit_row(design, i);
    design.sample(i, v);
    EXPECT_EQ(v[0], inputs[0].dist.quantile(u[0]));
    EXPECT_EQ(v[1], inputs[1].dist.quantile(u[1]));
  }
}

TEST(Design, RunValuesDoNotDependOnEvaluationOrder) {
  std::vector<ks::SamplingSpec> specs;
  for (SamplingMethod m : {SamplingMethod::mc, SamplingMethod::lhs, SamplingMethod::sobol,
                           SamplingMethod::halton, SamplingMethod::saltelli}) {
    specs.push_back(spec_of(m, 37, 5));
    if (m == SamplingMethod::sobol || m == SamplingMethod::halton) {
      specs.push_back(spec_of(m, 37, 5, true));
    }
  }
  specs.push_back(spec_of(SamplingMethod::grid, 0));
  specs.back().grid_levels = 3;
  specs.push_back(spec_of(SamplingMethod::morris, 0, 5));
  specs.back().trajectories = 6;
  std::vector<ks::VariedInput> inputs = {{"a", {ks::Normal{0, 1}}},
                                         {"b", {ks::TruncNormal{0, 1, -1, 2}}},
                                         {"c", {ks::Triangular{0, 1, 3}}}};
  for (const ks::SamplingSpec& spec : specs) {
    const ks::Design design(spec, inputs);
    const std::int64_t n = design.size();
    std::vector<std::vector<double>> in_order(static_cast<std::size_t>(n), std::vector<double>(3));
    for (std::int64_t i = 0; i < n; ++i) design.sample(i, in_order[static_cast<std::size_t>(i)]);
    std::vector<double> v(3);
    for (std::int64_t i = n; i-- > 0;) {  // reversed
      design.sample(i, v);
      EXPECT_EQ(v, in_order[static_cast<std::size_t>(i)]);
    }
    const ks::Design copy(spec, inputs);  // what another rank builds
    for (std::int64_t R : {2, 3, 7}) {
      for (std::int64_t r = 0; r < R; ++r) {
        for (std::int64_t i = r; i < n; i += R) {  // rank r of R, strided
          copy.sample(i, v);
          EXPECT_EQ(v, in_order[static_cast<std::size_t>(i)])
              << ks::method_name(spec.method) << " run " << i << " rank " << r << "/" << R;
        }
      }
    }
  }
}

TEST(Design, RefusesDesignsItCannotServe) {
  // saltelli: N·(P+2) over the limit, although N itself is allowed.
  EXPECT_THROW(ks::Design(spec_of(SamplingMethod::saltelli, 400'000'000), uniform_inputs(2)),
               kanesens::InputError);
  EXPECT_THROW(ks::Design(spec_of(SamplingMethod::saltelli, 10), {}), kanesens::InputError);
  EXPECT_THROW(ks::Design(spec_of(SamplingMethod::sobol, 10),
                          uniform_inputs(ks::SobolPoints::max_dimension() + 1)),
               kanesens::InputError);
  ks::SamplingSpec grid = spec_of(SamplingMethod::grid, 0);
  grid.grid_levels_by_input = {{"x7", 3, {"s.yaml", 4, 12}}};
  try {
    ks::Design(grid, uniform_inputs(2));
    ADD_FAILURE() << "no error for an unknown input in grid levels";
  } catch (const kanesens::InputError& e) {
    EXPECT_EQ(e.where().line, 4);
    EXPECT_EQ(e.key_path(), "sampling.levels.x7");
    EXPECT_NE(e.detail().find("varied inputs are: x0, x1"), std::string::npos) << e.what();
  }
  grid.grid_levels_by_input.clear();  // neither `levels: N` nor a map entry for x0
  EXPECT_THROW(ks::Design(grid, uniform_inputs(2)), kanesens::InputError);
  EXPECT_THROW(ks::Design(spec_of(SamplingMethod::mc, 5), {{"m", {ks::Uniform{2, 1}}}}),
               std::invalid_argument);
}

}  // namespace KANESENS_UNITY_ID
