// Directions evaluated in multi-tangent passes (math/multi_dual.hpp): k directions (Jacobian
// columns, sensitivities) split into blocks of the compiled widths (KANESENS_MULTI_DUAL_WIDTHS:
// 2 to 16), each with its own workspace (its parameter tangents set once per sample), embedding
// scratch and seeded state. Allocated at construction; evaluating a block allocates nothing.
#pragma once
#include <algorithm>
#include <memory>
#include <tuple>
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
// a 5-DOF scene exactly, 6 six sensitivities, 2 two). Fewer, wider passes win: each pass repeats the
// value work. W: the compiled widths, widest first.
template <int... W>
class TangentBlockSet {
 public:
  static constexpr int max_width = std::max({W...});
  TangentBlockSet() = default;
  TangentBlockSet(const model::Model& m, int directions) {
    for (int first = 0; first < directions; first += max_width) {
      const int c = std::min(max_width, directions - first);
      int width = max_width;
      for (int w : {W...})
        if (w >= c) width = std::min(width, w);
      ((W == width ? (std::get<Blocks<W>>(blocks_).push_back(std::make_unique<TangentBlock<W>>(m, first, c)), 0) : 0),
       ...);
    }
  }
  // f(block) for every block, the one holding direction 0 first (a generic callable: the blocks
  // have different widths).
  template <class F>
  void for_each(F&& f) {
    std::apply([&](auto&... blocks) { ((void)[&] { for (auto& b : blocks) f(*b); }(), ...); }, blocks_);
  }

 private:
  template <int V>
  using Blocks = std::vector<std::unique_ptr<TangentBlock<V>>>;
  std::tuple<Blocks<W>...> blocks_;
};

using TangentBlocks = TangentBlockSet<KANESENS_MULTI_DUAL_WIDTHS>;

}  // namespace kanesens::sim
