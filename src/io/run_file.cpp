#include "io/run_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "io/hdf5_text.hpp"
#include "io/run_schema.hpp"

namespace kanesens::io {
namespace {

// File access through MPI-IO. Format bounds 1.8: superblock version 2, which has no "file is
// open for writing" flag (the 1.10 format's v3 superblock does, and a file left by a killed
// run would then refuse to open until `h5clear -s`); 1.8 object headers also store root
// attributes over 64 KiB (long scene_yaml texts) in dense storage instead of failing.
PropertyList mpio_access(MPI_Comm comm, const std::string& path) {
  PropertyList fapl(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate(file access, " + path + ")");
  check(H5Pset_fapl_mpio(fapl.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio(" + path + ")");
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V18),
        "H5Pset_libver_bounds(" + path + ")");
  return fapl;
}

// Evaluates `f` on rank 0 only (file system queries) and gives every rank its result, so that
// all ranks take the same branch (and throw the same error) in collective code.
template <class F>
int on_root(MPI_Comm comm, F f) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int value = rank == 0 ? f() : 0;
  MPI_Bcast(&value, 1, MPI_INT, 0, comm);
  return value;
}

// Rank 0's text on every rank.
std::string broadcast_text(MPI_Comm comm, std::string text) {
  unsigned long long n = text.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  text.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(text.data(), static_cast<int>(n), MPI_CHAR, 0, comm);
  return text;
}

// Whether `path` names anything, a dangling symbolic link included (never followed).
bool file_exists(const std::string& path) {
  struct stat info {};
  return ::lstat(path.c_str(), &info) == 0;
}

// Renames `from` to `to`; unless `replace`, fails (EEXIST) when `to` exists, atomically where
// the file system supports it. Returns 0 or an errno value.
int rename_file(const std::string& from, const std::string& to, bool replace) {
  if (replace) return std::rename(from.c_str(), to.c_str()) == 0 ? 0 : errno;
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return 0;
  if (errno != EINVAL && errno != ENOSYS) return errno;
  // No RENAME_NOREPLACE on this file system: link() refuses an existing name as well.
  if (::link(from.c_str(), to.c_str()) != 0) return errno;
  ::unlink(from.c_str());
  return 0;
}

void expect_size(bool recorded, std::size_t given, std::size_t wanted, const char* what,
                 std::int64_t index) {
  if (recorded ? given == wanted : given == 0) return;
  throw std::invalid_argument("sample " + std::to_string(index) + ": " + what + " has " +
                              std::to_string(given) + " values, the run file expects " +
                              std::to_string(recorded ? wanted : 0) +
                              (recorded ? "" : " (not recorded)"));
}

}  // namespace

RunFile RunFile::create(MPI_Comm comm, const std::string& path, const RunLayout& layout,
                        bool overwrite) {
  silence_hdf5_errors();
  validate_layout(layout);
  if (!overwrite && on_root(comm, [&] { return file_exists(path) ? 1 : 0; })) {
    throw std::runtime_error("output file '" + path +
                             "' already exists; pass --overwrite to replace it or --resume to "
                             "continue it");
  }
  // Built under a temporary name and renamed once its metadata is on disk, so `path` never
  // names a half-made file, even if the run is killed during creation. The temporary file is
  // created exclusively (O_EXCL): an existing file, directory or symbolic link of that name is
  // never opened, truncated or followed. With --overwrite a stale one left by a killed
  // creation is unlinked first (a link is removed, its target is untouched); a directory stays.
  const std::string partial = path + ".partial";
  if (overwrite) {
    const int removed = on_root(comm, [&] {
      struct stat info {};
      if (::lstat(partial.c_str(), &info) != 0 || S_ISDIR(info.st_mode)) return 0;
      return ::unlink(partial.c_str()) == 0 ? 0 : errno;
    });
    if (removed != 0)
      throw std::runtime_error("cannot remove the stale '" + partial + "': " + std::strerror(removed));
  }
  const PropertyList fapl = mpio_access(comm, partial);
  File file(H5Fcreate(partial.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl.get()),
            "H5Fcreate(" + partial + ")");
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  try {
    write_schema(file.get(), layout, rank, message_size);
    check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "H5Fflush(" + partial + ")");
  } catch (...) {
    // E.g. the disk filled up while the datasets were allocated. The ranks need not fail
    // alike (one rank's write hits ENOSPC while the others wait in the next collective), so
    // no collective close here: abandon the handle (the caller aborts the job) and remove the
    // half-made file from whichever rank sees the failure.
    file.abandon();
    std::error_code ec;
    std::filesystem::remove(partial, ec);
    throw;
  }
  // Without --overwrite an output that appeared meanwhile is not replaced.
  if (const int error = on_root(comm, [&] { return rename_file(partial, path, overwrite); })) {
    throw std::runtime_error("cannot rename '" + partial + "' to '" + path + "': " + std::strerror(error));
  }
  return RunFile(path, std::move(file), layout);
}

