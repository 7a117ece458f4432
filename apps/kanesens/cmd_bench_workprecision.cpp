// `kanesens bench workprecision STUDY [--tolerances 1e-4,1e-6,...] [--methods M1,M2,...]
//  [--repeat K] [--reference-rtol 1e-13] [--reference-method M] [--reference-file F] [--with-sens]
//  [--json]`:
// speed against accuracy. For every method and tolerance the study's nominal sample is
// integrated, compared with a reference solution at the study's output times, and timed.
//
// Methods (all on the same KaneProblem):
//   bdf-exact         CVODES BDF, Newton, exact (dual-number) Jacobian
//   bdf-dq            CVODES BDF, Newton, CVODES's difference-quotient Jacobian
//   adams-newton      CVODES Adams–Moulton, Newton, exact Jacobian
//   adams-functional  CVODES Adams–Moulton, fixed-point iteration (no Jacobian)
//   dop853            explicit adaptive Runge–Kutta 8(5,3) (solve/dop853.hpp, solver.method: dop853)
//   rk4               classical fixed-step RK4 (solve/rk4.hpp); tolerance tol → step
//                     h = rk4_h_scale · tol^(1/4) (its global error is O(h⁴)), or the step
//                     counts of --rk4-steps (h = (t_end − t0)/N)
//   sens-exact        bdf-exact with the study's sensitivities, exact sensitivity RHS (duals)
//   sens-dq           bdf-exact with the study's sensitivities, CVODES's DQ sensitivity RHS
// The first six integrate the states only, unless --with-sens (then all integrate the study's
// sensitivities with the exact sensitivity RHS; RK4 and DOP853 by their own stages).
// Tolerances of the error-controlled methods: rtol = tol, atol = tol · atol_ratio (all states).
//
// Reference: --reference-method (bdf-exact; dop853 for non-stiff problems, whose BDF reference
// limits the measurable error to ~1e-9) at --reference-rtol (atol = reference_rtol · atol_ratio), with the
// study's sensitivities, or --reference-file: JSON/YAML with `time` and `states` (T × n) and
// optionally `state_names` and `sensitivities` (T × n × ns) — e.g. `kanesens simulate` output or
// a published solution (only the times it lists are compared; they must be output times).
//
// Errors (d = y − y_ref, at the reference's times):
//   final_rel_error  max over components of |d_i(T)| / max(|y_ref,i(T)|, error_floor)
//   l2_error         sqrt(mean over times and components of d²) (DiffEqDevTools :l2)
//   linf_error       max over times and components of |d|
//   sens_final_rel_error  max over (i, j) of |ds_ij(T)| / max(|s_ref,ij(T)|, floor · max_i |s_ref,ij(T)|)
//   sens_l2_error    as l2_error, over all sensitivities
// and diagnostics of the run itself: energy drift max |E(t) − E(t0)|, energy error against the
// reference, max | |quaternion| − 1 |, constraint residuals (max |g|, max |A u + a0|), and the
// growth rate of the sensitivity norm ln(‖S(t)‖_F / ‖S(t0)‖_F) / (t − t0) (a Lyapunov estimate
// for chaotic systems; also the least-squares slope of ln ‖S‖ over the second half of the run).
//
// Work: wall time of the integration alone (a recorder that does nothing), median of --repeat
// runs, each with a fresh Integrator (setup included); the errors come from one more, recorded,
// run (integration is deterministic). If that recorded run takes longer than --max-seconds,
// it is the only run and its time is reported (timed_with_recording = true).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>

#include "commands.hpp"
#include "model/build_model.hpp"
#include "sim/simulate.hpp"
#include "sim/solve/rk4.hpp"
#include "study/setup.hpp"
#include "util/error.hpp"
#include "util/json_writer.hpp"
#include "util/parse_number.hpp"

