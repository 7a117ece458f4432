// Parsing of the study's `sampling:` and `vary:` sections: defaults, every distribution, and
// error messages that point at the right line, column and key path.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <functional>

#include "study/design.hpp"
#include "study/parse_sampling.hpp"
#include "study/parse_vary.hpp"
#include "util/did_you_mean.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::study;
using kanesens::InputError;
using ks::SamplingMethod;

namespace {

const kanesens::SourceLocation file{"study.yaml"};

ks::SamplingSpec sampling(const std::string& yaml) {
  return ks::parse_sampling(YAML::Load(yaml)["sampling"], file);
}
std::vector<ks::VariedInput> vary(const std::string& yaml) {
  return ks::parse_vary(YAML::Load(yaml)["vary"], file);
}

// Runs `f`, expects an InputError at study.yaml:line:column for `key`, whose message contains
// `part`.
void expect_error(const std::function<void()>& f, int line, int column, const std::string& key,
                  const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one for " << key;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "study.yaml") << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().column, column) << e.what();
    EXPECT_EQ(e.key_path(), key) << e.what();
    EXPECT_NE(e.detail().find(part), std::string::npos) << e.what() << "\nexpected: " << part;
  }
}

}  // namespace

TEST(DidYouMean, SuggestsCloseKeysOnly) {
  EXPECT_EQ(kanesens::edit_distance("hgih", "high"), 1u);  // a transposition
  EXPECT_EQ(kanesens::edit_distance("kitten", "sitting"), 3u);
  const std::string_view keys[] = {"dist", "low", "high"};
  EXPECT_EQ(kanesens::closest_match("hgih", keys), "high");
  EXPECT_EQ(kanesens::closest_match("lo", keys), "low");
  EXPECT_EQ(kanesens::closest_match("mean", keys), "");
  EXPECT_EQ(kanesens::did_you_mean("hgih", keys), " (did you mean 'high'?)");
  EXPECT_EQ(kanesens::did_you_mean("xyz", keys), "");
}

TEST(ParseSampling, ReadsTheDesignExample) {
  const auto s = sampling("sampling: {method: sobol, samples: 1024, seed: 42}");
  EXPECT_EQ(s.method, SamplingMethod::sobol);
  EXPECT_EQ(s.samples, 1024);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_FALSE(s.randomize);
  EXPECT_EQ(s.where.line, 1);
  EXPECT_EQ(s.where.column, 11);
}

TEST(ParseSampling, DefaultsToMonteCarloWithSeedZero) {
  const auto s = sampling("sampling: {samples: 1e3}");
  EXPECT_EQ(s.method, SamplingMethod::mc);
  EXPECT_EQ(s.samples, 1000);
  EXPECT_EQ(s.seed, 0u);
}

TEST(ParseSampling, ReadsEveryMethodsOptions) {
  auto s = sampling("sampling: {method: saltelli, samples: 256, base: halton, randomize: yes}");
  EXPECT_EQ(s.method, SamplingMethod::saltelli);
  EXPECT_EQ(s.base, SamplingMethod::halton);
  EXPECT_TRUE(s.randomize);
  s = sampling("sampling: {method: morris, trajectories: 20, levels: 6, seed: 3}");
  EXPECT_EQ(s.trajectories, 20);
  EXPECT_EQ(s.morris_levels, 6);
  s = sampling("sampling: {method: morris, trajectories: 20}");
  EXPECT_EQ(s.morris_levels, 4);
  s = sampling("sampling: {method: grid, levels: 5}");
  EXPECT_EQ(s.grid_levels, 5);
  s = sampling("sampling:\n  method: grid\n  levels: {m2: 3, shoulder.q0: 7}\n");
  ASSERT_EQ(s.grid_levels_by_input.size(), 2u);
  EXPECT_EQ(s.grid_levels_by_input[1].input, "shoulder.q0");
  EXPECT_EQ(s.grid_levels_by_input[1].levels, 7);
  EXPECT_EQ(s.grid_levels_by_input[1].where.line, 3);
}

