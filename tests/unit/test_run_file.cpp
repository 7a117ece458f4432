// io::RunFile on one rank (MPI singleton): create, write, read back, refusals, resume checks.
// The multi-rank, kill -9 and xarray checks are tests/mpi/test_run_file_parallel.sh.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <span>
#include <string>
#include <vector>

#include "io/hdf5_text.hpp"
#include "io/run_file.hpp"

namespace kanesens::io {
namespace {

class MpiEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { MPI_Init(nullptr, nullptr); }
  void TearDown() override { MPI_Finalize(); }
};
[[maybe_unused]] const auto* const kMpi = ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

RunLayout small_layout() {
  RunLayout l;
  l.times = {0.0, 0.5, 1.0};
  l.state_names = {"q", "u"};
  l.parameter_names = {"k"};
  l.sensitivity_names = {"k"};
  l.constraint_names = {"c"};
  l.output_names = {"energy"};
  l.stat_names = {"steps"};
  l.nsamples = 3;
  l.record_sensitivities = l.record_multipliers = true;
  l.text_attributes = {{"study_hash", "abc"}, {"scene_yaml", "scene: {}\n"}};
  l.number_attributes = {{"seed", 7}};
  return l;
}

// A row for small_layout() whose values all equal 100 * index + position.
struct Row {
  std::vector<double> p{0}, x0{0, 0}, states{0, 0, 0, 0, 0, 0}, lambda{0, 0, 0},
      sens{0, 0, 0, 0, 0, 0}, outputs{0, 0, 0}, stats{0};
  SampleRow row(std::int64_t i, int status) {
    for (auto* v : {&p, &x0, &states, &lambda, &sens, &outputs, &stats}) {
      for (std::size_t k = 0; k < v->size(); ++k) (*v)[k] = 100.0 * i + k;
    }
    return {i, status, status == 1 ? "" : "failed", p, x0, states, lambda, sens, outputs, stats, {}, {}, {}, {}, std::nan(""), {}, {}, {}};
  }
};

// Reads a whole float64 dataset with the serial (sec2) driver, as a post-processing tool would.
std::vector<double> read_doubles(const std::string& path, const std::string& dataset) {
  File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  Dataset d(H5Dopen2(file.get(), dataset.c_str(), H5P_DEFAULT), "H5Dopen2");
  Dataspace space(H5Dget_space(d.get()), "H5Dget_space");
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  check(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "read");
  return values;
}

bool has_dataset(const std::string& path, const std::string& dataset) {
  File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  return H5Lexists(file.get(), dataset.c_str(), H5P_DEFAULT) > 0;
}

class RunFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("kanesens_test_run_file_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    path_ = (dir_ / "run.h5").string();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  std::string path_;
};

TEST_F(RunFileTest, WritesRowsAndReadsThemBack) {
  const RunLayout layout = small_layout();
  Row row;
  {
    RunFile file = RunFile::create(MPI_COMM_WORLD, path_, layout, false);
    EXPECT_EQ(file.read_status(), (std::vector<int>{0, 0, 0}));
    file.write_sample(row.row(2, 1));
    file.write_sample(row.row(0, -3));
    EXPECT_EQ(file.read_status(), (std::vector<int>{-3, 0, 1}));
  }  // destructor closes
  EXPECT_FALSE(std::filesystem::exists(path_ + ".partial"));
  const auto states = read_doubles(path_, "/states");  // [sample][time][state]
  ASSERT_EQ(states.size(), 3u * 3 * 2);
  EXPECT_EQ(states[2 * 6 + 5], 205.0);
  EXPECT_TRUE(std::isnan(states[1 * 6]));  // sample 1 never written: NaN fill
  EXPECT_EQ(read_doubles(path_, "/sensitivities")[2 * 6 + 3], 203.0);
  EXPECT_EQ(read_doubles(path_, "/multipliers")[2 * 3 + 1], 201.0);
  EXPECT_EQ(read_doubles(path_, "/outputs/energy")[2 * 3 + 2], 202.0);
  const auto steps = read_doubles(path_, "/solver_stats/steps");
  EXPECT_EQ(steps[0], 0.0);
  EXPECT_TRUE(std::isnan(steps[1]));
  EXPECT_EQ(steps[2], 200.0);
  EXPECT_EQ(read_doubles(path_, "/time"), layout.times);
  EXPECT_EQ(read_doubles(path_, "/sample"), (std::vector<double>{0, 1, 2}));

  File file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  Dataset names(H5Dopen2(file.get(), "/state", H5P_DEFAULT), "H5Dopen2");
  EXPECT_EQ(read_strings(names.get(), "/state"), layout.state_names);
  Dataset message(H5Dopen2(file.get(), "/message", H5P_DEFAULT), "H5Dopen2");
  EXPECT_EQ(read_strings(message.get(), "/message"), (std::vector<std::string>{"failed", "", ""}));
  EXPECT_EQ(read_text_attribute(file.get(), "study_hash"), "abc");
}

TEST_F(RunFileTest, RefusesToReplaceAnExistingFileUnlessOverwrite) {
  RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false).close();
  try {
    RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path_), std::string::npos) << what;
    EXPECT_NE(what.find("--overwrite"), std::string::npos) << what;
    EXPECT_NE(what.find("--resume"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(RunFile::create(MPI_COMM_WORLD, path_, small_layout(), true));
}

TEST_F(RunFileTest, ResumeKeepsWrittenSamples) {
  Row row;
  {
    RunFile file = RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false);
    file.write_sample(row.row(1, 1));
  }
  RunFile file = RunFile::open_for_resume(MPI_COMM_WORLD, path_, small_layout());
  EXPECT_EQ(file.read_status(), (std::vector<int>{0, 1, 0}));
  file.write_sample(row.row(0, 1));
  EXPECT_EQ(file.read_status(), (std::vector<int>{1, 1, 0}));
}

