// kanesens command line: check, eom, linearize, simulate, run, bench (see README "Command line").
// Errors become one line on stderr and a non-zero exit: 2 for bad input, 1 for anything else.
#include <CLI/CLI.hpp>
#include <iostream>

#include "commands.hpp"
#include "util/error.hpp"
#include "parallel/version.hpp"

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
    return app.exit(e);
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
