#include "util/did_you_mean.hpp"

#include <algorithm>
#include <numeric>

namespace kanesens {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Optimal string alignment (Levenshtein plus Damerau's transposition of neighbours).
  const std::size_t n = b.size();
  std::vector<std::size_t> prev2(n + 1), prev(n + 1), cur(n + 1);
  std::iota(prev.begin(), prev.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= n; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[n];
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  // Bounded work whatever the input: no suggestion for absurdly long names, and candidates whose
  // length alone puts them out of reach are skipped (the distance is at least the difference).
  if (word.size() > kMaxSuggestedLength) return {};
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::size_t gap = c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
    if (gap >= best_d || c.size() > kMaxSuggestedLength) continue;
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string m = closest_match(word, candidates);
  return m.empty() ? std::string{} : " (did you mean '" + m + "'?)";
}

std::string join_names(const std::vector<std::string>& names) {
  if (names.empty()) return "(none)";
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

static std::vector<std::string> to_strings(std::span<const std::string_view> v) {
  return std::vector<std::string>(v.begin(), v.end());
}
std::string closest_match(std::string_view word, std::span<const std::string_view> candidates) {
  return closest_match(word, to_strings(candidates));
}
std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates) {
  return did_you_mean(word, to_strings(candidates));
}
std::string join_names(std::span<const std::string_view> names) { return join_names(to_strings(names)); }

}  // namespace kanesens
