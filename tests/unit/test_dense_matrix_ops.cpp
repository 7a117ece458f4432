// The compiled dense SUNMatrix operations (sim/solve/dense_matrix_ops.hpp) must compute what
// SUNDIALS's own sunmatrix_dense computes, to the bit: zero, copy, and A = cA + I with the c that
// CVODES passes (−γ) and special ones (0, −0, ±1), on data with signed zeros, square and not;
// clones carry the compiled operations; a matrix of another shape is refused as SUNDIALS does.
#include <gtest/gtest.h>

#include <sunmatrix/sunmatrix_dense.h>

#include <cstring>
#include <random>
#include <stdexcept>

#include "sim/solve/dense_matrix_ops.hpp"
#include "sim/solve/sundials_handles.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;

// A matrix of SUNDIALS's implementation (ref) and one of the compiled (ours), equal data.
struct Pair {
  Pair(SUNContext ctx, sunindextype rows, sunindextype columns)
      : ref(SUNDenseMatrix(rows, columns, ctx)), ours(SUNDenseMatrix(rows, columns, ctx)) {
    kanesens::sim::use_compiled_dense_ops(ours.get());
  }
  void fill(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-2, 2);
    double* r = SM_DATA_D(ref.get());
    for (sunindextype k = 0; k < SM_LDATA_D(ref.get()); ++k) r[k] = u(rng);
    r[0] = -0.0;
    if (SM_LDATA_D(ref.get()) > 2) r[1] = 0.0, r[2] = -1.0;
    std::memcpy(SM_DATA_D(ours.get()), r, sizeof(double) * static_cast<std::size_t>(SM_LDATA_D(ref.get())));
  }
  bool same() const {
    return std::memcmp(SM_DATA_D(ref.get()), SM_DATA_D(ours.get()),
                       sizeof(double) * static_cast<std::size_t>(SM_LDATA_D(ref.get()))) == 0;
  }
  MatrixPtr ref, ours;
};

TEST(DenseMatrixOps, ComputeWhatSundialsComputesBitForBit) {
  ContextPtr ctx = make_context();
  std::mt19937 rng(11);
  for (auto [rows, columns] : {std::pair{1, 1}, {3, 3}, {10, 10}, {16, 16}, {4, 7}, {7, 4}}) {
    SCOPED_TRACE(std::to_string(rows) + "x" + std::to_string(columns));
    Pair a(ctx.get(), rows, columns), b(ctx.get(), rows, columns);
    for (double c : {-0.0123456789, 0.0, -0.0, 1.0, -1.0, 3.7e5}) {
      a.fill(rng);
      ASSERT_EQ(SUNMatScaleAddI(c, a.ref.get()), SUNMAT_SUCCESS);
      ASSERT_EQ(SUNMatScaleAddI(c, a.ours.get()), SUNMAT_SUCCESS);
      EXPECT_TRUE(a.same()) << "scale and add I, c = " << c;
    }
    a.fill(rng);
    b.fill(rng);
    ASSERT_EQ(SUNMatCopy(a.ref.get(), b.ref.get()), SUNMAT_SUCCESS);
    ASSERT_EQ(SUNMatCopy(a.ours.get(), b.ours.get()), SUNMAT_SUCCESS);
    EXPECT_TRUE(b.same()) << "copy";
    ASSERT_EQ(SUNMatZero(a.ref.get()), SUNMAT_SUCCESS);
    ASSERT_EQ(SUNMatZero(a.ours.get()), SUNMAT_SUCCESS);
    EXPECT_TRUE(a.same()) << "zero";
  }
}

TEST(DenseMatrixOps, ClonesCarryThemAndOtherShapesAreRefused) {
  ContextPtr ctx = make_context();
  MatrixPtr A = make_dense_matrix(5, ctx.get());  // the integrator's matrices get them
  MatrixPtr clone(SUNMatClone(A.get()));
  ASSERT_NE(clone, nullptr);
  EXPECT_EQ(clone->ops->scaleaddi, A->ops->scaleaddi);
  EXPECT_EQ(clone->ops->copy, A->ops->copy);
  EXPECT_EQ(clone->ops->clone, A->ops->clone);
  MatrixPtr library(SUNDenseMatrix(5, 5, ctx.get()));
  EXPECT_NE(library->ops->scaleaddi, A->ops->scaleaddi) << "the library's own, for comparison";
  MatrixPtr other(SUNDenseMatrix(4, 5, ctx.get()));
  EXPECT_EQ(SUNMatCopy(A.get(), other.get()), SUNMAT_ILL_INPUT);
  EXPECT_EQ(SUNMatCopy(library.get(), other.get()), SUNMAT_ILL_INPUT);
  EXPECT_THROW(kanesens::sim::use_compiled_dense_ops(nullptr), std::invalid_argument);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