namespace kanesens::cli {

using namespace kanesens::dynamics;
using namespace kanesens::model;
using namespace kanesens::sim;
using study::StudySpec;

namespace {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

struct WpOptions {
  std::string study;
  std::vector<std::string> set;
  std::string tolerances = "1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10";
  std::string methods;  // empty: the default list
  std::string rk4_steps;
  int repeat = 5;
  double reference_rtol = 1e-13;
  std::string reference_method = "bdf-exact";
  std::string reference_file;
  double atol_ratio = 1e-2;
  double error_floor = 1e-2;
  double rk4_h_scale = 0.1;
  double max_seconds = 2.0;
  long max_steps = 0;  // 0: the study's solver.max_steps
  long reference_max_steps = 100000000;
  bool with_sens = false;
  bool json = false;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const auto c = s.find(',', start);
    std::string item = s.substr(start, c == std::string::npos ? std::string::npos : c - start);
    if (!item.empty()) out.push_back(item);
    if (c == std::string::npos) break;
    start = c + 1;
  }
  return out;
}

std::vector<double> numbers(const std::string& s, const std::string& key) {
  std::vector<double> v;
  for (const std::string& item : split(s)) {
    const double x = parse_number(item, key);
    if (!(x > 0 && std::isfinite(x))) throw InputError({}, key, "values must be finite and > 0, found '" + item + "'");
    v.push_back(x);
  }
  if (v.empty()) throw InputError({}, key, "needs at least one value");
  return v;
}

// A solution at some output times (indices into the study's output times).
struct Solution {
  std::vector<std::size_t> index;      // output index of each time
  std::vector<double> states;          // index.size() × n
  std::vector<double> sensitivities;   // index.size() × n × ns (may be empty)
  std::vector<double> energy;          // index.size() (may be empty)
};

struct Errors {
  double final_rel = nan_value, final_abs = nan_value, l2 = nan_value, linf = nan_value;
  std::string worst_component;
  double sens_final_rel = nan_value, sens_l2 = nan_value;
  double energy_error = nan_value;
};

struct Diagnostics {
  double energy_drift = nan_value, energy_drift_final = nan_value;
  double quaternion_drift = nan_value;
  double position_residual = nan_value, velocity_residual = nan_value;
  double sens_rate = nan_value, sens_slope = nan_value, sens_norm_final = nan_value;
};

struct Row {
  std::string method;
  double tol = nan_value, rtol = nan_value, atol = nan_value, h = nan_value;
  long rk4_steps = 0;
  bool with_sens = false, ok = false, skipped = false, timed_with_recording = false;
  int status = 0;
  std::string message;
  double t_fail = nan_value;
  double wall_median = nan_value, wall_min = nan_value;
  int repeats = 0;
  sim::SolverStats stats;
  Errors err;
  Diagnostics diag;
};

struct Setup {
  const WpOptions& o;
  const StudySpec& study;
  const Model& model;
  const std::vector<double>& times;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Diagnostics of a recorded trajectory (its own outputs only).
Diagnostics diagnose(const Model& m, const std::vector<double>& times, const Trajectory& tr, std::size_t ns,
                     int outputs) {
  Diagnostics d;
  const std::size_t n = static_cast<std::size_t>(m.nstate());
  const std::size_t T = static_cast<std::size_t>(std::max(outputs, 0));
  if (T == 0) return d;
  if (!tr.energy.empty()) {
    d.energy_drift = 0;
    for (std::size_t k = 0; k < T; ++k) d.energy_drift = std::max(d.energy_drift, std::abs(tr.energy[k] - tr.energy[0]));
    d.energy_drift_final = tr.energy[T - 1] - tr.energy[0];
  }
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) continue;
    if (std::isnan(d.quaternion_drift)) d.quaternion_drift = 0;
    for (std::size_t k = 0; k < T; ++k) {
      const double* e = &tr.states[k * n + static_cast<std::size_t>(J.quaternion_offset)];
      const double norm = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
      d.quaternion_drift = std::max(d.quaternion_drift, std::abs(norm - 1));
    }
  }
  if (!tr.position_residual.empty()) {
    d.position_residual = d.velocity_residual = 0;
    for (std::size_t k = 0; k < T; ++k) {
      d.position_residual = std::max(d.position_residual, tr.position_residual[k]);
      d.velocity_residual = std::max(d.velocity_residual, tr.velocity_residual[k]);
    }
  }
  if (ns > 0 && !tr.sensitivities.empty() && T > 1) {
    std::vector<double> lognorm(T);
    for (std::size_t k = 0; k < T; ++k) {
      double s2 = 0;
      for (std::size_t j = 0; j < n * ns; ++j) s2 += tr.sensitivities[k * n * ns + j] * tr.sensitivities[k * n * ns + j];
      lognorm[k] = 0.5 * std::log(s2);
    }
    d.sens_norm_final = std::exp(lognorm[T - 1]);
    d.sens_rate = (lognorm[T - 1] - lognorm[0]) / (times[T - 1] - times[0]);
    // Least-squares slope over the second half of the outputs reached.
    const std::size_t k0 = T / 2;
    double st = 0, sl = 0, stt = 0, stl = 0, cnt = 0;
    for (std::size_t k = k0; k < T; ++k) {
      st += times[k];
      sl += lognorm[k];
      stt += times[k] * times[k];
      stl += times[k] * lognorm[k];
      cnt += 1;
    }
    const double den = cnt * stt - st * st;
    if (cnt >= 2 && den > 0) d.sens_slope = (cnt * stl - st * sl) / den;
  }
  return d;
}

