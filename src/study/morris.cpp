#include "study/morris.hpp"

#include <algorithm>
#include <cassert>

#include "study/counter_rng.hpp"
#include "study/keyed_permutation.hpp"

namespace kanesens::study {
namespace {

KeyedPermutation step_order(std::uint64_t seed, std::int64_t trajectory, std::size_t dimension) {
  return KeyedPermutation(
      dimension, hash_words(seed, Stream::morris_order, static_cast<std::uint64_t>(trajectory)));
}

}  // namespace

MorrisDesign::MorrisDesign(std::size_t dimension, std::int64_t levels, std::uint64_t seed)
    : dimension_(dimension), levels_(levels), seed_(seed) {
  assert(dimension >= 1 && levels >= 2 && levels % 2 == 0);
}

double MorrisDesign::delta() const {
  return static_cast<double>(levels_) / (2.0 * static_cast<double>(levels_ - 1));
}

std::int64_t MorrisDesign::start_level(std::int64_t trajectory, std::size_t input) const {
  const double u =
      hash_unit(seed_, Stream::morris_start, static_cast<std::uint64_t>(trajectory), input);
  return std::min<std::int64_t>(levels_ - 1, static_cast<std::int64_t>(u * levels_));
}

MorrisStep MorrisDesign::step(std::int64_t run) const {
  const auto width = static_cast<std::int64_t>(dimension_) + 1;
  MorrisStep s;
  s.trajectory = run / width;
  s.step = run % width;
  if (s.step == 0) return s;
  const KeyedPermutation order = step_order(seed_, s.trajectory, dimension_);
  // order(i) is the position (0-based) at which input i is changed; step s changes position s−1.
  s.input = static_cast<std::int64_t>(order.inverse(static_cast<std::uint64_t>(s.step - 1)));
  s.sign = start_level(s.trajectory, static_cast<std::size_t>(s.input)) < levels_ / 2 ? +1 : -1;
  return s;
}

// Level of input i after `done` steps of `trajectory`: it has moved by ±p/2 iff its position
// in the trajectory's order is below `done`.
std::int64_t MorrisDesign::level(std::int64_t trajectory, std::uint64_t position,
                                 std::uint64_t done, std::size_t input) const {
  const std::int64_t l = start_level(trajectory, input);
  const std::int64_t half = levels_ / 2;
  if (position >= done) return l;
  return l < half ? l + half : l - half;
}

void MorrisDesign::levels_at(std::int64_t run, std::span<std::int64_t> levels) const {
  assert(levels.size() == dimension_);
  const auto width = static_cast<std::int64_t>(dimension_) + 1;
  const std::int64_t trajectory = run / width;
  const auto done = static_cast<std::uint64_t>(run % width);  // inputs changed so far
  const KeyedPermutation order = step_order(seed_, trajectory, dimension_);
  for (std::size_t i = 0; i < dimension_; ++i) levels[i] = level(trajectory, order(i), done, i);
}

void MorrisDesign::unit_point(std::int64_t run, std::span<double> u) const {
  assert(u.size() == dimension_);
  const auto width = static_cast<std::int64_t>(dimension_) + 1;
  const std::int64_t trajectory = run / width;
  const auto done = static_cast<std::uint64_t>(run % width);
  const KeyedPermutation order = step_order(seed_, trajectory, dimension_);
  const auto p = static_cast<double>(levels_);
  for (std::size_t i = 0; i < dimension_; ++i) {
    u[i] = (static_cast<double>(level(trajectory, order(i), done, i)) + 0.5) / p;
  }
}

std::string MorrisDesign::label(const MorrisStep& s) {
  return "traj" + std::to_string(s.trajectory) + ".step" + std::to_string(s.step);
}

}  // namespace kanesens::study
