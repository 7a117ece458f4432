// "did you mean" suggestions for unknown names and keys (edit distance).
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace kanesens {

// Levenshtein distance between a and b.
int edit_distance(std::string_view a, std::string_view b);
// The closest candidate within a distance of max(1, |word|/3), or "" when none is close.
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or "" — ready to append to an error message.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);
// "a, b, c" (or "(none)").
std::string join_names(const std::vector<std::string>& names);

}  // namespace kanesens
