// libFuzzer: scene YAML text -> what `kanesens check` does: parse, build the model (validation,
// expressions, constraints and forces, nominal parameter checks), then the sample at its initial
// state (consistent initial conditions, the constraint rows, Kane's equations with its forces),
// and the exact Jacobian there (numerical failures, RecoverableError, are what a run reports).
// Bad input must be an InputError; any other exception, a crash, a hang or a sanitizer report is a
// finding. Mutations: yaml_mutator.hpp (numbers and names of the shipped scenes) and libFuzzer's.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/kane_problem.hpp"
#include "yaml_mutator.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace kanesens;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const model::Model m = model::build_model(model::parse_scene_text(text, "fuzz.yaml"));
    sim::KaneProblem problem(m, {});
    problem.validate_initial_state();
    // The exact Jacobian there, as BDF asks for it (closed form, residual pass or whole passes).
    // A RecoverableError is a numerical failure the solvers retry or report (a mass matrix
    // that is positive definite on doubles but not in the dual factorisation, for one).
    const std::size_t n = static_cast<std::size_t>(problem.size());
    std::vector<double> y(n), ydot(n), J(n * n);
    problem.initial_state(y.data());
    try {
      problem.rhs(problem.initial_time(), y.data(), ydot.data());
      problem.jacobian(problem.initial_time(), y.data(), ydot.data(), J.data());
    } catch (const sim::RecoverableError&) {
    }
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_scene: not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
