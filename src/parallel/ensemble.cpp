#include "parallel/ensemble.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <span>

#include "io/run_file.hpp"
#include "parallel/mpi_session.hpp"
#include "parallel/preflight.hpp"
#include "parallel/resources.hpp"
#include "parallel/stop_signal.hpp"
#include "sim/simulate.hpp"
#include "study/setup.hpp"
#include "parallel/version.hpp"
#include "util/did_you_mean.hpp"
#include "util/version.hpp"

namespace kanesens::parallel {

using namespace kanesens::model;
using namespace kanesens::sim;
using study::StudySpec;
using detail::check_memory;
using detail::check_output;
using detail::estimate_file_bytes;
using detail::kBlockBytes;
using detail::rethrow_io_error;
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Failure codes in /status besides CVODES's own (negative) flags.
constexpr int kStatusInvalidInputs = -100;  // sampled parameters are not physical (mass ≤ 0, ...)
constexpr int kStatusException = -101;      // any other error while running the sample

const std::vector<std::string> kStatNames = {"steps",          "rhs_evals",      "jac_evals",    "jtimes_evals",
                                             "nonlin_iters",   "error_test_fails", "sens_rhs_evals", "repartitions",
                                             "wall_seconds"};

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

// Rank 0's string on every rank.
std::string broadcast_string(MPI_Comm comm, std::string s) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  unsigned long long n = s.size();
  check_mpi(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm), "MPI_Bcast");
  s.resize(static_cast<std::size_t>(n));
  if (n > 0) check_mpi(MPI_Bcast(s.data(), static_cast<int>(n), MPI_CHAR, 0, comm), "MPI_Bcast");
  return s;
}

// Everything a run needs before it touches the output file: the study, the compiled model, the
// design, the resolved input names and the file layout. Construction validates all of it and
// throws InputError (file:line:column, key path) for bad input.
std::vector<std::string> set_arguments(const RunOptions& opt) {
  std::vector<std::string> set = opt.set;
  if (opt.samples > 0) set.push_back("sampling.samples=" + std::to_string(opt.samples));
  return set;
}

// The design's run labels and input distributions as the run file stores them.
io::DesignLabels run_labels(const study::Design& design) {
  return [design](std::int64_t first, std::span<std::int64_t> block, std::span<std::int64_t> row,
                  std::span<std::int64_t> input) {
    for (std::size_t k = 0; k < block.size(); ++k) {
      const study::RunLabel label = design.run_label(first + static_cast<std::int64_t>(k));
      block[k] = label.block;
      row[k] = label.row;
      input[k] = label.input;
    }
  };
}

io::InputDistribution input_distribution(const study::VariedInput& in) {
  io::InputDistribution d{in.name, std::string(in.dist.kind_name()), {}, {}};
  for (const auto& [key, value] : in.dist.named_parameters()) d.parameters.emplace_back(key, value);
  if (const auto* choice = std::get_if<study::Choice>(&in.dist.params)) d.values = choice->values;
  return d;
}

// Everything a run needs before it touches the output file: the study setup (which validates
// the study and throws InputError for bad input) and the file layout.
struct Prepared {
  Prepared(const std::string& study_path, const RunOptions& opt, int nranks)
      : setup(study::setup_study(study_path, set_arguments(opt))), sens(setup.recorded_sensitivities()) {
    const StudySpec& st = setup.spec;
    const Model& model = setup.model;
    const study::Design& design = setup.design;
    const RecordFlags& flags = setup.record;
    const std::vector<std::string>& set = setup.set;
    layout.times = st.output_times;
    layout.state_names = model.state_names;
    for (const auto& in : design.inputs()) layout.parameter_names.push_back(in.name);
    for (const auto& s : sens) layout.sensitivity_names.push_back(s.name);
    if (flags.energy) layout.output_names.push_back("energy");
    if (flags.constraint_residual) {
      layout.output_names.push_back("position_residual");
      layout.output_names.push_back("velocity_residual");
    }
    if (const sim::OutputPlan* plan = flags.outputs) {
      layout.output_names.insert(layout.output_names.end(), plan->series_names.begin(), plan->series_names.end());
      layout.scalar_output_names = plan->scalar_names;
      if (!sens.empty()) {
        layout.output_sensitivity_names = plan->series_names;
        layout.scalar_output_sensitivity_names = plan->scalar_names;
      }
      for (int v : plan->event_nodes) layout.event_names.push_back(plan->nodes[static_cast<std::size_t>(v)].name);
      layout.event_occurrences = static_cast<std::size_t>(plan->event_occurrences);
    }
    for (const auto& b : model.bodies) layout.body_names.push_back(b.name);
    layout.record_poses = flags.poses;
    layout.constraint_names = model.constraint_row_names;
    layout.stat_names = kStatNames;
    layout.nsamples = design.size();
    layout.record_states = flags.states;
    layout.record_sensitivities = flags.sensitivities;
    layout.record_multipliers = flags.multipliers;
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
    if (design.has_run_labels()) layout.design_labels = run_labels(design);
    for (const auto& in : design.inputs()) layout.distributions.push_back(input_distribution(in));
  }

