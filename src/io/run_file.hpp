// The run's HDF5 file: one file per `kanesens run`, written by all ranks.
//
// Everything that is metadata (datasets, dimension scales, attributes) is created, filled and
// flushed by RunFile::create before any sample is written; afterwards only raw data changes,
// one sample row at a time, /status last. So a run killed at any point (kill -9 included)
// leaves a file h5py can open in which every sample with status 1 is intact, and --resume
// (RunFile::open_for_resume + read_status) finishes exactly the samples whose status is 0.
// The schema itself is written down in io/run_schema.hpp.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "io/hdf5_handle.hpp"

namespace kanesens::io {

// Where each sample sits in a Saltelli or Morris design (the /design_* datasets; meaning in
// docs/reference/hdf5.md): fills block, row and input for samples first .. first + n − 1, n the
// spans' common size. Called on rank 0 only, while the file is created, a bounded chunk at a time.
using DesignLabels =
    std::function<void(std::int64_t first, std::span<std::int64_t> block,
                       std::span<std::int64_t> row, std::span<std::int64_t> input)>;

// The distribution of one varied input, for the /vary/<name> group.
struct InputDistribution {
  std::string name;                                        // one of RunLayout::parameter_names
  std::string distribution;                                // "uniform", "normal", ..., "fixed"
  std::vector<std::pair<std::string, double>> parameters;  // {"low", 0.8}, {"high", 1.2}
  std::vector<double> values;                              // choice: its values; else empty
};

// What a run records; sizes in brackets. Zero-sized lists are allowed except `times` and
// `state_names`; a dimension of size 0 and the datasets using it are simply not created.
struct RunLayout {
  std::vector<double> times;                   // output times [T], seconds
  std::vector<std::string> state_names;        // [nstate], e.g. "shoulder.q", "rod1.wx"
  std::vector<std::string> parameter_names;    // varied inputs (parameters, initial conditions) [P]
  std::vector<std::string> sensitivity_names;  // [S]
  std::vector<std::string> constraint_names;   // one per multiplier column [C]
  std::vector<std::string> output_names;       // (sample, time): "energy", ..., the study's series ("tip.x")
  std::vector<std::string> scalar_output_names;  // (sample): the study's scalar outputs ("work")
  // The outputs whose sensitivities are recorded, /output_sensitivities/<name>: series (sample,
  // time, sensitivity) and scalars (sample, sensitivity); each must be in the list above.
  std::vector<std::string> output_sensitivity_names, scalar_output_sensitivity_names;
  std::vector<std::string> body_names;         // [nbody], for /poses
  std::vector<std::string> stat_names;         // e.g. "steps", "rhs_evals", "wall_seconds"
  // The study's events, /events/<name>/time (sample, occurrence), count (sample) and, with
  // output sensitivities, time_sensitivities (sample, occurrence, sensitivity).
  std::vector<std::string> event_names;
  std::size_t event_occurrences = 0;           // [W], the occurrence dimension
  std::int64_t nsamples = 0;
  bool record_states = true, record_sensitivities = false, record_multipliers = false;
  bool record_poses = false;                   // /poses (sample, time, body, pose)
  std::map<std::string, std::string> text_attributes;  // root: kanesens_version, scene_yaml, ...
  std::map<std::string, double> number_attributes;     // root: mpi_ranks, seed, ...
  DesignLabels design_labels;                          // empty: no /design_* datasets
  std::vector<InputDistribution> distributions;        // /vary groups, in parameter order
};

// One sample's results, written once when the sample ends. A span of a dataset the file does
// not hold (not recorded, or a dimension of size 0) must be empty.
struct SampleRow {
  std::int64_t index = 0;
  int status = 0;                         // 1 ok, < 0 failure code (0 = not run, the fill value)
  std::string message;                    // why it failed; cut to RunFile::message_size bytes
  std::span<const double> parameters;     // [P]
  std::span<const double> initial_state;  // [nstate]
  std::span<const double> states;         // [T × nstate], row-major [time][state]
  std::span<const double> multipliers;    // [T × C], [time][constraint]
  std::span<const double> sensitivities;  // [T × nstate × S], [time][state][sensitivity]
  std::span<const double> outputs;        // [noutputs × T], [output][time]
  std::span<const double> stats;          // [nstats]
  std::span<const double> scalar_outputs;  // [nscalar]
  std::span<const double> output_sensitivities;         // [noutput_sens × T × S], [output][time][sens]
  std::span<const double> scalar_output_sensitivities;  // [nscalar_sens × S]
  std::span<const double> poses;          // [T × nbody × 7], [time][body][pose]
  double stopped_at = std::numeric_limits<double>::quiet_NaN();  // an event's stop time, NaN if none
  std::span<const double> event_times;              // [nevent × W], [event][occurrence]
  std::span<const double> event_time_sensitivities;  // [nevent × W × S]
  std::span<const double> event_counts;             // [nevent]
};

// Consecutive samples first .. first+count−1, flat in sample order (each entry as in SampleRow,
// concatenated): written with one H5Dwrite per dataset instead of one per sample and dataset.
struct SampleBlock {
  std::int64_t first = 0, count = 0;
  std::vector<int> status;
  std::vector<std::string> message;
  std::vector<double> parameters, initial_state, states, multipliers, sensitivities, outputs, stats;
  std::vector<double> scalar_outputs, output_sensitivities, scalar_output_sensitivities, poses;
  std::vector<double> stopped_at, event_times, event_time_sensitivities, event_counts;
  void clear() {
    stopped_at.clear();
    event_times.clear();
    event_time_sensitivities.clear();
    event_counts.clear();
    scalar_outputs.clear();
    output_sensitivities.clear();
    scalar_output_sensitivities.clear();
    poses.clear();
    count = 0;
    status.clear();
    message.clear();
    parameters.clear();
    initial_state.clear();
    states.clear();
    multipliers.clear();
    sensitivities.clear();
    outputs.clear();
    stats.clear();
  }
  // Appends one row (its index must be first + count).
  void append(const SampleRow& row);
};

class RunFile {
 public:
  static constexpr std::size_t message_size = 160;  // bytes per /message entry

