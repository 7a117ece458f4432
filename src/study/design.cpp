#include "study/design.hpp"

#include <cassert>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "study/counter_rng.hpp"
#include "study/halton_points.hpp"
#include "study/keyed_permutation.hpp"
#include "study/sobol_points.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::study {

struct Design::Impl {
  SamplingSpec spec;
  std::vector<VariedInput> inputs;
  std::int64_t runs = 0;
  SamplingMethod generator = SamplingMethod::mc;  // where base points come from
  std::int64_t base_points = 0;                   // N: lhs strata, saltelli base points
  std::size_t base_dimension = 0;                 // P, or 2P for saltelli's [A | B]
  std::optional<SobolPoints> sobol;
  std::optional<HaltonPoints> halton;
  std::vector<std::int64_t> levels;  // grid: L_d
  std::optional<MorrisDesign> morris;

  // Coordinate d of base point j, in (0,1).
  double base_coordinate(std::int64_t j, std::size_t d) const;
  // grid: L_d for every input (named ones, choice/fixed defaults, `levels: N`) and runs.
  void resolve_grid_levels();
};

namespace {

[[noreturn]] void fail(const SamplingSpec& spec, const std::string& key, const std::string& what) {
  throw InputError(spec.where, key, what);
}

// a·b, or nullopt when it exceeds max_design_runs.
std::optional<std::int64_t> runs_product(std::int64_t a, std::int64_t b) {
  std::int64_t out = 0;
  if (__builtin_mul_overflow(a, b, &out) || out > max_design_runs) return std::nullopt;
  return out;
}

std::string too_many_runs(std::string_view how) {
  return "the design has more than " + std::to_string(max_design_runs) + " runs (" +
         std::string(how) + "); expected at most " + std::to_string(max_design_runs);
}

}  // namespace

void Design::Impl::resolve_grid_levels() {
  Impl& d = *this;
  const SamplingSpec& spec = d.spec;
  d.levels.assign(d.inputs.size(), 0);
  for (const GridLevels& g : spec.grid_levels_by_input) {
    std::vector<std::string_view> names;
    std::size_t k = 0;
    for (; k < d.inputs.size() && d.inputs[k].name != g.input; ++k) {
    }
    if (k == d.inputs.size()) {
      for (const auto& in : d.inputs) names.push_back(in.name);
      throw InputError(g.where, "sampling.levels." + g.input,
                       "no varied input named '" + g.input + "'" + did_you_mean(g.input, names) +
                           "; varied inputs are: " + join_names(names));
    }
    d.levels[k] = g.levels;
  }
  std::int64_t runs = 1;
  for (std::size_t k = 0; k < d.inputs.size(); ++k) {
    if (d.levels[k] == 0) {
      const auto& params = d.inputs[k].dist.params;
      if (std::holds_alternative<Fixed>(params)) {
        d.levels[k] = 1;
      } else if (const auto* c = std::get_if<Choice>(&params)) {
        d.levels[k] = static_cast<std::int64_t>(c->values.size());
      } else if (spec.grid_levels > 0) {
        d.levels[k] = spec.grid_levels;
      } else {
        fail(spec, "sampling.levels",
             "no level count for input '" + d.inputs[k].name +
                 "'; expected `levels: N` for every input or `levels: {" + d.inputs[k].name +
                 ": N, ...}`");
      }
    }
    const auto product = runs_product(runs, d.levels[k]);
    if (!product) fail(spec, "sampling.levels", too_many_runs("the product of the levels"));
    runs = *product;
  }
  d.runs = runs;
}