Errors compare(const Setup& s, const Trajectory& tr, std::size_t ns, const Solution& ref) {
  Errors e;
  const std::size_t n = static_cast<std::size_t>(s.model.nstate());
  const std::size_t R = ref.index.size();
  double sum2 = 0, linf = 0;
  bool finite = true;
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t i = 0; i < n; ++i) {
      const double d = tr.states[ref.index[r] * n + i] - ref.states[r * n + i];
      if (!std::isfinite(d)) finite = false;
      sum2 += d * d;
      linf = std::max(linf, std::abs(d));
    }
  if (!finite) return e;  // failed run: outputs past the failure are NaN
  e.l2 = std::sqrt(sum2 / static_cast<double>(R * n));
  e.linf = linf;
  const std::size_t last = ref.index[R - 1];
  e.final_rel = e.final_abs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double yr = ref.states[(R - 1) * n + i];
    const double d = std::abs(tr.states[last * n + i] - yr);
    const double rel = d / std::max(std::abs(yr), s.o.error_floor);
    e.final_abs = std::max(e.final_abs, d);
    if (rel >= e.final_rel) {
      e.final_rel = rel;
      e.worst_component = s.model.state_names[i];
    }
  }
  if (!ref.energy.empty() && !tr.energy.empty()) {
    e.energy_error = 0;
    for (std::size_t r = 0; r < R; ++r) e.energy_error = std::max(e.energy_error, std::abs(tr.energy[ref.index[r]] - ref.energy[r]));
  }
  if (ns > 0 && !tr.sensitivities.empty() && !ref.sensitivities.empty()) {
    double s2 = 0;
    for (std::size_t r = 0; r < R; ++r)
      for (std::size_t j = 0; j < n * ns; ++j) {
        const double d = tr.sensitivities[ref.index[r] * n * ns + j] - ref.sensitivities[r * n * ns + j];
        s2 += d * d;
      }
    e.sens_l2 = std::sqrt(s2 / static_cast<double>(R * n * ns));
    e.sens_final_rel = 0;
    for (std::size_t p = 0; p < ns; ++p) {
      double scale = 0;
      for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(ref.sensitivities[((R - 1) * n + i) * ns + p]));
      for (std::size_t i = 0; i < n; ++i) {
        const double sr = ref.sensitivities[((R - 1) * n + i) * ns + p];
        const double d = std::abs(tr.sensitivities[(last * n + i) * ns + p] - sr);
        const double den = std::max(std::abs(sr), s.o.error_floor * scale);
        e.sens_final_rel = std::max(e.sens_final_rel, den > 0 ? d / den : d);
      }
    }
  }
  return e;
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

// Configures `opt` for an error-controlled method (CVODES or DOP853); false for an unknown name.
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

