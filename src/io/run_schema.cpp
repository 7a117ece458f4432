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
  vars.push_back({kStoppedAtPath, {"sample"}});
  for (const auto& name : l.event_names) {
    vars.push_back({event_path(name, "time"), {"sample", "occurrence"}});
    vars.push_back({event_path(name, "count"), {"sample"}});
    if (has_output_sensitivities(l))
      vars.push_back({event_path(name, "time_sensitivities"), {"sample", "occurrence", "sensitivity"}});
  }
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
  if (dim == "occurrence") return l.event_occurrences;
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

// Whether `path` exists in `file`. Every component must be a hard link: a soft or external link
// (a hostile file could point /states at a dataset of another file) is refused.
bool link_exists(hid_t file, const std::string& path) {
  // H5Lexists needs every intermediate group to exist: check them one by one.
  for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    const htri_t exists = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
    check(exists < 0 ? -1 : 0, "H5Lexists(" + prefix + ")");
    if (exists == 0) return false;
    H5L_info_t info;
    check(H5Lget_info(file, prefix.c_str(), &info, H5P_DEFAULT), "H5Lget_info(" + prefix + ")");
    if (info.type != H5L_TYPE_HARD) {
      throw std::runtime_error(prefix + " is a soft or external link, not an object of this file");
    }
    if (slash == std::string::npos) return true;
  }
}

// What a dataset of the file must be: its element type and its shape.
enum class Element { float64, int32, int64, text };

// Opens `path` and checks, before any of its data is read or written, that it is a dataset of
// `element` values (`text`: fixed-length strings, of `text_size` bytes unless 0) with exactly
// the dimensions `dims`, stored in this file (no external raw data, no virtual mapping, no
// filters). Throws a message naming the dataset otherwise.
Dataset open_checked(hid_t file, const std::string& path, Element element, const std::vector<hsize_t>& dims,
                     std::size_t text_size = 0) {
  auto fail = [&](const std::string& what) { throw std::runtime_error("dataset " + path + " " + what); };
  if (!link_exists(file, path)) fail("is missing");
  if (H5Oexists_by_name(file, path.c_str(), H5P_DEFAULT) <= 0) fail("does not resolve to an object");
  H5O_info_t object;
  check(H5Oget_info_by_name2(file, path.c_str(), &object, H5O_INFO_BASIC, H5P_DEFAULT), "H5Oget_info(" + path + ")");
  if (object.type != H5O_TYPE_DATASET) fail("is not a dataset");
  Dataset dataset(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "H5Dopen2(" + path + ")");
  const Datatype type(H5Dget_type(dataset.get()), "H5Dget_type(" + path + ")");
  const H5T_class_t type_class = H5Tget_class(type.get());
  const std::size_t size = H5Tget_size(type.get());
  switch (element) {
    case Element::float64:
      if (type_class != H5T_FLOAT || size != 8) fail("is not float64");
      break;
    case Element::int32:
    case Element::int64:
      if (type_class != H5T_INTEGER || size != (element == Element::int32 ? 4u : 8u))
        fail(element == Element::int32 ? "is not int32" : "is not int64");
      break;
    case Element::text:
      if (type_class != H5T_STRING || H5Tis_variable_str(type.get()) != 0) fail("is not of fixed-length strings");
      if (text_size != 0 && size != text_size) fail("has strings of " + std::to_string(size) + " bytes, expected " + std::to_string(text_size));
      if (size > 65536) fail("has strings of " + std::to_string(size) + " bytes");
      break;
  }
  const Dataspace space(H5Dget_space(dataset.get()), "H5Dget_space(" + path + ")");
  if (H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE) fail("is not an array");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> found(rank > 0 ? static_cast<std::size_t>(rank) : 0);
  if (rank < 0 || H5Sget_simple_extent_dims(space.get(), found.data(), nullptr) < 0) fail("has no readable shape");
  if (found != dims) {
    auto shape = [](const std::vector<hsize_t>& d) {
      std::string s;
      for (const hsize_t x : d) s += (s.empty() ? "" : ", ") + std::to_string(x);
      return "(" + s + ")";
    };
    fail("has shape " + shape(found) + ", this study writes " + shape(dims));
  }
  const PropertyList dcpl(H5Dget_create_plist(dataset.get()), "H5Dget_create_plist(" + path + ")");
  const H5D_layout_t layout = H5Pget_layout(dcpl.get());
  if (layout != H5D_CONTIGUOUS && layout != H5D_CHUNKED && layout != H5D_COMPACT) fail("is a virtual dataset");
  if (H5Pget_external_count(dcpl.get()) != 0) fail("keeps its data in an external file");
  if (H5Pget_nfilters(dcpl.get()) != 0) fail("is filtered (compressed); run files are not");
  return dataset;
}

std::vector<std::string> read_names(hid_t file, const std::string& path, std::size_t count) {
  if (!link_exists(file, path)) return {};
  const Dataset dataset = open_checked(file, path, Element::text, {count});
  return read_strings(dataset.get(), path);
}

