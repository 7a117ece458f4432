// The compiled serial vector operations (sim/solve/serial_vector_ops.hpp) must compute what
// SUNDIALS's own nvector_serial computes, to the bit: every operation CVODES may call, with the
// coefficients that select SUNDIALS's special cases (±1, a = b, a = −b, zeros), in place and
// not, on data with signed zeros. SUNDIALS's vectors (N_VNew_Serial with its fused operations
// enabled) are the reference; the same generic N_V* calls run on both.
#include <gtest/gtest.h>

#include <nvector/nvector_serial.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/solve/serial_vector_ops.hpp"
#include "sim/solve/sundials_handles.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace kanesens::testing;

constexpr int kVectors = 6;

// Vectors of SUNDIALS's implementation (ref) and of the compiled one (ours), with equal data.
class Pools {
 public:
  explicit Pools(sunindextype n) : ctx_(make_context()), n_(n) {
    for (int k = 0; k < kVectors; ++k) {
      N_Vector r = N_VNew_Serial(n, ctx_.get());
      N_VEnableFusedOps_Serial(r, SUNTRUE);
      ref_.emplace_back(r);
      ours_.push_back(make_serial_vector(static_cast<int>(n), ctx_.get()));
    }
  }
  // Fresh random data (one entry +0, one −0, one 1, one −1) in both pools alike.
  void fill(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-2, 2);
    for (int k = 0; k < kVectors; ++k) {
      double* r = N_VGetArrayPointer(ref_[static_cast<std::size_t>(k)].get());
      for (sunindextype i = 0; i < n_; ++i) r[i] = u(rng);
      r[0] = 0.0;
      if (n_ > 3) r[1] = -0.0, r[2] = 1.0, r[3] = -1.0;
      std::memcpy(N_VGetArrayPointer(ours_[static_cast<std::size_t>(k)].get()), r, sizeof(double) * static_cast<std::size_t>(n_));
    }
  }
  N_Vector ref(int k) { return ref_[static_cast<std::size_t>(k)].get(); }
  N_Vector ours(int k) { return ours_[static_cast<std::size_t>(k)].get(); }
  // Every vector's data equal bit for bit.
  void expect_same(const std::string& what) {
    for (int k = 0; k < kVectors; ++k)
      EXPECT_EQ(std::memcmp(N_VGetArrayPointer(ref(k)), N_VGetArrayPointer(ours(k)), sizeof(double) * static_cast<std::size_t>(n_)), 0)
          << what << ", vector " << k;
  }
  sunindextype n() const { return n_; }

 private:
  ContextPtr ctx_;
  sunindextype n_;
  std::vector<NVectorPtr> ref_, ours_;
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Runs op(pick) on both pools (pick(k) gives vector k of the pool) and compares the data and
// the returned value.
void check(Pools& p, std::mt19937& rng, const std::string& what, const std::function<double(const std::function<N_Vector(int)>&)>& op) {
  p.fill(rng);
  const double r = op([&](int k) { return p.ref(k); });
  const double o = op([&](int k) { return p.ours(k); });
  EXPECT_TRUE(same_bits(r, o)) << what << ": " << r << " vs " << o;
  p.expect_same(what);
}

