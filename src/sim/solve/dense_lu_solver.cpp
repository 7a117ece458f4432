#include "sim/solve/dense_lu_solver.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/LU>
#include <cmath>

namespace kanesens::sim {

namespace {

struct Content {
  explicit Content(sunindextype size) : n(size), lu(size), scratch(size) {}
  sunindextype n;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // sized once: compute() and solves allocate nothing
  Eigen::VectorXd scratch;                  // b when the solve is in place (x = b)
  sunindextype last_flag = SUNLS_SUCCESS;
};

Content& content(SUNLinearSolver S) { return *static_cast<Content*>(S->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver S) {
  content(S).last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
  Content& c = content(S);
  if (SUNMatGetID(A) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(A) != c.n || SUNDenseMatrix_Columns(A) != c.n)
    return static_cast<int>(c.last_flag = SUNLS_ILL_INPUT);
  c.lu.compute(Eigen::Map<const Eigen::MatrixXd>(SUNDenseMatrix_Data(A), c.n, c.n));
  // PartialPivLU does not stop at a zero pivot; U's diagonal tells.
  const auto pivots = c.lu.matrixLU().diagonal();
  for (Eigen::Index k = 0; k < pivots.size(); ++k)
    if (!(pivots[k] != 0) || !std::isfinite(pivots[k])) return static_cast<int>(c.last_flag = SUNLS_LUFACT_FAIL);
  return static_cast<int>(c.last_flag = SUNLS_SUCCESS);
}

int solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  Content& c = content(S);
  double* xd = N_VGetArrayPointer(x);
  const double* bd = N_VGetArrayPointer(b);
  if (xd == nullptr || bd == nullptr) return static_cast<int>(c.last_flag = SUNLS_MEM_FAIL);
  // x = P b gathered from another vector (Eigen permutes a vector in place only with a mask it
  // allocates), then the two triangular solves in place.
  Eigen::Map<Eigen::VectorXd> v(xd, c.n);
  if (xd == bd) {
    c.scratch = v;
    v = c.lu.permutationP() * c.scratch;
  } else {
    v = c.lu.permutationP() * Eigen::Map<const Eigen::VectorXd>(bd, c.n);
  }
  c.lu.matrixLU().template triangularView<Eigen::UnitLower>().solveInPlace(v);
  c.lu.matrixLU().template triangularView<Eigen::Upper>().solveInPlace(v);
  return static_cast<int>(c.last_flag = SUNLS_SUCCESS);
}

sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

int space(SUNLinearSolver S, long int* lenrw, long int* leniw) {
  const long int n = static_cast<long int>(content(S).n);
  *lenrw = n * n;
  *leniw = 2 * n;
  return SUNLS_SUCCESS;
}

int free_solver(SUNLinearSolver S) {
  if (S == nullptr) return SUNLS_SUCCESS;
  delete static_cast<Content*>(S->content);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver make_dense_lu_solver(sunindextype n, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == nullptr) return nullptr;
  try {
    S->content = new Content(n);
  } catch (...) {
    SUNLinSolFreeEmpty(S);
    return nullptr;
  }
  S->ops->gettype = get_type;
  S->ops->getid = get_id;
  S->ops->initialize = initialize;
  S->ops->setup = setup;
  S->ops->solve = solve;
  S->ops->lastflag = last_flag;
  S->ops->space = space;
  S->ops->free = free_solver;
  return S;
}

}  // namespace kanesens::sim
