#include "sim/solve/dop853.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/solve/dop853_stepper.hpp"
#include "sim/solve/output_times.hpp"

namespace kanesens::sim {

namespace {

using namespace dop853_detail;

// The event functions' values at the ends of the current step and the location of their
// crossings on the continuous extension.
class EventLocator {
 public:
  EventLocator(OdeEvents& events, std::size_t n)
      : events_(events), m_(static_cast<std::size_t>(events.size())), g_old(m_), g_new(m_), g_(m_), y_(n) {}

  void eval(double t, const double* y, std::vector<double>& out) {
    try {
      events_.g(t, y, out.data());
    } catch (const std::exception& e) {
      throw CallbackError{std::string("event function threw: ") + e.what()};
    }
  }
  // The functions that change sign in their direction from g_old to g_new.
  void crossings(std::vector<int>& out) const {
    out.clear();
    for (std::size_t i = 0; i < m_; ++i) {
      const int d = events_.direction(static_cast<int>(i));
      const bool rising = g_old[i] < 0 && g_new[i] >= 0, falling = g_old[i] > 0 && g_new[i] <= 0;
      if ((d >= 0 && rising) || (d <= 0 && falling)) out.push_back(static_cast<int>(i));
    }
  }
  // The crossing of g_i in the prepared step [t, t + h]: Illinois false position on the
  // continuous extension, to CVODES's rootfinding tolerance 100·ε·(|t| + |h|); the time
  // returned is on the far side of the root (g has crossed there), as CVODES's.
  double locate(const Stepper& st, int i, double t, double h) {
    const std::size_t ii = static_cast<std::size_t>(i);
    const double tol = 100 * std::numeric_limits<double>::epsilon() * (std::abs(t) + std::abs(h));
    double a = t, b = t + h, ga = g_old[ii], gb = g_new[ii];
    int side = 0;
    for (int iter = 0; iter < 200 && b - a > tol; ++iter) {
      double tm = b - gb * (b - a) / (gb - ga);
      if (!(tm > a && tm < b)) tm = 0.5 * (a + b);
      st.interpolate(tm, y_, y_.size());
      eval(tm, y_.data(), g_);
      const double gm = g_[ii];
      if (gm == 0) return tm;
      if ((gm < 0) == (ga < 0)) {
        a = tm;
        ga = gm;
        if (side == -1) gb *= 0.5;
        side = -1;
      } else {
        b = tm;
        gb = gm;
        if (side == 1) ga *= 0.5;
        side = 1;
      }
    }
    return b;
  }

  OdeEvents& events_;
  std::size_t m_;
  std::vector<double> g_old, g_new, g_, y_;
};

std::string at_time(const char* what, double t) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s at t = %.10g", what, t);
  return buf;
}

}  // namespace

