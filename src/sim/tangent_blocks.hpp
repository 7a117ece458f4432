// Directions evaluated in multi-tangent passes (math/multi_dual.hpp): k directions (Jacobian
// columns, sensitivities) split into blocks of the compiled widths 4, 6, 8, 10, 12, 16, each with its own
// workspace (its parameter tangents set once per sample), embedding scratch and seeded state.
// Allocated at construction; evaluating a block allocates nothing.
#pragma once
#include <algorithm>
#include <memory>
#include <vector>

#include "dynamics/embedding.hpp"
#include "dynamics/workspace.hpp"
#include "math/multi_dual.hpp"

namespace kanesens::sim {

template <int W>
struct TangentBlock {
  using Scalar = math::MultiDual<W>;
  TangentBlock(const model::Model& m, int first_direction, int directions)
      : first(first_direction),
        count(directions),
        ws(m),
        y(m.nstate()),
        ydot(m.nstate()),
        constraint_residual(m.nconstraint_rows) {}
  int first, count;  // directions [first, first + count), count ≤ W
  dynamics::Workspace<Scalar> ws;
  std::unique_ptr<dynamics::EmbeddingScratch<Scalar>> embedding;
  std::vector<Scalar> y, ydot;
  std::vector<Scalar> constraint_residual;  // m: c of dynamics::evaluate_residual
};

// k directions take ⌈k/16⌉ passes: blocks of 16 and one block of the smallest width that holds
// the rest (at most 3 idle directions, rounded up to whole SIMD packs; 10 holds the Jacobian of
// a 5-DOF scene exactly, 6 six sensitivities). Fewer, wider passes win: each pass repeats the
// value work.
class TangentBlocks {
 public:
  static constexpr int max_width = 16;
  TangentBlocks() = default;
  TangentBlocks(const model::Model& m, int directions) {
    for (int first = 0; first < directions; first += max_width) {
      const int c = std::min(max_width, directions - first);
      if (c <= 4) b4_.push_back(std::make_unique<TangentBlock<4>>(m, first, c));
      else if (c <= 6) b6_.push_back(std::make_unique<TangentBlock<6>>(m, first, c));
      else if (c <= 8) b8_.push_back(std::make_unique<TangentBlock<8>>(m, first, c));
      else if (c <= 10) b10_.push_back(std::make_unique<TangentBlock<10>>(m, first, c));
      else if (c <= 12) b12_.push_back(std::make_unique<TangentBlock<12>>(m, first, c));
      else b16_.push_back(std::make_unique<TangentBlock<16>>(m, first, c));
    }
  }
  // f(block) for every block, the one holding direction 0 first (a generic callable: the blocks
  // have different widths).
  template <class F>
  void for_each(F&& f) {
    for (auto& b : b16_) f(*b);
    for (auto& b : b12_) f(*b);
    for (auto& b : b10_) f(*b);
    for (auto& b : b8_) f(*b);
    for (auto& b : b6_) f(*b);
    for (auto& b : b4_) f(*b);
  }

 private:
  std::vector<std::unique_ptr<TangentBlock<16>>> b16_;
  std::vector<std::unique_ptr<TangentBlock<12>>> b12_;
  std::vector<std::unique_ptr<TangentBlock<10>>> b10_;
  std::vector<std::unique_ptr<TangentBlock<8>>> b8_;
  std::vector<std::unique_ptr<TangentBlock<6>>> b6_;
  std::vector<std::unique_ptr<TangentBlock<4>>> b4_;
};

}  // namespace kanesens::sim