// The reference solution from --reference-file (JSON is YAML).
Solution load_reference(const Setup& s, std::size_t ns) {
  const std::string& path = s.o.reference_file;
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError({path, 0, 0}, "--reference-file", std::string("cannot read: ") + e.what());
  }
  if (!doc["time"] || !doc["states"]) throw InputError({path, 0, 0}, "--reference-file", "needs 'time' and 'states'");
  const std::size_t n = static_cast<std::size_t>(s.model.nstate());
  std::vector<std::size_t> column(n);
  for (std::size_t i = 0; i < n; ++i) column[i] = i;
  if (doc["state_names"]) {
    std::map<std::string, std::size_t> where;
    for (std::size_t i = 0; i < doc["state_names"].size(); ++i) where[doc["state_names"][i].as<std::string>()] = i;
    for (std::size_t i = 0; i < n; ++i) {
      auto it = where.find(s.model.state_names[i]);
      if (it == where.end()) throw InputError({path, 0, 0}, "--reference-file", "no state named '" + s.model.state_names[i] + "'");
      column[i] = it->second;
    }
  }
  auto num = [](const YAML::Node& v) { return v.IsNull() ? nan_value : v.as<double>(); };
  Solution ref;
  const double scale = std::max(1.0, std::abs(s.times.back()));
  for (std::size_t r = 0; r < doc["time"].size(); ++r) {
    const double t = num(doc["time"][r]);
    auto it = std::find_if(s.times.begin(), s.times.end(), [&](double x) { return std::abs(x - t) <= 1e-9 * scale; });
    if (it == s.times.end())
      throw InputError({path, 0, 0}, "--reference-file", "time " + std::to_string(t) + " is not an output time of the study");
    ref.index.push_back(static_cast<std::size_t>(it - s.times.begin()));
    const YAML::Node row = doc["states"][r];
    for (std::size_t i = 0; i < n; ++i) ref.states.push_back(num(row[column[i]]));
    if (ns > 0 && doc["sensitivities"] && doc["sensitivities"].size() > r) {
      const YAML::Node sr = doc["sensitivities"][r];
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t p = 0; p < ns; ++p) ref.sensitivities.push_back(num(sr[column[i]][p]));
    }
  }
  if (ref.index.empty()) throw InputError({path, 0, 0}, "--reference-file", "has no times");
  if (ref.sensitivities.size() != ref.index.size() * n * ns) ref.sensitivities.clear();
  return ref;
}

void write_row(JsonWriter& j, const Row& r) {
  j.begin_object();
  j.key("method").value(r.method);
  j.key("tol").value(r.tol);
  j.key("rtol").value(r.rtol);
  j.key("atol").value(r.atol);
  j.key("h").value(r.h);
  j.key("with_sens").value(r.with_sens);
  j.key("ok").value(r.ok);
  j.key("skipped").value(r.skipped);
  j.key("status").value(r.status);
  j.key("message").value(r.message);
  j.key("t_fail").value(r.t_fail);
  j.key("wall_seconds").value(r.wall_median);
  j.key("wall_seconds_min").value(r.wall_min);
  j.key("repeats").value(r.repeats);
  j.key("timed_with_recording").value(r.timed_with_recording);
  j.key("steps").value(static_cast<long long>(r.stats.steps));
  j.key("rhs_evals").value(static_cast<long long>(r.stats.rhs_evals));
  j.key("rhs_evals_total").value(static_cast<long long>(r.stats.rhs_evals + r.stats.lin_rhs_evals + r.stats.rhs_evals_for_sens));
  j.key("jac_evals").value(static_cast<long long>(r.stats.jac_evals));
  j.key("lin_rhs_evals").value(static_cast<long long>(r.stats.lin_rhs_evals));
  j.key("sens_rhs_evals").value(static_cast<long long>(r.stats.sens_rhs_evals));
  j.key("rhs_evals_for_sens").value(static_cast<long long>(r.stats.rhs_evals_for_sens));
  j.key("error_test_fails").value(static_cast<long long>(r.stats.error_test_fails));
  j.key("nonlin_conv_fails").value(static_cast<long long>(r.stats.nonlin_conv_fails));
  j.key("final_rel_error").value(r.err.final_rel);
  j.key("final_rel_error_component").value(r.err.worst_component);
  j.key("final_abs_error").value(r.err.final_abs);
  j.key("l2_error").value(r.err.l2);
  j.key("linf_error").value(r.err.linf);
  j.key("sens_final_rel_error").value(r.err.sens_final_rel);
  j.key("sens_l2_error").value(r.err.sens_l2);
  j.key("energy_error").value(r.err.energy_error);
  j.key("energy_drift").value(r.diag.energy_drift);
  j.key("energy_drift_final").value(r.diag.energy_drift_final);
  j.key("quaternion_norm_drift").value(r.diag.quaternion_drift);
  j.key("constraint_position_residual").value(r.diag.position_residual);
  j.key("constraint_velocity_residual").value(r.diag.velocity_residual);
  j.key("sens_norm_final").value(r.diag.sens_norm_final);
  j.key("sens_growth_rate").value(r.diag.sens_rate);
  j.key("sens_growth_slope").value(r.diag.sens_slope);
  j.end_object();
}