RunFile RunFile::open_for_resume(MPI_Comm comm, const std::string& path, const RunLayout& layout) {
  silence_hdf5_errors();
  validate_layout(layout);
  if (!on_root(comm, [&] { return file_exists(path) ? 1 : 0; })) {
    throw std::runtime_error("cannot resume '" + path +
                             "': the file does not exist (run without --resume to create it)");
  }
  // The file is input like the study: rank 0 checks it read-only, every dataset's type, shape,
  // storage and the identifying attributes, before any rank opens it for writing.
  std::string problem;
  on_root(comm, [&] {
    try {
      File check_file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen(" + path + ")");
      verify_schema(check_file.get(), path, layout, message_size);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    return 0;
  });
  problem = broadcast_text(comm, problem);
  if (!problem.empty()) throw std::runtime_error(problem);
  const PropertyList fapl = mpio_access(comm, path);
  File file(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), "H5Fopen(" + path + ")");
  return RunFile(path, std::move(file), layout);
}

RunFile::RunFile(std::string path, File file, const RunLayout& l)
    : path_(std::move(path)),
      file_(std::move(file)),
      independent_(H5Pcreate(H5P_DATASET_XFER), "H5Pcreate(dataset transfer)"),
      nsamples_(l.nsamples),
      ntime_(l.times.size()),
      nstate_(l.state_names.size()),
      nparameter_(has_parameters(l) ? l.parameter_names.size() : 0),
      nconstraint_(has_multipliers(l) ? l.constraint_names.size() : 0),
      nsensitivity_(has_sensitivities(l) ? l.sensitivity_names.size() : 0),
      noutput_sensitivity_(has_output_sensitivities(l) ? l.sensitivity_names.size() : 0),
      nbody_(has_poses(l) ? l.body_names.size() : 0) {
  nevent_occurrences_ = l.event_occurrences;
  check(H5Pset_dxpl_mpio(independent_.get(), H5FD_MPIO_INDEPENDENT), "H5Pset_dxpl_mpio");
  auto open = [&](const std::string& p) {  // collective, like every H5Dopen under MPI-IO
    return Dataset(H5Dopen2(file_.get(), p.c_str(), H5P_DEFAULT), "H5Dopen2(" + p + ")");
  };
  if (has_parameters(l)) parameters_ = open("/parameters");
  initial_state_ = open("/initial_state");
  if (has_states(l)) states_ = open("/states");
  if (has_multipliers(l)) multipliers_ = open("/multipliers");
  if (has_sensitivities(l)) sensitivities_ = open("/sensitivities");
  for (const auto& name : l.output_names) outputs_.push_back(open(output_path(name)));
  for (const auto& name : l.scalar_output_names) scalar_outputs_.push_back(open(output_path(name)));
  if (has_output_sensitivities(l)) {
    for (const auto& name : l.output_sensitivity_names) output_sensitivities_.push_back(open(output_sensitivity_path(name)));
    for (const auto& name : l.scalar_output_sensitivity_names)
      scalar_output_sensitivities_.push_back(open(output_sensitivity_path(name)));
  }
  if (has_poses(l)) poses_ = open(kPosesPath);
  for (const auto& name : l.stat_names) stats_.push_back(open(stat_path(name)));
  stopped_at_ = open(kStoppedAtPath);
  for (const auto& name : l.event_names) {
    event_times_.push_back(open(event_path(name, "time")));
    event_counts_.push_back(open(event_path(name, "count")));
    if (has_output_sensitivities(l)) event_time_sensitivities_.push_back(open(event_path(name, "time_sensitivities")));
  }
  message_ = open(kMessagePath);
  status_ = open(kStatusPath);
}

