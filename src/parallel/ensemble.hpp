// The ensemble service behind `mpirun -np R kanesens run STUDY`: every rank builds the model
// and the sampling design, claims chunks of samples from a shared counter (dynamic scheduling:
// stiff or failing samples do not stall the others), integrates them, and writes each sample's
// row into the one HDF5 file as soon as it ends. Sample i's inputs depend only on (seed, i), so
// the datasets are bitwise identical whatever R.
#pragma once
#include <mpi.h>

#include <string>
#include <vector>

namespace kanesens::parallel {

struct RunOptions {
  std::string output;              // HDF5 path; "" = <study file stem>.h5 in the working directory
  bool resume = false;             // finish the samples whose status is 0 in an existing file
  bool overwrite = false;          // replace an existing file
  long long samples = 0;           // > 0: overrides sampling.samples
  std::vector<std::string> set;    // --set NAME=VALUE
  bool progress = false;           // progress lines on rank 0 (also when stderr is a terminal)
  long long chunk = 0;             // samples per claim; 0 = guided (shrinks as work runs out)
};

struct RunSummary {
  long long total = 0;        // samples in the design
  long long attempted = 0;    // samples run now (all, or the status-0 ones with --resume)
  long long ok = 0, failed = 0;
  double wall_seconds = 0;
  double io_seconds = 0;        // summed over ranks: HDF5 row writes
  double schedule_seconds = 0;  // summed over ranks: claiming work from the counter
  double compute_seconds = 0;   // summed over ranks: integrating samples
  int ranks = 1;
  std::string output;
  // Non-zero: the run stopped early on this signal (SIGINT, SIGTERM) with ok + failed <
  // attempted; the file is closed and complete samples are intact: finish it with --resume.
  int stop_signal = 0;
};

// Collective over comm. Throws InputError for bad input (on every rank alike: bad YAML, an
// output that exists, cannot be written or would not fit on its file system, a --resume file of
// another study) and std::runtime_error for I/O failures. Installs SIGINT/SIGTERM handlers
// (stop_signal.hpp): on a signal the ranks stop claiming samples, finish the ones in flight and
// close the file; the summary's stop_signal says so.
RunSummary run_ensemble(MPI_Comm comm, const std::string& study_path, const RunOptions& options);

// Validates what run_ensemble validates before it touches the output (study, scene, model,
// design, input names, --set), without MPI: throws the same InputError.
void validate_study(const std::string& study_path, const RunOptions& options);

}  // namespace kanesens::parallel
