#include <algorithm>
#include <cmath>

#include "sim/solve/rk4.hpp"
#include "workprecision.hpp"

namespace kanesens::bench {

using namespace kanesens::model;
using namespace kanesens::sim;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

RecordFlags flags_for(const Model& m, bool sens) {
  RecordFlags f;
  f.states = true;
  f.sensitivities = sens;
  f.energy = true;
  f.multipliers = false;
  f.constraint_residual = m.nconstraint_rows > 0;
  return f;
}

bool solver_method(const std::string& name, sim::SolverOptions& opt) {
  using namespace kanesens::sim;
  opt.jacobian = JacobianKind::exact;
  opt.iteration = Iteration::newton;
  opt.sens_rhs = SensitivityRhs::exact;
  if (name == "bdf-exact" || name == "sens-exact") opt.method = Method::bdf;
  else if (name == "sens-dq") {
    opt.method = Method::bdf;
    opt.sens_rhs = SensitivityRhs::dq;
  } else if (name == "bdf-dq") {
    opt.method = Method::bdf;
    opt.jacobian = JacobianKind::dq;
  } else if (name == "dop853") opt.method = Method::dop853;
  else if (name == "adams-newton") opt.method = Method::adams;
  else if (name == "adams-functional") {
    opt.method = Method::adams;
    opt.iteration = Iteration::functional;
  } else return false;
  return true;
}

// Runs one method at one tolerance (or RK4 step h) and fills the row (errors excepted).
Row run_method(const Setup& s, KaneProblem& problem, const std::string& method, double tol, double h,
               Trajectory& tr) {
  using clock = std::chrono::steady_clock;
  Row row;
  row.method = method;
  row.tol = tol;
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  row.with_sens = ns > 0;
  const RecordFlags flags = flags_for(s.model, ns > 0);
  const sim::RecordFn noop = [](int, double, const double*, const double* const*) {};
  std::vector<double> walls;

  if (method == "rk4") {
    sim::Rk4Options ro;
    ro.h = h;
    ro.sensitivities = ns > 0;
    row.h = 0;
    for (std::size_t k = 0; k + 1 < s.times.size(); ++k) {
      const double span = s.times[k + 1] - s.times[k];
      const double steps = std::max(1.0, std::ceil(span / h * (1 - 1e-12)));
      row.h = std::max(row.h, span / steps);
    }
    resize_trajectory(tr, problem, s.times.size(), flags);
    auto t0 = clock::now();
    tr.result = sim::integrate_rk4(problem, ro, s.times, make_recorder(problem, flags, tr));
    const double first = seconds_since(t0);
    if (first > s.o.max_seconds) {
      walls.push_back(first);
      row.timed_with_recording = true;
    } else {
      for (int r = 0; r < s.o.repeat; ++r) {
        t0 = clock::now();
        sim::integrate_rk4(problem, ro, s.times, noop);
        walls.push_back(seconds_since(t0));
      }
    }
  } else {
    sim::SolverOptions opt = s.study.solver;
    opt.rtol = tol;
    opt.atol = tol * s.o.atol_ratio;
    opt.atol_per_state.clear();
    if (s.o.max_steps > 0) opt.max_steps = s.o.max_steps;
    solver_method(method, opt);
    row.rtol = opt.rtol;
    row.atol = opt.atol;
    if (problem.has_projection() && opt.method == sim::Method::adams) {
      row.skipped = true;
      row.message = "skipped: constraint projection needs BDF (study uses stabilization: projection)";
      return row;
    }
    {
      sim::Integrator integ(opt);
      const auto t0 = clock::now();
      simulate(problem, integ, s.times, flags, tr);
      const double first = seconds_since(t0);
      if (first > s.o.max_seconds) {
        walls.push_back(first);
        row.timed_with_recording = true;
      }
    }
    for (int r = 0; r < s.o.repeat && !row.timed_with_recording; ++r) {
      sim::Integrator integ(opt);
      const auto t0 = clock::now();
      integ.integrate(problem, s.times, noop);
      walls.push_back(seconds_since(t0));
    }
  }
  std::sort(walls.begin(), walls.end());
  row.wall_median = walls[walls.size() / 2];
  row.wall_min = walls.front();
  row.repeats = static_cast<int>(walls.size());
  row.status = tr.result.status;
  row.ok = tr.result.ok();
  row.message = tr.result.message;
  row.t_fail = tr.result.t_fail;
  row.stats = tr.result.stats;
  row.diag = diagnose(s.model, s.times, tr, ns, tr.result.outputs_recorded);
  if (method == "rk4") row.rk4_steps = row.stats.steps;
  return row;
}


}  // namespace kanesens::bench
