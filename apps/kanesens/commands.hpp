// The kanesens subcommands. Each adds itself to the CLI and returns the action to run if chosen.
#pragma once
#include <CLI/CLI.hpp>
#include <cmath>
#include <functional>
#include <string>

namespace kanesens::cli {

using Action = std::function<int()>;

// A numeric option outside its range is a usage error like an unknown option: main() prints one
// line and exits 2 (CLI11's own Range lets NaN through, so doubles are checked here).
inline CLI::Validator finite_number(double lo = -HUGE_VAL, double hi = HUGE_VAL) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double x = 0;
        if (!CLI::detail::lexical_cast(text, x) || !std::isfinite(x))
          return "expected a finite number, found '" + text + "'";
        if (x < lo || x > hi)
          return "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found '" + text + "'";
        return {};
      },
      "FINITE");
}
inline CLI::Validator integer_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long x = 0;
        if (!CLI::detail::lexical_cast(text, x) || x < lo || x > hi)
          return "expected a whole number " +
                 (hi >= (1LL << 40) ? "≥ " + std::to_string(lo) : "from " + std::to_string(lo) + " to " + std::to_string(hi)) +
                 ", found '" + text + "'";
        return {};
      },
      "INT");
}

CLI::App* add_check(CLI::App& app, Action& action);
CLI::App* add_eom(CLI::App& app, Action& action);
CLI::App* add_linearize(CLI::App& app, Action& action);
CLI::App* add_simulate(CLI::App& app, Action& action);
CLI::App* add_run(CLI::App& app, Action& action);
CLI::App* add_bench(CLI::App& app, Action& action);

}  // namespace kanesens::cli
