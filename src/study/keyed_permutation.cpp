#include "study/keyed_permutation.hpp"

#include <cassert>

#include "study/counter_rng.hpp"

namespace kanesens::study {

KeyedPermutation::KeyedPermutation(std::uint64_t n, std::uint64_t key) : n_(n), key_(key) {
  assert(n >= 1 && n <= (std::uint64_t{1} << 62));
  half_bits_ = 1;
  while ((std::uint64_t{1} << (2 * half_bits_)) < n) ++half_bits_;
  half_mask_ = (std::uint64_t{1} << half_bits_) - 1;
}

std::uint64_t KeyedPermutation::round_function(int round, std::uint64_t half) const {
  return mix64(key_ ^ mix64(half + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(round + 1))) &
         half_mask_;
}

// x = (L, R) → (R, L ⊕ F_r(R)), `rounds` times.
std::uint64_t KeyedPermutation::encrypt(std::uint64_t x) const {
  std::uint64_t left = x >> half_bits_;
  std::uint64_t right = x & half_mask_;
  for (int r = 0; r < rounds; ++r) {
    const std::uint64_t next = left ^ round_function(r, right);
    left = right;
    right = next;
  }
  return (left << half_bits_) | right;
}

std::uint64_t KeyedPermutation::decrypt(std::uint64_t x) const {
  std::uint64_t left = x >> half_bits_;
  std::uint64_t right = x & half_mask_;
  for (int r = rounds - 1; r >= 0; --r) {
    const std::uint64_t prev = right ^ round_function(r, left);
    right = left;
    left = prev;
  }
  return (left << half_bits_) | right;
}

// Cycle walking: the orbit of i < n under the network returns to [0, n), and the first value
// met there defines a permutation of [0, n).
std::uint64_t KeyedPermutation::operator()(std::uint64_t i) const {
  assert(i < n_);
  std::uint64_t x = encrypt(i);
  while (x >= n_) x = encrypt(x);
  return x;
}

std::uint64_t KeyedPermutation::inverse(std::uint64_t j) const {
  assert(j < n_);
  std::uint64_t x = decrypt(j);
  while (x >= n_) x = decrypt(x);
  return x;
}

}  // namespace kanesens::study
