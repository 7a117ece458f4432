// Morris elementary-effects design (Morris 1991, Technometrics 33; Campolongo, Cariboni &
// Saltelli 2007, Environ. Model. Softw. 22 — whose μ* is computed from the same trajectories).
//
// Classic grid: each input takes p levels x ∈ {0, 1/(p−1), ..., 1}, p even, and a step changes
// one input by Δ = p/(2(p−1)), i.e. by p/2 levels. A trajectory is P + 1 points: a random start
// level ℓ_i ∈ {0..p−1} per input (uniform), then the inputs are changed one at a time in a
// random order; input i moves up by p/2 levels if ℓ_i < p/2, else down. This is the
// distribution of Morris's B* = (J x* + (Δ/2)[(2B − J) D* + J]) P* with random x*, D*, P*.
//
// Unit-cube mapping: the levels are placed at the midpoints of p equal-probability cells,
// u = (ℓ + ½)/p = (x(p−1) + ½)/p, an increasing affine map of the classic grid, so that every
// distribution (unbounded ones included) has finite quantiles. In u a step is ±Δ·(p−1)/p = ±½.
//
// Run ordering: run i is step s = i mod (P+1) of trajectory t = i div (P+1); step 0 is the
// start point, step s ≥ 1 changed exactly one input. Everything is a function of (seed, i):
// start levels are hashes of (seed, t, input); the order of inputs is a keyed permutation of
// [0, P) per trajectory.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace kanesens::study {

struct MorrisStep {
  std::int64_t trajectory = 0;
  std::int64_t step = 0;    // 0 .. P
  std::int64_t input = -1;  // the input changed at this step (0-based); −1 at step 0
  int sign = 0;             // +1 up, −1 down; 0 at step 0
};

class MorrisDesign {
 public:
  MorrisDesign(std::size_t dimension, std::int64_t levels, std::uint64_t seed);

  std::size_t dimension() const { return dimension_; }
  std::int64_t levels() const { return levels_; }
  double delta() const;  // Δ = p/(2(p−1)) on the classic grid [0,1]

  MorrisStep step(std::int64_t run) const;
  // The level ℓ ∈ {0..p−1} of every input at `run` (levels.size() == P).
  void levels_at(std::int64_t run, std::span<std::int64_t> levels) const;
  // u = (ℓ + ½)/p for every input (u.size() == P).
  void unit_point(std::int64_t run, std::span<double> u) const;

  static std::string label(const MorrisStep& s);  // "traj2.step1" (both 0-based)

 private:
  std::int64_t start_level(std::int64_t trajectory, std::size_t input) const;
  std::int64_t level(std::int64_t trajectory, std::uint64_t position, std::uint64_t done,
                     std::size_t input) const;

  std::size_t dimension_;
  std::int64_t levels_;
  std::uint64_t seed_;
};

}  // namespace kanesens::study
