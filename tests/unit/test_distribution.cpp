// Distribution quantiles against scipy.stats (tests/fixtures/gen_distribution_quantiles.py),
// describe(), and the invariants find_problem() enforces.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "study/distribution.hpp"
#include "study/parse_vary.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace ks = kanesens::study;

namespace {

struct Reference {
  const char* spec;  // as written under `vary:`
  double p;
  double expected;  // scipy.stats ppf(p)
};

constexpr Reference references[] = {
#include "../fixtures/distribution_quantiles.inc"
};

ks::Distribution parse(const char* yaml) {
  return ks::parse_distribution(YAML::Load(yaml), {"test.yaml"}, "vary.x");
}

}  // namespace

TEST(Distribution, QuantilesMatchScipyToRelative1e12) {
  ASSERT_GE(std::size(references), 60u);
  for (const Reference& r : references) {
    const double got = parse(r.spec).quantile(r.p);
    EXPECT_LE(std::fabs(got - r.expected), 1e-12 * std::fabs(r.expected))
        << r.spec << " at p = " << r.p << ": got " << got << ", scipy " << r.expected;
  }
}

TEST(Distribution, QuantileIsMonotone) {
  for (const char* spec :
       {"{dist: truncnormal, mean: 1, std: 2, low: 7, high: 11}",
        "{dist: lognormal, mu: 0.1, sigma: 0.4}", "{dist: choice, values: [3, 0.5, 2, 1]}"}) {
    const ks::Distribution d = parse(spec);
    double previous = -INFINITY;
    for (int k = 1; k < 1000; ++k) {
      const double x = d.quantile(k / 1000.0);
      EXPECT_GE(x, previous) << spec << " at p = " << k / 1000.0;
      previous = x;
    }
  }
}

TEST(Distribution, TruncNormalStaysInsideItsBounds) {
  const ks::Distribution d = parse("{dist: truncnormal, mean: 0, std: 1, low: 5, high: 5.5}");
  for (double p : {1e-12, 0.3, 1 - 1e-12}) {
    const double x = d.quantile(p);
    EXPECT_GE(x, 5.0);
    EXPECT_LE(x, 5.5);
  }
}

TEST(Distribution, ChoiceUsesEachValueForAnEqualShare) {
  const ks::Distribution d = parse("{dist: choice, values: [3, 0.5, 2, 1]}");
  // Midpoints of 4 equal cells map to the sorted values in turn.
  EXPECT_EQ(d.quantile(0.125), 0.5);
  EXPECT_EQ(d.quantile(0.375), 1.0);
  EXPECT_EQ(d.quantile(0.625), 2.0);
  EXPECT_EQ(d.quantile(0.875), 3.0);
}

TEST(Distribution, DescribeUsesShortestRoundTripNumbers) {
  EXPECT_EQ(parse("{dist: uniform, low: 0.8, high: 1.2}").describe(), "uniform(low=0.8, high=1.2)");
  EXPECT_EQ(parse("{dist: normal, mean: 0.5, std: 0.05}").describe(), "normal(mean=0.5, std=0.05)");
  EXPECT_EQ(parse("{dist: truncnormal, mean: 0, std: 1, low: -1, high: 2}").describe(),
            "truncnormal(mean=0, std=1, low=-1, high=2)");
  EXPECT_EQ(parse("{dist: lognormal, mu: 0.1, sigma: 0.4}").describe(),
            "lognormal(mu=0.1, sigma=0.4)");
  EXPECT_EQ(parse("{dist: triangular, low: 1, mode: 1.5, high: 3}").describe(),
            "triangular(low=1, mode=1.5, high=3)");
  EXPECT_EQ(parse("{dist: choice, values: [3, 0.5]}").describe(), "choice(values=[0.5, 3])");
  EXPECT_EQ(parse("{dist: fixed, value: 2.5}").describe(), "fixed(value=2.5)");
  EXPECT_EQ(parse("{dist: fixed, value: 2.5}").kind_name(), "fixed");
}

// named_parameters() (what the run file's /vary groups hold) gives back exactly the keys and
// numbers of the study text, whatever the kind.
TEST(Distribution, NamedParametersAreTheStudyKeys) {
  for (const char* text :
       {"{dist: uniform, low: 0.8, high: 1.2}", "{dist: normal, mean: 0.5, std: 0.05}",
        "{dist: truncnormal, mean: 0, std: 1, low: -1, high: 2}",
        "{dist: lognormal, mu: 0.1, sigma: 0.4}", "{dist: triangular, low: 1, mode: 1.5, high: 3}",
        "{dist: fixed, value: 2.5}", "{dist: choice, values: [3, 0.5]}"}) {
    const YAML::Node node = YAML::Load(text);
    const ks::Distribution d = parse(text);
    EXPECT_EQ(d.kind_name(), node["dist"].as<std::string>());
    std::size_t keys = 0;
    for (const auto& kv : node) {
      const auto key = kv.first.as<std::string>();
      if (key == "dist" || key == "values") continue;
      ++keys;
      const auto named = d.named_parameters();
      const auto it =
          std::find_if(named.begin(), named.end(), [&](const auto& e) { return e.first == key; });
      ASSERT_NE(it, named.end()) << text << ": " << key;
      EXPECT_EQ(it->second, kv.second.as<double>()) << text << ": " << key;
    }
    EXPECT_EQ(d.named_parameters().size(), keys) << text;
  }
}

TEST(Distribution, FindProblemNamesTheKeyAndTheValues) {
  struct Case {
    ks::Distribution d;
    const char* key;
    const char* message_part;
  };
  const Case cases[] = {
      {{ks::Uniform{1.2, 0.8}}, "high", "expected low < high, got low = 1.2, high = 0.8"},
      {{ks::Uniform{1, 1}}, "high", "expected low < high"},
      {{ks::Normal{0, 0}}, "std", "expected std > 0, got 0"},
      {{ks::Normal{0, NAN}}, "std", "finite"},
      {{ks::TruncNormal{0, 1, 2, 1}}, "high", "expected low < high"},
      {{ks::TruncNormal{0, 1, 60, 61}}, "low", "has probability"},
      {{ks::LogNormal{0, -1}}, "sigma", "expected sigma > 0, got -1"},
      {{ks::Triangular{0, 3, 2}}, "high", "expected mode <= high, got mode = 3, high = 2"},
      {{ks::Triangular{1, 0, 2}}, "mode", "expected low <= mode"},
      {{ks::Choice{{}}}, "values", "at least one value"},
      {{ks::Fixed{INFINITY}}, "value", "finite"},
  };
  for (const Case& c : cases) {
    const auto problem = c.d.find_problem();
    ASSERT_TRUE(problem.has_value()) << c.d.describe();
    EXPECT_EQ(problem->key, c.key) << c.d.describe();
    EXPECT_NE(problem->message.find(c.message_part), std::string::npos) << problem->message;
  }
  EXPECT_FALSE((ks::Distribution{ks::Triangular{0, 0, 2}}.find_problem()));
  EXPECT_FALSE((ks::Distribution{ks::TruncNormal{0, 1, 7, 8}}.find_problem()));
}

}  // namespace KANESENS_UNITY_ID
