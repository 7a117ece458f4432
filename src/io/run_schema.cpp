#include "io/run_schema.hpp"

#include <hdf5_hl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/hdf5_text.hpp"

namespace kanesens::io {
namespace {

// Chunks hold whole sample rows: one row, or as many as fit in ~64 KiB when rows are tiny
// (status, parameters, statistics), so a sample's write touches one chunk and the chunk index
// stays small. Rows above 256 MiB are split along time (HDF5 caps a chunk at 4 GiB).
constexpr hsize_t kChunkBytes = hsize_t{64} << 10;
constexpr hsize_t kMaxChunkBytes = hsize_t{256} << 20;

struct Dimension {
  std::string name;
  std::vector<std::string> labels;  // the string coordinate
};

// The string dimensions that exist for `layout`, in schema order (see run_schema.hpp).
std::vector<Dimension> string_dimensions(const RunLayout& l) {
  std::vector<Dimension> dims{{"state", l.state_names}};
  if (has_parameters(l)) dims.push_back({"parameter", l.parameter_names});
  if (has_sensitivity_dimension(l)) dims.push_back({"sensitivity", l.sensitivity_names});
  if (has_multipliers(l)) dims.push_back({"constraint", l.constraint_names});
  if (!all_output_names(l).empty()) dims.push_back({"output", all_output_names(l)});
  if (has_poses(l)) {
    dims.push_back({"body", l.body_names});
    dims.push_back({"pose", pose_components()});
  }
  return dims;
}

struct Variable {
  std::string path;
  std::vector<std::string> dims;
};

// The per-sample float64 datasets of `layout` with their dimensions.
std::vector<Variable> float_variables(const RunLayout& l) {
  std::vector<Variable> vars;
  if (has_parameters(l)) vars.push_back({"/parameters", {"sample", "parameter"}});
  vars.push_back({"/initial_state", {"sample", "state"}});
  if (has_states(l)) vars.push_back({"/states", {"sample", "time", "state"}});
  if (has_multipliers(l)) vars.push_back({"/multipliers", {"sample", "time", "constraint"}});
  if (has_sensitivities(l)) {
    vars.push_back({"/sensitivities", {"sample", "time", "state", "sensitivity"}});
  }
  for (const auto& name : l.output_names) vars.push_back({output_path(name), {"sample", "time"}});
  for (const auto& name : l.scalar_output_names) vars.push_back({output_path(name), {"sample"}});
  if (has_output_sensitivities(l)) {
    for (const auto& name : l.output_sensitivity_names)
      vars.push_back({output_sensitivity_path(name), {"sample", "time", "sensitivity"}});
    for (const auto& name : l.scalar_output_sensitivity_names)
      vars.push_back({output_sensitivity_path(name), {"sample", "sensitivity"}});
  }
  if (has_poses(l)) vars.push_back({kPosesPath, {"sample", "time", "body", "pose"}});
  for (const auto& name : l.stat_names) vars.push_back({stat_path(name), {"sample"}});
  return vars;
}

hsize_t dimension_size(const RunLayout& l, const std::string& dim) {
  if (dim == "sample") return static_cast<hsize_t>(l.nsamples);
  if (dim == "time") return l.times.size();
  if (dim == "state") return l.state_names.size();
  if (dim == "parameter") return l.parameter_names.size();
  if (dim == "sensitivity") return l.sensitivity_names.size();
  if (dim == "constraint") return l.constraint_names.size();
  if (dim == "body") return l.body_names.size();
  if (dim == "pose") return pose_components().size();
  return all_output_names(l).size();  // "output"
}

std::vector<hsize_t> chunk_shape(const std::vector<hsize_t>& shape, std::size_t element_size) {
  std::vector<hsize_t> chunk = shape;
  auto row_bytes = [&] {
    hsize_t bytes = element_size;
    for (std::size_t i = 1; i < chunk.size(); ++i) bytes *= chunk[i];
    return bytes;
  };
  while (chunk.size() > 1 && chunk[1] > 1 && row_bytes() > kMaxChunkBytes) {
    chunk[1] = (chunk[1] + 1) / 2;
  }
  chunk[0] = std::clamp<hsize_t>((kChunkBytes + row_bytes() - 1) / row_bytes(), 1, shape[0]);
  return chunk;
}

// Creates a dataset. With `fill` (per-sample data) it is chunked by sample and filled at
// allocation; without (coordinates, written right away) it is contiguous and not filled. Space
// is always allocated now (parallel HDF5 requires it; and no allocation happens later).
// Modification times are not tracked, so writing raw data never touches an object header.
Dataset create_dataset(hid_t file, const std::string& path, hid_t type,
                       const std::vector<hsize_t>& shape, const void* fill) {
  const std::string where = "(" + path + ")";
  Dataspace space(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
                  "H5Screate_simple" + where);
  PropertyList dcpl(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate" + where);
  check(H5Pset_obj_track_times(dcpl.get(), false), "H5Pset_obj_track_times" + where);
  check(H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY), "H5Pset_alloc_time" + where);
  if (fill != nullptr) {
    const auto chunk = chunk_shape(shape, H5Tget_size(type));
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()),
          "H5Pset_chunk" + where);
    check(H5Pset_fill_value(dcpl.get(), type, fill), "H5Pset_fill_value" + where);
    check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_ALLOC), "H5Pset_fill_time" + where);
  } else {
    check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time" + where);
  }
  return Dataset(
      H5Dcreate2(file, path.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      "H5Dcreate2" + where);
}

