// libFuzzer: study YAML text -> the `sampling:` and `vary:` parsers and the Design, then a few
// samples (first, last, middle). Bad input must be an InputError; crashes, other exceptions and
// sanitizer reports are findings.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "study/design.hpp"
#include "study/parse_sampling.hpp"
#include "study/parse_vary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace kanesens;
  const std::string text(reinterpret_cast<const char*>(data), size);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception&) {
    return 0;  // malformed YAML: model::load_yaml turns this into an InputError (unit-tested)
  }
  if (!doc.IsMap()) return 0;
  try {
    const SourceLocation file{"fuzz.yaml", 0, 0};
    std::vector<study::VariedInput> inputs = study::parse_vary(doc["vary"], file);
    study::SamplingSpec spec;
    if (doc["sampling"] && !doc["sampling"].IsNull()) spec = study::parse_sampling(doc["sampling"], file);
    else spec.samples = 1;
    const study::Design design(spec, std::move(inputs));
    std::vector<double> values(design.dimension());
    const std::int64_t n = design.size();
    for (const std::int64_t i : {std::int64_t{0}, n / 2, n - 1}) design.sample(i, values);
  } catch (const InputError&) {
  } catch (const std::invalid_argument&) {
    // Design's documented error for inputs parse_vary already rejects with a location.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_study: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
