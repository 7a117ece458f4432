// Newton's dense linear solver for CVODES: (I − γJ) x = b by Eigen's LU with partial pivoting
// (PartialPivLU, sized once) and substitutions written out for small sizes, behind SUNDIALS's
// generic SUNLinearSolver interface.
//
// Why not SUNLinSol_Dense: CVODES solves once per Newton iteration for the state and once more
// for each sensitivity (the simultaneous corrector), so on the small systems here the solves
// are a large share of a run with sensitivities, and SUNDIALS's GETRS (a division on every step
// of the back substitution's dependent chain, loops through column pointers that may alias the
// right-hand side) is the slower one at every size measured (bench/dense_lu_solve.cpp,
// bench/results/dense_lu_solve.json). Eigen's own triangular solves take its blocked path even
// at these sizes; the substitutions here use the reciprocal pivots formed at setup.
//
// Setup returns SUNLS_LUFACT_FAIL (recoverable: CVODES retries with a smaller step) on a zero or
// non-finite pivot, or one whose reciprocal overflows, as SUNLinSol_Dense does on a zero one.
#pragma once
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

namespace kanesens::sim {

// An n×n direct solver (SUNLINEARSOLVER_DIRECT) for a SUNDenseMatrix of that size; free it with
// SUNLinSolFree. nullptr if allocation fails. A right-hand side of k·n entries (a state stacked
// with its sensitivities) is solved block by block with the one factorisation: for n ≤ 16 by
// products with the inverse, formed from the factors at the first such solve after each setup
// (its entries independent, where the substitutions are a chain per block); a length that is
// not a multiple of n is SUNLS_ILL_INPUT.
SUNLinearSolver make_dense_lu_solver(sunindextype n, SUNContext ctx);

}  // namespace kanesens::sim
