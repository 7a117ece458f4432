#include "parallel/preflight.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "parallel/resources.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::parallel::detail {

using namespace kanesens::model;
using study::StudySpec;

// Bytes the run file will take on disk: every per-sample dataset is allocated (and filled) when
// the file is created (run_schema.cpp), so this is close to the final size. In double precision
// to stay meaningful for absurd sizes (1e9 samples × 1e7 times).
double estimate_file_bytes(const io::RunLayout& l) {
  const double T = static_cast<double>(l.times.size()), n = static_cast<double>(l.state_names.size());
  const double S = l.record_sensitivities ? static_cast<double>(l.sensitivity_names.size()) : 0.0;
  const double So = static_cast<double>(l.sensitivity_names.size());
  const double values = static_cast<double>(l.parameter_names.size()) + n + (l.record_states ? T * n : 0.0) +
                        T * n * S + static_cast<double>(l.output_names.size()) * T +
                        static_cast<double>(l.scalar_output_names.size()) +
                        static_cast<double>(l.output_sensitivity_names.size()) * T * So +
                        static_cast<double>(l.scalar_output_sensitivity_names.size()) * So +
                        (l.record_poses ? T * static_cast<double>(l.body_names.size()) * 7 : 0.0) +
                        static_cast<double>(l.stat_names.size()) + 1.0 +  // + /stopped_at
                        static_cast<double>(l.event_names.size()) *
                            (1.0 + static_cast<double>(l.event_occurrences) * (1.0 + So));
  const double labels = l.design_labels ? 3 * 8.0 : 0.0;
  const double per_sample =
      8.0 * values + static_cast<double>(io::RunFile::message_size) + 4.0 + 8.0 + labels;
  double text = 0;
  for (const auto& [k, v] : l.text_attributes) text += static_cast<double>(k.size() + v.size());
  return static_cast<double>(l.nsamples) * per_sample + 8.0 * T + text + (1 << 20);  // + 1 MiB of HDF5 metadata
}

namespace {
// Bytes of one sample's results (a row of the run file, as the trajectory buffers hold it).
double row_bytes(const io::RunLayout& l) {
  const double T = static_cast<double>(l.times.size()), n = static_cast<double>(l.state_names.size());
  const double S = l.record_sensitivities ? static_cast<double>(l.sensitivity_names.size()) : 0.0;
  const double C = l.record_multipliers ? static_cast<double>(l.constraint_names.size()) : 0.0;
  return 8.0 * (static_cast<double>(l.parameter_names.size()) + n + (l.record_states ? T * n : 0.0) + T * n * S +
                T * C * (1 + S) + T * (3 + static_cast<double>(l.output_names.size())) +
                static_cast<double>(l.stat_names.size()) + 1.0) +
         static_cast<double>(io::RunFile::message_size);
}
}  // namespace

// Checks that `ranks_here` ranks on one node can each hold a sample's results: the trajectory,
// its copy into the block of rows to write, and that block. Returns the InputError line or "".
std::string check_memory(const io::RunLayout& l, const StudySpec& st, int ranks_here) {
  const double row = row_bytes(l);
  const double per_rank = 2 * row + std::min(kBlockBytes + row, row * 64) + 8.0 * 4 * static_cast<double>(l.times.size());
  const double available = available_memory_bytes();
  if (per_rank * ranks_here <= available) return "";
  const std::size_t S = l.record_sensitivities ? l.sensitivity_names.size() : 0;
  return InputError::format(
      st.time_where, "time",
      "one sample's results (" + std::to_string(l.times.size()) + " times x " + std::to_string(l.state_names.size()) +
          " states x (1 + " + std::to_string(S) + " sensitivities)) need about " + human_bytes(per_rank) +
          " of memory per rank" +
          (ranks_here > 1 ? " (" + std::to_string(ranks_here) + " ranks on this node: " + human_bytes(per_rank * ranks_here) + ")" : "") +
          " but " + human_bytes(available) + " is available; use fewer output times, record less or fewer sensitivities" +
          (ranks_here > 1 ? ", or fewer ranks per node" : ""));
}

