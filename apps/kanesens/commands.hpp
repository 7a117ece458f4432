// The kanesens subcommands. Each adds itself to the CLI and returns the action to run if chosen.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace kanesens::cli {

using Action = std::function<int()>;

CLI::App* add_check(CLI::App& app, Action& action);
CLI::App* add_eom(CLI::App& app, Action& action);
CLI::App* add_linearize(CLI::App& app, Action& action);
CLI::App* add_simulate(CLI::App& app, Action& action);
CLI::App* add_run(CLI::App& app, Action& action);
CLI::App* add_bench(CLI::App& app, Action& action);
// `bench workprecision` (cmd_bench_workprecision.cpp), added to the `bench` subcommand by add_bench.
void add_bench_workprecision(CLI::App* bench, Action& action);

}  // namespace kanesens::cli
