// The `sampling:` section of a study file, parsed strictly.
//
//   sampling: {method: sobol, samples: 1024, seed: 42, randomize: true}
//
// Keys by method (all take `method`, default mc, and `seed`, default 0):
//   mc, lhs          samples (runs, required)
//   sobol, halton    samples (required), randomize (default false)
//   grid             levels: N for every input, or {input: N, ...}; choice inputs default to
//                    their number of values and fixed inputs to 1; runs = product of levels
//   saltelli         samples = base count N (required; runs = N·(P+2)), base (sobol, halton,
//                    mc, lhs; default sobol), randomize (sobol/halton base only)
//   morris           trajectories r (required; runs = r·(P+1)), levels p (even, default 4)
// A key that belongs to another method is an error naming the method it belongs to; other
// unknown keys get a did-you-mean suggestion. samples must be in [1, 1e9].
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

#include "study/sampling_spec.hpp"
#include "util/error.hpp"

namespace kanesens::study {

// file_ctx.file names the study file (line and column are taken from the nodes' marks).
// `path` is the key path of `node` in the study, for messages.
SamplingSpec parse_sampling(const YAML::Node& node, const SourceLocation& file_ctx,
                            const std::string& path = "sampling");

}  // namespace kanesens::study
