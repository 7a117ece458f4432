#include <gtest/gtest.h>

#include "parallel/version.hpp"

TEST(Version, ReportNamesEveryLibrary) {
  const std::string report = kanesens::parallel::version_report();
  for (const char* name : {"kanesens", "SUNDIALS 6.", "HDF5 1.", "MPI ", "Eigen 3."}) {
    EXPECT_NE(report.find(name), std::string::npos) << name << " missing from:\n" << report;
  }
}
