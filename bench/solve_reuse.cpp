// Cost of re-initialising one Integrator (CVodeReInit + CVodeSensReInit) versus building a
// fresh one (SUNContext, vectors, dense matrix and solver, cvode_mem, SensInit) per sample.
// Not part of the test gate. Build and run:
//   cmake --build build --target kanesens-solve-reuse && build/bench/kanesens-solve-reuse
// Timings alternate reuse/fresh rounds and keep each mode's best round (shared machine).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/solve/integrator.hpp"

namespace ks = kanesens::sim;

// A chain of m unit masses joined by springs k and dampers c, the first tied to the wall:
// n = 2m states (positions, velocities); sensitivities to k, c and the first initial position.
class Chain : public ks::OdeProblem {
 public:
  Chain(int m, bool sens) : m_(m), sens_(sens) {}
  double k = 4, c = 0.4;
  int size() const override { return 2 * m_; }
  void initial_state(double* y) const override {
    for (int i = 0; i < 2 * m_; ++i) y[i] = 0;
    y[0] = 1;
  }
  double force(const double* x, const double* v, int i, double kk, double cc) const {
    const double left = i == 0 ? 0 : x[i - 1], vleft = i == 0 ? 0 : v[i - 1];
    const double right = i + 1 < m_ ? x[i + 1] : x[i], vright = i + 1 < m_ ? v[i + 1] : v[i];
    return kk * (left - 2 * x[i] + right) + cc * (vleft - 2 * v[i] + vright);
  }
  void rhs(double, const double* y, double* f) override {
    for (int i = 0; i < m_; ++i) {
      f[i] = y[m_ + i];
      f[m_ + i] = force(y, y + m_, i, k, c);
    }
  }
  bool has_jacobian() const override { return true; }
  void jacobian(double, const double*, const double*, double* J) override {
    const int n = 2 * m_;
    for (int i = 0; i < n * n; ++i) J[i] = 0;
    for (int i = 0; i < m_; ++i) {
      J[i + (m_ + i) * n] = 1;
      const double diag = i + 1 < m_ ? -2.0 : -1.0;  // the last mass has a free right end
      J[(m_ + i) + i * n] = diag * k;
      J[(m_ + i) + (m_ + i) * n] = diag * c;
      if (i > 0) {
        J[(m_ + i) + (i - 1) * n] = k;
        J[(m_ + i) + (m_ + i - 1) * n] = c;
      }
      if (i + 1 < m_) {
        J[(m_ + i) + (i + 1) * n] = k;
        J[(m_ + i) + (m_ + i + 1) * n] = c;
      }
    }
  }
  int num_sensitivities() const override { return sens_ ? 3 : 0; }
  void initial_sensitivity(int i, double* s0) const override {
    for (int j = 0; j < 2 * m_; ++j) s0[j] = 0;
    if (i == 2) s0[0] = 1;
  }
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double t, const double* y, const double*, int i, const double* s,
                       double* sdot) override {
    rhs(t, s, sdot);  // linear: J s = f(s)
    if (i == 0)
      for (int j = 0; j < m_; ++j) sdot[m_ + j] += force(y, y + m_, j, 1, 0);
    if (i == 1)
      for (int j = 0; j < m_; ++j) sdot[m_ + j] += force(y, y + m_, j, 0, 1);
  }
  std::vector<double> sensitivity_scales() const override { return {k, c, 1}; }

 private:
  int m_;
  bool sens_;
};

int main() {
  std::vector<double> long_run;  // 0..10 s, 101 outputs
  for (int i = 0; i <= 100; ++i) long_run.push_back(0.1 * i);
  const std::vector<double> short_run{0, 1e-3};  // a few steps: setup cost dominates
  double sink = 0;
  auto record = [&](int, double, const double* y, const double* const*) { sink += y[0]; };
  std::printf("%-6s %-5s %-6s %-8s %12s %12s %8s\n", "n", "sens", "t_end", "samples", "reuse_us",
              "fresh_us", "ratio");
  for (const std::vector<double>& times : {short_run, long_run})
    for (int m : {1, 10, 40}) {
      for (bool sens : {false, true}) {
        const int samples = times.size() == 2 ? 2000 : (m >= 40 ? 50 : 500);
        ks::SolverOptions o;  // defaults: BDF, rtol 1e-8, exact Jacobian, staggered
        Chain chain(m, sens);
        long steps_reuse = 0, steps_fresh = 0;
        auto time_it = [&](bool reuse) {
          ks::Integrator shared(o);
          long steps = 0;
          const auto start = std::chrono::steady_clock::now();
          for (int s = 0; s < samples; ++s) {
            chain.k = 4 + 0.001 * s;
            if (reuse) {
              steps += shared.integrate(chain, times, record).stats.steps;
            } else {
              ks::Integrator fresh(o);
              steps += fresh.integrate(chain, times, record).stats.steps;
            }
          }
          (reuse ? steps_reuse : steps_fresh) = steps;
          return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
                     .count() /
                 samples;
        };
        double reuse = 1e300, fresh = 1e300;
        for (int round = 0; round < 5; ++round) {
          reuse = std::min(reuse, time_it(true));
          fresh = std::min(fresh, time_it(false));
        }
        if (steps_reuse != steps_fresh)
          std::printf("steps differ: %ld vs %ld\n", steps_reuse, steps_fresh);
        std::printf("%-6d %-5s %-6g %-8d %12.1f %12.1f %8.3f\n", 2 * m, sens ? "yes" : "no",
                    times.back(), samples, reuse, fresh, fresh / reuse);
      }
    }
  return sink == 12345 ? 1 : 0;
}
