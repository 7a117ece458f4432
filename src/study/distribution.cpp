#include "study/distribution.hpp"

#include <algorithm>
#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/triangular.hpp>
#include <boost/math/distributions/uniform.hpp>
#include <charconv>
#include <cmath>

namespace kanesens::study {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

std::string number(double x) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

// Probability mass of [a, b] under the standard normal, computed in the tail where the interval
// lies so that intervals far in one tail keep their relative precision.
double standard_normal_mass(double a, double b) {
  const boost::math::normal_distribution<double> n01;
  if (a >= 0) return cdf(complement(n01, a)) - cdf(complement(n01, b));
  return cdf(n01, b) - cdf(n01, a);
}

// Truncated normal quantile: z = Φ⁻¹(Φ(a) + p (Φ(b) − Φ(a))), with a, b the standardised bounds.
// When the interval lies in the upper tail (a ≥ 0) the same formula is written with survival
// functions, Q(a) − p (Q(a) − Q(b)), which do not round to 1.
double truncnormal_quantile(const TruncNormal& d, double p) {
  const boost::math::normal_distribution<double> n01;
  const double a = (d.low - d.mean) / d.std;
  const double b = (d.high - d.mean) / d.std;
  double z;
  if (a >= 0) {
    const double qa = cdf(complement(n01, a));
    const double qb = cdf(complement(n01, b));
    z = quantile(complement(n01, qa - p * (qa - qb)));
  } else {
    const double fa = cdf(n01, a);
    const double fb = cdf(n01, b);
    z = quantile(n01, fa + p * (fb - fa));
  }
  return std::clamp(d.mean + d.std * z, d.low, d.high);
}

bool finite(double x) {
  return std::isfinite(x);
}

std::optional<DistributionProblem> not_finite(std::string_view key, double x) {
  if (finite(x)) return std::nullopt;
  return DistributionProblem{std::string(key), "expected a finite number, got " + number(x)};
}

// "expected low < high, got low = 1.2, high = 0.8" attached to `key`.
std::optional<DistributionProblem> ordered(std::string_view lo_key, double lo,
                                           std::string_view hi_key, double hi, bool strict) {
  if (strict ? lo < hi : lo <= hi) return std::nullopt;
  return DistributionProblem{std::string(hi_key),
                             "expected " + std::string(lo_key) + (strict ? " < " : " <= ") +
                                 std::string(hi_key) + ", got " + std::string(lo_key) + " = " +
                                 number(lo) + ", " + std::string(hi_key) + " = " + number(hi)};
}

std::optional<DistributionProblem> positive(std::string_view key, double x) {
  if (x > 0) return std::nullopt;
  return DistributionProblem{std::string(key),
                             "expected " + std::string(key) + " > 0, got " + number(x)};
}

// The first problem among the candidates, in order.
std::optional<DistributionProblem> first(
    std::initializer_list<std::optional<DistributionProblem>> checks) {
  for (const auto& c : checks) {
    if (c) return c;
  }
  return std::nullopt;
}

}  // namespace

Distribution make_choice(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return Distribution{Choice{std::move(values)}};
}

double Distribution::quantile(double p) const {
  return std::visit(Overloaded{
                        [p](const Uniform& d) {
                          return boost::math::quantile(
                              boost::math::uniform_distribution<double>(d.low, d.high), p);
                        },
                        [p](const Normal& d) {
                          return boost::math::quantile(
                              boost::math::normal_distribution<double>(d.mean, d.std), p);
                        },
                        [p](const TruncNormal& d) { return truncnormal_quantile(d, p); },
                        [p](const LogNormal& d) {
                          return boost::math::quantile(
                              boost::math::lognormal_distribution<double>(d.mu, d.sigma), p);
                        },
                        [p](const Triangular& d) {
                          return boost::math::quantile(
                              boost::math::triangular_distribution<double>(d.low, d.mode, d.high),
                              p);
                        },
                        [p](const Choice& d) {
                          const auto n = static_cast<double>(d.values.size());
                          const double k = std::clamp(std::ceil(p * n) - 1.0, 0.0, n - 1.0);
                          return d.values[static_cast<std::size_t>(k)];
                        },
                        [](const Fixed& d) { return d.value; },
                    },
                    params);
}