std::string fmt(double v, const char* f = "%.2e") {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

int run_bench_workprecision(const WpOptions& o) {
  if (o.repeat < 1) throw InputError({}, "--repeat", "must be at least 1");
  if (!(o.reference_rtol > 0)) throw InputError({}, "--reference-rtol", "must be > 0");
  {
    sim::SolverOptions probe;
    if (o.reference_method.rfind("sens-", 0) == 0 || !solver_method(o.reference_method, probe))
      throw InputError({}, "--reference-method", "expected bdf-exact, bdf-dq, adams-newton, adams-functional or dop853, got '" +
                                                    o.reference_method + "'");
  }
  if (!(o.atol_ratio > 0)) throw InputError({}, "--atol-ratio", "must be > 0");
  if (!(o.error_floor > 0)) throw InputError({}, "--error-floor", "must be > 0");
  const study::StudySetup setup = study::setup_study(o.study, o.set);
  const StudySpec& study = setup.spec;
  const Model& model = setup.model;
  const Setup s{o, study, model, study.output_times};
  const SampleInputs& inputs = setup.base;
  const std::vector<InputRef>& sens_refs = setup.sensitivities;
  const std::size_t ns = sens_refs.size();

  const std::vector<double> tols = numbers(o.tolerances, "--tolerances");
  std::vector<std::string> methods = split(o.methods);
  if (methods.empty()) {
    methods = {"bdf-exact", "bdf-dq", "adams-newton", "adams-functional", "dop853", "rk4"};
    if (ns > 0) {
      methods.push_back("sens-exact");
      methods.push_back("sens-dq");
    }
  }
  for (const std::string& m : methods) {
    sim::SolverOptions probe;
    if (m != "rk4" && !solver_method(m, probe))
      throw InputError({}, "--methods", "unknown method '" + m + "'; expected bdf-exact, bdf-dq, adams-newton, adams-functional, dop853, rk4, sens-exact, sens-dq");
    if (m.rfind("sens-", 0) == 0 && ns == 0)
      throw InputError({}, "--methods", "'" + m + "' needs a study with sensitivities");
  }
  std::vector<long> rk4_steps;
  for (double v : (o.rk4_steps.empty() ? std::vector<double>{} : numbers(o.rk4_steps, "--rk4-steps")))
    rk4_steps.push_back(static_cast<long>(std::llround(v)));

  KaneProblem plain(model, {}, study.constraints, study.output_times.front());
  plain.set_sample(inputs);
  KaneProblem with(model, sens_refs, study.constraints, study.output_times.front());
  with.set_sample(inputs);

  // Reference.
  Trajectory ref_traj;
  Row ref_row;
  Solution ref;
  if (o.reference_file.empty()) {
    sim::SolverOptions opt = s.study.solver;
    opt.rtol = o.reference_rtol;
    opt.atol = o.reference_rtol * o.atol_ratio;
    opt.atol_per_state.clear();
    opt.max_steps = o.reference_max_steps;
    solver_method(o.reference_method, opt);
    sim::Integrator integ(opt);
    const auto t0 = std::chrono::steady_clock::now();
    simulate(with, integ, s.times, flags_for(s.model, ns > 0), ref_traj);
    ref_row.wall_median = seconds_since(t0);
    ref_row.method = o.reference_method;
    ref_row.rtol = opt.rtol;
    ref_row.atol = opt.atol;
    ref_row.tol = opt.rtol;
    ref_row.status = ref_traj.result.status;
    ref_row.ok = ref_traj.result.ok();
    ref_row.message = ref_traj.result.message;
    ref_row.stats = ref_traj.result.stats;
    ref_row.with_sens = ns > 0;
    ref_row.repeats = 1;
    ref_row.diag = diagnose(s.model, s.times, ref_traj, ns, ref_traj.result.outputs_recorded);
    if (!ref_row.ok) throw std::runtime_error("the reference run failed: " + ref_traj.result.message);
    const std::size_t n = static_cast<std::size_t>(s.model.nstate());
    for (std::size_t k = 0; k < s.times.size(); ++k) ref.index.push_back(k);
    ref.states = ref_traj.states;
    ref.sensitivities = ref_traj.sensitivities;
    ref.energy = ref_traj.energy;
    (void)n;
  } else {
    ref = load_reference(s, ns);
  }

  std::vector<Row> rows;
  Trajectory tr;
  for (const std::string& m : methods) {
    const bool sens = m.rfind("sens-", 0) == 0 || (o.with_sens && ns > 0);
    KaneProblem& problem = sens ? with : plain;
    if (m == "rk4") {
      std::vector<std::pair<double, double>> sweep;  // (tol, h)
      if (!rk4_steps.empty())
        for (long N : rk4_steps) sweep.emplace_back(nan_value, (s.times.back() - s.times.front()) / static_cast<double>(N));
      else
        for (double tol : tols) sweep.emplace_back(tol, o.rk4_h_scale * std::pow(tol, 0.25));
      for (const auto& [tol, h] : sweep) {
        Row r = run_method(s, problem, m, tol, h, tr);
        r.err = compare(s, tr, sens ? ns : 0, ref);
        rows.push_back(std::move(r));
        if (!o.json) std::cerr << "  " << m << " h=" << fmt(rows.back().h) << " done\n";
      }
    } else {
      for (double tol : tols) {
        Row r = run_method(s, problem, m, tol, 0, tr);
        if (!r.skipped) r.err = compare(s, tr, sens ? ns : 0, ref);
        rows.push_back(std::move(r));
      }
    }
  }

  if (o.json) {
    JsonWriter j(std::cout);
    j.begin_object();
    j.key("study").value(o.study);
    j.key("scene").value(s.model.name);
    j.key("nq").value(s.model.nq);
    j.key("nu").value(s.model.nu);
    j.key("nconstraint_rows").value(s.model.nconstraint_rows);
    j.key("t0").value(s.times.front());
    j.key("t_end").value(s.times.back());
    j.key("outputs").value(static_cast<long long>(s.times.size()));
    j.key("sensitivity_names").array(s.study.sensitivities);
    j.key("set").array(o.set);
    j.key("atol_ratio").value(o.atol_ratio);
    j.key("error_floor").value(o.error_floor);
    j.key("repeat").value(o.repeat);
    j.key("rk4_h_scale").value(o.rk4_h_scale);
    j.key("reference").begin_object();
    if (o.reference_file.empty()) {
      j.key("kind").value("computed");
      j.key("row");
      write_row(j, ref_row);
    } else {
      j.key("kind").value("file");
      j.key("file").value(o.reference_file);
      j.key("times").value(static_cast<long long>(ref.index.size()));
    }
    j.end_object();
    j.key("rows").begin_array();
    for (const Row& r : rows) write_row(j, r);
    j.end_array();
    j.end_object();
    std::cout << "\n";
  } else {
    std::cout << "work-precision: " << o.study << " (scene '" << s.model.name << "', t = " << s.times.front() << " .. "
              << s.times.back() << ", " << s.times.size() << " outputs)\n";
    if (o.reference_file.empty())
      std::cout << "reference: bdf-exact rtol " << fmt(ref_row.rtol) << ", " << ref_row.stats.steps << " steps, "
                << fmt(ref_row.wall_median, "%.3f") << " s\n";
    else
      std::cout << "reference: " << o.reference_file << "\n";
    char line[256];
    std::snprintf(line, sizeof line, "%-17s %9s %9s %10s %10s %10s %10s %9s %9s %9s  %s\n", "method", "tol", "h",
                  "final_rel", "l2", "sens_rel", "time_s", "steps", "rhs", "E_drift", "status");
    std::cout << line;
    for (const Row& r : rows) {
      std::snprintf(line, sizeof line, "%-17s %9s %9s %10s %10s %10s %10s %9ld %9ld %9s  %s\n", r.method.c_str(),
                    fmt(r.tol, "%.0e").c_str(), fmt(r.h, "%.2e").c_str(), fmt(r.err.final_rel).c_str(),
                    fmt(r.err.l2).c_str(), fmt(r.err.sens_final_rel).c_str(), fmt(r.wall_median, "%.4f").c_str(),
                    r.stats.steps, r.stats.rhs_evals + r.stats.lin_rhs_evals + r.stats.rhs_evals_for_sens,
                    fmt(r.diag.energy_drift).c_str(), r.skipped ? "skipped" : (r.ok ? "ok" : r.message.substr(0, 40).c_str()));
      std::cout << line;
    }
  }
  return 0;
}
}  // namespace