// Rank 0 checks, before anything is created, that the output can be written: its directory
// exists and is writable, it is not a directory, it does not exist (unless --resume or
// --overwrite), and, for a new file, that the file system has room for it (statvfs). Returns
// the formatted InputError line, or "" when all is well.
std::string check_output(const std::string& output, const RunOptions& opt, const io::RunLayout& layout,
                         const StudySpec& st, int ranks_here) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path out(output);
  const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  auto error = [](const std::string& key, const std::string& what, SourceLocation where = {}) {
    return InputError::format(where, key, what);
  };
  if (opt.resume && opt.overwrite) return error("--resume", "--resume and --overwrite exclude each other");
  if (std::string problem = check_memory(layout, st, ranks_here); !problem.empty()) return problem;
  if (!fs::exists(dir, ec)) return error("-o", "cannot write '" + output + "': directory '" + dir.string() + "' does not exist");
  if (!fs::is_directory(dir, ec)) return error("-o", "cannot write '" + output + "': '" + dir.string() + "' is not a directory");
  // symlink_status: a name that is taken counts, even by a dangling symbolic link.
  const bool exists = fs::exists(fs::symlink_status(out, ec));
  if (exists && fs::is_directory(out, ec)) return error("-o", "'" + output + "' is a directory; name an .h5 file");
  if (opt.resume) {
    if (!exists) return error("--resume", "no file '" + output + "' to resume; run without --resume to start it");
    if (::access(output.c_str(), R_OK | W_OK) != 0)
      return error("--resume", "cannot open '" + output + "' for reading and writing: " + std::strerror(errno));
    return "";  // its space was allocated when it was created
  }
  if (exists && !opt.overwrite)
    return error("-o", "output file '" + output + "' already exists; pass --overwrite to replace it or --resume to continue it");
  // The file is built as OUT.partial (created exclusively, never through a link) and renamed
  // when complete; one left by a run killed during creation is replaced only with --overwrite.
  const fs::path partial = output + ".partial";
  const fs::file_status partial_status = fs::symlink_status(partial, ec);
  if (fs::is_directory(partial_status))
    return error("-o", "'" + partial.string().append("'") + " (the name the output is built under) is a directory; remove it or choose another -o");
  if (fs::exists(partial_status) && !opt.overwrite)
    return error("-o", "'" + partial.string().append("'") + " exists (the name the output is built under, left by an interrupted run?); remove it or pass --overwrite");
  if (::access(dir.c_str(), W_OK) != 0)
    return error("-o", "cannot write '" + output + "': directory '" + dir.string() + "' is not writable (" + std::strerror(errno) + ")");
  // Fault injection for the disk-full test: skip this check so that HDF5 itself hits ENOSPC.
  const bool skip_space_check = std::getenv("KANESENS_FAULT_IGNORE_FREE_SPACE") != nullptr;
  struct statvfs fsinfo;
  if (!skip_space_check && ::statvfs(dir.c_str(), &fsinfo) == 0) {
    const double free_bytes = static_cast<double>(fsinfo.f_bavail) * static_cast<double>(fsinfo.f_frsize);
    const double need = estimate_file_bytes(layout);
    if (need > free_bytes) {
      const std::size_t T = layout.times.size(), n = layout.state_names.size();
      const std::size_t S = layout.record_sensitivities ? layout.sensitivity_names.size() : 0;
      const SourceLocation& where = st.sampling.where;
      return error("sampling.samples",
                   "the output would need about " + human_bytes(need) + " (" + std::to_string(layout.nsamples) +
                       " samples x " + std::to_string(T) + " times x " + std::to_string(n) + " states x (1 + " +
                       std::to_string(S) + " sensitivities) x 8 bytes, plus per-sample metadata) but the file system of '" +
                       dir.string() + "' has " + human_bytes(free_bytes) +
                       " free; use fewer samples or outputs, record less, or write elsewhere with -o",
                   where);
    }
  }
  return "";
}

// An I/O error, told with what the user can do about it: the file, whether the disk is full
// (free space below what the file needs, or below 4 MiB once the file exists), and what state
// the file is in. `need`: estimated bytes of the file being created (0 once it exists).
[[noreturn]] void rethrow_io_error(const std::exception& e, const std::string& output, const std::string& study,
                                   double need) {
  const bool created = need == 0;
  std::string what = std::string(created ? "writing '" : "creating '") + output + "' failed";
  const std::filesystem::path dir =
      std::filesystem::path(output).parent_path().empty() ? "." : std::filesystem::path(output).parent_path();
  struct statvfs fsinfo;
  if (::statvfs(dir.c_str(), &fsinfo) == 0) {
    const double free_bytes = static_cast<double>(fsinfo.f_bavail) * static_cast<double>(fsinfo.f_frsize);
    if (created ? free_bytes < 4.0 * (1 << 20) : free_bytes < need)
      what += ": the disk is full (the file system of '" + dir.string() + "' has " + human_bytes(free_bytes) +
              " free" + (created ? "" : ", the file needs about " + human_bytes(need)) + ")";
  }
  what += std::string(" [") + e.what() + "]";
  if (created)
    what += "; samples with status 1 are intact: free space, then finish with: kanesens run " + study + " -o " +
            output + " --resume";
  else
    what += "; no output was written: free space (or choose another -o) and run again";
  throw std::runtime_error(what);
}

}  // namespace kanesens::parallel::detail
