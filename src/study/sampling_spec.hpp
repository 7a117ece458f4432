// What the `sampling:` section of a study file asks for. Plain data with
// defaults; parse_sampling() fills it strictly and Design validates it against the inputs.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "util/error.hpp"

namespace kanesens::study {

enum class SamplingMethod { mc, lhs, sobol, halton, grid, saltelli, morris };

std::string_view method_name(SamplingMethod m);
std::optional<SamplingMethod> method_from_name(std::string_view name);

// One entry of `levels: {name: count, ...}` for a grid, with where it was written.
struct GridLevels {
  std::string input;
  std::int64_t levels = 0;
  SourceLocation where;
};

struct SamplingSpec {
  SamplingMethod method = SamplingMethod::mc;
  // mc, lhs, sobol, halton: the number of runs. saltelli: the base sample count N (runs =
  // N·(P+2)). Unused (0) for grid and morris.
  std::int64_t samples = 0;
  std::uint64_t seed = 0;
  // sobol: Owen nested uniform scramble; halton: Cranley–Patterson random shift; saltelli: the
  // same for its sobol/halton base. Both keyed by `seed`.
  bool randomize = false;
  // saltelli: the sequence the 2P-dimensional base points [A | B] come from (mc, lhs, sobol,
  // halton).
  SamplingMethod base = SamplingMethod::sobol;
  // grid: level count for every input not named in grid_levels_by_input (0: none given).
  std::int64_t grid_levels = 0;
  std::vector<GridLevels> grid_levels_by_input;
  // morris: r trajectories on a p-level grid (p even, ≥ 2).
  std::int64_t trajectories = 0;
  std::int64_t morris_levels = 4;
  // The `sampling:` node, for errors only found when the design meets its inputs.
  SourceLocation where;
};

// Designs larger than this are refused (a typo such as an extra zero, not a real study).
inline constexpr std::int64_t max_design_runs = 1'000'000'000;

}  // namespace kanesens::study
