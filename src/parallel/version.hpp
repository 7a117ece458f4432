// `kanesens --version`: the kanesens version and git revision, and the versions of the libraries
// it was built against (SUNDIALS, HDF5, MPI, Eigen, the compiler). Also stored in every run file.
#pragma once
#include <string>

namespace kanesens::parallel {

// One line per component, e.g. "kanesens 0.1.0 (git abc123)\nSUNDIALS 6.4.1 (CVODES)\n...".
std::string version_report();

}  // namespace kanesens::parallel