RunFile::~RunFile() {
  try {
    close();
  } catch (...) {  // a destructor never throws; close() explicitly to see the error
  }
}

std::vector<int> RunFile::read_status() const {
  if (!file_) throw std::logic_error("read_status on a closed run file");
  std::vector<int> status(static_cast<std::size_t>(nsamples_));
  check(H5Dread(status_.get(), H5T_NATIVE_INT, H5S_ALL, H5S_ALL, independent_.get(), status.data()),
        "H5Dread(" + path_ + ":/status)");
  return status;
}

void RunFile::write_sample(const SampleRow& row) {
  if (!file_) throw std::logic_error("write_sample on a closed run file");
  const std::int64_t i = row.index;
  if (i < 0 || i >= nsamples_) {
    throw std::invalid_argument("sample index " + std::to_string(i) + " outside 0.." +
                                std::to_string(nsamples_ - 1) + " of " + path_);
  }
  // Check every size before writing anything: a bad row leaves the file untouched.
  expect_size(bool(parameters_), row.parameters.size(), nparameter_, "parameters", i);
  expect_size(true, row.initial_state.size(), nstate_, "initial_state", i);
  expect_size(bool(states_), row.states.size(), ntime_ * nstate_, "states", i);
  expect_size(bool(multipliers_), row.multipliers.size(), ntime_ * nconstraint_, "multipliers", i);
  expect_size(bool(sensitivities_), row.sensitivities.size(), ntime_ * nstate_ * nsensitivity_,
              "sensitivities", i);
  expect_size(true, row.outputs.size(), outputs_.size() * ntime_, "outputs", i);
  expect_size(true, row.scalar_outputs.size(), scalar_outputs_.size(), "scalar outputs", i);
  expect_size(true, row.output_sensitivities.size(), output_sensitivities_.size() * ntime_ * noutput_sensitivity_,
              "output sensitivities", i);
  expect_size(true, row.scalar_output_sensitivities.size(), scalar_output_sensitivities_.size() * noutput_sensitivity_,
              "scalar output sensitivities", i);
  expect_size(bool(poses_), row.poses.size(), ntime_ * nbody_ * 7, "poses", i);
  expect_size(true, row.stats.size(), stats_.size(), "stats", i);
  const std::size_t W = nevent_occurrences_;
  expect_size(true, row.event_times.size(), event_times_.size() * W, "event times", i);
  expect_size(true, row.event_counts.size(), event_counts_.size(), "event counts", i);
  expect_size(true, row.event_time_sensitivities.size(), event_time_sensitivities_.size() * W * noutput_sensitivity_,
              "event time sensitivities", i);

  const hid_t f64 = H5T_NATIVE_DOUBLE;
  if (parameters_) write_row(parameters_, "/parameters", f64, row.parameters.data(), i);
  write_row(initial_state_, "/initial_state", f64, row.initial_state.data(), i);
  if (states_) write_row(states_, "/states", f64, row.states.data(), i);
  if (multipliers_) write_row(multipliers_, "/multipliers", f64, row.multipliers.data(), i);
  if (sensitivities_) {
    write_row(sensitivities_, "/sensitivities", f64, row.sensitivities.data(), i);
  }
  for (std::size_t k = 0; k < outputs_.size(); ++k) {
    write_row(outputs_[k], "/outputs", f64, row.outputs.data() + k * ntime_, i);
  }
  for (std::size_t k = 0; k < scalar_outputs_.size(); ++k)
    write_row(scalar_outputs_[k], "/outputs", f64, row.scalar_outputs.data() + k, i);
  for (std::size_t k = 0; k < output_sensitivities_.size(); ++k)
    write_row(output_sensitivities_[k], "/output_sensitivities", f64,
              row.output_sensitivities.data() + k * ntime_ * noutput_sensitivity_, i);
  for (std::size_t k = 0; k < scalar_output_sensitivities_.size(); ++k)
    write_row(scalar_output_sensitivities_[k], "/output_sensitivities", f64,
              row.scalar_output_sensitivities.data() + k * noutput_sensitivity_, i);
  if (poses_) write_row(poses_, kPosesPath, f64, row.poses.data(), i);
  for (std::size_t k = 0; k < stats_.size(); ++k) {
    write_row(stats_[k], "/solver_stats", f64, row.stats.data() + k, i);
  }
  write_row(stopped_at_, kStoppedAtPath, f64, &row.stopped_at, i);
  for (std::size_t k = 0; k < event_times_.size(); ++k) {
    write_row(event_times_[k], "/events", f64, row.event_times.data() + k * W, i);
    write_row(event_counts_[k], "/events", f64, row.event_counts.data() + k, i);
  }
  for (std::size_t k = 0; k < event_time_sensitivities_.size(); ++k)
    write_row(event_time_sensitivities_[k], "/events", f64,
              row.event_time_sensitivities.data() + k * W * noutput_sensitivity_, i);
  std::vector<char> message(message_size, '\0');
  const std::string fitted = fit_utf8(row.message, message_size);
  std::memcpy(message.data(), fitted.data(), fitted.size());
  write_row(message_, kMessagePath, make_string_type(message_size).get(), message.data(), i);
  // Last: a status of 1 on disk means every value above is on disk too.
  const int status = row.status;
  write_row(status_, kStatusPath, H5T_NATIVE_INT, &status, i);
}

