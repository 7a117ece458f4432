// One right-hand side pass on double, on Dual (one direction) and on MultiDual<4>/<8> (4/8
// directions) through the real dynamics, and the exact Jacobian column by column (Dual) vs in
// blocked multi-tangent passes. Built with -DKANESENS_BENCH=ON (bench/CMakeLists.txt):
//   build/bench/tangent_passes configs/arm_3d.yaml        wall-clock medians and ratios
//   valgrind --tool=callgrind --instr-atstart=no build/bench/tangent_passes SCENE MODE ITERS
//       MODE = rhs | dual | w4 | w8: ITERS passes between CALLGRIND_START/STOP (instructions)
#include <algorithm>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <valgrind/callgrind.h>

#include "dynamics/equations.hpp"
#include "math/dual.hpp"
#include "math/multi_dual.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"

using namespace kanesens;
using namespace kanesens::dynamics;
using namespace kanesens::model;
using math::Dual;

template <class F>
double time_ns(F&& f) {
  using clock = std::chrono::steady_clock;
  long n = 1;
  for (;;) {
    auto t0 = clock::now();
    for (long i = 0; i < n; ++i) f();
    double s = std::chrono::duration<double>(clock::now() - t0).count();
    if (s > 2e-3) break;
    n *= 2;
  }
  std::vector<double> v;
  for (int r = 0; r < 15; ++r) {
    auto t0 = clock::now();
    for (long i = 0; i < n; ++i) f();
    v.push_back(std::chrono::duration<double>(clock::now() - t0).count() / n * 1e9);
  }
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <int W>
struct Blocked {
  Workspace<math::MultiDual<W>> ws;
  std::vector<math::MultiDual<W>> y, ydot;
  Blocked(const Model& m, const std::vector<double>& p) : ws(m), y(m.nstate()), ydot(m.nstate()) {
    std::vector<math::MultiDual<W>> pd(p.begin(), p.end());
    set_parameters(m, ws, pd.data());
  }
  // Jacobian columns [c0, c0 + W) in one pass.
  void jac(const Model& m, const std::vector<double>& yv, double* J, int n) {
    for (int c0 = 0; c0 < n; c0 += W) {
      for (int r = 0; r < n; ++r) {
        y[r] = math::MultiDual<W>(yv[r]);
        if (r >= c0 && r < c0 + W) y[r].set_d(r - c0, 1.0);
      }
      evaluate_rhs(m, ws, math::MultiDual<W>(0.0), y.data(), ydot.data());
      for (int c = c0; c < std::min(n, c0 + W); ++c)
        for (int r = 0; r < n; ++r) J[c * n + r] = ydot[r].d(c - c0);
    }
  }
};

int main(int argc, char** argv) {
  const std::string scene = argc > 1 ? argv[1] : "configs/arm_3d.yaml";
  Model m = build_model(parse_scene_file(scene));
  const std::vector<double> p = m.nominal_parameters();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uni(-1, 1);
  const int n = m.nstate();
  std::vector<double> y(n), ydot(n);
  for (double& v : y) v = uni(rng);
  for (const Joint& J : m.joints)
    if (J.quaternion_offset >= 0) {
      double* e = y.data() + J.quaternion_offset;
      double s = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      for (int i = 0; i < 4; ++i) e[i] /= s;
    }
  Workspace<double> ws(m);
  set_parameters(m, ws, p.data());
  Workspace<Dual> wd(m);
  std::vector<Dual> pd(p.begin(), p.end());
  set_parameters(m, wd, pd.data());
  std::vector<Dual> yd(y.begin(), y.end()), yddot(n);
  std::vector<double> J1(n * n), J4(n * n), J8(n * n);
  Blocked<4> b4(m, p);
  Blocked<8> b8(m, p);
  double sink = 0;
  if (argc > 3) {  // callgrind: MODE ITERS
    const std::string mode = argv[2];
    const long it = std::atol(argv[3]);
    CALLGRIND_START_INSTRUMENTATION;
    for (long i = 0; i < it; ++i) {
      if (mode == "rhs") evaluate_rhs(m, ws, 0.0, y.data(), ydot.data());
      else if (mode == "dual") evaluate_rhs(m, wd, Dual(0.0), yd.data(), yddot.data());
      else if (mode == "w4") evaluate_rhs(m, b4.ws, math::MultiDual<4>(0.0), b4.y.data(), b4.ydot.data());
      else if (mode == "w8") evaluate_rhs(m, b8.ws, math::MultiDual<8>(0.0), b8.y.data(), b8.ydot.data());
    }
    CALLGRIND_STOP_INSTRUMENTATION;
    return 0;
  }
  const double rhs = time_ns([&] { evaluate_rhs(m, ws, 0.0, y.data(), ydot.data()); sink += ydot[0]; });
  const double dual1 = time_ns([&] { yd[0].d = 1; evaluate_rhs(m, wd, Dual(0.0), yd.data(), yddot.data()); yd[0].d = 0; sink += yddot[0].d; });
  const double jac1 = time_ns([&] {
    for (int c = 0; c < n; ++c) {
      yd[c].d = 1;
      evaluate_rhs(m, wd, Dual(0.0), yd.data(), yddot.data());
      yd[c].d = 0;
      for (int r = 0; r < n; ++r) J1[c * n + r] = yddot[r].d;
    }
  });
  const double jac4 = time_ns([&] { b4.jac(m, y, J4.data(), n); });
  const double jac8 = time_ns([&] { b8.jac(m, y, J8.data(), n); });
  const double pass4 = time_ns([&] { evaluate_rhs(m, b4.ws, math::MultiDual<4>(0.0), b4.y.data(), b4.ydot.data()); });
  const double pass8 = time_ns([&] { evaluate_rhs(m, b8.ws, math::MultiDual<8>(0.0), b8.y.data(), b8.ydot.data()); });
  double err4 = 0, err8 = 0;
  for (int i = 0; i < n * n; ++i) {
    err4 = std::max(err4, std::abs(J4[i] - J1[i]));
    err8 = std::max(err8, std::abs(J8[i] - J1[i]));
  }
  std::printf("%s: n = %d, nu = %d\n", scene.c_str(), n, m.nu);
  std::printf("rhs %.0f ns; one Dual pass %.0f ns (%.2fx); pass W=4 %.0f ns (%.2fx); pass W=8 %.0f ns (%.2fx)\n", rhs, dual1,
              dual1 / rhs, pass4, pass4 / rhs, pass8, pass8 / rhs);
  std::printf("jacobian: Dual x n %.0f ns (%.1fx rhs); W=4 blocks %.0f ns (%.1fx); W=8 blocks %.0f ns (%.1fx); max diff %.1e %.1e\n",
              jac1, jac1 / rhs, jac4, jac4 / rhs, jac8, jac8 / rhs, err4, err8);
  return sink == 12345.0;
}
