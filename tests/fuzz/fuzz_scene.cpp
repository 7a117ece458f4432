// libFuzzer: scene YAML text -> what `kanesens check` does: parse, build the model (validation,
// expressions, constraints and forces, nominal parameter checks), then the sample at its initial
// state (consistent initial conditions, the constraint rows, Kane's equations with its forces).
// Bad input must be an InputError; any other exception, a crash, a hang or a sanitizer report is a
// finding. Mutations: yaml_mutator.hpp (numbers and names of the shipped scenes) and libFuzzer's.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "yaml_mutator.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace kanesens;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const model::Model m = model::build_model(model::parse_scene_text(text, "fuzz.yaml"));
    sim::KaneProblem(m, {}).validate_initial_state();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_scene: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