void SampleBlock::append(const SampleRow& row) {
  if (count == 0) first = row.index;
  if (row.index != first + count) throw std::invalid_argument("SampleBlock: samples must be consecutive");
  ++count;
  status.push_back(row.status);
  message.push_back(row.message);
  parameters.insert(parameters.end(), row.parameters.begin(), row.parameters.end());
  initial_state.insert(initial_state.end(), row.initial_state.begin(), row.initial_state.end());
  states.insert(states.end(), row.states.begin(), row.states.end());
  multipliers.insert(multipliers.end(), row.multipliers.begin(), row.multipliers.end());
  sensitivities.insert(sensitivities.end(), row.sensitivities.begin(), row.sensitivities.end());
  outputs.insert(outputs.end(), row.outputs.begin(), row.outputs.end());
  scalar_outputs.insert(scalar_outputs.end(), row.scalar_outputs.begin(), row.scalar_outputs.end());
  output_sensitivities.insert(output_sensitivities.end(), row.output_sensitivities.begin(), row.output_sensitivities.end());
  scalar_output_sensitivities.insert(scalar_output_sensitivities.end(), row.scalar_output_sensitivities.begin(),
                                     row.scalar_output_sensitivities.end());
  poses.insert(poses.end(), row.poses.begin(), row.poses.end());
  stats.insert(stats.end(), row.stats.begin(), row.stats.end());
  stopped_at.push_back(row.stopped_at);
  event_times.insert(event_times.end(), row.event_times.begin(), row.event_times.end());
  event_time_sensitivities.insert(event_time_sensitivities.end(), row.event_time_sensitivities.begin(),
                                  row.event_time_sensitivities.end());
  event_counts.insert(event_counts.end(), row.event_counts.begin(), row.event_counts.end());
}