std::vector<double> read_doubles(hid_t file, const std::string& path, std::size_t count) {
  const Dataset dataset = open_checked(file, path, Element::float64, {count});
  std::vector<double> values(count);
  if (count > 0)
    check(H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "H5Dread(" + path + ")");
  return values;
}

// The number of elements of dimension `path` (a 1-D dataset) in the file, 0 when it has none.
std::size_t dimension_length(hid_t file, const std::string& path) {
  if (!link_exists(file, path)) return 0;
  const Dataset dataset(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "H5Dopen2(" + path + ")");
  const Dataspace space(H5Dget_space(dataset.get()), "H5Dget_space(" + path + ")");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  return n > 0 ? static_cast<std::size_t>(n) : 0;
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
  check_names(l.event_names, "event", true);
  if (!l.event_names.empty() && l.event_occurrences == 0)
    throw std::invalid_argument("run file: events with no occurrence dimension");
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
  if (!l.event_names.empty()) {  // occurrence k = 1, 2, ... (1-based, as `occurrence:` in the study)
    std::vector<std::int64_t> k(l.event_occurrences);
    for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::int64_t>(i + 1);
    scales["occurrence"] = create_dataset(file, "/occurrence", H5T_STD_I64LE, {k.size()}, nullptr);
    write_values(scales["occurrence"], "/occurrence", H5T_NATIVE_INT64, k.data(), rank);
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
  if (!l.event_names.empty()) {
    Group(H5Gcreate2(file, "/events", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2(/events)");
    for (const auto& name : l.event_names)
      Group(H5Gcreate2(file, ("/events/" + name).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
            "H5Gcreate2(/events/" + name + ")");
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

void verify_schema(hid_t file, const std::string& path, const RunLayout& l, std::size_t message_size) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("cannot resume '" + path + "': " + what +
                             "; it was written for another study (start a new file instead)");
  };
  auto compare = [&](const std::string& what, const std::string& dim, const std::vector<std::string>& wanted) {
    const std::size_t n = dimension_length(file, "/" + dim);
    if (n != wanted.size() && n > (std::size_t{1} << 20)) {  // not worth reading to show them
      fail("it has " + std::to_string(n) + " " + what + ", this study " + std::to_string(wanted.size()));
    }
    const std::vector<std::string> in_file = read_names(file, "/" + dim, n);
    if (in_file != wanted) {
      fail("its " + what + " " + join(in_file) + " differ from this study's " + join(wanted));
    }
  };
  try {
    // Identity first: a file without the study's hash is not this study's output.
    const auto hash_in_file = read_text_attribute(file, "study_hash");
    const auto wanted_hash = l.text_attributes.find("study_hash");
    if (wanted_hash != l.text_attributes.end()) {
      if (!hash_in_file) fail("it has no study_hash attribute");
      if (*hash_in_file != wanted_hash->second) {
        fail("its study_hash " + *hash_in_file + " differs from this study's " + wanted_hash->second);
      }
    }
    const std::size_t n = static_cast<std::size_t>(l.nsamples);
    if (const std::size_t found = dimension_length(file, "/sample"); found != n) {
      fail("it has " + std::to_string(found) + " samples, this study " + std::to_string(n));
    }
    open_checked(file, "/sample", Element::int64, {n});
    const std::size_t ntime = dimension_length(file, "/time");
    if (ntime != l.times.size() || read_doubles(file, "/time", ntime) != l.times) {
      fail("its " + std::to_string(ntime) + " output times differ from this study's " + std::to_string(l.times.size()));
    }
    const std::vector<std::string> none;
    compare("state names", "state", l.state_names);
    compare("parameter names", "parameter", l.parameter_names);
    compare("sensitivity names", "sensitivity", has_sensitivity_dimension(l) ? l.sensitivity_names : none);
    compare("constraint names", "constraint", has_multipliers(l) ? l.constraint_names : none);
    compare("output names", "output", all_output_names(l));
    compare("body names", "body", has_poses(l) ? l.body_names : none);
    if (link_exists(file, "/states") != has_states(l)) {
      fail(has_states(l) ? "it does not record states" : "it records states");
    }
    for (const auto& name : l.stat_names) {
      if (!link_exists(file, stat_path(name))) fail("it has no solver statistic '" + name + "'");
    }
    // Every dataset a sample row is written to, with the type and shape the writer assumes.
    for (const auto& var : float_variables(l)) {
      std::vector<hsize_t> shape;
      for (const auto& dim : var.dims) shape.push_back(dimension_size(l, dim));
      open_checked(file, var.path, Element::float64, shape);
    }
    open_checked(file, kStatusPath, Element::int32, {n});
    open_checked(file, kMessagePath, Element::text, {n}, message_size);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    if (what.rfind("cannot resume", 0) == 0) throw;
    throw std::runtime_error("cannot resume '" + path + "': " + what + "; it is not a run file kanesens wrote");
  }
}

}  // namespace kanesens::io