TEST(SerialVectorOps, SameBitsAsSundials) {
  std::mt19937 rng(71);
  const std::vector<std::pair<double, double>> coefficients = {
      {1, 1}, {1, -1}, {-1, 1}, {-1, -1}, {1, 0.3}, {0.3, 1}, {-1, 0.3}, {0.3, -1},
      {0.7, 0.7}, {0.7, -0.7}, {-0.7, 0.7}, {0, 0}, {0, 0.3}, {0.3, 0}, {0.3, -1.9}, {2.5, 0.1}};
  for (sunindextype n : {1, 7, 10, 33}) {
    SCOPED_TRACE("length " + std::to_string(n));
    Pools p(n);
    for (const auto& coefficient : coefficients) {
      const double a = coefficient.first, b = coefficient.second;
      const std::string ab = " a " + std::to_string(a) + " b " + std::to_string(b);
      // z distinct, z = x, z = y.
      for (int z : {2, 0, 1})
        check(p, rng, "LinearSum z=" + std::to_string(z) + ab, [&](const auto& v) {
          N_VLinearSum(a, v(0), b, v(1), v(z));
          return 0.0;
        });
      check(p, rng, "LinearCombination 2" + ab, [&](const auto& v) {
        double c[2] = {a, b};
        N_Vector X[2] = {v(0), v(1)};
        N_VLinearCombination(2, c, X, v(2));
        return 0.0;
      });
      for (int k : {1, 3})
        for (int z : {4, 0})  // Z distinct, Z = X (the same array), Z = Y
          check(p, rng, "LinearSumVectorArray " + std::to_string(k) + " z=" + std::to_string(z) + ab, [&](const auto& v) {
            N_Vector X[3] = {v(0), v(1), v(2)}, Y[3] = {v(3), v(4), v(5)}, W[3] = {v(3), v(4), v(5)};
            N_VLinearSumVectorArray(k, a, X, b, Y, z == 0 ? X : W);
            return 0.0;
          });
      check(p, rng, "LinearSumVectorArray in place of Y" + ab, [&](const auto& v) {
        N_Vector X[3] = {v(0), v(1), v(2)}, Y[3] = {v(3), v(4), v(5)};
        N_VLinearSumVectorArray(3, a, X, b, Y, Y);
        return 0.0;
      });
      check(p, rng, "LinearCombinationVectorArray nsum 2" + ab, [&](const auto& v) {
        double c[2] = {a, b};
        N_Vector X0[2] = {v(0), v(1)}, X1[2] = {v(2), v(3)}, Z[2] = {v(4), v(5)};
        N_Vector* X[2] = {X0, X1};
        N_VLinearCombinationVectorArray(2, 2, c, X, Z);
        return 0.0;
      });
    }
    for (double c : {1.0, -1.0, 0.0, 0.37}) {
      const std::string cs = " c " + std::to_string(c);
      for (int z : {1, 0}) check(p, rng, "Scale z=" + std::to_string(z) + cs, [&](const auto& v) { N_VScale(c, v(0), v(z)); return 0.0; });
      check(p, rng, "Const" + cs, [&](const auto& v) { N_VConst(c, v(0)); return 0.0; });
      check(p, rng, "AddConst" + cs, [&](const auto& v) { N_VAddConst(v(0), c, v(1)); return 0.0; });
      check(p, rng, "Compare" + cs, [&](const auto& v) { N_VCompare(c, v(0), v(1)); return 0.0; });
      check(p, rng, "ConstVectorArray" + cs, [&](const auto& v) {
        N_Vector Z[3] = {v(0), v(1), v(2)};
        N_VConstVectorArray(3, c, Z);
        return 0.0;
      });
    }
    check(p, rng, "Prod", [&](const auto& v) { N_VProd(v(0), v(1), v(2)); return 0.0; });
    check(p, rng, "Div", [&](const auto& v) { N_VDiv(v(0), v(1), v(2)); return 0.0; });
    check(p, rng, "Abs", [&](const auto& v) { N_VAbs(v(0), v(1)); return 0.0; });
    check(p, rng, "Inv", [&](const auto& v) { N_VInv(v(0), v(1)); return 0.0; });
    check(p, rng, "DotProd", [&](const auto& v) { return N_VDotProd(v(0), v(1)); });
    check(p, rng, "MaxNorm", [&](const auto& v) { return N_VMaxNorm(v(0)); });
    check(p, rng, "WrmsNorm", [&](const auto& v) { return N_VWrmsNorm(v(0), v(1)); });
    check(p, rng, "WrmsNormMask", [&](const auto& v) { return N_VWrmsNormMask(v(0), v(1), v(2)); });
    check(p, rng, "Min", [&](const auto& v) { return N_VMin(v(0)); });
    check(p, rng, "WL2Norm", [&](const auto& v) { return N_VWL2Norm(v(0), v(1)); });
    check(p, rng, "L1Norm", [&](const auto& v) { return N_VL1Norm(v(0)); });
    check(p, rng, "InvTest (a zero entry)", [&](const auto& v) { return static_cast<double>(N_VInvTest(v(0), v(1))); });
    check(p, rng, "InvTest (none)", [&](const auto& v) {
      N_VAbs(v(0), v(0));
      N_VAddConst(v(0), 0.5, v(0));
      return static_cast<double>(N_VInvTest(v(0), v(1)));
    });
    check(p, rng, "ConstrMask", [&](const auto& v) {
      double* c = N_VGetArrayPointer(v(0));
      for (sunindextype i = 0; i < n; ++i) c[i] = static_cast<double>(static_cast<int>(i % 5) - 2);  // −2 … 2
      return static_cast<double>(N_VConstrMask(v(0), v(1), v(2)));
    });
    check(p, rng, "MinQuotient", [&](const auto& v) { return N_VMinQuotient(v(0), v(1)); });
    check(p, rng, "MinQuotient (a NaN last)", [&](const auto& v) {
      N_VGetArrayPointer(v(0))[n - 1] = std::nan("");
      return N_VMinQuotient(v(0), v(1));
    });
    check(p, rng, "WSqrSumLocal", [&](const auto& v) { return N_VWSqrSumLocal(v(0), v(1)); });
    check(p, rng, "WSqrSumMaskLocal", [&](const auto& v) { return N_VWSqrSumMaskLocal(v(0), v(1), v(2)); });
    for (int k : {1, 3, 5}) {
      const std::string ks = " k " + std::to_string(k);
      for (double c0 : {1.0, 0.6}) {
        for (int z : {5, 0})  // z distinct, z = X[0]
          check(p, rng, "LinearCombination z=" + std::to_string(z) + " c0 " + std::to_string(c0) + ks, [&](const auto& v) {
            double c[5] = {c0, -0.4, 1.0, -1.0, 0.25};
            N_Vector X[5] = {v(0), v(1), v(2), v(3), v(4)};
            N_VLinearCombination(k, c, X, v(z));
            return 0.0;
          });
      }
      check(p, rng, "ScaleAddMulti" + ks, [&](const auto& v) {
        double a[3] = {0.3, 1.0, -1.0};
        N_Vector Y[3] = {v(1), v(2), v(3)}, Z[3] = {v(4), v(5), v(1)};
        N_VScaleAddMulti(std::min(k, 3), a, v(0), Y, Z);
        return 0.0;
      });
      check(p, rng, "ScaleAddMulti in place" + ks, [&](const auto& v) {
        double a[3] = {0.3, 1.0, -1.0};
        N_Vector Y[3] = {v(1), v(2), v(3)};
        N_VScaleAddMulti(std::min(k, 3), a, v(0), Y, Y);
        return 0.0;
      });
      check(p, rng, "DotProdMulti" + ks, [&](const auto& v) {
        double d[3] = {0, 0, 0};
        N_Vector Y[3] = {v(1), v(2), v(3)};
        N_VDotProdMulti(std::min(k, 3), v(0), Y, d);
        return d[0] + 2 * d[1] + 4 * d[2];
      });
      check(p, rng, "ScaleVectorArray" + ks, [&](const auto& v) {
        double c[3] = {1.0, -1.0, 0.3};
        N_Vector X[3] = {v(0), v(1), v(2)}, Z[3] = {v(3), v(4), v(5)};
        N_VScaleVectorArray(std::min(k, 3), c, X, Z);
        N_VScaleVectorArray(std::min(k, 3), c, Z, Z);
        return 0.0;
      });
      check(p, rng, "WrmsNormVectorArray" + ks, [&](const auto& v) {
        double nrm[3] = {0, 0, 0};
        N_Vector X[3] = {v(0), v(1), v(2)}, W[3] = {v(3), v(4), v(5)};
        N_VWrmsNormVectorArray(std::min(k, 3), X, W, nrm);
        return nrm[0] + 2 * nrm[1] + 4 * nrm[2];
      });
      check(p, rng, "WrmsNormMaskVectorArray" + ks, [&](const auto& v) {
        double nrm[2] = {0, 0};
        N_Vector X[2] = {v(0), v(1)}, W[2] = {v(2), v(3)};
        N_VWrmsNormMaskVectorArray(std::min(k, 2), X, W, v(4), nrm);
        return nrm[0] + 2 * nrm[1];
      });
      for (int nsum : {1, 2}) {
        const std::string sums = ks + " nsum " + std::to_string(nsum);
        for (bool in_place : {false, true})
          check(p, rng, std::string("ScaleAddMultiVectorArray") + (in_place ? " in place" : "") + sums, [&](const auto& v) {
            double a[2] = {0.3, -1.0};
            const int nvec = std::min(k, 2);
            N_Vector X[2] = {v(0), v(1)}, Y0[2] = {v(2), v(3)}, Y1[2] = {v(4), v(5)}, Z0[2] = {v(4), v(5)}, Z1[2] = {v(2), v(3)};
            N_Vector* Y[2] = {Y0, Y1};
            N_Vector* Z[2] = {Z0, Z1};
            N_VScaleAddMultiVectorArray(nvec, nsum == 1 ? 1 : 2, a, X, Y, in_place ? Y : Z);
            return 0.0;
          });
      }
      for (int nsum : {1, 3, 4})
        for (double c0 : {1.0, 0.6})
          for (bool in_place : {false, true})
            check(p, rng, std::string("LinearCombinationVectorArray") + (in_place ? " in place" : "") + ks + " nsum " + std::to_string(nsum) + " c0 " + std::to_string(c0),
                  [&](const auto& v) {
                    double c[4] = {c0, -0.4, 1.0, -1.0};
                    const int nvec = std::min(k, 2);
                    N_Vector X0[2] = {v(0), v(1)}, X1[2] = {v(2), v(3)}, X2[2] = {v(4), v(5)}, X3[2] = {v(1), v(3)}, Z[2] = {v(4), v(5)};
                    N_Vector* X[4] = {X0, X1, X2, X3};
                    N_VLinearCombinationVectorArray(nvec, nsum, c, X, in_place ? X0 : Z);
                    return 0.0;
                  });
    }
  }
}

