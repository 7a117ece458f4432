#include "parallel/ensemble.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "io/run_file.hpp"
#include "model/build_model.hpp"
#include "parallel/mpi_session.hpp"
#include "sim/simulate.hpp"
#include "study/design.hpp"
#include "study/parse_sampling.hpp"
#include "study/parse_vary.hpp"
#include "study/study_spec.hpp"
#include "util/version.hpp"

namespace kanesens::parallel {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Failure codes in /status besides CVODES's own (negative) flags.
constexpr int kStatusInvalidInputs = -100;  // sampled parameters are not physical (mass ≤ 0, ...)
constexpr int kStatusException = -101;      // any other error while running the sample

const std::vector<std::string> kStatNames = {"steps", "rhs_evals", "jac_evals", "nonlin_iters",
                                             "error_test_fails", "sens_rhs_evals", "wall_seconds"};

std::string fnv1a_hex(const std::string& s) {
  unsigned long long h = 1469598103934665603ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", h);
  return buf;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

study::Design make_design(const StudySpec& st) {
  std::vector<study::VariedInput> inputs = study::parse_vary(st.vary, {st.file, 0, 0});
  study::SamplingSpec spec;
  if (st.sampling && !st.sampling.IsNull()) {
    spec = study::parse_sampling(st.sampling, {st.file, 0, 0});
  } else {
    spec.method = study::SamplingMethod::mc;
    spec.samples = 1;  // no sampling section: the nominal sample (plus any vary draws)
  }
  return study::Design(spec, std::move(inputs));
}

}  // namespace

RunSummary run_ensemble(MPI_Comm comm, const std::string& study_path, const RunOptions& opt) {
  const auto t_start = Clock::now();
  int rank = 0, nranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &nranks);

  std::vector<std::string> set = opt.set;
  if (opt.samples > 0) set.push_back("sampling.samples=" + std::to_string(opt.samples));
  const StudySpec st = parse_study_file(study_path, set);
  std::map<std::string, double> parameter_overrides;
  for (const auto& [name, v] : st.set_inputs)
    for (const auto& p : st.scene.parameters)
      if (p.name == name) parameter_overrides[name] = v;
  const Model model = build_model(st.scene, parameter_overrides);
  SampleInputs base(model);
  for (const auto& [name, v] : st.set_inputs)
    if (!parameter_overrides.count(name)) base.set(resolve_input(model, name, "--set " + name), v);

  const study::Design design = make_design(st);
  std::vector<InputRef> varied;
  for (const auto& in : design.inputs()) varied.push_back(resolve_input(model, in.name, "vary." + in.name));
  std::vector<InputRef> sens;
  for (std::size_t i = 0; i < st.sensitivities.size(); ++i)
    sens.push_back(resolve_input(model, st.sensitivities[i], "sensitivities[" + std::to_string(i) + "]"));

  RecordFlags flags;
  flags.states = st.record.count("states") > 0;
  flags.sensitivities = st.record.count("sensitivities") > 0 && !sens.empty();
  flags.energy = st.record.count("energy") > 0;
  flags.multipliers = st.record.count("multipliers") > 0 && model.nconstraint_rows > 0;
  flags.constraint_residual = st.record.count("constraint_residual") > 0 && model.nconstraint_rows > 0;
  if (st.record.count("sensitivities") && sens.empty())
    throw InputError({st.file, 0, 0}, "record", "'sensitivities' is recorded but the study lists no sensitivities");
  if (!flags.sensitivities) sens.clear();  // what is not recorded is not computed

