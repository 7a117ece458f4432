// The build's identity: kanesens version and git revision. The libraries' versions are added by
// parallel/version.hpp, where SUNDIALS, HDF5 and MPI are linked.
#pragma once
#include <string>

namespace kanesens {

// "0.1.0 (git abc123)".
std::string version_short();
// What the build was compiled for: "-march=VALUE (the extensions it requires)" or the
// compiler's baseline (util/instruction_set.cpp, which also stops a program on a processor that
// lacks them).
std::string instruction_set();

}  // namespace kanesens
