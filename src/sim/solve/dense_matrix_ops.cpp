// The dense SUNMatrix's operations compiled with the project (sim/solve/dense_matrix_ops.hpp):
// what SUNDIALS 6.4's sunmatrix_dense computes, entry by entry.
#include "sim/solve/dense_matrix_ops.hpp"

#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <stdexcept>

namespace kanesens::sim {

namespace {

bool same_shape(SUNMatrix A, SUNMatrix B) {
  return SUNMatGetID(B) == SUNMATRIX_DENSE && SM_ROWS_D(A) == SM_ROWS_D(B) && SM_COLUMNS_D(A) == SM_COLUMNS_D(B);
}

int op_zero(SUNMatrix A) {
  std::fill(SM_DATA_D(A), SM_DATA_D(A) + SM_LDATA_D(A), 0.0);
  return SUNMAT_SUCCESS;
}

// B = A.
int op_copy(SUNMatrix A, SUNMatrix B) {
  if (!same_shape(A, B)) return SUNMAT_ILL_INPUT;
  std::copy(SM_DATA_D(A), SM_DATA_D(A) + SM_LDATA_D(A), SM_DATA_D(B));
  return SUNMAT_SUCCESS;
}

// A = c A + I: each entry scaled, then 1 added on the diagonal, as SUNMatScaleAddI_Dense.
int op_scale_add_identity(realtype c, SUNMatrix A) {
  const sunindextype rows = SM_ROWS_D(A), columns = SM_COLUMNS_D(A);
  realtype* a = SM_DATA_D(A);
  for (sunindextype k = 0; k < rows * columns; ++k) a[k] *= c;
  for (sunindextype j = 0; j < std::min(rows, columns); ++j) a[j * rows + j] += 1.0;
  return SUNMAT_SUCCESS;
}

SUNMatrix op_clone(SUNMatrix A) {
  SUNMatrix B = SUNDenseMatrix(SM_ROWS_D(A), SM_COLUMNS_D(A), A->sunctx);
  if (B != nullptr) use_compiled_dense_ops(B);
  return B;
}

}  // namespace

void use_compiled_dense_ops(SUNMatrix A) {
  if (A == nullptr || SUNMatGetID(A) != SUNMATRIX_DENSE)
    throw std::invalid_argument("use_compiled_dense_ops: not a dense SUNMatrix");
  A->ops->zero = op_zero;
  A->ops->copy = op_copy;
  A->ops->scaleaddi = op_scale_add_identity;
  A->ops->clone = op_clone;
}

}  // namespace kanesens::sim
