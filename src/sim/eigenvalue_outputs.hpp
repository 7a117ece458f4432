// Study outputs of type eigenvalues (docs/reference/study.md): the eigenvalues of the linearized
// system (sim/linearize.hpp) at a sample's consistent initial state, and their exact derivatives
// with respect to the sample's sensitivities.
#pragma once
#include "sim/kane_problem.hpp"
#include "sim/output_plan.hpp"

namespace kanesens::sim {

// The node's values (re0, im0, re1, ... : 2 × eigenvalue_count, from values[0]) and tangents
// (tangents[c × ns + i] for component c and sensitivity i) at the problem's current sample.
//
// dλ/dε_i = wᴴ (dA/dε_i) v / (wᴴ v), with dA/dε_i the derivative of A along (ṗ_i, s_i(t0)): the
// parameter's tangent and the consistent initial state's sensitivity, so a parameter that moves
// the initial state is accounted for. Eigenvalues are sorted as modes() sorts them (decreasing
// real part, then decreasing imaginary part). A repeated eigenvalue has NaN derivatives.
// Throws std::runtime_error ("outputs.NAME: ...") when the sample cannot be linearized.
void evaluate_eigenvalues(const OutputNode& node, KaneProblem& problem, double* values, double* tangents);

}  // namespace kanesens::sim
