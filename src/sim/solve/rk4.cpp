#include "sim/solve/rk4.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/solve/output_times.hpp"

namespace kanesens::sim {

namespace {
bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}
}  // namespace

IntegrationResult integrate_rk4(OdeProblem& problem, const Rk4Options& options,
                                std::span<const double> times, const RecordFn& record) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  if (!(options.h > 0 && std::isfinite(options.h)))
    throw std::invalid_argument("rk4: step h must be a finite number > 0");
  check_output_times(times, "rk4");
  const int ns = options.sensitivities ? problem.num_sensitivities() : 0;
  if (ns > 0 && !problem.has_sensitivity_rhs())
    throw std::invalid_argument("rk4: sensitivities need the problem's exact sensitivity_rhs");

  const std::size_t n = static_cast<std::size_t>(problem.size());
  const std::size_t m = static_cast<std::size_t>(ns);
  // y and the ns sensitivities, stored as (1 + ns) blocks of n: block 0 = y, block 1+i = s_i.
  const std::size_t N = n * (1 + m);
  std::vector<double> y(N), stage(N), k1(N), k2(N), k3(N), k4(N);
  problem.initial_state(y.data());
  for (int i = 0; i < ns; ++i) problem.initial_sensitivity(i, y.data() + n * (1 + static_cast<std::size_t>(i)));
  std::vector<const double*> sp(m);
  auto pointers = [&](const std::vector<double>& v) {
    for (std::size_t i = 0; i < m; ++i) sp[i] = v.data() + n * (1 + i);
    return m ? sp.data() : nullptr;
  };

  IntegrationResult r;
  r.t_fail = std::numeric_limits<double>::quiet_NaN();
  // f(t, z) for the stacked state z into dz.
  auto f = [&](double t, const std::vector<double>& z, std::vector<double>& dz) {
    problem.rhs(t, z.data(), dz.data());
    ++r.stats.rhs_evals;
    for (int i = 0; i < ns; ++i) {
      const std::size_t o = n * (1 + static_cast<std::size_t>(i));
      problem.sensitivity_rhs(t, z.data(), dz.data(), i, z.data() + o, dz.data() + o);
      ++r.stats.sens_rhs_evals;
    }
  };

  auto finish = [&](int status, double when, const std::string& message) {
    r.status = status;
    r.message = message;
    r.t_fail = when;
    r.stats.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
    return r;
  };
  record(0, times[0], y.data(), pointers(y));
  r.outputs_recorded = 1;
  char buf[160];
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double span = times[k + 1] - times[k];
    const long steps = std::max(1L, static_cast<long>(std::ceil(span / options.h * (1 - 1e-12))));
    const double h = span / static_cast<double>(steps);
    for (long s = 0; s < steps; ++s) {
      const double t = times[k] + h * static_cast<double>(s);
      try {
        f(t, y, k1);
        for (std::size_t j = 0; j < N; ++j) stage[j] = y[j] + 0.5 * h * k1[j];
        f(t + 0.5 * h, stage, k2);
        for (std::size_t j = 0; j < N; ++j) stage[j] = y[j] + 0.5 * h * k2[j];
        f(t + 0.5 * h, stage, k3);
        for (std::size_t j = 0; j < N; ++j) stage[j] = y[j] + h * k3[j];
        f(t + h, stage, k4);
      } catch (const std::exception& e) {
        std::snprintf(buf, sizeof buf, "RK4_CALLBACK_FAILED at t = %.10g: ", t);
        return finish(rk4_callback_failed, t, buf + std::string(e.what()));
      }
      for (std::size_t j = 0; j < N; ++j) y[j] += h / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
      ++r.stats.steps;
      if (!all_finite(y)) {
        std::snprintf(buf, sizeof buf, "RK4_NONFINITE at t = %.10g: the solution became non-finite (h = %.6g)",
                      t + h, h);
        return finish(rk4_nonfinite, t + h, buf);
      }
    }
    record(static_cast<int>(k + 1), times[k + 1], y.data(), pointers(y));
    ++r.outputs_recorded;
  }
  r.status = 1;
  r.stats.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  return r;
}

}  // namespace kanesens::sim
