// The schema of the run file, in one place: what RunFile::create writes and what
// RunFile::open_for_resume checks. Sizes: N samples, T times, nstate, P, S, C as in RunLayout.
//
//   dimension scales (netCDF-4 dimensions; h5netcdf names a dimension after its scale dataset)
//     /sample       (sample)        int64 0..N-1
//     /time         (time)          float64, seconds
//     /state        (state)         string, the state names: ds.sel(state="elbow.q")
//     /parameter    (parameter)     string                        [only if P > 0]
//     /sensitivity  (sensitivity)   string         [only if sensitivities recorded, S > 0]
//     /constraint   (constraint)    string         [only if multipliers recorded, C > 0]
//     /output       (output)        string, names of /outputs/*   [only if any output]
//   the same names again as plain variables, for readers that look names up by these keys:
//     /state_name (state), /parameter_name, /sensitivity_name, /constraint_name, /output_name
//   per-sample data, chunked by sample, preallocated, filled with NaN (status 0, message "")
//     /parameters     (sample, parameter)                   float64
//     /initial_state  (sample, state)                       float64
//     /states         (sample, time, state)                 float64  [record_states]
//     /multipliers    (sample, time, constraint)            float64  [record_multipliers]
//     /sensitivities  (sample, time, state, sensitivity)    float64  [record_sensitivities]
//     /outputs/<name> (sample, time) or (sample)           float64  [output_names, scalar_output_names]
//     /output_sensitivities/<name> (sample, time, sensitivity) or (sample, sensitivity)
//                                                           float64  [output_sensitivity_names, ...]
//     /poses          (sample, time, body, pose)            float64  [record_poses]; pose = x y z qw qx qy qz
//     /solver_stats/<name> (sample)                         float64
//     /status         (sample)  int32: 0 not run, 1 ok, < 0 failure code
//     /message        (sample)  string of RunFile::message_size bytes
//   design labels, written whole at creation (rank 0), only if RunLayout::design_labels is set
//     /design_block, /design_row, /design_input  (sample)  int64
//   /vary/<name>   group per RunLayout::distributions entry; attributes: distribution (string),
//                  its parameters (float64), values (float64 array, choice)
//   root attributes: RunLayout::text_attributes (strings), number_attributes (float64)
// All strings are fixed-length, null-padded UTF-8 with _Encoding = "utf-8" (io/hdf5_text.hpp).
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

#include "io/run_file.hpp"

namespace kanesens::io {

// Throws std::invalid_argument when `layout` cannot be written (no times or states, N < 1,
// duplicate names in a list, an output or statistic name that is not a valid dataset name).
void validate_layout(const RunLayout& layout);

// Collective: creates every object of the schema in `file` (freshly created) and, on rank 0,
// writes the coordinate values. The caller flushes.
void write_schema(hid_t file, const RunLayout& layout, int rank, std::size_t message_size);

// Throws std::runtime_error("cannot resume '<path>': ...") naming the first way in which `file`
// differs from what `layout` would create: a missing or different study_hash attribute (when the
// layout has one), names, times, and the element type, shape and storage of every dataset a
// sample row is written to (no soft or external links, external raw data, virtual datasets or
// filters). Reads only what it has checked the shape of first.
void verify_schema(hid_t file, const std::string& path, const RunLayout& layout, std::size_t message_size);

// Dataset paths (absolute) used by RunFile for the per-sample data.
inline constexpr const char* kStatusPath = "/status";
inline constexpr const char* kMessagePath = "/message";
inline constexpr const char* kDesignBlockPath = "/design_block";
inline constexpr const char* kDesignRowPath = "/design_row";
inline constexpr const char* kDesignInputPath = "/design_input";
inline constexpr const char* kVaryPath = "/vary";
inline std::string output_path(const std::string& name) {
  return "/outputs/" + name;
}
inline std::string output_sensitivity_path(const std::string& name) {
  return "/output_sensitivities/" + name;
}
inline constexpr const char* kPosesPath = "/poses";
inline constexpr const char* kStoppedAtPath = "/stopped_at";
inline std::string event_path(const std::string& name, const char* what) {
  return "/events/" + name + "/" + what;
}
inline std::string stat_path(const std::string& name) {
  return "/solver_stats/" + name;
}

// Whether the layout records each optional dataset (a dimension of size 0 records nothing).
inline bool has_parameters(const RunLayout& l) {
  return !l.parameter_names.empty();
}
inline bool has_states(const RunLayout& l) {
  return l.record_states;
}
inline bool has_multipliers(const RunLayout& l) {
  return l.record_multipliers && !l.constraint_names.empty();
}
inline bool has_sensitivities(const RunLayout& l) {
  return l.record_sensitivities && !l.sensitivity_names.empty();
}
inline bool has_output_sensitivities(const RunLayout& l) {
  return !l.sensitivity_names.empty() &&
         (!l.output_sensitivity_names.empty() || !l.scalar_output_sensitivity_names.empty());
}
// The /sensitivity dimension: for state or output sensitivities.
inline bool has_sensitivity_dimension(const RunLayout& l) {
  return has_sensitivities(l) || has_output_sensitivities(l);
}
inline bool has_poses(const RunLayout& l) {
  return l.record_poses && !l.body_names.empty();
}
// The names of /outputs/*: series, then scalars.
inline std::vector<std::string> all_output_names(const RunLayout& l) {
  std::vector<std::string> names = l.output_names;
  names.insert(names.end(), l.scalar_output_names.begin(), l.scalar_output_names.end());
  return names;
}
// The seven pose components (/pose).
inline const std::vector<std::string>& pose_components() {
  static const std::vector<std::string> names = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  return names;
}

}  // namespace kanesens::io