// Rank 0 writes the values of a coordinate (independent I/O, the default transfer mode).
void write_values(const Dataset& dataset, const std::string& path, hid_t memtype, const void* data,
                  int rank) {
  if (rank != 0) return;
  check(H5Dwrite(dataset.get(), memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
        "H5Dwrite(" + path + ")");
}

Dataset create_strings(hid_t file, const std::string& path, const std::vector<std::string>& s,
                       int rank) {
  const std::size_t size = string_size(s);
  const Datatype type = make_string_type(size);
  Dataset dataset = create_dataset(file, path, type.get(), {s.size()}, nullptr);
  write_text_attribute(dataset.get(), "_Encoding", "utf-8");
  write_values(dataset, path, type.get(), pack_strings(s, size).data(), rank);
  return dataset;
}

void set_scale(const Dataset& dataset, const std::string& dim) {
  check(H5DSset_scale(dataset.get(), dim.c_str()), "H5DSset_scale(/" + dim + ")");
}

void attach(const Dataset& dataset, const std::string& path, const std::vector<std::string>& dims,
            const std::map<std::string, Dataset>& scales) {
  for (std::size_t axis = 0; axis < dims.size(); ++axis) {
    check(H5DSattach_scale(dataset.get(), scales.at(dims[axis]).get(), static_cast<unsigned>(axis)),
          "H5DSattach_scale(" + path + ", /" + dims[axis] + ")");
  }
}

void check_names(const std::vector<std::string>& names, const std::string& what,
                 bool dataset_names) {
  std::set<std::string> seen;
  for (const auto& name : names) {
    if (!seen.insert(name).second) {
      throw std::invalid_argument("run file: duplicate " + what + " name '" + name + "'");
    }
    if (dataset_names && (name.empty() || name == "." || name.find('/') != std::string::npos)) {
      throw std::invalid_argument("run file: " + what + " name '" + name +
                                  "' cannot name an HDF5 dataset (empty, '.' or contains '/')");
    }
  }
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return "[" + s + "]";
}

bool link_exists(hid_t file, const std::string& path) {
  // H5Lexists needs every intermediate group to exist: check them one by one.
  for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    const htri_t exists = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
    check(exists < 0 ? -1 : 0, "H5Lexists(" + prefix + ")");
    if (exists == 0) return false;
    if (slash == std::string::npos) return true;
  }
}

std::vector<std::string> read_names(hid_t file, const std::string& path) {
  if (!link_exists(file, path)) return {};
  Dataset dataset(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "H5Dopen2(" + path + ")");
  return read_strings(dataset.get(), path);
}

std::vector<double> read_doubles(hid_t file, const std::string& path) {
  if (!link_exists(file, path)) return {};
  Dataset dataset(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "H5Dopen2(" + path + ")");
  Dataspace space(H5Dget_space(dataset.get()), "H5Dget_space(" + path + ")");
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  check(H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
        "H5Dread(" + path + ")");
  return values;
}