  io::RunLayout layout;
  layout.times = st.output_times;
  layout.state_names = model.state_names;
  for (const auto& in : design.inputs()) layout.parameter_names.push_back(in.name);
  for (const auto& s : sens) layout.sensitivity_names.push_back(s.name);
  if (flags.energy) layout.output_names.push_back("energy");
  if (flags.constraint_residual) {
    layout.output_names.push_back("position_residual");
    layout.output_names.push_back("velocity_residual");
  }
  layout.constraint_names = model.constraint_row_names;
  layout.record_multipliers = flags.multipliers;
  layout.stat_names = kStatNames;
  layout.nsamples = design.size();
  layout.record_states = flags.states;
  layout.record_sensitivities = flags.sensitivities;
  std::string hash_input = st.text + "\n--scene--\n" + st.scene.text;
  for (const auto& s : set) hash_input += "\n--set " + s;
  layout.text_attributes = {{"kanesens_version", version_short()},
                            {"kanesens_build", version_report()},
                            {"scene_yaml", st.scene.text},
                            {"study_yaml", st.text},
                            {"study_file", st.file},
                            {"set_arguments", [&] { std::string s; for (auto& x : set) s += (s.empty() ? "" : " ") + x; return s; }()},
                            {"created_utc", utc_now()},
                            {"sampling_method", std::string(study::method_name(design.spec().method))},
                            {"study_hash", fnv1a_hex(hash_input)}};
  layout.number_attributes = {{"mpi_ranks", nranks}, {"seed", static_cast<double>(design.spec().seed)},
                              {"samples", static_cast<double>(design.size())}};
  if (design.spec().method == study::SamplingMethod::saltelli) {
    layout.number_attributes["saltelli_base_samples"] = static_cast<double>(design.spec().samples);
    layout.text_attributes["saltelli_order"] = "per base point j: A_j, B_j, AB_j^(1..P)";
  }
  if (design.spec().method == study::SamplingMethod::morris) {
    layout.number_attributes["morris_trajectories"] = static_cast<double>(design.spec().trajectories);
    layout.number_attributes["morris_levels"] = static_cast<double>(design.spec().morris_levels);
    layout.number_attributes["morris_delta"] = design.morris_delta();
  }

  std::string output = opt.output;
  if (output.empty()) output = std::filesystem::path(study_path).stem().string() + ".h5";
  if (opt.resume && opt.overwrite) throw InputError({}, "--resume", "--resume and --overwrite exclude each other");
  if (opt.resume && !std::filesystem::exists(output))
    throw InputError({}, "--resume", "no file '" + output + "' to resume; run without --resume to start it");
  io::RunFile file = opt.resume ? io::RunFile::open_for_resume(comm, output, layout)
                                : io::RunFile::create(comm, output, layout, opt.overwrite);
  // Samples to run, by position: all of them (no list: memory per rank does not grow with the
  // number of samples), or with --resume those whose status is still 0.
  std::vector<long long> pending;
  if (opt.resume) {
    const std::vector<int> status = file.read_status();
    for (std::size_t i = 0; i < status.size(); ++i)
      if (status[i] == 0) pending.push_back(static_cast<long long>(i));
  }
  check_mpi(MPI_Barrier(comm), "MPI_Barrier");  // everyone has read /status before anyone writes

  SharedCounter next(comm, 0), done(comm, 0);
  const long long npending = opt.resume ? static_cast<long long>(pending.size()) : design.size();
  KaneProblem problem(model, sens, st.constraints);
  std::vector<double> outputs;
  solve::Integrator integrator(st.solver);
  Trajectory traj;
  resize_trajectory(traj, problem, st.output_times.size(), flags);
  std::vector<double> values(design.dimension()), y0(static_cast<std::size_t>(model.nstate()));
  std::vector<double> stats(kStatNames.size());
  RunSummary sum;
  sum.total = design.size();
  sum.attempted = npending;
  sum.ranks = nranks;
  sum.output = output;
  long long local_ok = 0, local_failed = 0;
  double io_s = 0, sched_s = 0, compute_s = 0;
  const bool progress = rank == 0 && (opt.progress || isatty(STDERR_FILENO));
  // Fault injection for the kill-and-resume test: SIGKILL this process after it wrote N rows.
  const char* kill_env = std::getenv("KANESENS_FAULT_KILL_AFTER_SAMPLES");
  const long long kill_after = kill_env ? std::atoll(kill_env) : -1;
  long long written = 0;
  auto last_progress = Clock::now();