double Design::Impl::base_coordinate(std::int64_t j, std::size_t d) const {
  const auto uj = static_cast<std::uint64_t>(j);
  switch (generator) {
    case SamplingMethod::sobol:
      return spec.randomize ? sobol->scrambled_coordinate(uj, d, spec.seed)
                            : sobol->coordinate(uj + 1, d);
    case SamplingMethod::halton:
      return spec.randomize ? halton->shifted_coordinate(uj, d, spec.seed)
                            : halton->coordinate(uj + 1, d);
    case SamplingMethod::lhs: {
      const KeyedPermutation stratum(static_cast<std::uint64_t>(base_points),
                                     hash_words(spec.seed, Stream::lhs_permutation, d));
      const double jitter = hash_unit(spec.seed, Stream::lhs_jitter, uj, d);
      const double u =
          (static_cast<double>(stratum(uj)) + jitter) / static_cast<double>(base_points);
      return std::min(u, std::nextafter(1.0, 0.0));  // (N−1 + jitter)/N may round to 1
    }
    default:
      return hash_unit(spec.seed, Stream::mc, uj, d);
  }
}

Design::Design(SamplingSpec spec, std::vector<VariedInput> inputs) {
  auto impl = std::make_shared<Impl>();
  impl->spec = std::move(spec);
  impl->inputs = std::move(inputs);
  Impl& d = *impl;
  const SamplingSpec& s = d.spec;
  const std::size_t P = d.inputs.size();

  for (std::size_t k = 0; k < P; ++k) {
    if (const auto problem = d.inputs[k].dist.find_problem()) {
      throw std::invalid_argument("input '" + d.inputs[k].name + "': " + problem->key + ": " +
                                  problem->message);
    }
    for (std::size_t m = 0; m < k; ++m) {
      if (d.inputs[m].name == d.inputs[k].name) {
        throw std::invalid_argument("input '" + d.inputs[k].name + "' is varied twice");
      }
    }
  }

  const std::string method(method_name(s.method));
  switch (s.method) {
    case SamplingMethod::mc:
    case SamplingMethod::lhs:
    case SamplingMethod::sobol:
    case SamplingMethod::halton:
    case SamplingMethod::saltelli:
      if (s.samples <= 0 || s.samples > max_design_runs) {
        fail(s, "sampling.samples",
             "expected 1 <= samples <= " + std::to_string(max_design_runs) + ", got " +
                 std::to_string(s.samples));
      }
      d.generator = s.method == SamplingMethod::saltelli ? s.base : s.method;
      d.base_points = s.samples;
      d.base_dimension = s.method == SamplingMethod::saltelli ? 2 * P : P;
      d.runs = s.samples;
      if (s.method == SamplingMethod::saltelli) {
        if (P == 0) fail(s, "vary", "saltelli needs at least one varied input, got none");
        const auto runs = runs_product(s.samples, static_cast<std::int64_t>(P) + 2);
        if (!runs) fail(s, "sampling.samples", too_many_runs("samples × (inputs + 2)"));
        d.runs = *runs;
      }
      break;
    case SamplingMethod::grid:
      d.resolve_grid_levels();
      break;
    case SamplingMethod::morris: {
      if (P == 0) fail(s, "vary", "morris needs at least one varied input, got none");
      if (s.morris_levels < 2 || s.morris_levels % 2 != 0) {
        fail(s, "sampling.levels",
             "expected an even number of levels >= 2, got " + std::to_string(s.morris_levels));
      }
      if (s.trajectories <= 0) {
        fail(s, "sampling.trajectories",
             "expected trajectories >= 1, got " + std::to_string(s.trajectories));
      }
      const auto runs = runs_product(s.trajectories, static_cast<std::int64_t>(P) + 1);
      if (!runs) fail(s, "sampling.trajectories", too_many_runs("trajectories × (inputs + 1)"));
      d.runs = *runs;
      d.morris.emplace(P, s.morris_levels, s.seed);
      break;
    }
  }

  // Point generators (grid and morris have none: base_dimension stays 0).
  if (d.base_dimension > 0 && d.generator == SamplingMethod::sobol) {
    if (d.base_dimension > SobolPoints::max_dimension()) {
      fail(s, "sampling.method",
           method + " needs a " + std::to_string(d.base_dimension) +
               "-dimensional Sobol' sequence; Boost's table has at most " +
               std::to_string(SobolPoints::max_dimension()) + " dimensions");
    }
    d.sobol.emplace(d.base_dimension);
  }
  if (d.base_dimension > 0 && d.generator == SamplingMethod::halton) {
    d.halton.emplace(d.base_dimension);
  }
  impl_ = std::move(impl);
}

