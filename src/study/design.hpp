// The sampling design of a study: which input values each run uses. Built once per run from the
// parsed spec and the varied inputs, then shared (immutable, cheap to copy) by every rank.
//
// Run i's values depend only on (spec, inputs, i) — never on the rank, the number of ranks or
// the order in which runs are evaluated — so an ensemble is bitwise identical for any mpirun -np.
// Each method maps i to a point u ∈ (0,1)^P (unit_sample), then every input's quantile function
// maps u_d to its value (sample). Points are computed on demand in O(P) memory, no allocation:
//   mc       u_d = hash(seed, i, d): counter-based SplitMix64 (counter_rng.hpp)
//   lhs      u_d = (π_d(i) + hash(seed, i, d)) / N, π_d a keyed permutation of [0, N) per
//            dimension (keyed_permutation.hpp): one point per stratum, O(1) memory
//   sobol    Boost.Random's Sobol' sequence, random access (sobol_points.hpp). Unrandomized,
//            run i is point i + 1 (the origin is skipped, as Boost's engine does, so u ≠ 0);
//            randomize: Owen scramble keyed by seed, run i is point i (origin kept: scrambled
//            points are inside (0,1) and the first 2^m runs keep the net property)
//   halton   radical inverses in the first P primes, same skip rule; randomize: Cranley–
//            Patterson shift keyed by seed
//   grid     u_d = (k_d + ½)/L_d, midpoints of L_d equal-probability cells; runs in row-major
//            order (the last input varies fastest), like numpy.meshgrid(indexing="ij").ravel()
//   saltelli N·(P+2) runs in blocks per base point, see saltelli.hpp
//   morris   r·(P+1) runs, r trajectories, see morris.hpp
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "study/distribution.hpp"
#include "study/morris.hpp"
#include "study/saltelli.hpp"
#include "study/sampling_spec.hpp"
#include "study/varied_input.hpp"

namespace kanesens::study {

// A run's place in a Saltelli or Morris design, as the run file records it (/design_block,
// /design_row, /design_input; docs/reference/hdf5.md). saltelli: block = base point j, row 0 = A_j,
// 1 = B_j, 2 + k = AB_j^(k), input = k (−1 for A_j and B_j). morris: block = trajectory, row =
// step, input = the input that step moved (−1 at step 0). Inputs are 0-based, in input order.
struct RunLabel {
  std::int64_t block = 0, row = 0, input = -1;
};

class Design {
 public:
  // Throws InputError (at spec.where) when the spec cannot serve these inputs (unknown input in
  // grid levels, too many dimensions for Sobol', more than max_design_runs runs, saltelli or
  // morris without inputs) and std::invalid_argument for an invalid distribution or duplicate
  // input names (parse_vary reports those with their location first).
  Design(SamplingSpec spec, std::vector<VariedInput> inputs);

  std::int64_t size() const;      // runs: saltelli N·(P+2), grid Π L_d, morris r·(P+1)
  std::size_t dimension() const;  // P, the number of varied inputs
  const SamplingSpec& spec() const;
  const std::vector<VariedInput>& inputs() const;

  // Values of run i (0 ≤ i < size()), values.size() == P, in input order.
  void sample(std::int64_t i, std::span<double> values) const;
  // The point in (0,1)^P before the quantile transform, u.size() == P.
  void unit_sample(std::int64_t i, std::span<double> u) const;

  // "A", "B", "AB3" (saltelli), "traj2.step1" (morris), "" for other methods.
  std::string block_label(std::int64_t i) const;
  bool has_run_labels() const;                         // saltelli and morris designs
  RunLabel run_label(std::int64_t i) const;            // those only (logic_error)
  SaltelliIndex saltelli_index(std::int64_t i) const;  // method saltelli only (logic_error)
  MorrisStep morris_step(std::int64_t i) const;        // method morris only (logic_error)
  double morris_delta() const;                         // Δ = p/(2(p−1)); morris only
  std::span<const std::int64_t> grid_levels() const;   // L_d per input; grid only (else empty)

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

}  // namespace kanesens::study