std::string Distribution::describe() const {
  return std::visit(Overloaded{
                        [](const Uniform& d) {
                          return "uniform(low=" + number(d.low) + ", high=" + number(d.high) + ")";
                        },
                        [](const Normal& d) {
                          return "normal(mean=" + number(d.mean) + ", std=" + number(d.std) + ")";
                        },
                        [](const TruncNormal& d) {
                          return "truncnormal(mean=" + number(d.mean) + ", std=" + number(d.std) +
                                 ", low=" + number(d.low) + ", high=" + number(d.high) + ")";
                        },
                        [](const LogNormal& d) {
                          return "lognormal(mu=" + number(d.mu) + ", sigma=" + number(d.sigma) +
                                 ")";
                        },
                        [](const Triangular& d) {
                          return "triangular(low=" + number(d.low) + ", mode=" + number(d.mode) +
                                 ", high=" + number(d.high) + ")";
                        },
                        [](const Choice& d) {
                          std::string s = "choice(values=[";
                          for (std::size_t k = 0; k < d.values.size(); ++k) {
                            s += (k ? ", " : "") + number(d.values[k]);
                          }
                          return s + "])";
                        },
                        [](const Fixed& d) { return "fixed(value=" + number(d.value) + ")"; },
                    },
                    params);
}

std::string_view Distribution::kind_name() const {
  static constexpr std::string_view names[] = {"uniform",    "normal", "truncnormal", "lognormal",
                                               "triangular", "choice", "fixed"};
  return names[params.index()];
}

std::vector<std::pair<std::string_view, double>> Distribution::named_parameters() const {
  using Named = std::vector<std::pair<std::string_view, double>>;
  return std::visit(
      Overloaded{
          [](const Uniform& d) {
            return Named{{"low", d.low}, {"high", d.high}};
          },
          [](const Normal& d) {
            return Named{{"mean", d.mean}, {"std", d.std}};
          },
          [](const TruncNormal& d) {
            return Named{{"mean", d.mean}, {"std", d.std}, {"low", d.low}, {"high", d.high}};
          },
          [](const LogNormal& d) {
            return Named{{"mu", d.mu}, {"sigma", d.sigma}};
          },
          [](const Triangular& d) {
            return Named{{"low", d.low}, {"mode", d.mode}, {"high", d.high}};
          },
          [](const Choice&) { return Named{}; },
          [](const Fixed& d) {
            return Named{{"value", d.value}};
          },
      },
      params);
}

std::optional<DistributionProblem> Distribution::find_problem() const {
  return std::visit(
      Overloaded{
          [](const Uniform& d) {
            return first({not_finite("low", d.low), not_finite("high", d.high),
                          ordered("low", d.low, "high", d.high, true)});
          },
          [](const Normal& d) {
            return first(
                {not_finite("mean", d.mean), not_finite("std", d.std), positive("std", d.std)});
          },
          [](const TruncNormal& d) -> std::optional<DistributionProblem> {
            if (auto p =
                    first({not_finite("mean", d.mean), not_finite("std", d.std),
                           not_finite("low", d.low), not_finite("high", d.high),
                           positive("std", d.std), ordered("low", d.low, "high", d.high, true)})) {
              return p;
            }
            const double mass =
                standard_normal_mass((d.low - d.mean) / d.std, (d.high - d.mean) / d.std);
            if (!(mass > 1e-300)) {
              return DistributionProblem{
                  "low", "[low, high] = [" + number(d.low) + ", " + number(d.high) +
                             "] has probability " + number(mass) +
                             " under normal(mean=" + number(d.mean) + ", std=" + number(d.std) +
                             "); expected an interval the normal can reach"};
            }
            return std::nullopt;
          },
          [](const LogNormal& d) {
            return first(
                {not_finite("mu", d.mu), not_finite("sigma", d.sigma), positive("sigma", d.sigma)});
          },
          [](const Triangular& d) {
            return first({not_finite("low", d.low), not_finite("mode", d.mode),
                          not_finite("high", d.high), ordered("low", d.low, "high", d.high, true),
                          ordered("low", d.low, "mode", d.mode, false),
                          ordered("mode", d.mode, "high", d.high, false)});
          },
          [](const Choice& d) -> std::optional<DistributionProblem> {
            if (d.values.empty()) {
              return DistributionProblem{"values", "expected at least one value, got none"};
            }
            for (std::size_t k = 0; k < d.values.size(); ++k) {
              if (!finite(d.values[k])) {
                return not_finite("values[" + std::to_string(k) + "]", d.values[k]);
              }
            }
            return std::nullopt;
          },
          [](const Fixed& d) { return not_finite("value", d.value); },
      },
      params);
}

}  // namespace kanesens::study