  io::SampleBlock block;
  auto flush_block = [&] {
    const auto tw = Clock::now();
    file.write_samples(block);
    io_s += seconds_since(tw);
    written += block.count;
    block.clear();
    if (kill_after > 0 && written >= kill_after) std::raise(SIGKILL);
  };
  for (;;) {
    auto t0 = Clock::now();
    long long chunk = opt.chunk;
    if (chunk <= 0) {
      // Guided: a quarter of the remaining work per rank, at most 64, at least 1.
      const long long seen = next.read();
      chunk = std::clamp((npending - seen) / (4LL * nranks), 1LL, 64LL);
    }
    const long long first = next.fetch_add(chunk);
    sched_s += seconds_since(t0);
    if (first >= npending) break;
    const long long last = std::min(npending, first + chunk);
    for (long long pos = first; pos < last; ++pos) {
      const long long i = opt.resume ? pending[static_cast<std::size_t>(pos)] : pos;
      t0 = Clock::now();
      SampleInputs in = base;
      design.sample(i, values);
      for (std::size_t d = 0; d < values.size(); ++d) in.set(varied[d], values[d]);
      int status = 1;
      std::string message;
      std::fill(y0.begin(), y0.end(), std::nan(""));
      std::fill(stats.begin(), stats.end(), std::nan(""));
      try {
        problem.set_sample(in);
        problem.initial_state(y0.data());
        simulate(problem, integrator, st.output_times, flags, traj);
        const auto& s = traj.result.stats;
        stats = {static_cast<double>(s.steps), static_cast<double>(s.rhs_evals), static_cast<double>(s.jac_evals),
                 static_cast<double>(s.nonlin_iters), static_cast<double>(s.error_test_fails),
                 static_cast<double>(s.sens_rhs_evals), s.wall_seconds};
        if (!traj.result.ok()) {
          status = traj.result.status;
          message = traj.result.message;
        }
      } catch (const InputError& e) {
        status = kStatusInvalidInputs;
        message = e.detail();
        resize_trajectory(traj, problem, st.output_times.size(), flags);
      } catch (const std::exception& e) {
        status = kStatusException;
        message = e.what();
        resize_trajectory(traj, problem, st.output_times.size(), flags);
      }
      compute_s += seconds_since(t0);
      (status == 1 ? local_ok : local_failed)++;
      io::SampleRow row;
      row.index = i;
      row.status = status;
      row.message = message;
      row.parameters = values;
      row.initial_state = y0;
      row.states = traj.states;
      row.sensitivities = traj.sensitivities;
      outputs.clear();  // [output][time], in layout.output_names order
      outputs.insert(outputs.end(), traj.energy.begin(), traj.energy.end());
      outputs.insert(outputs.end(), traj.position_residual.begin(), traj.position_residual.end());
      outputs.insert(outputs.end(), traj.velocity_residual.begin(), traj.velocity_residual.end());
      row.outputs = outputs;
      row.multipliers = traj.multipliers;
      row.stats = stats;
      // Rows of consecutive samples are written together (one H5Dwrite per dataset per block).
      if (block.count > 0 && i != block.first + block.count) flush_block();
      block.append(row);
    }
    flush_block();  // a chunk's samples reach the file when the chunk ends
    // One message per chunk, not per sample: at scale the counter on rank 0 sees one atomic per
    // claimed chunk plus one here.
    t0 = Clock::now();
    done.fetch_add(last - first);
    sched_s += seconds_since(t0);
    if (progress && seconds_since(last_progress) >= 1.0) {
      last_progress = Clock::now();
      const long long d = done.read();
      const double el = seconds_since(t_start);
      const double rate = d / std::max(el, 1e-9);
      std::fprintf(stderr, "kanesens: %lld/%lld samples, %.1f samples/s, ETA %.0f s\n", d, npending, rate,
                   rate > 0 ? (npending - d) / rate : 0.0);
    }
  }
  long long counts[2] = {local_ok, local_failed}, total_counts[2] = {0, 0};
  double times[3] = {io_s, sched_s, compute_s}, total_times[3] = {0, 0, 0};
  check_mpi(MPI_Allreduce(counts, total_counts, 2, MPI_LONG_LONG, MPI_SUM, comm), "MPI_Allreduce");
  check_mpi(MPI_Allreduce(times, total_times, 3, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  file.close();
  sum.ok = total_counts[0];
  sum.failed = total_counts[1];
  sum.io_seconds = total_times[0];
  sum.schedule_seconds = total_times[1];
  sum.compute_seconds = total_times[2];
  sum.wall_seconds = seconds_since(t_start);
  return sum;
}

}  // namespace kanesens::parallel
