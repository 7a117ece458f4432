#include "study/sampling_spec.hpp"

#include <array>

namespace kanesens::study {
namespace {
constexpr std::array<std::string_view, 7> names = {"mc",   "lhs",      "sobol", "halton",
                                                   "grid", "saltelli", "morris"};
}

std::string_view method_name(SamplingMethod m) {
  return names[static_cast<std::size_t>(m)];
}

std::optional<SamplingMethod> method_from_name(std::string_view name) {
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return static_cast<SamplingMethod>(k);
  }
  return std::nullopt;
}

}  // namespace kanesens::study