void add_bench_workprecision(CLI::App* bench, Action& action) {
  auto* wp = bench->add_subcommand("workprecision",
                                   "Error against work for BDF/Adams/RK4 (and exact/DQ sensitivities) over a tolerance sweep");
  auto o = std::make_shared<WpOptions>();
  wp->add_option("study", o->study, "Study YAML file")->required();
  wp->add_option("--set", o->set, "Override a parameter, initial condition or study setting (as in simulate); repeatable");
  wp->add_option("--tolerances", o->tolerances, "Comma-separated rtol values (atol = rtol · atol-ratio)");
  wp->add_option("--methods", o->methods,
                 "Comma-separated: bdf-exact, bdf-dq, adams-newton, adams-functional, dop853, rk4, sens-exact, sens-dq");
  wp->add_option("--repeat", o->repeat, "Timed runs per point (the median is reported)")->check(integer_in(1, 100000));
  wp->add_option("--reference-rtol", o->reference_rtol, "rtol of the reference run")->check(finite_number(1e-300, 1));
  wp->add_option("--reference-method", o->reference_method,
                 "Method of the reference run: bdf-exact (default), dop853 (non-stiff problems), ...");
  wp->add_option("--reference-file", o->reference_file,
                 "Reference solution (JSON/YAML with time, states[, state_names, sensitivities]) instead of a computed one");
  wp->add_option("--atol-ratio", o->atol_ratio, "atol = rtol · this (default 0.01)")->check(finite_number(1e-300, 1e300));
  wp->add_option("--error-floor", o->error_floor, "Floor of the denominator of relative errors (default 0.01)")->check(finite_number(0, 1e300));
  wp->add_option("--rk4-steps", o->rk4_steps, "Comma-separated step counts N for rk4 (h = (t_end − t0)/N)");
  wp->add_option("--rk4-h-scale", o->rk4_h_scale, "rk4 step for tolerance tol: h = scale · tol^(1/4) (default 0.1)")->check(finite_number(1e-300, 1e300));
  wp->add_option("--max-seconds", o->max_seconds, "A point whose first run takes longer is not repeated")->check(finite_number(0, 1e9));
  wp->add_option("--max-steps", o->max_steps, "Step budget per run (default: the study's solver.max_steps)")->check(integer_in(0, 1LL << 40));
  wp->add_option("--reference-max-steps", o->reference_max_steps, "Step budget of the reference run")->check(integer_in(1, 1LL << 40));
  wp->add_flag("--with-sens", o->with_sens, "Integrate the study's sensitivities with every method");
  wp->add_flag("--json", o->json, "Print JSON");
  wp->callback([&action, o] { action = [o] { return run_bench_workprecision(*o); }; });
}

}  // namespace kanesens::cli
