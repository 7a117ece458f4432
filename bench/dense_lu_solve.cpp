// One solve with a factored n×n Newton matrix, as CVODES asks for it (SUNLinSolSolve: copy b to
// x, solve in x): SUNDIALS's SUNLinSol_Dense (GETRS) and kanesens's dense LU solver
// (sim/solve/dense_lu_solver.hpp: Eigen's PartialPivLU factors, substituted by hand, behind the
// same interface), and for reference Eigen's PartialPivLU solve called directly on vector maps.
// Not part of the test gate. Build and run:
//   cmake --build build --target kanesens-dense-lu && build/bench/kanesens-dense-lu > OUT.json
// Rounds alternate the three; the figure per size and solver is the median over rounds of the
// mean time of a batch.
#include <sunlinsol/sunlinsol_dense.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/solve/dense_lu_solver.hpp"
#include "sim/solve/sundials_handles.hpp"

namespace ks = kanesens::sim;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main() {
  const int rounds = 15;
  std::printf("{\n \"command\": \"build/bench/kanesens-dense-lu\",\n \"rounds\": %d,\n \"rows\": [\n", rounds);
  const std::vector<int> sizes = {8, 10, 13, 16, 32, 64};
  double sink = 0;
  for (std::size_t si = 0; si < sizes.size(); ++si) {
    const int n = sizes[si];
    ks::ContextPtr ctx = ks::make_context();
    ks::NVectorPtr x = ks::make_serial_vector(n, ctx.get()), b = ks::make_serial_vector(n, ctx.get());
    // I − γJ with a J of unit-size entries, as CVODES forms it.
    Eigen::MatrixXd M(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) M(i, j) = (i == j ? 1.0 : 0.0) - 0.1 * std::cos(1.0 + 7 * i + 3 * j);
    ks::MatrixPtr As = ks::make_dense_matrix(n, ctx.get()), Ao = ks::make_dense_matrix(n, ctx.get());
    for (SUNMatrix A : {As.get(), Ao.get()})
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) SM_ELEMENT_D(A, i, j) = M(i, j);
    ks::LinearSolverPtr sundials(SUNLinSol_Dense(x.get(), As.get(), ctx.get()));
    ks::LinearSolverPtr ours = ks::make_dense_solver(n, ctx.get());
    if (SUNLinSolSetup(sundials.get(), As.get()) != 0 || SUNLinSolSetup(ours.get(), Ao.get()) != 0) return 1;
    Eigen::PartialPivLU<Eigen::MatrixXd> eigen(n);
    eigen.compute(M);
    double* bd = N_VGetArrayPointer(b.get());
    double* xd = N_VGetArrayPointer(x.get());
    for (int i = 0; i < n; ++i) bd[i] = std::sin(1.0 + i);
    const int batch = std::max(1000, 400000 / n);
    std::vector<double> t_sundials, t_ours, t_eigen;
    for (int r = 0; r < rounds; ++r) {
      double t0 = now();
      for (int k = 0; k < batch; ++k) {
        SUNLinSolSolve(sundials.get(), As.get(), x.get(), b.get(), 0.0);
        sink += xd[0];
      }
      double t1 = now();
      for (int k = 0; k < batch; ++k) {
        SUNLinSolSolve(ours.get(), Ao.get(), x.get(), b.get(), 0.0);
        sink += xd[0];
      }
      double t2 = now();
      for (int k = 0; k < batch; ++k) {
        Eigen::Map<Eigen::VectorXd>(xd, n) = eigen.solve(Eigen::Map<const Eigen::VectorXd>(bd, n));
        sink += xd[0];
      }
      double t3 = now();
      t_sundials.push_back((t1 - t0) / batch * 1e9);
      t_ours.push_back((t2 - t1) / batch * 1e9);
      t_eigen.push_back((t3 - t2) / batch * 1e9);
    }
    // The three agree: the residual of our solve.
    SUNLinSolSolve(ours.get(), Ao.get(), x.get(), b.get(), 0.0);
    const double residual = (M * Eigen::Map<Eigen::VectorXd>(xd, n) - Eigen::Map<Eigen::VectorXd>(bd, n)).norm();
    std::printf("  {\"n\": %d, \"sundials_dense_ns\": %.1f, \"kanesens_dense_lu_ns\": %.1f, \"eigen_partial_piv_lu_direct_ns\": %.1f, "
                "\"residual\": %.2e}%s\n",
                n, median(t_sundials), median(t_ours), median(t_eigen), residual, si + 1 < sizes.size() ? "," : "");
  }
  std::printf(" ],\n \"checksum\": %.6g\n}\n", sink);
  return 0;
}
