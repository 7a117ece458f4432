// Test driver for io::RunFile under mpirun (tests/mpi/test_run_file_parallel.sh): writes a
// small run file whose every value is a known function of its indices (check_run_file.py
// recomputes them), each rank writing the samples i with i % R == rank.
//
//   run_file_writer OUT.h5 [--kill-after K] [--resume] [--study-hash H]
//     --kill-after K  rank 0 kills itself (SIGKILL) right after writing its K-th sample
//     --resume        open OUT.h5 with open_for_resume and write only samples of status 0
#include <mpi.h>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <cmath>
#include <string>
#include <vector>

#include "io/run_file.hpp"

namespace {

constexpr std::int64_t kSamples = 10;
constexpr int kFailedSample = 7;  // written with status -4 and a message longer than 160 bytes

kanesens::io::RunLayout demo_layout(int ranks, const std::string& study_hash) {
  kanesens::io::RunLayout l;
  l.times = {0.0, 0.25, 0.5, 0.75, 1.0};
  l.state_names = {"shoulder.q", "elbow.q", "shoulder.u", "elbow.u"};
  l.parameter_names = {"m2", "shoulder.q0"};
  l.sensitivity_names = {"m2"};
  l.constraint_names = {"tip.x", "tip.y"};
  l.output_names = {"energy", "constraint_residual"};
  l.stat_names = {"steps", "rhs_evals", "wall_seconds"};
  l.nsamples = kSamples;
  l.record_states = l.record_sensitivities = l.record_multipliers = true;
  l.text_attributes = {{"kanesens_version", "0.1.0"},
                       {"scene_yaml", "scene:\n  name: démo α\n"},
                       {"study_yaml", "sampling: {method: sobol}\n"},
                       {"created_utc", "2024-01-01T00:00:00Z"},
                       {"sampling_method", "sobol"},
                       {"study_hash", study_hash}};
  l.number_attributes = {{"mpi_ranks", ranks}, {"seed", 42}};
  return l;
}

// Writes sample i; the formulas are mirrored in check_run_file.py.
void write_demo_sample(kanesens::io::RunFile& file, const kanesens::io::RunLayout& l,
                       std::int64_t i) {
  const std::size_t T = l.times.size(), n = l.state_names.size(), C = l.constraint_names.size();
  const std::size_t S = l.sensitivity_names.size(), P = l.parameter_names.size();
  const double x = static_cast<double>(i);
  std::vector<double> parameters, initial, states, multipliers, sens, outputs, stats;
  for (std::size_t p = 0; p < P; ++p) parameters.push_back(x + 0.1 * p);
  for (std::size_t j = 0; j < n; ++j) initial.push_back(10 * x + j);
  for (std::size_t t = 0; t < T; ++t) {
    for (std::size_t j = 0; j < n; ++j) states.push_back(1000 * x + 10 * t + j);
    for (std::size_t c = 0; c < C; ++c) multipliers.push_back(-(1000 * x + 10 * t + c));
    for (std::size_t j = 0; j < n; ++j) {
      for (std::size_t s = 0; s < S; ++s) sens.push_back(1000 * x + 100 * t + 10 * j + s);
    }
  }
  for (std::size_t k = 0; k < l.output_names.size(); ++k) {
    for (std::size_t t = 0; t < T; ++t) outputs.push_back(x + 0.01 * t + 100 * k);
  }
  for (std::size_t k = 0; k < l.stat_names.size(); ++k) stats.push_back(10 * x + k);
  const bool failed = i == kFailedSample;
  file.write_sample({.index = i,
                     .status = failed ? -4 : 1,
                     .message = failed ? "CVODE failed at t = 0.5: " + std::string(200, 'x') : "",
                     .parameters = parameters,
                     .initial_state = initial,
                     .states = states,
                     .multipliers = multipliers,
                     .sensitivities = sens,
                     .outputs = outputs,
                     .stats = stats,
                     .scalar_outputs = {},
                     .output_sensitivities = {},
                     .scalar_output_sensitivities = {},
                     .poses = {},
                     .stopped_at = std::nan(""),
                     .event_times = {},
                     .event_time_sensitivities = {},
                     .event_counts = {}});
}

int run(int argc, char** argv) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::string path, study_hash = "hash-1";
  int kill_after = -1;
  bool resume = false;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--kill-after" && a + 1 < argc) {
      kill_after = std::atoi(argv[++a]);
    } else if (arg == "--study-hash" && a + 1 < argc) {
      study_hash = argv[++a];
    } else if (arg == "--resume") {
      resume = true;
    } else {
      path = arg;
    }
  }
  const auto layout = demo_layout(ranks, study_hash);
  auto file = resume ? kanesens::io::RunFile::open_for_resume(MPI_COMM_WORLD, path, layout)
                     : kanesens::io::RunFile::create(MPI_COMM_WORLD, path, layout, false);
  const std::vector<int> status = file.read_status();
  int written = 0;
  for (std::int64_t i = rank; i < kSamples; i += ranks) {
    if (status[static_cast<std::size_t>(i)] != 0) continue;
    write_demo_sample(file, layout, i);
    if (rank == 0 && ++written == kill_after) std::raise(SIGKILL);
  }
  file.close();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rc = 0;
  try {
    rc = run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "run_file_writer: " << e.what() << "\n";
    rc = 1;
  }
  MPI_Finalize();
  return rc;
}