TEST_F(RunFileTest, ResumeRefusesAnotherLayout) {
  RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false).close();
  auto expect_refused = [&](const RunLayout& other, const std::string& says) {
    try {
      RunFile::open_for_resume(MPI_COMM_WORLD, path_, other);
      ADD_FAILURE() << "expected an error saying " << says;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path_), std::string::npos) << e.what();
    }
  };
  RunLayout l = small_layout();
  l.state_names = {"q", "v"};
  expect_refused(l, "state names [q, u] differ from this study's [q, v]");
  l = small_layout();
  l.times.back() = 2.0;
  expect_refused(l, "output times differ");
  l = small_layout();
  l.nsamples = 4;
  expect_refused(l, "it has 3 samples, this study 4");
  l = small_layout();
  l.text_attributes["study_hash"] = "xyz";
  expect_refused(l, "study_hash abc differs from this study's xyz");
  l = small_layout();
  l.record_multipliers = false;
  expect_refused(l, "constraint names [c] differ from this study's []");
  l = small_layout();
  l.stat_names.push_back("rhs_evals");
  expect_refused(l, "no solver statistic 'rhs_evals'");
}

TEST_F(RunFileTest, ResumeOfAMissingFileSaysSo) {
  try {
    RunFile::open_for_resume(MPI_COMM_WORLD, path_, small_layout());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

TEST_F(RunFileTest, RejectsRowsOfTheWrongSizeWithoutWriting) {
  RunFile file = RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false);
  Row row;
  SampleRow bad = row.row(0, 1);
  bad.states = bad.states.first(5);
  EXPECT_THROW(file.write_sample(bad), std::invalid_argument);
  SampleRow out_of_range = row.row(0, 1);
  out_of_range.index = 3;
  EXPECT_THROW(file.write_sample(out_of_range), std::invalid_argument);
  EXPECT_EQ(file.read_status(), (std::vector<int>{0, 0, 0}));
}

TEST_F(RunFileTest, EmptyDimensionsCreateNoDatasets) {
  RunLayout l = small_layout();
  l.constraint_names.clear();
  l.record_sensitivities = false;
  l.parameter_names.clear();
  l.output_names.clear();
  {
    RunFile file = RunFile::create(MPI_COMM_WORLD, path_, l, false);
    const std::vector<double> x0{1, 2}, states(6, 3.0), stats{4}, lambda(3, 0.0);
    SampleRow row;  // (designated initializers that skip members warn under -Wextra)
    row.status = 1;
    row.initial_state = x0;
    row.states = states;
    row.stats = stats;
    file.write_sample(row);
    row.index = 1;
    row.multipliers = lambda;  // not recorded: an error
    EXPECT_THROW(file.write_sample(row), std::invalid_argument);
  }
  for (const char* absent : {"/multipliers", "/constraint", "/sensitivities", "/sensitivity",
                             "/parameters", "/parameter", "/outputs", "/output"}) {
    EXPECT_FALSE(has_dataset(path_, absent)) << absent;
  }
  EXPECT_TRUE(has_dataset(path_, "/states"));
}

// Reads a whole int64 dataset, or a float64 attribute of a group (any shape), serially.
std::vector<std::int64_t> read_int64s(const std::string& path, const std::string& dataset) {
  File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  Dataset d(H5Dopen2(file.get(), dataset.c_str(), H5P_DEFAULT), "H5Dopen2");
  Dataspace space(H5Dget_space(d.get()), "H5Dget_space");
  std::vector<std::int64_t> values(
      static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  check(H5Dread(d.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "read");
  return values;
}

std::vector<double> read_number_attribute(hid_t object, const std::string& name) {
  Attribute attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen");
  Dataspace space(H5Aget_space(attr.get()), "H5Aget_space");
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, values.data()), "H5Aread");
  return values;
}

TEST_F(RunFileTest, WritesDesignLabelsInChunksAndDistributions) {
  RunLayout l = small_layout();
  l.record_sensitivities = l.record_multipliers = false;
  l.nsamples = 70000;  // more than one chunk of labels
  l.parameter_names = {"k", "m"};
  std::int64_t seen = 0;
  std::size_t largest = 0;
  l.design_labels = [&](std::int64_t first, std::span<std::int64_t> block,
                        std::span<std::int64_t> row, std::span<std::int64_t> input) {
    EXPECT_EQ(first, seen);
    seen += static_cast<std::int64_t>(block.size());
    largest = std::max(largest, block.size());
    for (std::size_t k = 0; k < block.size(); ++k) {
      const std::int64_t i = first + static_cast<std::int64_t>(k);
      block[k] = i / 3;
      row[k] = i % 3;
      input[k] = i % 3 - 1;
    }
  };
  l.distributions = {{"k", "uniform", {{"low", 0.8}, {"high", 1.2}}, {}},
                     {"m", "choice", {}, {0.5, 3.0}}};
  RunFile::create(MPI_COMM_WORLD, path_, l, false).close();
  EXPECT_EQ(seen, l.nsamples);
  EXPECT_LT(largest, static_cast<std::size_t>(l.nsamples));  // bounded memory
  const auto block = read_int64s(path_, "/design_block"), row = read_int64s(path_, "/design_row"),
             input = read_int64s(path_, "/design_input");
  ASSERT_EQ(block.size(), 70000u);
  for (std::int64_t i : {0L, 1L, 2L, 65535L, 65536L, 65537L, 69999L}) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(block[k], i / 3);
    EXPECT_EQ(row[k], i % 3);
    EXPECT_EQ(input[k], i % 3 - 1);
  }
  File file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  Group k(H5Gopen2(file.get(), "/vary/k", H5P_DEFAULT), "H5Gopen2");
  EXPECT_EQ(read_text_attribute(k.get(), "distribution"), "uniform");
  EXPECT_EQ(read_number_attribute(k.get(), "low"), std::vector<double>{0.8});
  EXPECT_EQ(read_number_attribute(k.get(), "high"), std::vector<double>{1.2});
  Group m(H5Gopen2(file.get(), "/vary/m", H5P_DEFAULT), "H5Gopen2");
  EXPECT_EQ(read_text_attribute(m.get(), "distribution"), "choice");
  EXPECT_EQ(read_number_attribute(m.get(), "values"), (std::vector<double>{0.5, 3.0}));
}