TEST(ParseSampling, ErrorsPointAtTheOffendingKey) {
  expect_error([] { sampling("sampling:\n  method: sobl\n  samples: 8\n"); }, 2, 11,
               "sampling.method", "did you mean 'sobol'?");
  expect_error([] { sampling("sampling:\n  samples: 8\n  sead: 3\n"); }, 3, 3, "sampling.sead",
               "unknown key 'sead' (did you mean 'seed'?)");
  expect_error([] { sampling("sampling: {method: mc, samples: 4, randomize: true}"); }, 1, 36,
               "sampling.randomize", "does not apply to method mc");
  expect_error([] { sampling("sampling: {method: sobol, seed: 1}"); }, 1, 11, "sampling",
               "missing key 'samples'");
  expect_error([] { sampling("sampling:\n  samples: 0\n"); }, 2, 12, "sampling.samples",
               "expected an integer in [1, 1000000000], got 0");
  expect_error([] { sampling("sampling:\n  samples: 2000000000\n"); }, 2, 12, "sampling.samples",
               "likely typo");
  expect_error([] { sampling("sampling:\n  samples: 10.5\n"); }, 2, 12, "sampling.samples",
               "expected an integer, got '10.5'");
  expect_error([] { sampling("sampling:\n  samples: 10\n  seed: -1\n"); }, 3, 9, "sampling.seed",
               "non-negative integer");
  expect_error([] { sampling("sampling:\n  method: sobol\n  samples: 8\n  randomize: maybe\n"); },
               4, 14, "sampling.randomize", "expected true or false, got 'maybe'");
  expect_error(
      [] { sampling("sampling: {method: saltelli, samples: 8, base: lhs, randomize: true}"); }, 1,
      64, "sampling.randomize", "sobol or halton base");
  expect_error([] { sampling("sampling: {method: saltelli, samples: 8, base: grid}"); }, 1, 48,
               "sampling.base", "expected a base sequence");
  expect_error([] { sampling("sampling:\n  method: morris\n  levels: 4\n"); }, 2, 3, "sampling",
               "missing key 'trajectories'");
  expect_error([] { sampling("sampling:\n  method: morris\n  trajectories: 5\n  levels: 3\n"); }, 4,
               11, "sampling.levels", "even number of levels");
  expect_error([] { sampling("sampling:\n  method: grid\n  levels: {m2: 0}\n"); }, 3, 16,
               "sampling.levels.m2", "expected an integer in [1,");
  expect_error([] { sampling("sampling:\n  samples: 4\n  samples: 5\n"); }, 3, 3,
               "sampling.samples", "given twice");
  expect_error([] { sampling("sampling: [mc, 4]"); }, 1, 11, "sampling", "expected a map");
}

TEST(ParseVary, ReadsEveryDistributionInFileOrder) {
  const auto inputs = vary(R"(vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
  shoulder.q0: {dist: normal, mean: 0.5, std: 0.05}
  k: {dist: truncnormal, mean: 10, std: 2, low: 8, high: 14}
  c: {dist: lognormal, mu: 0.1, sigma: 0.4}
  L1: {dist: triangular, low: 0.9, mode: 1.0, high: 1.2}
  n: {dist: choice, values: [3, 1, 2]}
  g: {dist: fixed, value: 9.81}
)");
  ASSERT_EQ(inputs.size(), 7u);
  const char* names[] = {"m2", "shoulder.q0", "k", "c", "L1", "n", "g"};
  const char* described[] = {"uniform(low=0.8, high=1.2)",
                             "normal(mean=0.5, std=0.05)",
                             "truncnormal(mean=10, std=2, low=8, high=14)",
                             "lognormal(mu=0.1, sigma=0.4)",
                             "triangular(low=0.9, mode=1, high=1.2)",
                             "choice(values=[1, 2, 3])",
                             "fixed(value=9.81)"};
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    EXPECT_EQ(inputs[k].name, names[k]);
    EXPECT_EQ(inputs[k].dist.describe(), described[k]);
  }
  EXPECT_TRUE(vary("vary:\n").empty());
  EXPECT_TRUE(vary("other: 1\n").empty());
}

