// RAII owners for the SUNDIALS objects the integrator uses, and return-code checks that turn a
// failed SUNDIALS call into a std::runtime_error naming the call and the flag:
//   "CVodeSetMaxNumSteps failed: CV_MEM_NULL (-21)".
// Each owner is move-only and frees its object with the matching SUNDIALS destructor.
// Destroy in the reverse order of creation: cvode_mem before the solvers, matrices and vectors
// it references, the SUNContext last (declare members in creation order).
#pragma once
#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <memory>
#include <string>
#include <type_traits>
#include <utility>

namespace kanesens::sim {

static_assert(std::is_same_v<sunrealtype, double>, "kanesens needs SUNDIALS built with double");

// CVODES flag name, e.g. "CV_TOO_MUCH_WORK" (CVodeGetReturnFlagName; its malloc'd string is
// freed here). CVodeGetLinReturnFlagName for the CVLS_* flags of the linear-solver interface.
std::string cvode_flag_name(int flag);
std::string cvode_ls_flag_name(int flag);

// Throw std::runtime_error("<call> failed: <FLAG_NAME> (<flag>)") when flag < 0 (CVODES
// functions). check_ls_flag is the same for CVLS functions (CVodeSetLinearSolver, CVodeSetJacFn,
// CVodeGetNumJacEvals, ...) whose negative codes overlap the CV_* ones numerically.
void check_flag(int flag, const char* call);
void check_ls_flag(int flag, const char* call);
// Throw when a SUNDIALS constructor returned nullptr.
void check_ptr(const void* ptr, const char* call);

namespace detail {
struct ContextFree {
  void operator()(SUNContext ctx) const noexcept { SUNContext_Free(&ctx); }
};
struct NVectorFree {
  void operator()(N_Vector v) const noexcept { N_VDestroy(v); }
};
struct MatrixFree {
  void operator()(SUNMatrix m) const noexcept { SUNMatDestroy(m); }
};
struct LinearSolverFree {
  void operator()(SUNLinearSolver ls) const noexcept { SUNLinSolFree(ls); }
};
struct NonlinearSolverFree {
  void operator()(SUNNonlinearSolver nls) const noexcept { SUNNonlinSolFree(nls); }
};
struct CvodeFree {
  void operator()(void* mem) const noexcept { CVodeFree(&mem); }
};
}  // namespace detail

using ContextPtr = std::unique_ptr<std::remove_pointer_t<SUNContext>, detail::ContextFree>;
using NVectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, detail::NVectorFree>;
using MatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, detail::MatrixFree>;
using LinearSolverPtr =
    std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, detail::LinearSolverFree>;
using NonlinearSolverPtr =
    std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, detail::NonlinearSolverFree>;
using CvodeMemPtr = std::unique_ptr<void, detail::CvodeFree>;

// Constructors that check for nullptr.
ContextPtr make_context();
NVectorPtr make_serial_vector(int n, SUNContext ctx);
MatrixPtr make_dense_matrix(int n, SUNContext ctx);
// LU with partial pivoting for an n×n SUNDenseMatrix (sim/solve/dense_lu_solver.hpp).
LinearSolverPtr make_dense_solver(int n, SUNContext ctx);
// Matrix-free GMRES (SUNLinSol_SPGMR), left preconditioning, SUNDIALS's default Krylov dimension.
LinearSolverPtr make_gmres_solver(N_Vector y, SUNContext ctx);
CvodeMemPtr make_cvode(int lmm, SUNContext ctx);

// An array of `count` vectors cloned from a template (N_VCloneVectorArray /
// N_VDestroyVectorArray), e.g. the sensitivities yS.
class NVectorArray {
 public:
  NVectorArray() = default;
  NVectorArray(int count, N_Vector like);
  ~NVectorArray() { reset(); }
  NVectorArray(const NVectorArray&) = delete;
  NVectorArray& operator=(const NVectorArray&) = delete;
  NVectorArray(NVectorArray&& o) noexcept
      : vectors_(std::exchange(o.vectors_, nullptr)), count_(std::exchange(o.count_, 0)) {}
  NVectorArray& operator=(NVectorArray&& o) noexcept {
    if (this != &o) {
      reset();
      vectors_ = std::exchange(o.vectors_, nullptr);
      count_ = std::exchange(o.count_, 0);
    }
    return *this;
  }

  N_Vector* get() const { return vectors_; }
  int size() const { return count_; }
  N_Vector operator[](int i) const { return vectors_[i]; }
  double* data(int i) const { return N_VGetArrayPointer(vectors_[i]); }

 private:
  void reset() noexcept {
    if (vectors_ != nullptr) N_VDestroyVectorArray(vectors_, count_);
    vectors_ = nullptr;
    count_ = 0;
  }
  N_Vector* vectors_ = nullptr;
  int count_ = 0;
};

}  // namespace kanesens::sim
