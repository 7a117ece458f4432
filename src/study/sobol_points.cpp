#include "study/sobol_points.hpp"

#include <bit>
#include <boost/random/sobol.hpp>
#include <cassert>

#include "study/counter_rng.hpp"

namespace kanesens::study {

std::size_t SobolPoints::max_dimension() {
  return boost::random::default_sobol_table::max_dimension;
}

// Reading the direction numbers out of Boost: the engine's output vector n is the point whose
// Gray code is gray(n + 1), and gray(2^(r+1) − 1) = 2^r, so seeding the engine at
// n = 2^(r+1) − 2 yields exactly the direction numbers v_r of every dimension.
SobolPoints::SobolPoints(std::size_t dimension)
    : dimension_(dimension), direction_(64 * dimension) {
  boost::random::sobol engine(dimension);
  for (unsigned r = 0; r < 64; ++r) {
    const std::uint64_t n = (r == 63) ? ~std::uint64_t{0} - 1 : (std::uint64_t{2} << r) - 2;
    engine.seed(n);
    for (std::size_t d = 0; d < dimension; ++d) direction_[r * dimension + d] = engine();
  }
}

std::uint64_t SobolPoints::bits(std::uint64_t k, std::size_t d) const {
  assert(d < dimension_);
  std::uint64_t gray = k ^ (k >> 1);
  std::uint64_t x = 0;
  while (gray != 0) {
    const int r = std::countr_zero(gray);
    x ^= direction_[static_cast<std::size_t>(r) * dimension_ + d];
    gray &= gray - 1;
  }
  return x;
}

double SobolPoints::coordinate(std::uint64_t k, std::size_t d) const {
  return static_cast<double>(bits(k, d) >> 11) * 0x1.0p-53;
}

double SobolPoints::scrambled_coordinate(std::uint64_t k, std::size_t d, std::uint64_t seed) const {
  const std::uint64_t x = bits(k, d);
  std::uint64_t out = 0;
  for (int depth = 0; depth < 53; ++depth) {
    const int b = 63 - depth;
    const std::uint64_t prefix = depth == 0 ? 0 : x >> (b + 1);
    const std::uint64_t flip = hash_words(seed, Stream::sobol_scramble, d, depth, prefix) & 1;
    out |= (((x >> b) & 1) ^ flip) << b;
  }
  return to_open_unit(out);
}

}  // namespace kanesens::study
