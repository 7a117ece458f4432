// `mpirun -np R kanesens run STUDY [-o OUT.h5] [--resume|--overwrite] [--samples N] [--set ...]`:
// the ensemble. Prints an end-of-run summary on rank 0; exit code 0 unless every sample failed.
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "parallel/ensemble.hpp"
#include "parallel/mpi_session.hpp"
#include "parallel/stop_signal.hpp"
#include "util/error.hpp"

namespace kanesens::cli {

namespace {
int run_run(const parallel::RunOptions& o, const std::string& study, bool json) {
  parallel::MpiSession mpi(nullptr, nullptr);
  try {
    const parallel::RunSummary s = parallel::run_ensemble(MPI_COMM_WORLD, study, o);
    if (mpi.rank() == 0) {
      const double busy = s.compute_seconds + s.io_seconds + s.schedule_seconds;
      // Finished samples: after a signal fewer than attempted.
      const double rate = static_cast<double>(s.ok + s.failed) / std::max(s.wall_seconds, 1e-9);
      if (json) {
        std::printf(
            "{\"output\": \"%s\", \"samples\": %lld, \"attempted\": %lld, \"ok\": %lld, \"failed\": %lld, "
            "\"ranks\": %d, \"wall_seconds\": %.6f, \"samples_per_second\": %.6g, \"compute_seconds\": %.6f, "
            "\"io_seconds\": %.6f, \"schedule_seconds\": %.6f}\n",
            s.output.c_str(), s.total, s.attempted, s.ok, s.failed, s.ranks, s.wall_seconds, rate,
            s.compute_seconds, s.io_seconds, s.schedule_seconds);
      } else {
        std::printf("kanesens run: %lld samples (%lld run now) on %d rank%s -> %s\n", s.total, s.attempted, s.ranks,
                    s.ranks == 1 ? "" : "s", s.output.c_str());
        std::printf("  ok %lld, failed %lld; wall %.3f s, %.1f samples/s\n", s.ok, s.failed, s.wall_seconds, rate);
        std::printf("  rank time: integrate %.1f%%, HDF5 writes %.2f%%, scheduling %.2f%%\n",
                    100 * s.compute_seconds / std::max(busy, 1e-12), 100 * s.io_seconds / std::max(busy, 1e-12),
                    100 * s.schedule_seconds / std::max(busy, 1e-12));
        if (s.failed > 0)
          std::printf("  failed samples have status < 0 and a message: kanesens-post summary %s\n", s.output.c_str());
      }
    }
    if (s.stop_signal != 0) {
      // Interrupted (SIGINT/SIGTERM): the file is closed, complete samples are intact and the
      // rest have status 0; say how to finish. 128 + signal, the shell's convention.
      if (mpi.rank() == 0) {
        const long long left = s.attempted - s.ok - s.failed;
        std::fflush(stdout);
        std::fprintf(stderr,
                     "kanesens: interrupted by %s: %lld of %lld samples not run; '%s' is closed and "
                     "resumable: kanesens run %s -o %s --resume\n",
                     parallel::signal_name(s.stop_signal), left, s.total, s.output.c_str(), study.c_str(),
                     s.output.c_str());
      }
      return 128 + s.stop_signal;
    }
    return (s.attempted > 0 && s.ok == 0) ? 5 : 0;
  } catch (const InputError& e) {
    // Every rank read the same input and fails the same way; one line is enough.
    if (mpi.rank() == 0) std::cerr << "kanesens: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "kanesens: error (rank " << mpi.rank() << "): " << e.what() << "\n";
    if (mpi.size() > 1) MPI_Abort(MPI_COMM_WORLD, 1);  // the others may wait in a collective call
    return 1;
  }
}
}  // namespace

CLI::App* add_run(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("run", "Run a study's ensemble (under mpirun for several ranks) into one HDF5 file");
  auto o = std::make_shared<parallel::RunOptions>();
  auto study = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("study", *study, "Study YAML file")->required();
  cmd->add_option("-o,--output", o->output, "Output HDF5 file (default: the study file's name with .h5, in the working directory)");
  cmd->add_flag("--resume", o->resume, "Finish the samples not yet run in an existing output of the same study");
  cmd->add_flag("--overwrite", o->overwrite, "Replace an existing output file");
  cmd->add_option("--samples", o->samples, "Override sampling.samples")->check(integer_in(1, 1LL << 62));
  cmd->add_option("--set", o->set, "Override a parameter, initial condition or study setting: NAME=VALUE");
  cmd->add_flag("--progress", o->progress, "Print progress on rank 0 (default when stderr is a terminal)");
  cmd->add_option("--chunk", o->chunk, "Samples claimed per request (default: guided, shrinking from 64 to 1)")
      ->check(integer_in(1, 1LL << 30));
  cmd->add_flag("--json", *json, "Print the end-of-run summary as JSON");
  cmd->callback([&action, o, study, json] { action = [o, study, json] { return run_run(*o, *study, *json); }; });
  return cmd;
}

}  // namespace kanesens::cli
