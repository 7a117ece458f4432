// How a study treats constraints (study YAML `solver.constraints`).
#pragma once

namespace kanesens::sim {

struct ConstraintOptions {
  enum class Formulation { multipliers, embedding };
  // Drift of the position and velocity constraints: left alone (none), damped by Baumgarte
  // terms in the acceleration constraint (A u̇ = b − 2α(Au + a0) − β²g), or removed after every
  // step by projecting the state onto the constraint manifold (CVODES projection with BDF, or
  // after every accepted DOP853 step; not with Adams).
  enum class Stabilization { none, baumgarte, projection };
  Formulation formulation = Formulation::multipliers;
  Stabilization stabilization = Stabilization::projection;
  double alpha = 5.0, beta = 5.0;  // Baumgarte rates, 1/s
  bool correct_initial = true;     // make q0, u0 consistent (and report the correction)
  // With projection: project the recorded sensitivities onto the constraints' tangent space at
  // each output (CVODES projects y only; docs/explanation/constraints.md measures the difference).
  bool project_sensitivities = true;
};

}  // namespace kanesens::sim
