#include "parallel/version.hpp"

#include <mpi.h>

#include <Eigen/Core>
#include <sstream>

#include "io/hdf5_handle.hpp"
#include "sim/solve/integrator.hpp"
#include "util/version.hpp"

namespace kanesens::parallel {

std::string version_report() {
  std::ostringstream out;
  out << "kanesens " << version_short() << "\n";
  out << "SUNDIALS " << sim::sundials_version() << " (CVODES)\n";
  out << "HDF5 " << io::hdf5_version() << "\n";
#if defined(OMPI_MAJOR_VERSION)
  out << "MPI " << MPI_VERSION << "." << MPI_SUBVERSION << " (Open MPI " << OMPI_MAJOR_VERSION << "."
      << OMPI_MINOR_VERSION << "." << OMPI_RELEASE_VERSION << ")\n";
#else
  out << "MPI " << MPI_VERSION << "." << MPI_SUBVERSION << "\n";
#endif
  out << "Eigen " << EIGEN_WORLD_VERSION << "." << EIGEN_MAJOR_VERSION << "." << EIGEN_MINOR_VERSION
      << "\n";
  out << "compiler " << __VERSION__ << ", instruction set " << instruction_set() << "\n";
  return out.str();
}

}  // namespace kanesens::parallel
