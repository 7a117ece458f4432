#include "sim/solve/sundials_handles.hpp"

#include <cvodes/cvodes_ls.h>
#include "sim/solve/dense_lu_solver.hpp"
#include "sim/solve/dense_matrix_ops.hpp"
#include "sim/solve/serial_vector_ops.hpp"
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstdlib>
#include <stdexcept>

namespace kanesens::sim {

namespace {
// CVodeGetReturnFlagName and CVodeGetLinReturnFlagName return a malloc'd string the caller
// must free (a CVODES quirk: forgetting it leaks 24 bytes per call).
std::string take_c_string(char* s) {
  if (s == nullptr) return "UNKNOWN";
  std::string out(s);
  std::free(s);
  return out;
}
}  // namespace

std::string cvode_flag_name(int flag) {
  return take_c_string(CVodeGetReturnFlagName(flag));
}
std::string cvode_ls_flag_name(int flag) {
  return take_c_string(CVodeGetLinReturnFlagName(flag));
}

void check_flag(int flag, const char* call) {
  if (flag < 0) {
    throw std::runtime_error(std::string(call) + " failed: " + cvode_flag_name(flag) + " (" +
                             std::to_string(flag) + ")");
  }
}

void check_ls_flag(int flag, const char* call) {
  if (flag < 0) {
    throw std::runtime_error(std::string(call) + " failed: " + cvode_ls_flag_name(flag) + " (" +
                             std::to_string(flag) + ")");
  }
}

void check_ptr(const void* ptr, const char* call) {
  if (ptr == nullptr) throw std::runtime_error(std::string(call) + " failed: returned NULL");
}

ContextPtr make_context() {
  SUNContext ctx = nullptr;
  const int flag = SUNContext_Create(nullptr, &ctx);
  if (flag != 0 || ctx == nullptr) {
    throw std::runtime_error("SUNContext_Create failed: " + std::to_string(flag));
  }
  return ContextPtr(ctx);
}

NVectorPtr make_serial_vector(int n, SUNContext ctx) {
  // An empty vector given the compiled operations, then cloned: the clone has them and its data
  // is aligned as theirs wants (use_compiled_serial_ops).
  NVectorPtr empty(N_VNewEmpty_Serial(n, ctx));
  check_ptr(empty.get(), "N_VNewEmpty_Serial");
  use_compiled_serial_ops(empty.get());
  NVectorPtr owned(N_VClone(empty.get()));
  check_ptr(owned.get(), "N_VClone");
  return owned;
}

MatrixPtr make_dense_matrix(int n, SUNContext ctx) {
  SUNMatrix m = SUNDenseMatrix(n, n, ctx);
  check_ptr(m, "SUNDenseMatrix");
  MatrixPtr owned(m);
  use_compiled_dense_ops(m);
  return owned;
}

LinearSolverPtr make_dense_solver(int n, SUNContext ctx) {
  SUNLinearSolver ls = make_dense_lu_solver(n, ctx);
  check_ptr(ls, "make_dense_lu_solver");
  return LinearSolverPtr(ls);
}

LinearSolverPtr make_gmres_solver(N_Vector y, SUNContext ctx) {
  // Preconditioned on the left (the integrator's); maxl 0 = SUNDIALS's default Krylov dimension.
  SUNLinearSolver ls = SUNLinSol_SPGMR(y, SUN_PREC_LEFT, 0, ctx);
  check_ptr(ls, "SUNLinSol_SPGMR");
  return LinearSolverPtr(ls);
}

CvodeMemPtr make_cvode(int lmm, SUNContext ctx) {
  void* mem = CVodeCreate(lmm, ctx);
  check_ptr(mem, "CVodeCreate");
  return CvodeMemPtr(mem);
}

NVectorArray::NVectorArray(int count, N_Vector like) {
  vectors_ = N_VCloneVectorArray(count, like);
  check_ptr(vectors_, "N_VCloneVectorArray");
  count_ = count;
}

}  // namespace kanesens::sim