TEST_F(RunFileTest, NoLabelsOrDistributionsUnlessGiven) {
  RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false).close();
  for (const char* absent : {"/design_block", "/design_row", "/design_input", "/vary"}) {
    EXPECT_FALSE(has_dataset(path_, absent)) << absent;
  }
}

TEST_F(RunFileTest, RefusesDistributionsOfUnknownOrUnnamableInputs) {
  RunLayout l = small_layout();
  l.distributions = {{"m", "uniform", {{"low", 0.0}, {"high", 1.0}}, {}}};  // "m" is no parameter
  EXPECT_THROW(RunFile::create(MPI_COMM_WORLD, path_, l, false), std::invalid_argument);
  l.parameter_names = {"a/b"};
  l.distributions = {{"a/b", "uniform", {{"low", 0.0}, {"high", 1.0}}, {}}};
  EXPECT_THROW(RunFile::create(MPI_COMM_WORLD, path_, l, false), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path_));
}

TEST_F(RunFileTest, StoresLongTextAttributes) {
  RunLayout l = small_layout();
  const std::string scene(100000, 'y');  // above the 64 KiB of a compact attribute
  l.text_attributes["scene_yaml"] = scene;
  RunFile::create(MPI_COMM_WORLD, path_, l, false).close();
  File file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  EXPECT_EQ(read_text_attribute(file.get(), "scene_yaml"), scene);
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(RunFileTest, CreateNeverFollowsOrTruncatesWhatIsAtThePartialName) {
  const std::string target = (dir_ / "precious.txt").string(), partial = path_ + ".partial";
  { std::ofstream(target) << "precious\n"; }
  std::filesystem::create_symlink(target, partial);
  // Without --overwrite: refused (exclusive creation), the link and its target untouched.
  EXPECT_THROW(RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false), std::runtime_error);
  EXPECT_EQ(file_bytes(target), "precious\n");
  EXPECT_TRUE(std::filesystem::is_symlink(partial));
  EXPECT_FALSE(std::filesystem::exists(path_));
  // With --overwrite the stale link is removed, never written through.
  RunFile::create(MPI_COMM_WORLD, path_, small_layout(), true).close();
  EXPECT_EQ(file_bytes(target), "precious\n");
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(partial)));
  // An output that is itself a link to a file is replaced as a name (--overwrite), not written
  // through.
  std::filesystem::remove(path_);
  std::filesystem::create_symlink(target, path_);
  EXPECT_THROW(RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false), std::runtime_error);
  RunFile::create(MPI_COMM_WORLD, path_, small_layout(), true).close();
  EXPECT_EQ(file_bytes(target), "precious\n");
  EXPECT_FALSE(std::filesystem::is_symlink(path_));
}

