#include <gtest/gtest.h>

#include "parallel/version.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

TEST(Version, ReportNamesEveryLibrary) {
  const std::string report = kanesens::parallel::version_report();
  for (const char* name : {"kanesens", "SUNDIALS 6.", "HDF5 1.", "MPI ", "Eigen 3."}) {
    EXPECT_NE(report.find(name), std::string::npos) << name << " missing from:\n" << report;
  }
}

}  // namespace KANESENS_UNITY_ID
