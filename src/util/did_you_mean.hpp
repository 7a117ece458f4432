// "did you mean" suggestions for unknown names and keys (edit distance).
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace kanesens {

// Edit distance between a and b (insertions, deletions, substitutions, transpositions).
std::size_t edit_distance(std::string_view a, std::string_view b);
// Names longer than this get no suggestion (keeps the search linear in the input's size).
inline constexpr std::size_t kMaxSuggestedLength = 256;
// The closest candidate within a distance of max(1, |word|/3), or "" when none is close.
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or "" — ready to append to an error message.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);
// "a, b, c" (or "(none)").
std::string join_names(const std::vector<std::string>& names);

// The same for lists of string views.
std::string closest_match(std::string_view word, std::span<const std::string_view> candidates);
std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates);
std::string join_names(std::span<const std::string_view> names);

}  // namespace kanesens
