// libFuzzer: scene YAML text -> parse_scene_text + build_model (validation, expression
// compilation, nominal parameter checks). Bad input must be an InputError; any other exception,
// a crash or a sanitizer report is a finding.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const kanesens::Model m = kanesens::build_model(kanesens::parse_scene_text(text, "fuzz.yaml"));
    (void)m;
  } catch (const kanesens::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_scene: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
