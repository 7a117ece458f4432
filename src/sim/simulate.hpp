// One trajectory of a KaneProblem: integrate to the output times and collect states,
// sensitivities and outputs into flat row-major buffers (the layout of one HDF5 sample row).
#pragma once
#include <span>
#include <string>
#include <vector>

#include "sim/kane_problem.hpp"
#include "sim/output_plan.hpp"
#include "sim/solve/integrator.hpp"

namespace kanesens::sim {

struct RecordFlags {
  bool states = true, sensitivities = true, energy = true;
  bool multipliers = false, constraint_residual = false;  // only for scenes with constraints
  bool poses = false;                                     // every body's pose (record: poses)
  // The study's outputs (sim/output_plan.hpp), or none. Their sensitivities are recorded
  // whenever the problem has sensitivities (whatever `sensitivities` says about the states').
  const OutputPlan* outputs = nullptr;
};

struct Trajectory {
  std::vector<double> states;         // T × nstate
  std::vector<double> sensitivities;  // T × nstate × nsens
  std::vector<double> energy;         // T
  std::vector<double> multipliers;    // T × m
  std::vector<double> multiplier_sensitivities;  // T × m × nsens (with multipliers and sensitivities)
  std::vector<double> position_residual, velocity_residual;  // T: max |g|, max |A u + a0|
  // The study's outputs, in OutputPlan::series_names / scalar_names order:
  std::vector<double> outputs;                      // nseries × T
  std::vector<double> output_sensitivities;         // nseries × T × nsens
  std::vector<double> scalar_outputs;               // nscalar
  std::vector<double> scalar_output_sensitivities;  // nscalar × nsens
  std::vector<double> poses;                        // T × nbody × 7: position, quaternion (w, x, y, z)
  // The study's events, in OutputPlan::event_nodes order, W = OutputPlan::event_occurrences:
  std::vector<double> event_times;              // nevent × W, NaN-padded past each event's occurrences
  std::vector<double> event_time_sensitivities;  // nevent × W × nsens
  std::vector<double> event_counts;             // nevent
  IntegrationResult result;
};

// Preallocates the buffers for `ntimes` outputs (reuse across samples: no reallocation).
void resize_trajectory(Trajectory& traj, const KaneProblem& problem, std::size_t ntimes, const RecordFlags& flags);

// The record callback simulate() passes to the integrator: fills `traj` (already sized by
// resize_trajectory) at output k. For other integrators of the same problem (integrate_rk4).
// It records everything but the study's outputs (flags.outputs), which need simulate().
RecordFn make_recorder(KaneProblem& problem, const RecordFlags& flags, Trajectory& traj);

// Integrates the problem's current sample. Outputs past a failure stay NaN, and so do the
// integral/mean/rms outputs of a failed sample. Throws std::invalid_argument if an `at:` time of
// the outputs lies outside the output times' span.
void simulate(KaneProblem& problem, Integrator& integrator, std::span<const double> times,
              const RecordFlags& flags, Trajectory& traj);

}  // namespace kanesens::sim