IntegrationResult integrate_dop853(OdeProblem& problem, const SolverOptions& options,
                                   std::span<const double> times, const RecordFn& record, OdeQuadrature* quad,
                                   OdeEvents* events) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  options.validate(problem.size());
  check_output_times(times, "dop853");
  const int ns = problem.num_sensitivities();
  if (ns > 0 && (!problem.has_sensitivity_rhs() || options.sens_rhs != SensitivityRhs::exact))
    throw std::invalid_argument("solver.method = dop853 needs the exact sensitivity right-hand side "
                                "(solver.sensitivity.rhs: exact)");

  Stepper st(problem, options, ns, quad);
  const std::size_t n = st.states();
  problem.initial_state(st.z.data());
  for (int i = 0; i < ns; ++i) problem.initial_sensitivity(i, st.z.data() + n * (1 + static_cast<std::size_t>(i)));
  std::vector<double> corr(n);
  const bool projecting = problem.has_projection() && options.projection_frequency > 0;
  const bool checking = problem.has_step_check();

  IntegrationResult r;
  r.t_fail = std::numeric_limits<double>::quiet_NaN();
  auto finish = [&](int status, double t, const std::string& message) {
    r.status = status;
    r.t_fail = t;
    r.message = message;
    r.stats.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
    return r;
  };

  record(0, times[0], st.z.data(), st.sensitivities());
  st.record_quadrature(0, times[0]);
  r.outputs_recorded = 1;
  double t = times[0];
  const double h_max = options.max_step > 0 ? options.max_step : times.back() - times.front();
  double h = 0;
  bool rejected = false;  // the last trial step was rejected
  double err_old = 1e-4;  // the last accepted step's error (dop853.f's FACOLD)
  std::size_t k = 1;      // the next output
  try {
    if (times.size() > 1) {
      st.f(t, st.z, st.first_stage(), r.stats);
      if (!st.recoverable_message.empty())  // nothing to retry at the initial state
        return finish(status_rhs_failed, t, at_time("DOP853_RHSFUNC_FAIL", t) + ": " + st.recoverable_message);
      h = options.initial_step > 0 ? std::min(options.initial_step, h_max) : st.initial_step(t, h_max, r.stats);
    }
    // Steps are cut only to land on the last output time; the outputs inside a step are read
    // from its continuous extension before the step is projected or the coordinates change.
    std::vector<double> dense(st.size());
    const double t_end = times.back();
    std::unique_ptr<EventLocator> ev;
    std::vector<int> crossing;
    std::vector<std::pair<double, int>> located;
    if (events && events->size() > 0) {
      ev = std::make_unique<EventLocator>(*events, n);
      ev->eval(t, st.z.data(), ev->g_old);
    }
    // Records the outputs before (or at, if `inclusive`) time tb from the prepared step.
    auto record_dense = [&](double tb, bool inclusive) {
      for (; k < times.size() && (times[k] < tb || (inclusive && times[k] == tb)); ++k) {
        st.interpolate(times[k], dense);
        record(static_cast<int>(k), times[k], dense.data(), st.sensitivities(&dense));
        st.record_quadrature(static_cast<int>(k), times[k], &dense);
        ++r.outputs_recorded;
      }
    };
    while (k < times.size()) {
      if (r.stats.steps >= options.max_steps)
        return finish(status_too_much_work, t,
                      at_time("DOP853_TOO_MUCH_WORK", t) + ": solver.max_steps = " +
                          std::to_string(options.max_steps) + " steps taken before reaching the output time");
      const bool to_end = t + h >= t_end - 1e-13 * std::abs(t_end);
      const double h_try = to_end ? t_end - t : h;
      const double err = st.step(t, h_try, r.stats);
      if (!(err <= 1.0)) {  // rejected: error too large, or NaN (a non-finite stage)
        ++r.stats.error_test_fails;
        if (std::isnan(err)) ++r.stats.callback_recoverable;
        const double factor = std::isnan(err) ? 0.25 : std::max(min_factor, safety * std::pow(err, error_exponent));
        h = h_try * factor;
        rejected = true;
        if (h < 16 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t)))
          return finish(status_step_too_small, t,
                        at_time("DOP853_ERR_FAILURE", t) + ": the step size fell below round-off of t (" +
                            (!std::isnan(err)                  ? std::string("repeated error-test failures")
                             : st.recoverable_message.empty() ? std::string("the right-hand side is not finite")
                                                              : st.recoverable_message) +
                            ")");
        continue;
      }
      double factor = err == 0 ? max_factor
                               : std::min(max_factor, std::max(min_factor, safety * std::pow(err, error_exponent) *
                                                                               std::pow(err_old, beta)));
      err_old = std::max(err, 1e-4);
      if (rejected) factor = std::min(factor, 1.0);
      rejected = false;
      const double t_new = to_end ? t_end : t + h_try;
      bool prepared = false;
      if (ev) {
        ev->eval(t_new, st.z_new.data(), ev->g_new);
        ev->crossings(crossing);
        if (!crossing.empty()) {
          st.prepare_dense(t, h_try, r.stats);
          prepared = true;
          located.clear();
          for (int i : crossing) located.emplace_back(ev->locate(st, i, t, h_try), i);
          std::stable_sort(located.begin(), located.end(),
                           [](const auto& x, const auto& y) { return x.first < y.first; });
          // A stop takes effect after the crossings at the same time (within the tolerance).
          const double same = 100 * std::numeric_limits<double>::epsilon() * (std::abs(t) + std::abs(h_try));
          double stop_at = std::numeric_limits<double>::quiet_NaN();
          for (const auto& [tau, i] : located) {
            if (!std::isnan(stop_at) && tau > stop_at + same) break;
            record_dense(tau, false);
            st.interpolate(tau, dense);
            try {
              if (events->occurred(i, tau, dense.data(), st.sensitivities(&dense)) && std::isnan(stop_at)) stop_at = tau;
            } catch (const std::exception& e) {
              throw CallbackError{std::string("event handler threw: ") + e.what()};
            }
          }
          if (!std::isnan(stop_at)) {
            record_dense(stop_at, true);
            r.stopped_at = stop_at;
            r.message = at_time("stopped by an event", stop_at);
            r.stats.steps += 1;
            r.status = 1;
            r.stats.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
            return r;
          }
        }
      }
      if (times[k] < t_new) {
        if (!prepared) st.prepare_dense(t, h_try, r.stats);
        record_dense(t_new, false);
      }
      st.accept();
      t = t_new;
      ++r.stats.steps;
      h = std::min(h_try * factor, h_max);
      if (projecting && r.stats.steps % options.projection_frequency == 0 && !st.project(t, corr, r.stats))
        return finish(status_step_too_small, t, at_time("DOP853_PROJECTION_FAILED", t) +
                                                    ": the projection onto the constraints did not converge");
      if (checking && t < t_end) st.after_step(t, r.stats);
      if (ev && (projecting || checking))
        ev->eval(t, st.z.data(), ev->g_old);  // the state may have moved
      else if (ev)
        ev->g_old.swap(ev->g_new);
      if (k < times.size() && times[k] == t) {
        record(static_cast<int>(k), t, st.z.data(), st.sensitivities());
        st.record_quadrature(static_cast<int>(k), t);
        ++r.outputs_recorded;
        ++k;
      }
    }
  } catch (const CallbackError& e) {
    return finish(status_rhs_failed, t, at_time("DOP853_RHSFUNC_FAIL", t) + ": " + e.what);
  }
  r.status = 1;
  r.stats.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  return r;
}

}  // namespace kanesens::sim
