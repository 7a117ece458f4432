// kanesens command line: check, eom, simulate, run, bench (see README "Command line").
#include <CLI/CLI.hpp>
#include <iostream>

#include "util/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"kanesens: Kane's equations, CVODES sensitivities and MPI ensembles"};
  app.require_subcommand(0, 1);
  bool show_version = false;
  app.add_flag("--version", show_version, "Print versions of kanesens and its libraries");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (show_version) {
    std::cout << kanesens::version_report();
    return 0;
  }
  std::cout << app.help();
  return 0;
}
