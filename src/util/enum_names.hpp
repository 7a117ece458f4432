// An enum's values with their names in the input files, as one table {name, value} per enum:
// the parser reads it (in its order, which its "expected one of ..." lists) and so does the
// printer, so that the two cannot disagree.
#pragma once
#include <cstddef>
#include <string_view>
#include <utility>

namespace kanesens {

template <class E>
using EnumName = std::pair<std::string_view, E>;

// The name of `value` in `names` ("?" for a value the table lacks). The names are literals, so
// name_of(...).data() is null-terminated.
template <class E, std::size_t N>
constexpr std::string_view name_of(const EnumName<E> (&names)[N], E value) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}

}  // namespace kanesens