  study::StudySetup setup;
  std::vector<InputRef> sens;  // computed: those recorded
  io::RunLayout layout;
};

}  // namespace

void validate_study(const std::string& study_path, const RunOptions& options) {
  const Prepared prepared(study_path, options, 1);
  if (const std::string problem = check_memory(prepared.layout, prepared.setup.spec, 1); !problem.empty())
    throw InputError({}, "", problem);
}

RunSummary run_ensemble(MPI_Comm comm, const std::string& study_path, const RunOptions& opt) {
  const auto t_start = Clock::now();
  int rank = 0, nranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &nranks);

  const Prepared prepared(study_path, opt, nranks);
  const study::StudySetup& setup = prepared.setup;
  const StudySpec& st = setup.spec;
  const Model& model = setup.model;
  const study::Design& design = setup.design;
  const std::vector<InputRef>& sens = prepared.sens;
  const RecordFlags& flags = setup.record;
  const io::RunLayout& layout = prepared.layout;

  std::string output = opt.output;
  if (output.empty()) output = std::filesystem::path(study_path).stem().string() + ".h5";
  // Every rank takes rank 0's verdict, so all throw the same InputError (one line, exit 2).
  // Ranks sharing rank 0's node share its memory.
  int ranks_here = 1;
  {
    MPI_Comm node = MPI_COMM_NULL;
    check_mpi(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
    MPI_Comm_size(node, &ranks_here);
    MPI_Comm_free(&node);
  }
  if (const std::string problem = broadcast_string(comm, rank == 0 ? check_output(output, opt, layout, st, ranks_here) : "");
      !problem.empty())
    throw InputError({}, "", problem);
  install_stop_handlers();
  io::RunFile file = [&] {
    if (!opt.resume) {
      try {
        return io::RunFile::create(comm, output, layout, opt.overwrite);
      } catch (const std::runtime_error& e) {
        rethrow_io_error(e, output, study_path, estimate_file_bytes(layout));
      }
    }
    try {  // a file that is not ours, or of another study: every rank fails alike
      return io::RunFile::open_for_resume(comm, output, layout);
    } catch (const std::runtime_error& e) {
      throw InputError({}, "--resume", e.what());
    }
  }();
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
  KaneProblem problem(model, sens, st.constraints, st.output_times.front());
  std::vector<double> outputs;
  sim::Integrator integrator(st.solver);
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
  // Rows of consecutive samples are written together: one H5Dwrite per dataset per block.
  io::SampleBlock block;
  auto flush_block = [&] {
    const auto tw = Clock::now();
    try {
      file.write_samples(block);
    } catch (const std::runtime_error& e) {
      rethrow_io_error(e, output, study_path, 0);
    }
    io_s += seconds_since(tw);
    written += block.count;
    block.clear();
    if (kill_after > 0 && written >= kill_after) std::raise(SIGKILL);
  };

  int stopped_by = 0;
  try {
    for (;;) {
      if ((stopped_by = stop_signal()) != 0) {
        // Push the shared counter past the end: the other ranks stop at their next claim even
        // if the signal reached only this process.
        next.fetch_add(npending);
        break;
      }
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
      for (long long pos = first; pos < last && stop_signal() == 0; ++pos) {  // unstarted ones stay status 0
        const long long i = opt.resume ? pending[static_cast<std::size_t>(pos)] : pos;
        t0 = Clock::now();
        int status = 1;
        std::string message;
        double stopped_at = std::nan("");
        std::fill(values.begin(), values.end(), std::nan(""));
        std::fill(y0.begin(), y0.end(), std::nan(""));
        std::fill(stats.begin(), stats.end(), std::nan(""));
        try {
          // Inside the try: a quantile can overflow (Boost.Math throws std::overflow_error for
          // a lognormal far in its tail), which is this sample's failure, not the run's.
          problem.set_sample(setup.sample(i, values));
          problem.initial_state(y0.data());
          simulate(problem, integrator, st.output_times, flags, traj);
          const auto& s = traj.result.stats;
          stats = {static_cast<double>(s.steps), static_cast<double>(s.rhs_evals), static_cast<double>(s.jac_evals),
                   static_cast<double>(s.jtimes_evals), static_cast<double>(s.nonlin_iters), static_cast<double>(s.error_test_fails),
                   static_cast<double>(s.sens_rhs_evals), static_cast<double>(s.repartitions), s.wall_seconds};
          // An ok sample's message says what it should: stopped by an event, an at_event output NaN.
          message = traj.result.message;
          stopped_at = traj.result.stopped_at;
          if (!traj.result.ok()) status = traj.result.status;
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
        outputs.insert(outputs.end(), traj.outputs.begin(), traj.outputs.end());
        row.outputs = outputs;
        row.scalar_outputs = traj.scalar_outputs;
        row.output_sensitivities = traj.output_sensitivities;
        row.scalar_output_sensitivities = traj.scalar_output_sensitivities;
        row.poses = traj.poses;
        row.multipliers = traj.multipliers;
        row.stats = stats;
        row.stopped_at = stopped_at;
        row.event_times = traj.event_times;
        row.event_time_sensitivities = traj.event_time_sensitivities;
        row.event_counts = traj.event_counts;
        if (block.count > 0 && i != block.first + block.count) flush_block();
        block.append(row);
        if (8.0 * static_cast<double>(block.states.size() + block.sensitivities.size() + block.multipliers.size() +
                                      block.outputs.size()) >= kBlockBytes)
          flush_block();  // bounded memory (check_memory counts on it)
      }
      flush_block();  // a chunk's samples reach the file when the chunk ends (or stops)
      // One message per chunk, not per sample: at scale the counter on rank 0 sees one atomic
      // per claimed chunk plus one here.
      auto t1 = Clock::now();
      done.fetch_add(last - first);
      sched_s += seconds_since(t1);
      if (progress && seconds_since(last_progress) >= 1.0) {
        last_progress = Clock::now();
        const long long d = done.read();
        const double el = seconds_since(t_start);
        const double rate = d / std::max(el, 1e-9);
        std::fprintf(stderr, "kanesens: %lld/%lld samples, %.1f samples/s, ETA %.0f s\n", d, npending, rate,
                     rate > 0 ? (npending - d) / rate : 0.0);
      }
    }
  } catch (...) {
    // This rank cannot go on (e.g. a failed write) while the others may be mid-sample: no
    // collective call from here on; the caller prints the error and aborts the job.
    file.abandon();
    throw;
  }
  if (stopped_by == 0) stopped_by = stop_signal();
  long long counts[3] = {local_ok, local_failed, stopped_by}, total_counts[3] = {0, 0, 0};
  double times[3] = {io_s, sched_s, compute_s}, total_times[3] = {0, 0, 0};
  check_mpi(MPI_Allreduce(counts, total_counts, 2, MPI_LONG_LONG, MPI_SUM, comm), "MPI_Allreduce");
  check_mpi(MPI_Allreduce(&counts[2], &total_counts[2], 1, MPI_LONG_LONG, MPI_MAX, comm), "MPI_Allreduce");
  check_mpi(MPI_Allreduce(times, total_times, 3, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  file.close();
  sum.ok = total_counts[0];
  sum.failed = total_counts[1];
  sum.stop_signal = static_cast<int>(total_counts[2]);
  sum.io_seconds = total_times[0];
  sum.schedule_seconds = total_times[1];
  sum.compute_seconds = total_times[2];
  sum.wall_seconds = seconds_since(t_start);
  return sum;
}

}  // namespace kanesens::parallel
