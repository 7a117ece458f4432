// kanesens command line: check, eom, linearize, simulate, run, bench (see README "Command line").
// Errors become one line on stderr and a non-zero exit: 2 for bad input, 1 for anything else.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "util/error.hpp"
#include "parallel/version.hpp"

namespace {
// This process's rank in an MPI job, from the launcher's environment (the command line is parsed
// before MPI_Init): every rank parses the same arguments, and only rank 0 reports their errors.
bool is_first_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"})
    if (const char* v = std::getenv(name)) return std::atoi(v) == 0;
  return true;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"kanesens: Kane's equations, CVODES sensitivities and MPI ensembles of multibody systems"};
  app.require_subcommand(0, 1);
  bool show_version = false;
  app.add_flag("--version", show_version, "Print versions of kanesens and the libraries it was built with");
  kanesens::cli::Action action;
  std::vector<CLI::App*> subs = {kanesens::cli::add_check(app, action), kanesens::cli::add_eom(app, action),
                                kanesens::cli::add_linearize(app, action),
                                kanesens::cli::add_simulate(app, action),
                                kanesens::cli::add_run(app, action),
                                kanesens::cli::add_bench(app, action)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    // A usage error is bad input like any other: one line, exit 2 (docs/reference/exit-codes.md).
    std::string what = e.what();
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    if (is_first_rank()) std::cerr << "kanesens: error: " << what << " (kanesens --help lists the options)\n";
    return 2;
  }
  if (show_version) {
    std::cout << kanesens::parallel::version_report();
    return 0;
  }
  if (!action) {
    std::cout << app.help();
    return 0;
  }
  try {
    return action();
  } catch (const kanesens::InputError& e) {
    std::cerr << "kanesens: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "kanesens: error: " << e.what() << "\n";
    return 1;
  }
}