TEST_F(RunFileTest, CreateRefusesADirectoryAtThePartialName) {
  std::filesystem::create_directory(path_ + ".partial");
  EXPECT_THROW(RunFile::create(MPI_COMM_WORLD, path_, small_layout(), true), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_directory(path_ + ".partial"));
  EXPECT_FALSE(std::filesystem::exists(path_));
}

// A run file is input too: each hostile edit of a real file must be refused by --resume, with
// the file left byte-identical, instead of being written through (a heap overflow or heap
// memory in the file, before these checks).
TEST_F(RunFileTest, ResumeRefusesFilesWhoseDatasetsAreNotWhatItWrites) {
  auto replace = [](hid_t f, const char* name, hid_t type, std::vector<hsize_t> dims, hid_t dcpl = H5P_DEFAULT) {
    check(H5Ldelete(f, name, H5P_DEFAULT), "H5Ldelete");
    Dataspace space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), "space");
    Dataset(H5Dcreate2(f, name, type, space.get(), H5P_DEFAULT, dcpl, H5P_DEFAULT), "H5Dcreate2");
  };
  const std::vector<std::pair<std::string, std::function<void(hid_t)>>> edits = {
      {"dataset /status has shape (5)", [&](hid_t f) { replace(f, "/status", H5T_STD_I32LE, {5}); }},
      {"dataset /states has shape (3, 3, 3)", [&](hid_t f) { replace(f, "/states", H5T_IEEE_F64LE, {3, 3, 3}); }},
      {"dataset /status is not int32", [&](hid_t f) { replace(f, "/status", H5T_IEEE_F64LE, {3}); }},
      {"dataset /parameters is not float64", [&](hid_t f) { replace(f, "/parameters", H5T_STD_I8LE, {3, 1}); }},
      {"dataset /message has strings of 8 bytes", [&](hid_t f) {
         const Datatype t = make_string_type(8);
         replace(f, "/message", t.get(), {3});
       }},
      {"dataset /message is not of fixed-length strings", [&](hid_t f) {
         Datatype t(H5Tcopy(H5T_C_S1), "H5Tcopy");
         check(H5Tset_size(t.get(), H5T_VARIABLE), "H5Tset_size");
         replace(f, "/message", t.get(), {3});
       }},
      {"it has 4 samples, this study 3", [&](hid_t f) { replace(f, "/sample", H5T_STD_I64LE, {4}); }},
      {"dataset /sample is not int64", [&](hid_t f) { replace(f, "/sample", H5T_IEEE_F32LE, {3}); }},
      {"/states is a soft or external link", [&](hid_t f) {
         check(H5Ldelete(f, "/states", H5P_DEFAULT), "H5Ldelete");
         check(H5Lcreate_soft("/sensitivities", f, "/states", H5P_DEFAULT, H5P_DEFAULT), "soft");
       }},
      {"/status is a soft or external link", [&](hid_t f) {
         check(H5Ldelete(f, "/status", H5P_DEFAULT), "H5Ldelete");
         check(H5Lcreate_external("elsewhere.h5", "/status", f, "/status", H5P_DEFAULT, H5P_DEFAULT), "ext");
       }},
      {"dataset /states keeps its data in an external file", [&](hid_t f) {
         PropertyList dcpl(H5Pcreate(H5P_DATASET_CREATE), "dcpl");
         check(H5Pset_external(dcpl.get(), "precious.bin", 0, H5F_UNLIMITED), "H5Pset_external");
         replace(f, "/states", H5T_IEEE_F64LE, {3, 3, 2}, dcpl.get());
       }},
      {"dataset /initial_state is filtered", [&](hid_t f) {
         PropertyList dcpl(H5Pcreate(H5P_DATASET_CREATE), "dcpl");
         const hsize_t chunk[2] = {1, 2};
         check(H5Pset_chunk(dcpl.get(), 2, chunk), "H5Pset_chunk");
         check(H5Pset_shuffle(dcpl.get()), "H5Pset_shuffle");
         replace(f, "/initial_state", H5T_IEEE_F64LE, {3, 2}, dcpl.get());
       }},
      {"dataset /multipliers is missing", [&](hid_t f) { check(H5Ldelete(f, "/multipliers", H5P_DEFAULT), "del"); }},
      {"dataset /solver_stats/steps is not a dataset", [&](hid_t f) {
         check(H5Ldelete(f, "/solver_stats/steps", H5P_DEFAULT), "H5Ldelete");
         Group(H5Gcreate2(f, "/solver_stats/steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2");
       }},
      {"it has no study_hash attribute", [&](hid_t f) { check(H5Adelete(f, "study_hash"), "H5Adelete"); }},
      {"attribute study_hash is not a single string", [&](hid_t f) {
         check(H5Adelete(f, "study_hash"), "H5Adelete");
         const Datatype t = make_string_type(3);
         const hsize_t two = 2;
         Dataspace space(H5Screate_simple(1, &two, nullptr), "space");
         Attribute(H5Acreate2(f, "study_hash", t.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2");
       }},
      {"state names [] differ from this study's [q, u]", [&](hid_t f) {  // 5 empty names
         const Datatype t = make_string_type(4);
         replace(f, "/state", t.get(), {5});
       }},
  };
  for (const auto& [says, edit] : edits) {
    std::filesystem::remove(path_);
    RunFile::create(MPI_COMM_WORLD, path_, small_layout(), false).close();
    {
      File f(H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "H5Fopen");
      edit(f.get());
    }
    const std::string before = file_bytes(path_);
    try {
      RunFile file = RunFile::open_for_resume(MPI_COMM_WORLD, path_, small_layout());
      ADD_FAILURE() << "accepted a file where " << says;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("cannot resume '" + path_ + "'"), std::string::npos) << e.what();
    }
    EXPECT_EQ(file_bytes(path_), before) << says;
  }
}

TEST_F(RunFileTest, StudyOutputsTheirSensitivitiesAndPoses) {
  RunLayout l = small_layout();
  l.output_names = {"energy", "tip.x"};
  l.scalar_output_names = {"work"};
  l.output_sensitivity_names = {"tip.x"};
  l.scalar_output_sensitivity_names = {"work"};
  l.body_names = {"rod"};
  l.record_poses = true;
  // Written as a block of two samples (the ensemble's path) and as one row.
  std::vector<double> outputs(2 * 3), scalars{1.5}, output_sens(3 * 1), scalar_sens{2.5}, poses(3 * 1 * 7), stats{7};
  for (std::size_t k = 0; k < outputs.size(); ++k) outputs[k] = 10.0 + k;
  for (std::size_t k = 0; k < output_sens.size(); ++k) output_sens[k] = 20.0 + k;
  for (std::size_t k = 0; k < poses.size(); ++k) poses[k] = 30.0 + k;
  const auto set_outputs = [&](SampleRow& row) {
    row.outputs = outputs;
    row.scalar_outputs = scalars;
    row.output_sensitivities = output_sens;
    row.scalar_output_sensitivities = scalar_sens;
    row.poses = poses;
  };
  Row r;
  SampleBlock block;
  for (std::int64_t i = 0; i < 2; ++i) {
    SampleRow row = r.row(i, 1);
    set_outputs(row);
    row.stats = stats;
    block.append(row);
  }
  {
    RunFile file = RunFile::create(MPI_COMM_WORLD, path_, l, false);
    file.write_samples(block);
    SampleRow row = r.row(2, 1);
    set_outputs(row);
    file.write_sample(row);
    SampleRow missing = row;
    missing.poses = {};
    EXPECT_THROW(file.write_sample(missing), std::invalid_argument);
  }
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read_doubles(path_, "/outputs/tip.x")[i * 3 + 2], 15.0);
    EXPECT_EQ(read_doubles(path_, "/outputs/work")[i], 1.5);
    EXPECT_EQ(read_doubles(path_, "/output_sensitivities/tip.x")[i * 3 + 1], 21.0);  // (sample, time, sens)
    EXPECT_EQ(read_doubles(path_, "/output_sensitivities/work")[i], 2.5);
    EXPECT_EQ(read_doubles(path_, "/poses")[i * 21 + 7 * 2 + 6], 30.0 + 20);  // (sample, time, body, pose)
  }
  File file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen");
  Dataset pose(H5Dopen2(file.get(), "/pose", H5P_DEFAULT), "H5Dopen2");
  EXPECT_EQ(read_strings(pose.get(), "/pose"), (std::vector<std::string>{"x", "y", "z", "qw", "qx", "qy", "qz"}));
  Dataset output(H5Dopen2(file.get(), "/output", H5P_DEFAULT), "H5Dopen2");
  EXPECT_EQ(read_strings(output.get(), "/output"), (std::vector<std::string>{"energy", "tip.x", "work"}));
  RunLayout other = l;
  other.scalar_output_names = {"work2"};
  other.scalar_output_sensitivity_names = {"work2"};
  EXPECT_THROW(RunFile::open_for_resume(MPI_COMM_WORLD, path_, other), std::runtime_error);
  EXPECT_NO_THROW(RunFile::open_for_resume(MPI_COMM_WORLD, path_, l));
}

}  // namespace
}  // namespace kanesens::io