TEST(SerialVectorOps, ClonesInheritThemAndOthersAreRefused) {
  ContextPtr ctx = make_context();
  NVectorPtr v = make_serial_vector(4, ctx.get());
  NVectorArray clones(2, v.get());
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(clones[k]->ops->nvlinearsum, v->ops->nvlinearsum);
    EXPECT_EQ(clones[k]->ops->nvlinearsumvectorarray, v->ops->nvlinearsumvectorarray);
  }
  // Their data starts on a cache line, as the operations' 64-byte loads want (any length).
  for (int n : {1, 4, 7, 70}) {
    NVectorPtr u = make_serial_vector(n, ctx.get());
    NVectorArray more(3, u.get());
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(N_VGetArrayPointer(u.get())) % 64, 0u) << n;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(reinterpret_cast<std::uintptr_t>(more.data(k)) % 64, 0u) << n;
  }
  EXPECT_NE(v->ops->nvlinearsum, &N_VLinearSum_Serial) << "the compiled operations are in place";
  EXPECT_NE(v->ops->nvlinearcombinationvectorarray, nullptr) << "vector-array operations enabled";
  EXPECT_THROW(use_compiled_serial_ops(nullptr), std::invalid_argument);
}

// The error norm of a state stacked with its sensitivities: the largest block's WRMS norm (as
// SUNDIALS's N_VWrmsNorm of each block alone computes it, to the bit), or the first block's;
// a NaN in any block counted; sizes it cannot take refused, with nothing changed.
TEST(SerialVectorOps, BlockErrorNorms) {
  ContextPtr ctx = make_context();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2), w(0.5, 1e4);
  for (int n : {1, 2, 7, 10, 16, 33, kMaxErrorNormBlock}) {
    SCOPED_TRACE(n);
    const int blocks = 5;
    NVectorPtr x = make_serial_vector(n * blocks, ctx.get()), wt = make_serial_vector(n * blocks, ctx.get());
    N_Vector xb = N_VNew_Serial(n, ctx.get()), wb = N_VNew_Serial(n, ctx.get());  // SUNDIALS's own
    for (int trial = 0; trial < 10; ++trial) {
      double* xd = N_VGetArrayPointer(x.get());
      double* wd = N_VGetArrayPointer(wt.get());
      for (int i = 0; i < n * blocks; ++i) xd[i] = u(rng), wd[i] = w(rng);
      double largest = 0;
      std::vector<double> norms;
      for (int k = 0; k < blocks; ++k) {
        std::copy(xd + k * n, xd + (k + 1) * n, N_VGetArrayPointer(xb));
        std::copy(wd + k * n, wd + (k + 1) * n, N_VGetArrayPointer(wb));
        norms.push_back(N_VWrmsNorm_Serial(xb, wb));
        largest = std::max(largest, norms.back());
      }
      ASSERT_TRUE(use_block_error_norm(x.get(), n, true));
      EXPECT_EQ(N_VWrmsNorm(x.get(), wt.get()), largest);
      NVectorArray clone(1, x.get());
      EXPECT_EQ(clone[0]->ops->nvwrmsnorm, x->ops->nvwrmsnorm) << "clones inherit it";
      ASSERT_TRUE(use_block_error_norm(x.get(), n, false));
      EXPECT_EQ(N_VWrmsNorm(x.get(), wt.get()), norms[0]);
      ASSERT_TRUE(use_block_error_norm(x.get(), n, true));
      for (int k : {blocks - 1, 1, 0}) {  // a NaN wins from any block, with others after it
        const double kept = xd[k * n + n / 2];
        xd[k * n + n / 2] = std::nan("");
        EXPECT_TRUE(std::isnan(N_VWrmsNorm(x.get(), wt.get()))) << "NaN in block " << k;
        xd[k * n + n / 2] = kept;
      }
    }
    N_VDestroy(xb);
    N_VDestroy(wb);
  }
  NVectorPtr v = make_serial_vector(12, ctx.get());
  const auto before = v->ops->nvwrmsnorm;
  for (int block : {0, -1, 5, 24, kMaxErrorNormBlock + 1}) EXPECT_FALSE(use_block_error_norm(v.get(), block, true)) << block;
  EXPECT_FALSE(use_block_error_norm(nullptr, 3, true));
  EXPECT_EQ(v->ops->nvwrmsnorm, before);
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
