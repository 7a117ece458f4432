// A libFuzzer custom mutator for YAML scene and study files (include in one harness file).
// Half the time it mutates like a careless or hostile user edits a working file: one number
// becomes another (0, -1, 1e308, 1e-320, .nan, 1e400, x·10^k, ...), one name becomes another name
// of the same file (a joint used as a body, a body of a welded joint in a constraint, a speed
// listed twice), a name grows, shrinks or gains a dot, or a line is repeated or dropped; the
// other half it uses libFuzzer's own byte-level mutations. Seeded from the shipped scenes and
// studies (configs/), the number and name mutations reach the model build, the constraint and
// force construction and the initial-state checks with valid YAML most of the time.
#pragma once
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace kanesens_fuzz {

struct Token {
  std::size_t begin, end;
  bool number;
};

inline bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }

// Numbers (not digits inside names such as rod1) and names (letters, digits, _, dots).
inline std::vector<Token> tokens(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    const bool after_name = i > 0 && name_char(s[i - 1]);
    if (!after_name && (std::isdigit(static_cast<unsigned char>(c)) || ((c == '-' || c == '+' || c == '.') && i + 1 < s.size() &&
                                                                          std::isdigit(static_cast<unsigned char>(s[i + 1]))))) {
      std::size_t j = i + 1;
      while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == 'e' || s[j] == 'E' ||
                              ((s[j] == '-' || s[j] == '+') && (s[j - 1] == 'e' || s[j - 1] == 'E'))))
        ++j;
      out.push_back({i, j, true});
      i = j;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t j = i + 1;
      while (j < s.size() && name_char(s[j])) ++j;
      out.push_back({i, j, false});
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

inline std::string mutate_number(const std::string& x, std::minstd_rand& rng) {
  static const char* special[] = {"0",     "-0",   "1",     "-1",     "2",    "0.5",  "1e-12", "1e-320", "1e16",
                                  "1e200", "1e308", "-1e308", "1e400", ".nan", ".inf", "nan",   "3.0e+8", "4294967297",
                                  "9223372036854775807", "-5", "10000000", "0.0000001"};
  const std::size_t n_special = sizeof special / sizeof special[0];
  switch (rng() % 4) {
    case 0:
    case 1: return special[rng() % n_special];
    case 2: return (rng() % 2 ? "-" : "") + x;
    default: return x + "e" + std::to_string(static_cast<int>(rng() % 41) - 20);
  }
}

inline std::string mutate_text(const std::string& s, std::minstd_rand& rng) {
  const std::vector<Token> t = tokens(s);
  if (t.empty()) return s;
  const Token& k = t[rng() % t.size()];
  const std::string word = s.substr(k.begin, k.end - k.begin);
  std::string replacement;
  const unsigned what = rng() % 10;
  if (what == 0) {  // repeat or drop the line of the token
    const std::size_t line_begin = s.rfind('\n', k.begin) == std::string::npos ? 0 : s.rfind('\n', k.begin) + 1;
    std::size_t line_end = s.find('\n', k.begin);
    line_end = line_end == std::string::npos ? s.size() : line_end + 1;
    const std::string line = s.substr(line_begin, line_end - line_begin);
    return s.substr(0, line_begin) + (rng() % 2 ? line + line : std::string()) + s.substr(line_end);
  }
  if (k.number) {
    replacement = mutate_number(word, rng);
  } else {
    std::vector<std::size_t> names;
    for (std::size_t i = 0; i < t.size(); ++i)
      if (!t[i].number) names.push_back(i);
    switch (what % 5) {
      case 0: replacement = word + word.substr(0, 1); break;          // a name that almost exists
      case 1: replacement = word.size() > 1 ? word.substr(0, word.size() - 1) : "x"; break;
      case 2: replacement = word + ".x"; break;                        // row-name and state-name shapes
      default: {                                                       // another name of the file
        const Token& o = t[names[rng() % names.size()]];
        replacement = s.substr(o.begin, o.end - o.begin);
      }
    }
  }
  return s.substr(0, k.begin) + replacement + s.substr(k.end);
}

}  // namespace kanesens_fuzz

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  std::minstd_rand rng(seed);
  if (rng() % 2 == 0) return LLVMFuzzerMutate(data, size, max_size);
  std::string text(reinterpret_cast<const char*>(data), size);
  for (unsigned n = 1 + rng() % 3; n > 0; --n) text = kanesens_fuzz::mutate_text(text, rng);
  if (text.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, text.data(), text.size());
  return text.size();
}
