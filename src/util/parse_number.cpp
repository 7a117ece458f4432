#include "util/parse_number.hpp"

#include <cmath>
#include <cstdlib>

#include "util/error.hpp"

namespace kanesens {

double parse_number(const std::string& text, const std::string& what, const std::string& hint) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  while (end && *end == ' ') ++end;
  if (text.empty() || end == begin || *end != '\0')
    throw InputError({}, what, "expected a number, found '" + text + "'" + (hint.empty() ? "" : "; " + hint));
  if (!std::isfinite(v)) throw InputError({}, what, "value must be finite, found '" + text + "'");
  return v;
}

std::vector<double> parse_number_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    out.push_back(parse_number(item, what + "[" + std::to_string(out.size()) + "]"));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::map<std::string, std::string> parse_assignments(const std::vector<std::string>& items) {
  std::map<std::string, std::string> out;
  for (const auto& s : items) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({}, "--set", "expected NAME=VALUE, found '" + s + "'");
    out[s.substr(0, eq)] = s.substr(eq + 1);
  }
  return out;
}

}  // namespace kanesens
