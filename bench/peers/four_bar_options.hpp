// The command line both four-bar peer programs take: [--repeat R] [--batch-seconds B] times one
// evaluation; --integrate NAME integrates, with the program's step option (--dt or --accuracy).
// C++17 (the Simbody program cannot be compiled as C++20).
#pragma once
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace four_bar {

struct Options {
  int repeat = 31;
  double batch_seconds = 2e-3;
  std::string which;  // --integrate; empty: time one evaluation
  double step = 1e-3;  // the value of `step_option`
};

// False, with a message on stderr, for an option it does not take or one without its value;
// `usage` is a printf format with two %s, the program's name.
inline bool parse_options(int argc, char** argv, const char* step_option, const char* usage, Options& o) {
  for (int i = 1; i < argc; i += 2) {
    if (i + 1 >= argc) { std::fprintf(stderr, "option %s needs a value\n", argv[i]); return false; }
    if (!std::strcmp(argv[i], "--repeat")) o.repeat = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--batch-seconds")) o.batch_seconds = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--integrate")) o.which = argv[i + 1];
    else if (!std::strcmp(argv[i], step_option)) o.step = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, usage, argv[0], argv[0]);
      return false;
    }
  }
  return true;
}

}  // namespace four_bar
