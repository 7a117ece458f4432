// What the equations of motion are, beyond the model: settings chosen by the caller (the study's
// solver.constraints), passed to every evaluation. Not per-thread data: one value for all
// workspaces, so the Jacobian and the sensitivities differentiate the equations that are
// integrated.
#pragma once

namespace kanesens::dynamics {

struct DynamicsOptions {
  // Baumgarte stabilisation of the acceleration constraint, 1/s: A u̇ = b − 2α (A u + a0) − β² g.
  // Both 0 (the default): no stabilisation terms.
  double baumgarte_alpha = 0, baumgarte_beta = 0;
};

}  // namespace kanesens::dynamics
