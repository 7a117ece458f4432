// Marginal distributions of varied inputs. A Distribution maps a point p ∈ (0,1) of the unit
// hypercube to a value through its quantile function (inverse CDF), so every sampler works in
// (0,1)^P and the distributions are applied last (the "quantile transform").
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace kanesens::study {

struct Uniform {
  double low, high;  // low < high
};
struct Normal {
  double mean, std;  // std > 0
};
struct TruncNormal {
  double mean, std, low, high;  // normal(mean, std) restricted to [low, high], low < high
};
struct LogNormal {
  double mu, sigma;  // log X ~ normal(mu, sigma), sigma > 0
};
struct Triangular {
  double low, mode, high;  // low ≤ mode ≤ high, low < high
};
struct Choice {
  std::vector<double> values;  // equal weights, sorted (see make_choice), non-empty
};
struct Fixed {
  double value;
};

// Which parameter of a distribution is wrong, and why (expected vs actual). `key` is the YAML
// key of the offending parameter ("high", "values[2]") so the parser can point at it.
struct DistributionProblem {
  std::string key;
  std::string message;
};

struct Distribution {
  std::variant<Uniform, Normal, TruncNormal, LogNormal, Triangular, Choice, Fixed> params;

  // Inverse CDF at p ∈ (0,1), via Boost.Math quantiles. choice: the smallest value v with
  // F(v) ≥ p, i.e. values[ceil(p·n) − 1] (scipy's rv_discrete.ppf convention). Does not
  // allocate; undefined for p outside (0,1) (samplers never produce 0 or 1).
  double quantile(double p) const;

  // "uniform(low=0.8, high=1.2)": numbers in their shortest round-trip form.
  std::string describe() const;

  // The YAML name of the kind: "uniform", "normal", ..., "fixed".
  std::string_view kind_name() const;

  // The parameters under their study-file keys, in the order of the study format:
  // {"low", 0.8}, {"high", 1.2}. choice has none here: its values are Choice::values.
  std::vector<std::pair<std::string_view, double>> named_parameters() const;

  // First violated invariant (finite numbers, low < high, std > 0, low ≤ mode ≤ high,
  // sigma > 0, non-empty values, truncnormal interval with non-negligible probability), or
  // nullopt when the distribution is valid.
  std::optional<DistributionProblem> find_problem() const;
};

// choice: sorts the values so that quantile() is monotone (the order of the YAML list does not
// matter; repeated values count with their multiplicity).
Distribution make_choice(std::vector<double> values);

}  // namespace kanesens::study
