// Sobol' points with random access. The direction numbers are Boost.Random's (`boost::random::
// sobol`, Joe & Kuo 2008 "new-joe-kuo-6" primitive polynomials and initial numbers, 64-bit
// words), read out of the engine once; point k is then the XOR of the direction numbers picked
// by the bits of the Gray code of k (Antonov & Saleev 1979), O(log k) per coordinate, so any
// point can be computed without stepping the engine through the ones before it.
//
// Indexing: `point k` is the k-th point of the Gray-code-ordered sequence, k = 0 being the
// origin. Boost's engine skips the origin: its n-th output vector (n = 0, 1, ...) is our point
// n + 1. (Joe & Kuo's and scipy's tables list the origin first; the published 2-D start after
// it is (0.5, 0.5), (0.75, 0.25), (0.25, 0.75), (0.375, 0.375), (0.875, 0.875), ...)
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace kanesens::study {

class SobolPoints {
 public:
  explicit SobolPoints(std::size_t dimension);  // 1 ≤ dimension ≤ max_dimension()

  static std::size_t max_dimension();
  std::size_t dimension() const { return dimension_; }

  // Coordinate d of point k as a 64-bit binary fraction (value = bits · 2⁻⁶⁴).
  std::uint64_t bits(std::uint64_t k, std::size_t d) const;

  // bits / 2⁶⁴ rounded down to 53 bits (exact for k < 2^53). In (0,1) for k ≥ 1: each 1-D
  // projection of points 0..2^m−1 is {j/2^m}, with 0 taken by the origin.
  double coordinate(std::uint64_t k, std::size_t d) const;

  // Owen's nested uniform scramble (Owen 1995) of coordinate d of point k, returned as the
  // midpoint of its 2⁻⁵³ cell (so strictly inside (0,1)). Bit b (from the most significant) is
  // flipped iff a hash of (seed, d, b, bits above b) is odd: one random flip per node of the
  // binary tree of elementary intervals, which is nested uniform scrambling realised lazily.
  // Keeps the (t,m,s)-net property; the scrambled origin is a valid point.
  double scrambled_coordinate(std::uint64_t k, std::size_t d, std::uint64_t seed) const;

 private:
  std::size_t dimension_;
  std::vector<std::uint64_t> direction_;  // 64 × dimension, direction_[r·dimension + d] = v_{r,d}
};

}  // namespace kanesens::study
