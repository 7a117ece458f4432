#include "study/halton_points.hpp"

#include <cassert>
#include <cmath>

#include "study/counter_rng.hpp"

namespace kanesens::study {

HaltonPoints::HaltonPoints(std::size_t dimension) {
  bases_.reserve(dimension);
  for (std::uint64_t candidate = 2; bases_.size() < dimension; ++candidate) {
    bool prime = true;
    for (const std::uint64_t p : bases_) {
      if (p * p > candidate) break;
      if (candidate % p == 0) {
        prime = false;
        break;
      }
    }
    if (prime) bases_.push_back(candidate);
  }
}

double HaltonPoints::coordinate(std::uint64_t k, std::size_t d) const {
  const std::uint64_t b = bases_[d];
  std::uint64_t reversed = 0;
  std::uint64_t denominator = 1;
  for (; k != 0; k /= b) {
    reversed = reversed * b + k % b;
    denominator *= b;
  }
  assert(denominator < (std::uint64_t{1} << 53));
  return static_cast<double>(reversed) / static_cast<double>(denominator);
}

double HaltonPoints::shifted_coordinate(std::uint64_t k, std::size_t d, std::uint64_t seed) const {
  double u = coordinate(k, d) + hash_unit(seed, Stream::halton_shift, d);
  if (u >= 1.0) u -= 1.0;
  if (u <= 0.0) u = 0x1.0p-54;
  if (u >= 1.0) u = std::nextafter(1.0, 0.0);
  return u;
}

}  // namespace kanesens::study
