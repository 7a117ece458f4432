// The dense SUNMatrix's operations that CVODES's Newton setup calls on every rebuild of
// I − γJ (copy the saved Jacobian, zero, scale and add the identity), compiled with the project.
//
// Why not SUNDIALS's own: Debian 12's libsundials (6.4) is built without optimisation, as for the
// vector operations (sim/solve/serial_vector_ops.hpp), and these loops over the n² entries were a
// few percent of a BDF solve. They compute what sunmatrix_dense computes, entry by entry in the
// same order (c·a, then + 1 on the diagonal), so the results are SUNDIALS's to the bit
// (tests/unit/test_dense_matrix_ops.cpp compares them with the library's).
#pragma once
#include <sundials/sundials_matrix.h>

namespace kanesens::sim {

// Points A's zero, copy, scaleaddi and clone operations at the compiled ones (clones get them
// too). Throws std::invalid_argument unless A is a dense SUNMatrix.
void use_compiled_dense_ops(SUNMatrix A);

}  // namespace kanesens::sim
