// `kanesens simulate STUDY [--set NAME=VALUE ...] [--sens P1,P2] [--format json|csv]`:
// integrates the nominal sample of a study and prints the trajectory with its sensitivities.
#include <iostream>

#include "commands.hpp"
#include "parallel/resources.hpp"
#include "sim/simulate.hpp"
#include "study/setup.hpp"
#include "util/json_writer.hpp"

namespace kanesens::cli {

using namespace kanesens::dynamics;
using namespace kanesens::model;
using namespace kanesens::sim;

namespace {
struct SimulateOptions {
  std::string study, sens, format = "json";
  std::vector<std::string> set;
  int repeat = 1;
};

// The integration's counters in the JSON's stats, in this order.
constexpr std::pair<const char*, long SolverStats::*> kPrintedCounters[] = {
    {"steps", &SolverStats::steps}, {"rhs_evals", &SolverStats::rhs_evals}, {"jac_evals", &SolverStats::jac_evals},
    {"lin_rhs_evals", &SolverStats::lin_rhs_evals}, {"jtimes_evals", &SolverStats::jtimes_evals},
    {"lin_iters", &SolverStats::lin_iters}, {"nonlin_iters", &SolverStats::nonlin_iters},
    {"nonlin_conv_fails", &SolverStats::nonlin_conv_fails}, {"error_test_fails", &SolverStats::error_test_fails},
    {"sens_rhs_evals", &SolverStats::sens_rhs_evals}, {"rhs_evals_for_sens", &SolverStats::rhs_evals_for_sens},
    {"sens_error_test_fails", &SolverStats::sens_error_test_fails}, {"repartitions", &SolverStats::repartitions}};

// [T][width] of a time-major buffer; [] when nothing was recorded (an empty buffer).
void write_rows(JsonWriter& j, const std::vector<double>& flat, std::size_t T, std::size_t width) {
  j.begin_array();
  for (std::size_t k = 0; k < T && !flat.empty(); ++k) j.array(&flat[k * width], width);
  j.end_array();
}

// [T][rows][width] of a time-major buffer; [] when nothing was recorded.
void write_row_blocks(JsonWriter& j, const std::vector<double>& flat, std::size_t T, std::size_t rows,
                      std::size_t width) {
  j.begin_array();
  for (std::size_t k = 0; k < T && !flat.empty(); ++k) {
    j.begin_array();
    for (std::size_t r = 0; r < rows; ++r) j.array(&flat[(k * rows + r) * width], width);
    j.end_array();
  }
  j.end_array();
}

void print_json(const Model& m, const KaneProblem& problem, const std::vector<double>& times, const Trajectory& tr,
                const OutputPlan* plan, const std::vector<double>& repeat_walls) {
  const std::size_t n = static_cast<std::size_t>(m.nstate()), ns = problem.sensitivities().size();
  JsonWriter j(std::cout);
  j.begin_object();
  j.key("scene").value(m.name);
  j.key("status").value(tr.result.status);
  j.key("message").value(tr.result.message);
  j.key("time").array(times);
  j.key("state_names").array(m.state_names);
  j.key("states");
  write_rows(j, tr.states, times.size(), n);
  j.key("sensitivity_names").begin_array();
  for (const auto& s : problem.sensitivities()) j.value(s.name);
  j.end_array();
  j.key("sensitivities");
  write_row_blocks(j, tr.sensitivities, times.size(), n, ns);
  const std::size_t nc = static_cast<std::size_t>(m.nconstraint_rows);
  j.key("constraint_names").array(m.constraint_row_names);
  j.key("multipliers");
  write_rows(j, tr.multipliers, times.size(), nc);
  j.key("multiplier_sensitivities");
  write_row_blocks(j, tr.multiplier_sensitivities, times.size(), nc, ns);
  j.key("constraint_residuals").begin_object();
  j.key("position").array(tr.position_residual);
  j.key("velocity").array(tr.velocity_residual);
  j.end_object();
  j.key("initial_correction").begin_object();
  j.key("position").value(problem.initial_position_correction());
  j.key("velocity").value(problem.initial_velocity_correction());
  j.end_object();
  // The study's outputs after energy: series [T] (sensitivities [T][S]), scalars a number ([S]).
  const std::size_t T = times.size();
  j.key("outputs").begin_object();
  if (!tr.energy.empty()) j.key("energy").array(tr.energy);
  if (plan) {
    for (std::size_t v = 0; v < plan->series_names.size(); ++v) j.key(plan->series_names[v]).array(&tr.outputs[v * T], T);
    for (std::size_t v = 0; v < plan->scalar_names.size(); ++v) j.key(plan->scalar_names[v]).value(tr.scalar_outputs[v]);
  }
  j.end_object();
  j.key("output_sensitivities").begin_object();
  if (plan && ns > 0) {
    for (std::size_t v = 0; v < plan->series_names.size(); ++v) {
      j.key(plan->series_names[v]).begin_array();
      for (std::size_t k = 0; k < T; ++k) j.array(&tr.output_sensitivities[(v * T + k) * ns], ns);
      j.end_array();
    }
    for (std::size_t v = 0; v < plan->scalar_names.size(); ++v)
      j.key(plan->scalar_names[v]).array(&tr.scalar_output_sensitivities[v * ns], ns);
  }
  j.end_object();
  const auto& s = tr.result.stats;
  j.key("stats").begin_object();
  j.key("linear_solver").value(std::string(to_string(tr.result.linear_solver)));
  j.key("sensitivity_method").value(std::string(to_string(tr.result.sensitivity_method)));
  for (const auto& [name, counter] : kPrintedCounters) j.key(name).value(static_cast<long long>(s.*counter));
  j.key("wall_seconds").value(s.wall_seconds);
  if (repeat_walls.size() > 1) j.key("wall_seconds_repeats").array(repeat_walls);
  j.end_object();
  j.end_object();
  std::cout << "\n";
}

void print_csv(const Model& m, const KaneProblem& problem, const std::vector<double>& times, const Trajectory& tr,
               const OutputPlan* plan) {
  const std::size_t n = static_cast<std::size_t>(m.nstate()), ns = problem.sensitivities().size();
  std::cout << "time";
  for (const auto& s : m.state_names) std::cout << "," << s;
  for (const auto& s : m.state_names)
    for (const auto& p : problem.sensitivities()) std::cout << ",d(" << s << ")/d(" << p.name << ")";
  if (!tr.energy.empty()) std::cout << ",energy";
  if (plan)
    for (const auto& name : plan->series_names) std::cout << "," << name;
  std::cout << "\n";
  char buf[32];
  auto num = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
  };
  for (std::size_t k = 0; k < times.size(); ++k) {
    std::cout << num(times[k]);
    for (std::size_t r = 0; r < n && !tr.states.empty(); ++r) std::cout << "," << num(tr.states[k * n + r]);
    for (std::size_t r = 0; r < n && !tr.sensitivities.empty(); ++r)
      for (std::size_t i = 0; i < ns; ++i) std::cout << "," << num(tr.sensitivities[(k * n + r) * ns + i]);
    if (!tr.energy.empty()) std::cout << "," << num(tr.energy[k]);
    for (std::size_t v = 0; plan && v < plan->series_names.size(); ++v) std::cout << "," << num(tr.outputs[v * times.size() + k]);
    std::cout << "\n";
  }
}

int run_simulate(const SimulateOptions& o) {
  if (o.format != "json" && o.format != "csv") throw InputError({}, "--format", "expected json or csv, found '" + o.format + "'");
  // The whole study is checked, as `run` would (sampling and vary too, which simulate does not
  // use): a typo there is an error here as well, not a surprise hours later.
  const study::StudySetup setup = study::setup_study(o.study, o.set);
  const study::StudySpec& study = setup.spec;
  const Model& m = setup.model;
  std::vector<InputRef> sens = setup.sensitivities;
  if (o.sens == "none") {
    sens.clear();
  } else if (!o.sens.empty()) {
    sens.clear();
    std::size_t start = 0;
    for (;;) {
      const auto c = o.sens.find(',', start);
      const std::string name = o.sens.substr(start, c == std::string::npos ? std::string::npos : c - start);
      for (const InputRef& given : sens)
        if (given.name == name) throw InputError({}, "--sens", "'" + name + "' is listed twice");
      sens.push_back(resolve_input(m, name, "--sens"));
      if (c == std::string::npos) break;
      start = c + 1;
    }
  }
  {
    // The trajectory is held in memory (and printed): check it fits, as `run` does per rank.
    const double T = static_cast<double>(study.output_times.size()), S = static_cast<double>(sens.size());
    const double bytes = 8.0 * T * ((m.nstate() + m.nconstraint_rows) * (1 + S) + 3);
    const double available = parallel::available_memory_bytes();
    if (bytes > available)
      throw InputError(study.time_where, "time",
                       "the trajectory (" + std::to_string(study.output_times.size()) + " times x " +
                           std::to_string(m.nstate()) + " states x (1 + " + std::to_string(sens.size()) +
                           " sensitivities)) needs about " + parallel::human_bytes(bytes) + " of memory but " +
                           parallel::human_bytes(available) + " is available; use fewer output times or sensitivities");
  }
  if (o.repeat < 1) throw InputError({}, "--repeat", "expected a count of at least 1, found " + std::to_string(o.repeat));
  KaneProblem problem(m, sens, study.constraints, study.output_times.front());
  sim::Integrator integrator(study.solver);
  RecordFlags flags;
  flags.states = true;
  flags.sensitivities = !sens.empty();
  flags.energy = true;
  flags.multipliers = m.nconstraint_rows > 0;
  flags.constraint_residual = m.nconstraint_rows > 0;
  flags.outputs = setup.record.outputs;
  // Each repeat starts from the nominal sample with the same problem and integrator, as a rank
  // integrates one sample after another; the first also pays for touching code and memory for
  // the first time.
  Trajectory tr;
  std::vector<double> repeat_walls;
  for (int r = 0; r < o.repeat; ++r) {
    tr = Trajectory{};
    problem.set_sample(setup.base);
    simulate(problem, integrator, study.output_times, flags, tr);
    repeat_walls.push_back(tr.result.stats.wall_seconds);
  }
  if (o.format == "json") print_json(m, problem, study.output_times, tr, flags.outputs, repeat_walls);
  else print_csv(m, problem, study.output_times, tr, flags.outputs);
  if (!tr.result.ok()) {
    std::cerr << "kanesens: integration failed: " << tr.result.message << "\n";
    return 4;
  }
  return 0;
}
}  // namespace

CLI::App* add_simulate(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("simulate", "Integrate the nominal sample of a study; prints the trajectory (JSON or CSV)");
  auto o = std::make_shared<SimulateOptions>();
  cmd->add_option("study", o->study, "Study YAML file")->required();
  cmd->add_option("--set", o->set, "Override a parameter (m2=0.9), an initial condition (elbow.q0=0.3) or a study setting (solver.rtol=1e-10); repeatable");
  cmd->add_option("--sens", o->sens, "Sensitivity parameters, comma-separated (replaces the study's list; 'none' for none)");
  cmd->add_option("--format", o->format, "json (default) or csv");
  cmd->add_option("--repeat", o->repeat,
                  "Integrate N times in this process and print the last; the JSON's stats list each one's wall time (timing)");
  cmd->callback([&action, o] { action = [o] { return run_simulate(*o); }; });
  return cmd;
}

}  // namespace kanesens::cli
