#include "util/version.hpp"

#include <hdf5.h>
#include <mpi.h>
#include <sundials/sundials_config.h>

#include <Eigen/Core>
#include <sstream>

#include "kanesens/git_revision.hpp"
#include "kanesens/version_config.hpp"

namespace kanesens {

std::string version_short() {
  return std::string(KANESENS_VERSION_STRING) + " (git " + KANESENS_GIT_REVISION + ")";
}

std::string version_report() {
  std::ostringstream out;
  out << "kanesens " << version_short() << "\n";
  out << "SUNDIALS " << SUNDIALS_VERSION << " (CVODES)\n";
  out << "HDF5 " << H5_VERS_MAJOR << "." << H5_VERS_MINOR << "." << H5_VERS_RELEASE
#ifdef H5_HAVE_PARALLEL
      << " (parallel)"
#endif
      << "\n";
#if defined(OMPI_MAJOR_VERSION)
  out << "MPI " << MPI_VERSION << "." << MPI_SUBVERSION << " (Open MPI " << OMPI_MAJOR_VERSION << "."
      << OMPI_MINOR_VERSION << "." << OMPI_RELEASE_VERSION << ")\n";
#else
  out << "MPI " << MPI_VERSION << "." << MPI_SUBVERSION << "\n";
#endif
  out << "Eigen " << EIGEN_WORLD_VERSION << "." << EIGEN_MAJOR_VERSION << "." << EIGEN_MINOR_VERSION
      << "\n";
  out << "compiler " << __VERSION__ << "\n";
  return out.str();
}

}  // namespace kanesens