  // Collective over comm. Creates `path` with every dataset of `layout` preallocated and
  // filled (status 0, NaN), dimension scales and root attributes, flushed to disk. The file is
  // built as `path`.partial and renamed when complete. Throws if `path` exists and !overwrite.
  static RunFile create(MPI_Comm comm, const std::string& path, const RunLayout& layout,
                        bool overwrite);
  // Collective over comm. Opens an existing run file to continue it; throws naming the first
  // difference when it was written for another layout (names, times, nsamples, what is
  // recorded, or the "study_hash" text attribute when both have one).
  static RunFile open_for_resume(MPI_Comm comm, const std::string& path, const RunLayout& layout);

  RunFile(RunFile&& other) noexcept = default;
  RunFile& operator=(RunFile&&) = delete;
  RunFile(const RunFile&) = delete;
  RunFile& operator=(const RunFile&) = delete;
  ~RunFile();  // close(), errors swallowed (collective: every rank must destroy its RunFile)

  // /status of every sample [nsamples]: 0 not run, 1 ok, < 0 failure code. Independent read,
  // any rank may call it alone.
  std::vector<int> read_status() const;
  // Independent I/O from whichever rank ran the sample; no collective call. Writes the data
  // first and /status last. Throws std::invalid_argument on a wrong index or span size.
  void write_sample(const SampleRow& row);
  // The same for a block of consecutive samples; statuses are written last, after all data.
  void write_samples(const SampleBlock& block);
  void flush();  // collective (H5Fflush with the MPI-IO driver)
  void close();  // collective; further calls do nothing
  // Error path of one rank (an exception while the others run on): forgets every handle
  // without the collective close, which could wait forever. Call it, then MPI_Abort. The file
  // on disk is as after kill -9: every row with status 1 is intact and --resume finishes it.
  void abandon() noexcept;

  const std::string& path() const { return path_; }
  std::int64_t nsamples() const { return nsamples_; }

 private:
  RunFile(std::string path, File file, const RunLayout& layout);
  // Writes row `index` of `dataset` (all its other dimensions) from `data`, independent I/O.
  void write_rows(const Dataset& dataset, const std::string& path, hid_t memtype, const void* data,
                  std::int64_t first, std::int64_t count) const;
  void write_row(const Dataset& dataset, const std::string& path, hid_t memtype, const void* data,
                 std::int64_t index) const;

  std::string path_;
  File file_;  // declared first: destroyed after the datasets below
  PropertyList independent_;
  std::int64_t nsamples_ = 0;
  std::size_t ntime_ = 0, nstate_ = 0, nparameter_ = 0, nconstraint_ = 0, nsensitivity_ = 0;
  std::size_t noutput_sensitivity_ = 0, nbody_ = 0;  // the sensitivity dimension of /output_sensitivities
  Dataset parameters_, initial_state_, states_, multipliers_, sensitivities_, poses_;
  Dataset stopped_at_;
  std::vector<Dataset> event_times_, event_time_sensitivities_, event_counts_;
  std::size_t nevent_occurrences_ = 0;
  std::vector<Dataset> outputs_, stats_, scalar_outputs_, output_sensitivities_, scalar_output_sensitivities_;
  Dataset message_, status_;
};

}  // namespace kanesens::io
