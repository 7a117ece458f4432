// libFuzzer: a run file is input too. Each input is a list of edits applied to a real run file
// (made once by io::RunFile::create, one sample written): datasets deleted, re-created with
// another element type, rank or shape, replaced by groups, soft or external links, external raw
// storage or filters; values overwritten (/status, /time, /sample, names); attributes deleted or
// re-created with another type or shape. The edited file goes through what `run --resume` does:
// RunFile::open_for_resume, read_status, then a row written for every sample still to run. A
// refusal (std::runtime_error) is expected; a crash, another exception or a sanitizer report (a
// write past a buffer, heap memory put into the file) is a finding. HDF5's own parsing of
// corrupt bytes is out of scope: the edits go through the HDF5 API, so every file is well-formed.
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"
#include "io/hdf5_text.hpp"
#include "io/run_file.hpp"
#include "../support/scratch_dir.hpp"

namespace {

using namespace kanesens::io;

RunLayout layout() {
  RunLayout l;
  l.times = {0.0, 0.5, 1.0};
  l.state_names = {"j.q", "j.u"};
  l.parameter_names = {"k"};
  l.sensitivity_names = {"k"};
  l.constraint_names = {"c"};
  l.output_names = {"energy"};
  l.stat_names = {"steps"};
  l.nsamples = 4;
  l.record_sensitivities = l.record_multipliers = true;
  l.text_attributes = {{"study_hash", "0123456789abcdef"}, {"scene_yaml", "scene: {}\n"}};
  l.number_attributes = {{"seed", 7}, {"samples", 4}};
  return l;
}

struct Files {
  std::filesystem::path dir;
  std::string path;
  std::string pristine;  // the bytes of the real run file
};

Files& files() {
  static const kanesens::testing::ScratchDir scratch("kanesens_fuzz_resume");  // removed at exit
  static Files f = [] {
    Files x;
    x.dir = scratch.path();
    x.path = (x.dir / "run.h5").string();
    {
      RunFile file = RunFile::create(MPI_COMM_SELF, x.path, layout(), true);
      const std::vector<double> p{1}, x0{0, 0}, states(6, 0.5), lambda(3, 0.25), sens(6, 0.125), out(3, 2.0), stats{10};
      file.write_sample({.index = 1, .status = 1, .message = "", .parameters = p, .initial_state = x0, .states = states,
                         .multipliers = lambda, .sensitivities = sens, .outputs = out, .stats = stats});
      file.close();
    }
    std::ifstream in(x.path, std::ios::binary);
    x.pristine.assign(std::istreambuf_iterator<char>(in), {});
    return x;
  }();
  return f;
}

// Reads the input a byte at a time (0 when it runs out).
struct Bytes {
  const std::uint8_t* p;
  std::size_t n;
  std::uint8_t next() { return n ? (--n, *p++) : 0; }
  bool empty() const { return n == 0; }
};

const char* const kPaths[] = {"/status",      "/message",    "/states",   "/parameters",    "/initial_state",
                              "/multipliers", "/sensitivities", "/outputs/energy", "/solver_stats/steps",
                              "/sample",      "/time",       "/state",    "/parameter",     "/sensitivity",
                              "/constraint",  "/output",     "/state_name", "/outputs",     "/solver_stats"};
constexpr std::size_t kNumPaths = sizeof kPaths / sizeof kPaths[0];
const char* const kAttributes[] = {"study_hash", "seed", "samples", "scene_yaml"};

hid_t element_type(std::uint8_t b, Datatype& keep) {
  switch (b % 9) {
    case 0: return H5T_STD_I8LE;
    case 1: return H5T_STD_I32LE;
    case 2: return H5T_STD_I64LE;
    case 3: return H5T_IEEE_F32LE;
    case 4: return H5T_IEEE_F64LE;
    case 5: return H5T_STD_U16BE;
    case 6:
      keep = Datatype(H5Tcopy(H5T_C_S1), "H5Tcopy");
      check(H5Tset_size(keep.get(), H5T_VARIABLE), "H5Tset_size");
      return keep.get();
    default:
      keep = make_string_type(1 + b % 300);
      return keep.get();
  }
}

// Small, or (for datasets, whose storage HDF5 allocates lazily) up to 2^19 along an axis. An
// attribute is written whole into the object header when created, so its dimensions stay small.
std::vector<hsize_t> dims(Bytes& in, bool allow_large) {
  std::vector<hsize_t> d(in.next() % 4);
  for (auto& x : d) {
    const std::uint8_t b = in.next();
    x = b < 250 || !allow_large ? b % 9 : hsize_t{1} << (10 + b % 10);
  }
  return d;
}

void remove(hid_t f, const char* path) {
  if (H5Lexists(f, path, H5P_DEFAULT) > 0) H5Ldelete(f, path, H5P_DEFAULT);
}

// One edit; HDF5 failures (an edit that does not apply) are ignored.
void edit(hid_t f, Bytes& in) {
  const std::uint8_t op = in.next();
  const char* path = kPaths[in.next() % kNumPaths];
  switch (op % 9) {
    case 0:
      remove(f, path);
      break;
    case 1: {  // another type, rank or shape, maybe chunked and filtered, or stored elsewhere
      Datatype keep;
      const hid_t type = element_type(in.next(), keep);
      const std::vector<hsize_t> d = dims(in, true);
      PropertyList dcpl(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate");
      const std::uint8_t storage = in.next() % 4;
      if (storage == 1 && !d.empty()) {
        std::vector<hsize_t> chunk(d.size(), 1);
        H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
        H5Pset_shuffle(dcpl.get());
      } else if (storage == 2) {
        // HDF5 reads and writes that file: keep it in the work directory, not the current one.
        H5Pset_external(dcpl.get(), (files().dir / "precious.bin").c_str(), 0, H5F_UNLIMITED);
      } else if (storage == 3) {
        H5Pset_layout(dcpl.get(), H5D_COMPACT);
      }
      remove(f, path);
      Dataspace space(d.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr),
                      "H5Screate");
      const hid_t id = H5Dcreate2(f, path, type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT);
      if (id >= 0) H5Dclose(id);
      break;
    }
    case 2: {  // a soft link to another object of the file
      const char* target = kPaths[in.next() % kNumPaths];
      remove(f, path);
      H5Lcreate_soft(target, f, path, H5P_DEFAULT, H5P_DEFAULT);
      break;
    }
    case 3:
      remove(f, path);
      H5Lcreate_external("elsewhere.h5", kPaths[in.next() % kNumPaths], f, path, H5P_DEFAULT, H5P_DEFAULT);
      break;
    case 4: {
      remove(f, path);
      const hid_t g = H5Gcreate2(f, path, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (g >= 0) H5Gclose(g);
      break;
    }
    case 5: {  // overwrite values with the input's bytes, converted to the dataset's own type
      const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
      if (d < 0) break;
      const hid_t space = H5Dget_space(d);
      const hssize_t n = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
      if (n > 0 && n < 4096) {
        std::vector<std::int32_t> v(static_cast<std::size_t>(n));
        for (auto& x : v) x = static_cast<std::int8_t>(in.next());
        H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
      }
      if (space >= 0) H5Sclose(space);
      H5Dclose(d);
      break;
    }
    case 6: {  // an attribute removed, or re-created with another type or shape
      const char* name = kAttributes[in.next() % 4];
      if (H5Aexists(f, name) > 0) H5Adelete(f, name);
      if (in.next() % 2) break;
      Datatype keep;
      const hid_t type = element_type(in.next(), keep);
      const std::vector<hsize_t> d = dims(in, false);
      Dataspace space(d.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr),
                      "H5Screate");
      const hid_t a = H5Acreate2(f, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT);
      if (a >= 0) H5Aclose(a);
      break;
    }
    case 7:  // a hard link: two paths, one object
      remove(f, path);
      H5Lcreate_hard(f, kPaths[in.next() % kNumPaths], f, path, H5P_DEFAULT, H5P_DEFAULT);
      break;
    default: {  // the study_hash kept, its value changed
      if (H5Aexists(f, "study_hash") > 0) H5Adelete(f, "study_hash");
      std::string text;
      for (std::uint8_t len = in.next() % 24; len > 0; --len) text.push_back(static_cast<char>('0' + in.next() % 40));
      write_text_attribute(f, "study_hash", in.next() % 2 ? std::string("0123456789abcdef") : text);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  MPI_Init(argc, argv);
  silence_hdf5_errors();
  files();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Files& f = files();
  std::ofstream(f.path, std::ios::binary | std::ios::trunc) << f.pristine;
  {
    const hid_t file = H5Fopen(f.path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0) return 0;
    Bytes in{data, size};
    for (int k = 0; k < 8 && !in.empty(); ++k) edit(file, in);
    H5Fclose(file);
  }
  try {
    RunFile file = RunFile::open_for_resume(MPI_COMM_SELF, f.path, layout());
    const std::vector<int> status = file.read_status();
    const std::vector<double> p{1}, x0{0, 0}, states(6, 0.5), lambda(3, 0.25), sens(6, 0.125), out(3, 2.0), stats{10};
    for (std::size_t i = 0; i < status.size(); ++i)
      if (status[i] == 0) file.write_sample({.index = static_cast<std::int64_t>(i), .status = 1, .message = "resumed", .parameters = p,
                           .initial_state = x0, .states = states, .multipliers = lambda, .sensitivities = sens,
                           .outputs = out, .stats = stats});
    file.close();
  } catch (const std::runtime_error&) {  // refused (or an HDF5 call failed): a clear error, not a crash
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_resume: unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
