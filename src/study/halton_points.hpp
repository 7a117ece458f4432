// Halton points (Halton 1960): coordinate d of point k is the radical inverse of k in the d-th
// prime base (2, 3, 5, 7, ...). Point 0 is the origin; the unrandomized design skips it.
// The optional randomization is a Cranley–Patterson rotation (Cranley & Patterson 1976):
// u = frac(x + s_d) with one uniform shift s_d per dimension, keyed by the seed.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace kanesens::study {

class HaltonPoints {
 public:
  explicit HaltonPoints(std::size_t dimension);

  std::size_t dimension() const { return bases_.size(); }
  std::uint64_t base(std::size_t d) const { return bases_[d]; }

  // Radical inverse of k in base(d), correctly rounded: the reversed digits and b^m are formed
  // as integers (exact while k · base < 2^53, true for every design kanesens accepts).
  double coordinate(std::uint64_t k, std::size_t d) const;

  // frac(coordinate(k, d) + s_d), s_d = hash-uniform of (seed, d); a result that rounds to 0 or
  // 1 (probability ~2⁻⁵³) is moved to the nearest double inside (0,1).
  double shifted_coordinate(std::uint64_t k, std::size_t d, std::uint64_t seed) const;

 private:
  std::vector<std::uint64_t> bases_;  // the first `dimension` primes
};

}  // namespace kanesens::study