void RunFile::write_samples(const SampleBlock& b) {
  if (!file_) throw std::logic_error("write_samples on a closed run file");
  if (b.count == 0) return;
  const std::int64_t first = b.first, n = b.count;
  if (first < 0 || first + n > nsamples_)
    throw std::invalid_argument("samples " + std::to_string(first) + ".." + std::to_string(first + n - 1) +
                                " outside 0.." + std::to_string(nsamples_ - 1) + " of " + path_);
  const auto un = static_cast<std::size_t>(n);
  expect_size(bool(parameters_), b.parameters.size(), un * nparameter_, "parameters", first);
  expect_size(true, b.initial_state.size(), un * nstate_, "initial_state", first);
  expect_size(bool(states_), b.states.size(), un * ntime_ * nstate_, "states", first);
  expect_size(bool(multipliers_), b.multipliers.size(), un * ntime_ * nconstraint_, "multipliers", first);
  expect_size(bool(sensitivities_), b.sensitivities.size(), un * ntime_ * nstate_ * nsensitivity_, "sensitivities", first);
  expect_size(true, b.outputs.size(), un * outputs_.size() * ntime_, "outputs", first);
  expect_size(true, b.scalar_outputs.size(), un * scalar_outputs_.size(), "scalar outputs", first);
  expect_size(true, b.output_sensitivities.size(), un * output_sensitivities_.size() * ntime_ * noutput_sensitivity_,
              "output sensitivities", first);
  expect_size(true, b.scalar_output_sensitivities.size(),
              un * scalar_output_sensitivities_.size() * noutput_sensitivity_, "scalar output sensitivities", first);
  expect_size(bool(poses_), b.poses.size(), un * ntime_ * nbody_ * 7, "poses", first);
  expect_size(true, b.stats.size(), un * stats_.size(), "stats", first);
  expect_size(true, b.stopped_at.size(), un, "stopped_at", first);
  const std::size_t W = nevent_occurrences_;
  expect_size(true, b.event_times.size(), un * event_times_.size() * W, "event times", first);
  expect_size(true, b.event_counts.size(), un * event_counts_.size(), "event counts", first);
  expect_size(true, b.event_time_sensitivities.size(), un * event_time_sensitivities_.size() * W * noutput_sensitivity_,
              "event time sensitivities", first);
  const hid_t f64 = H5T_NATIVE_DOUBLE;
  if (parameters_) write_rows(parameters_, "/parameters", f64, b.parameters.data(), first, n);
  write_rows(initial_state_, "/initial_state", f64, b.initial_state.data(), first, n);
  if (states_) write_rows(states_, "/states", f64, b.states.data(), first, n);
  if (multipliers_) write_rows(multipliers_, "/multipliers", f64, b.multipliers.data(), first, n);
  if (sensitivities_) write_rows(sensitivities_, "/sensitivities", f64, b.sensitivities.data(), first, n);
  std::vector<double> column(un * std::max<std::size_t>(ntime_, 1));
  for (std::size_t k = 0; k < outputs_.size(); ++k) {  // [sample][output][time] → [sample][time]
    for (std::size_t s = 0; s < un; ++s)
      std::copy_n(b.outputs.data() + (s * outputs_.size() + k) * ntime_, ntime_, column.data() + s * ntime_);
    write_rows(outputs_[k], "/outputs", f64, column.data(), first, n);
  }
  // The other per-output datasets the same way: [sample][output][row] → [sample][row] per output.
  auto write_columns = [&](const std::vector<Dataset>& datasets, const std::vector<double>& data, std::size_t row,
                           const char* what) {
    std::vector<double> col(un * std::max<std::size_t>(row, 1));
    for (std::size_t k = 0; k < datasets.size(); ++k) {
      for (std::size_t s = 0; s < un; ++s)
        std::copy_n(data.data() + (s * datasets.size() + k) * row, row, col.data() + s * row);
      write_rows(datasets[k], what, f64, col.data(), first, n);
    }
  };
  write_columns(scalar_outputs_, b.scalar_outputs, 1, "/outputs");
  write_columns(output_sensitivities_, b.output_sensitivities, ntime_ * noutput_sensitivity_, "/output_sensitivities");
  write_columns(scalar_output_sensitivities_, b.scalar_output_sensitivities, noutput_sensitivity_, "/output_sensitivities");
  if (poses_) write_rows(poses_, kPosesPath, f64, b.poses.data(), first, n);
  for (std::size_t k = 0; k < stats_.size(); ++k) {
    for (std::size_t s = 0; s < un; ++s) column[s] = b.stats[s * stats_.size() + k];
    write_rows(stats_[k], "/solver_stats", f64, column.data(), first, n);
  }
  write_rows(stopped_at_, kStoppedAtPath, f64, b.stopped_at.data(), first, n);
  write_columns(event_times_, b.event_times, W, "/events");
  write_columns(event_counts_, b.event_counts, 1, "/events");
  write_columns(event_time_sensitivities_, b.event_time_sensitivities, W * noutput_sensitivity_, "/events");
  std::vector<char> messages(un * message_size, '\0');
  for (std::size_t s = 0; s < un; ++s) {
    const std::string fitted = fit_utf8(b.message[s], message_size);
    std::memcpy(messages.data() + s * message_size, fitted.data(), fitted.size());
  }
  write_rows(message_, kMessagePath, make_string_type(message_size).get(), messages.data(), first, n);
  // Last: a status of 1 on disk means every value above is on disk too.
  write_rows(status_, kStatusPath, H5T_NATIVE_INT, b.status.data(), first, n);
}

