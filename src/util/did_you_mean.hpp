// "Did you mean" suggestions for misspelt keys and names in user input.
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace kanesens {

// Levenshtein distance (insert, delete, substitute; each costs 1) plus adjacent transpositions
// (optimal string alignment), so "hgih" is one edit from "high".
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word` if it is close enough to be a plausible typo (distance ≤ 2 and
// less than half the word's length, ties go to the first candidate), otherwise "".
std::string closest_match(std::string_view word, std::span<const std::string_view> candidates);

// " (did you mean 'high'?)" or "" — ready to append to an error message.
std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates);

// "a, b, c" — for messages listing what is allowed.
std::string join_names(std::span<const std::string_view> names);

}  // namespace kanesens
