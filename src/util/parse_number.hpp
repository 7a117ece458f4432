// Strict parsing of numbers given on the command line (--set, --q, --u).
#pragma once
#include <map>
#include <string>
#include <vector>

namespace kanesens {

// The whole string must be a finite number; otherwise InputError naming `what`.
// hint, if given, is added to the message when text is not a number at all.
double parse_number(const std::string& text, const std::string& what, const std::string& hint = {});
// "0.1,-2,3e-4" → {0.1, -2, 3e-4}.
std::vector<double> parse_number_list(const std::string& text, const std::string& what);
// {"m2=0.9", "elbow.q0=0.3"} → {{"m2", 0.9}, {"elbow.q0", 0.3}}.
std::map<std::string, std::string> parse_assignments(const std::vector<std::string>& items);

}  // namespace kanesens