void RunFile::write_row(const Dataset& dataset, const std::string& path, hid_t memtype,
                        const void* data, std::int64_t index) const {
  write_rows(dataset, path, memtype, data, index, 1);
}

void RunFile::write_rows(const Dataset& dataset, const std::string& path, hid_t memtype,
                         const void* data, std::int64_t index, std::int64_t nrows) const {
  const std::string where = "(" + path_ + ":" + path + ", sample " + std::to_string(index) + ")";
  Dataspace file_space(H5Dget_space(dataset.get()), "H5Dget_space" + where);
  const int rank = H5Sget_simple_extent_ndims(file_space.get());
  check(rank, "H5Sget_simple_extent_ndims" + where);
  std::vector<hsize_t> count(static_cast<std::size_t>(rank)), start(count.size(), 0);
  check(H5Sget_simple_extent_dims(file_space.get(), count.data(), nullptr),
        "H5Sget_simple_extent_dims" + where);
  start[0] = static_cast<hsize_t>(index);
  count[0] = static_cast<hsize_t>(nrows);
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        "H5Sselect_hyperslab" + where);
  hsize_t elements = 1;
  for (const hsize_t c : count) elements *= c;
  Dataspace memory_space(H5Screate_simple(1, &elements, nullptr), "H5Screate_simple" + where);
  check(H5Dwrite(dataset.get(), memtype, memory_space.get(), file_space.get(), independent_.get(),
                 data),
        "H5Dwrite" + where);
}

void RunFile::abandon() noexcept {
  parameters_.abandon();
  initial_state_.abandon();
  states_.abandon();
  multipliers_.abandon();
  sensitivities_.abandon();
  for (auto& d : outputs_) d.abandon();
  for (auto& d : scalar_outputs_) d.abandon();
  for (auto& d : output_sensitivities_) d.abandon();
  for (auto& d : scalar_output_sensitivities_) d.abandon();
  poses_.abandon();
  for (auto& d : stats_) d.abandon();
  stopped_at_.abandon();
  for (auto& d : event_times_) d.abandon();
  for (auto& d : event_counts_) d.abandon();
  for (auto& d : event_time_sensitivities_) d.abandon();
  message_.abandon();
  status_.abandon();
  independent_.abandon();
  file_.abandon();
}

void RunFile::flush() {
  if (file_) check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), "H5Fflush(" + path_ + ")");
}

void RunFile::close() {
  if (!file_) return;
  // Datasets first: with the MPI-IO driver a file closes only when nothing in it is open.
  parameters_.reset();
  initial_state_.reset();
  states_.reset();
  multipliers_.reset();
  sensitivities_.reset();
  outputs_.clear();
  scalar_outputs_.clear();
  output_sensitivities_.clear();
  scalar_output_sensitivities_.clear();
  poses_.reset();
  stats_.clear();
  stopped_at_.reset();
  event_times_.clear();
  event_counts_.clear();
  event_time_sensitivities_.clear();
  message_.reset();
  status_.reset();
  independent_.reset();
  file_.close("H5Fclose(" + path_ + ")");
}

}  // namespace kanesens::io
