// A pseudo-random permutation of [0, n) evaluated point-wise in O(1) memory: a balanced Feistel
// network on the smallest even number of bits 2k with 4^k ≥ n, restricted to [0, n) by cycle
// walking (Black & Rogaway, "Ciphers with arbitrary finite domains", CT-RSA 2002). The domain
// is < 4n, so on average fewer than 4 network evaluations are needed per call. Used for Latin
// hypercube strata (one permutation per dimension) and the order of Morris steps.
#pragma once
#include <cstdint>

namespace kanesens::study {

class KeyedPermutation {
 public:
  KeyedPermutation(std::uint64_t n, std::uint64_t key);  // n ≥ 1, n ≤ 2^62

  std::uint64_t size() const { return n_; }
  std::uint64_t operator()(std::uint64_t i) const;  // π(i), i < n
  std::uint64_t inverse(std::uint64_t j) const;     // π⁻¹(j), j < n

 private:
  static constexpr int rounds = 8;
  std::uint64_t encrypt(std::uint64_t x) const;
  std::uint64_t decrypt(std::uint64_t x) const;
  std::uint64_t round_function(int round, std::uint64_t half) const;

  std::uint64_t n_;
  std::uint64_t key_;
  unsigned half_bits_;
  std::uint64_t half_mask_;
};

}  // namespace kanesens::study
