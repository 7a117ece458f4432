// The study's outputs (study/output_spec.hpp) resolved against the model into the plan the sim
// layer evaluates (sim/output_plan.hpp): names of bodies, joints, constraints and forces (with a
// did-you-mean), points and expressions compiled, the outputs put in evaluation order. Every
// problem is an InputError at the key where it was written:
//   "study.yaml:14:20: outputs.tip.body: unknown body 'rod3' (did you mean 'rod2'?); bodies are: rod1, rod2"
#pragma once
#include <functional>
#include <span>
#include <vector>

#include "model/model.hpp"
#include "sim/linearize.hpp"
#include "sim/output_plan.hpp"
#include "study/output_spec.hpp"

namespace kanesens::study {

// The nominal sample's linearization at its consistent initial state with the given options
// (outputs of type eigenvalues take their reduced coordinates and speeds, and their number, from it).
using NominalLinearization = std::function<sim::Linearization(const sim::LinearizeOptions&)>;

// output_times: the study's (`at:` must lie in their span; `end` is the last).
sim::OutputPlan build_output_plan(const std::vector<OutputSpec>& specs, const model::Model& model,
                                  std::span<const double> output_times, const NominalLinearization& nominal = {});

// Names an output may not take: they name the run file's other outputs (/outputs/energy, ...).
bool is_reserved_output_name(const std::string& name);

}  // namespace kanesens::study
