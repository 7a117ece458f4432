// One trajectory of a KaneProblem: integrate to the output times and collect states,
// sensitivities and outputs into flat row-major buffers (the layout of one HDF5 sample row).
#pragma once
#include <span>
#include <string>
#include <vector>

#include "sim/kane_problem.hpp"
#include "sim/solve/integrator.hpp"

namespace kanesens::sim {

struct RecordFlags {
  bool states = true, sensitivities = true, energy = true;
  bool multipliers = false, constraint_residual = false;  // only for scenes with constraints
};

struct Trajectory {
  std::vector<double> states;         // T × nstate
  std::vector<double> sensitivities;  // T × nstate × nsens
  std::vector<double> energy;         // T
  std::vector<double> multipliers;    // T × m
  std::vector<double> multiplier_sensitivities;  // T × m × nsens (with multipliers and sensitivities)
  std::vector<double> position_residual, velocity_residual;  // T: max |g|, max |A u + a0|
  IntegrationResult result;
};

// Preallocates the buffers for `ntimes` outputs (reuse across samples: no reallocation).
void resize_trajectory(Trajectory& traj, const KaneProblem& problem, std::size_t ntimes, const RecordFlags& flags);

// The record callback simulate() passes to the integrator: fills `traj` (already sized by
// resize_trajectory) at output k. For other integrators of the same problem (integrate_rk4).
RecordFn make_recorder(KaneProblem& problem, const RecordFlags& flags, Trajectory& traj);

// Integrates the problem's current sample. Outputs past a failure stay NaN.
void simulate(KaneProblem& problem, Integrator& integrator, std::span<const double> times,
              const RecordFlags& flags, Trajectory& traj);

}  // namespace kanesens::sim