std::int64_t Design::size() const {
  return impl_->runs;
}
std::size_t Design::dimension() const {
  return impl_->inputs.size();
}
const SamplingSpec& Design::spec() const {
  return impl_->spec;
}
const std::vector<VariedInput>& Design::inputs() const {
  return impl_->inputs;
}

void Design::unit_sample(std::int64_t i, std::span<double> u) const {
  const Impl& d = *impl_;
  const std::size_t P = d.inputs.size();
  assert(i >= 0 && i < d.runs && u.size() == P);
  switch (d.spec.method) {
    case SamplingMethod::grid:
      // Row-major: the last input varies fastest.
      for (std::size_t k = P; k-- > 0;) {
        const std::int64_t level = i % d.levels[k];
        i /= d.levels[k];
        u[k] = (static_cast<double>(level) + 0.5) / static_cast<double>(d.levels[k]);
      }
      return;
    case SamplingMethod::saltelli: {
      const SaltelliIndex s = study::saltelli_index(i, P);
      for (std::size_t k = 0; k < P; ++k) {
        const bool from_b =
            s.block == SaltelliBlock::B || (s.block == SaltelliBlock::AB && k == s.input);
        u[k] = d.base_coordinate(s.base, from_b ? P + k : k);
      }
      return;
    }
    case SamplingMethod::morris:
      d.morris->unit_point(i, u);
      return;
    default:
      for (std::size_t k = 0; k < P; ++k) u[k] = d.base_coordinate(i, k);
      return;
  }
}

void Design::sample(std::int64_t i, std::span<double> values) const {
  unit_sample(i, values);
  const auto& inputs = impl_->inputs;
  for (std::size_t k = 0; k < inputs.size(); ++k) values[k] = inputs[k].dist.quantile(values[k]);
}

std::string Design::block_label(std::int64_t i) const {
  switch (impl_->spec.method) {
    case SamplingMethod::saltelli:
      return saltelli_label(saltelli_index(i));
    case SamplingMethod::morris:
      return MorrisDesign::label(morris_step(i));
    default:
      return "";
  }
}

bool Design::has_run_labels() const {
  return impl_->spec.method == SamplingMethod::saltelli ||
         impl_->spec.method == SamplingMethod::morris;
}

RunLabel Design::run_label(std::int64_t i) const {
  if (impl_->spec.method == SamplingMethod::saltelli) {
    const SaltelliIndex s = saltelli_index(i);
    const bool ab = s.block == SaltelliBlock::AB;
    const auto input = static_cast<std::int64_t>(s.input);
    return {s.base, s.block == SaltelliBlock::A ? 0 : ab ? 2 + input : 1, ab ? input : -1};
  }
  if (impl_->spec.method == SamplingMethod::morris) {
    const MorrisStep s = morris_step(i);
    return {s.trajectory, s.step, s.input};
  }
  throw std::logic_error("Design::run_label: only saltelli and morris designs label their runs");
}

SaltelliIndex Design::saltelli_index(std::int64_t i) const {
  if (impl_->spec.method != SamplingMethod::saltelli) {
    throw std::logic_error("Design::saltelli_index: the design is not a saltelli design");
  }
  return study::saltelli_index(i, dimension());
}

MorrisStep Design::morris_step(std::int64_t i) const {
  if (!impl_->morris) throw std::logic_error("Design::morris_step: not a morris design");
  return impl_->morris->step(i);
}

double Design::morris_delta() const {
  if (!impl_->morris) throw std::logic_error("Design::morris_delta: not a morris design");
  return impl_->morris->delta();
}

std::span<const std::int64_t> Design::grid_levels() const {
  return impl_->levels;
}

}  // namespace kanesens::study
