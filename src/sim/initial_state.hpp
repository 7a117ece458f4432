// The initial state of a sample and its sensitivities, consistent with the constraints.
//
// y0(p) comes from the scene's q0/u0 expressions of the parameters, the sample's explicit
// initial values and the normalisation of quaternions; with constraints (and correct_initial)
// it is corrected onto them: positions by Newton on dependent coordinates, then speeds by the
// linear solve for dependent speeds. The whole computation runs in dual arithmetic, one tangent
// per sensitivity, so s_i(t0) = ∂y0/∂p_i is the tangent of the corrected state. Every tangent is
// carried through the same iteration: one Newton sequence (and one factorisation per step) for
// the state and all its sensitivities.
#pragma once
#include <vector>

#include "sim/constraint_options.hpp"
#include "sim/holonomic.hpp"
#include "sim/inputs.hpp"
#include "sim/sample_workspaces.hpp"

namespace kanesens::sim {

struct InitialState {
  std::vector<double> y;               // nstate: [q; u]
  std::vector<std::vector<double>> s;  // ns × nstate: ∂y/∂(sensitivity i)
  // Size of the correction that made y consistent: max over the components of |Δq|, |Δu| (0
  // without one).
  double position_correction = 0, velocity_correction = 0;
};

// Throws InputError when a quaternion's initial value is zero or the position constraints
// cannot be satisfied at t0 (Newton does not converge). `workspaces` and `holonomic` must hold
// the sample's parameters.
InitialState consistent_initial_state(const model::Model& model, const SampleInputs& inputs,
                                      const std::vector<InputRef>& sensitivities, const ConstraintOptions& options,
                                      double t0, SampleWorkspaces& workspaces, HolonomicConstraints& holonomic);

}  // namespace kanesens::sim
