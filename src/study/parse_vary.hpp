// The `vary:` section of a study file: one entry per varied input, in file order
// (the order of the design's columns and of the HDF5 `parameter` dimension).
//
//   vary:
//     m2: {dist: uniform, low: 0.8, high: 1.2}
//     shoulder.q0: {dist: normal, mean: 0.5, std: 0.05}
//
// dist and its keys: uniform {low, high}; normal {mean, std}; truncnormal {mean, std, low,
// high}; lognormal {mu, sigma} (of log X); triangular {low, mode, high}; choice {values: [...]};
// fixed {value}. Every key is required, no other key is allowed (did-you-mean on typos), numbers
// must be finite and the distribution valid (Distribution::find_problem); errors point at the
// offending value with its key path, e.g. "study.yaml:9:36: vary.m2.high: expected low < high,
// got low = 1.2, high = 0.8". Whether a name is a parameter or initial condition of the scene
// is checked where the scene is known, not here.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "study/varied_input.hpp"
#include "util/error.hpp"

namespace kanesens::study {

// file_ctx.file names the study file (line and column are taken from the nodes' marks).
// A null or absent node gives no inputs.
std::vector<VariedInput> parse_vary(const YAML::Node& node, const SourceLocation& file_ctx,
                                    const std::string& path = "vary");
// One entry's distribution, e.g. the map {dist: uniform, low: 0.8, high: 1.2} at path vary.m2.
Distribution parse_distribution(const YAML::Node& node, const SourceLocation& file_ctx, const std::string& path);

}  // namespace kanesens::study
