// Counter-based pseudo-random numbers: a value is a pure function of its key (seed, stream,
// indices), never the state of a sequential engine, so sample i is the same whichever rank
// computes it and in whichever order.
//
// The mixer is the SplitMix64 finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom
// number generators", OOPSLA 2014), a bijection of 64-bit words with full avalanche. Keys are
// absorbed one word at a time: h ← mix(h ⊕ word + golden·(position+1)).
#pragma once
#include <cstdint>

namespace kanesens::study {

// Separate streams so that different uses of the same (seed, i, d) are independent.
enum class Stream : std::uint64_t {
  mc = 1,
  lhs_jitter = 2,
  lhs_permutation = 3,
  sobol_scramble = 4,
  halton_shift = 5,
  morris_start = 6,
  morris_order = 7,
};

constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

constexpr std::uint64_t hash_words(std::uint64_t seed, Stream stream, std::uint64_t a,
                                   std::uint64_t b = 0, std::uint64_t c = 0) {
  constexpr std::uint64_t golden = 0x9e3779b97f4a7c15ULL;
  std::uint64_t h = mix64(seed + golden);
  h = mix64(h ^ (static_cast<std::uint64_t>(stream) + 2 * golden));
  h = mix64(h ^ (a + 3 * golden));
  h = mix64(h ^ (b + 4 * golden));
  return mix64(h ^ (c + 5 * golden));
}

// The 53 top bits of a word as the midpoint of a cell of width 2⁻⁵³: strictly inside (0,1).
constexpr double to_open_unit(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53;
}

// A uniform in (0,1) keyed by (seed, stream, a, b, c).
constexpr double hash_unit(std::uint64_t seed, Stream stream, std::uint64_t a, std::uint64_t b = 0,
                           std::uint64_t c = 0) {
  return to_open_unit(hash_words(seed, stream, a, b, c));
}

}  // namespace kanesens::study
