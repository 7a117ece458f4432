// kanesens-workprecision: the work-precision benchmark (workprecision.hpp), a program of its own
// beside the product CLI. Errors: one line on stderr; exit 2 for bad input, 1 otherwise.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "study/setup.hpp"
#include "util/error.hpp"
#include "util/parse_number.hpp"
#include "workprecision.hpp"

namespace kanesens::bench {
namespace {

using namespace kanesens::model;
using namespace kanesens::sim;
using study::StudySpec;

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
}  // namespace kanesens::bench

int main(int argc, char** argv) {
  using kanesens::bench::WpOptions;
  CLI::App app{"kanesens-workprecision: error against work for BDF/Adams/DOP853/RK4 (and exact/DQ sensitivities) over a tolerance sweep"};
  WpOptions o;
  WpOptions* const op = &o;
  app.add_option("study", op->study, "Study YAML file")->required();
  app.add_option("--set", op->set, "Override a parameter, initial condition or study setting (as in simulate); repeatable");
  app.add_option("--tolerances", op->tolerances, "Comma-separated rtol values (atol = rtol · atol-ratio)");
  app.add_option("--methods", op->methods,
                 "Comma-separated: bdf-exact, bdf-dq, adams-newton, adams-functional, dop853, rk4, sens-exact, sens-dq");
  app.add_option("--repeat", op->repeat, "Timed runs per point (the median is reported)");
  app.add_option("--reference-rtol", op->reference_rtol, "rtol of the reference run");
  app.add_option("--reference-method", op->reference_method,
                 "Method of the reference run: bdf-exact (default), dop853 (non-stiff problems), ...");
  app.add_option("--reference-file", op->reference_file,
                 "Reference solution (JSON/YAML with time, states[, state_names, sensitivities]) instead of a computed one");
  app.add_option("--atol-ratio", op->atol_ratio, "atol = rtol · this (default 0.01)");
  app.add_option("--error-floor", op->error_floor, "Floor of the denominator of relative errors (default 0.01)");
  app.add_option("--rk4-steps", op->rk4_steps, "Comma-separated step counts N for rk4 (h = (t_end − t0)/N)");
  app.add_option("--rk4-h-scale", op->rk4_h_scale, "rk4 step for tolerance tol: h = scale · tol^(1/4) (default 0.1)");
  app.add_option("--max-seconds", op->max_seconds, "A point whose first run takes longer is not repeated");
  app.add_option("--max-steps", op->max_steps, "Step budget per run (default: the study's solver.max_steps)");
  app.add_option("--reference-max-steps", op->reference_max_steps, "Step budget of the reference run");
  app.add_flag("--with-sens", op->with_sens, "Integrate the study's sensitivities with every method");
  app.add_flag("--json", op->json, "Print JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    return kanesens::bench::run_bench_workprecision(o);
  } catch (const kanesens::InputError& e) {
    std::cerr << "kanesens-workprecision: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "kanesens-workprecision: error: " << e.what() << "\n";
    return 1;
  }
}
