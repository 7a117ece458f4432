// libFuzzer: study YAML text -> what `simulate` and `run` check before anything is created
// (study::setup_study: the study, its scene — inline, or a shipped scene beside it — the solver
// and time settings, sampling and vary, every name, the nominal sample at its initial state),
// then a few samples of the design (first, middle, last). Bad input must be an InputError;
// crashes, other exceptions, hangs and sanitizer reports are findings.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../support/scratch_dir.hpp"
#include "study/setup.hpp"
#include "yaml_mutator.hpp"

namespace {
// A directory with a copy of the shipped scenes, where each input is written as study.yaml.
// Removed, with its files, when the harness exits.
const std::filesystem::path& work_dir() {
  static const kanesens::testing::ScratchDir dir("kanesens_fuzz_study");
  static const bool copied = [] {
    for (const auto& f : std::filesystem::directory_iterator(KANESENS_CONFIGS_DIR))
      if (f.path().extension() == ".yaml")
        std::filesystem::copy_file(f.path(), dir.path() / f.path().filename(),
                                   std::filesystem::copy_options::overwrite_existing);
    return true;
  }();
  (void)copied;
  return dir.path();
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  work_dir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace kanesens;
  const std::string path = (work_dir() / "study.yaml").string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    const study::StudySetup setup = study::setup_study(path);
    std::vector<double> values(setup.design.dimension());
    const std::int64_t n = setup.design.size();
    for (const std::int64_t i : {std::int64_t{0}, n / 2, n - 1}) {
      try {
        setup.sample(i, values);
      } catch (const std::exception&) {
        // A quantile that overflows is that sample's recorded failure in a run (status < 0).
      }
    }
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_study: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