// Rank 0 writes the design labels a chunk at a time (memory does not grow with the samples);
// every rank takes part in creating the datasets (collective metadata).
void write_design_labels(hid_t file, const RunLayout& l, int rank,
                         const std::map<std::string, Dataset>& scales) {
  const hsize_t n = static_cast<hsize_t>(l.nsamples);
  const std::pair<const char*, const char*> names[] = {
      {kDesignBlockPath, "saltelli: base point j; morris: trajectory"},
      {kDesignRowPath, "saltelli: 0 = A_j, 1 = B_j, 2 + k = AB_j^(k); morris: step 0..P"},
      {kDesignInputPath,
       "saltelli: k of AB_j^(k), -1 for A_j and B_j; morris: the input the "
       "step moved (index into /parameter), -1 at step 0"}};
  std::vector<Dataset> datasets;
  for (const auto& [path, description] : names) {
    datasets.push_back(create_dataset(file, path, H5T_STD_I64LE, {n}, nullptr));
    write_text_attribute(datasets.back().get(), "description", description);
    attach(datasets.back(), path, {"sample"}, scales);
  }
  if (rank != 0) return;
  constexpr hsize_t kChunk = hsize_t{1} << 16;
  std::vector<std::int64_t> columns[3];
  for (auto& c : columns) c.resize(static_cast<std::size_t>(std::min(n, kChunk)));
  for (hsize_t first = 0; first < n; first += kChunk) {
    const hsize_t count = std::min(kChunk, n - first);
    const auto m = static_cast<std::size_t>(count);
    l.design_labels(static_cast<std::int64_t>(first), std::span(columns[0]).first(m),
                    std::span(columns[1]).first(m), std::span(columns[2]).first(m));
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string where = std::string("(") + names[k].first + ")";
      Dataspace file_space(H5Dget_space(datasets[k].get()), "H5Dget_space" + where);
      check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &first, nullptr, &count, nullptr),
            "H5Sselect_hyperslab" + where);
      Dataspace memory_space(H5Screate_simple(1, &count, nullptr), "H5Screate_simple" + where);
      check(H5Dwrite(datasets[k].get(), H5T_NATIVE_INT64, memory_space.get(), file_space.get(),
                     H5P_DEFAULT, columns[k].data()),
            "H5Dwrite" + where);
    }
  }
}

