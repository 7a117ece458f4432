// The build's identity: kanesens version, git revision and the library versions it was built
// against. Printed by `kanesens --version` and stored in every output file.
#pragma once
#include <string>

namespace kanesens {

// One line per component, e.g. "kanesens 0.1.0 (git abc123)\nSUNDIALS 6.4.1\n...".
std::string version_report();
// "0.1.0 (git abc123)".
std::string version_short();

}  // namespace kanesens