TEST(ParseVary, ErrorsPointAtTheOffendingValue) {
  expect_error([] { vary("vary:\n  m2: {dist: uniform, low: 1.2, high: 0.8}\n"); }, 2, 39,
               "vary.m2.high", "expected low < high, got low = 1.2, high = 0.8");
  expect_error([] { vary("vary:\n  m2: {dist: uniform, low: 0.8, hgih: 1.2}\n"); }, 2, 33,
               "vary.m2.hgih", "unknown key 'hgih' (did you mean 'high'?)");
  expect_error([] { vary("vary:\n  m2:\n    dist: uniform\n    low: 0.8\n"); }, 3, 5, "vary.m2",
               "missing key 'high'; uniform needs: low, high");
  expect_error([] { vary("vary:\n  m2: {dist: normla, mean: 1, std: 0.1}\n"); }, 2, 14,
               "vary.m2.dist", "unknown distribution 'normla' (did you mean 'normal'?)");
  expect_error([] { vary("vary:\n  m2: {dsit: normal, mean: 1, std: 0.1}\n"); }, 2, 8,
               "vary.m2.dsit", "did you mean 'dist'?");
  expect_error([] { vary("vary:\n  m2: {dist: normal, mean: 1, std: -0.1}\n"); }, 2, 36,
               "vary.m2.std", "expected std > 0, got -0.1");
  expect_error([] { vary("vary:\n  m2: {dist: normal, mean: abc, std: 0.1}\n"); }, 2, 28,
               "vary.m2.mean", "expected a finite number, got 'abc'");
  expect_error([] { vary("vary:\n  m2: {dist: normal, mean: .inf, std: 0.1}\n"); }, 2, 28,
               "vary.m2.mean", "expected a finite number");
  expect_error([] { vary("vary:\n  c: {dist: lognormal, mu: 0, sigma: 0}\n"); }, 2, 38,
               "vary.c.sigma", "expected sigma > 0, got 0");
  expect_error([] { vary("vary:\n  L: {dist: triangular, low: 1, mode: 3, high: 2}\n"); }, 2, 48,
               "vary.L.high", "expected mode <= high, got mode = 3, high = 2");
  expect_error([] { vary("vary:\n  L: {dist: triangular, low: 1, mode: 0, high: 2}\n"); }, 2, 39,
               "vary.L.mode", "expected low <= mode");
  expect_error([] { vary("vary:\n  k: {dist: truncnormal, mean: 0, std: 1, low: 2, high: 1}\n"); },
               2, 57, "vary.k.high", "expected low < high");
  expect_error([] { vary("vary:\n  n: {dist: choice, values: []}\n"); }, 2, 29, "vary.n.values",
               "expected at least one value");
  expect_error([] { vary("vary:\n  n: {dist: choice, values: [1, .nan]}\n"); }, 2, 33,
               "vary.n.values[1]", "expected a finite number");
  expect_error([] { vary("vary:\n  n: {dist: choice, values: 3}\n"); }, 2, 29, "vary.n.values",
               "expected a list of numbers");
  expect_error(
      [] { vary("vary:\n  m2: {dist: fixed, value: 1}\n  m2: {dist: fixed, value: 2}\n"); }, 3, 3,
      "vary.m2", "varied twice");
  expect_error([] { vary("vary:\n  m2: 1.0\n"); }, 2, 7, "vary.m2", "expected a map, got '1.0'");
  expect_error([] { vary("vary:\n  m2: {dist: fixed, value: 1, value: 2}\n"); }, 2, 31,
               "vary.m2.value", "given twice");
}

TEST(ParseStudy, GridLevelsNameOnlyVariedInputs) {
  const std::string yaml = R"(sampling:
  method: grid
  levels: {m2: 3, shouldr.q0: 2}
vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
  shoulder.q0: {dist: normal, mean: 0.5, std: 0.05}
)";
  expect_error(
      [&] { ks::Design(sampling(yaml), vary(yaml)); }, 3, 31, "sampling.levels.shouldr.q0",
      "no varied input named 'shouldr.q0' (did you mean 'shoulder.q0'?); varied inputs are: m2, "
      "shoulder.q0");
}

TEST(ParseStudy, ParsedSpecBuildsTheDesignItDescribes) {
  const std::string yaml = R"(sampling: {method: saltelli, samples: 64, seed: 9, randomize: true}
vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
  shoulder.q0: {dist: normal, mean: 0.5, std: 0.05}
  n: {dist: choice, values: [1, 2]}
)";
  const ks::Design design(sampling(yaml), vary(yaml));
  EXPECT_EQ(design.dimension(), 3u);
  EXPECT_EQ(design.size(), 64 * 5);
  std::vector<double> v(3);
  for (std::int64_t i = 0; i < design.size(); ++i) {
    design.sample(i, v);
    EXPECT_GE(v[0], 0.8);
    EXPECT_LE(v[0], 1.2);
    EXPECT_TRUE(v[2] == 1.0 || v[2] == 2.0);
  }
  const std::string too_big = R"(sampling: {method: saltelli, samples: 500000000}
vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
)";
  expect_error([&] { ks::Design(sampling(too_big), vary(too_big)); }, 1, 11, "sampling.samples",
               "more than 1000000000 runs");
}

}  // namespace KANESENS_UNITY_ID