// /vary/<name>: one group per varied input, its distribution as attributes (collective).
void write_distributions(hid_t file, const RunLayout& l) {
  Group vary(H5Gcreate2(file, kVaryPath, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             std::string("H5Gcreate2(") + kVaryPath + ")");
  for (const InputDistribution& d : l.distributions) {
    Group group(H5Gcreate2(vary.get(), d.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                std::string("H5Gcreate2(") + kVaryPath + "/" + d.name + ")");
    write_text_attribute(group.get(), "distribution", d.distribution);
    for (const auto& [key, value] : d.parameters) write_number_attribute(group.get(), key, value);
    if (!d.values.empty()) write_numbers_attribute(group.get(), "values", d.values);
  }
}

}  // namespace

void validate_layout(const RunLayout& l) {
  if (l.nsamples < 1) throw std::invalid_argument("run file: nsamples must be at least 1");
  if (l.times.empty()) throw std::invalid_argument("run file: no output times");
  if (l.state_names.empty()) throw std::invalid_argument("run file: no state names");
  check_names(l.state_names, "state", false);
  check_names(l.parameter_names, "parameter", false);
  check_names(l.sensitivity_names, "sensitivity", false);
  check_names(l.constraint_names, "constraint", false);
  check_names(all_output_names(l), "output", true);
  check_names(l.body_names, "body", false);
  auto subset = [](const std::vector<std::string>& part, const std::vector<std::string>& of) {
    for (const auto& name : part)
      if (std::find(of.begin(), of.end(), name) == of.end())
        throw std::invalid_argument("run file: sensitivities of '" + name + "', which is not an output of that shape");
  };
  subset(l.output_sensitivity_names, l.output_names);
  subset(l.scalar_output_sensitivity_names, l.scalar_output_names);
  check_names(l.stat_names, "solver statistic", true);
  std::vector<std::string> varied;
  for (const auto& d : l.distributions) {
    varied.push_back(d.name);
    if (std::find(l.parameter_names.begin(), l.parameter_names.end(), d.name) ==
        l.parameter_names.end()) {
      throw std::invalid_argument("run file: distribution of '" + d.name +
                                  "', which is not a parameter");
    }
  }
  check_names(varied, "varied input", true);
}

void write_schema(hid_t file, const RunLayout& l, int rank, std::size_t message_size) {
  for (const auto& [name, text] : l.text_attributes) write_text_attribute(file, name, text);
  for (const auto& [name, value] : l.number_attributes) write_number_attribute(file, name, value);

  // Dimension scales with their coordinate values, and the *_name aliases.
  std::map<std::string, Dataset> scales;
  std::vector<std::int64_t> samples(static_cast<std::size_t>(l.nsamples));
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<std::int64_t>(i);
  scales["sample"] = create_dataset(file, "/sample", H5T_STD_I64LE, {samples.size()}, nullptr);
  write_values(scales["sample"], "/sample", H5T_NATIVE_INT64, samples.data(), rank);
  scales["time"] = create_dataset(file, "/time", H5T_IEEE_F64LE, {l.times.size()}, nullptr);
  write_values(scales["time"], "/time", H5T_NATIVE_DOUBLE, l.times.data(), rank);
  for (const auto& dim : string_dimensions(l)) {
    scales[dim.name] = create_strings(file, "/" + dim.name, dim.labels, rank);
    const std::string alias = "/" + dim.name + "_name";
    attach(create_strings(file, alias, dim.labels, rank), alias, {dim.name}, scales);
  }
  for (const auto& [name, scale] : scales) set_scale(scale, name);

  // Per-sample data, filled so that an unwritten row reads as "not run".
  if (!all_output_names(l).empty()) {
    Group(H5Gcreate2(file, "/outputs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          "H5Gcreate2(/outputs)");
  }
  if (has_output_sensitivities(l)) {
    Group(H5Gcreate2(file, "/output_sensitivities", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          "H5Gcreate2(/output_sensitivities)");
  }
  if (!l.stat_names.empty()) {
    Group(H5Gcreate2(file, "/solver_stats", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          "H5Gcreate2(/solver_stats)");
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& var : float_variables(l)) {
    std::vector<hsize_t> shape;
    for (const auto& dim : var.dims) shape.push_back(dimension_size(l, dim));
    attach(create_dataset(file, var.path, H5T_IEEE_F64LE, shape, &nan), var.path, var.dims, scales);
  }
  const std::int32_t not_run = 0;
  const hsize_t n = static_cast<hsize_t>(l.nsamples);
  attach(create_dataset(file, kStatusPath, H5T_STD_I32LE, {n}, &not_run), kStatusPath, {"sample"},
         scales);
  const Datatype message_type = make_string_type(message_size);
  const std::vector<char> empty(message_size, '\0');
  Dataset message = create_dataset(file, kMessagePath, message_type.get(), {n}, empty.data());
  write_text_attribute(message.get(), "_Encoding", "utf-8");
  attach(message, kMessagePath, {"sample"}, scales);
  if (l.design_labels) write_design_labels(file, l, rank, scales);
  if (!l.distributions.empty()) write_distributions(file, l);
}

void verify_schema(hid_t file, const std::string& path, const RunLayout& l) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("cannot resume '" + path + "': " + what +
                             "; it was written for another study (start a new file instead)");
  };
  auto compare = [&](const std::string& what, const std::vector<std::string>& in_file,
                     const std::vector<std::string>& wanted) {
    if (in_file != wanted) {
      fail("its " + what + " " + join(in_file) + " differ from this study's " + join(wanted));
    }
  };
  const auto samples = read_doubles(file, "/sample");
  if (samples.size() != static_cast<std::size_t>(l.nsamples)) {
    fail("it has " + std::to_string(samples.size()) + " samples, this study " +
         std::to_string(l.nsamples));
  }
  const auto times = read_doubles(file, "/time");
  if (times != l.times) {
    fail("its " + std::to_string(times.size()) + " output times differ from this study's " +
         std::to_string(l.times.size()));
  }
  compare("state names", read_names(file, "/state"), l.state_names);
  compare("parameter names", read_names(file, "/parameter"), l.parameter_names);
  const std::vector<std::string> none;
  compare("sensitivity names", read_names(file, "/sensitivity"),
          has_sensitivity_dimension(l) ? l.sensitivity_names : none);
  compare("constraint names", read_names(file, "/constraint"),
          has_multipliers(l) ? l.constraint_names : none);
  compare("output names", read_names(file, "/output"), all_output_names(l));
  compare("body names", read_names(file, "/body"), has_poses(l) ? l.body_names : none);
  if (link_exists(file, "/states") != has_states(l)) {
    fail(has_states(l) ? "it does not record states" : "it records states");
  }
  for (const auto& name : l.stat_names) {
    if (!link_exists(file, stat_path(name))) fail("it has no solver statistic '" + name + "'");
  }
  for (const auto& var : float_variables(l))
    if (!link_exists(file, var.path)) fail("it has no dataset " + var.path);
  const auto hash_in_file = read_text_attribute(file, "study_hash");
  const auto wanted_hash = l.text_attributes.find("study_hash");
  if (hash_in_file && wanted_hash != l.text_attributes.end() &&
      *hash_in_file != wanted_hash->second) {
    fail("its study_hash " + *hash_in_file + " differs from this study's " + wanted_hash->second);
  }
}

}  // namespace kanesens::io
