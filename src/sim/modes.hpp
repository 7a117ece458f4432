// Eigenvalues and eigenvectors of a linearized system ẋ = A x (sim/linearize.hpp): its modes.
#pragma once
#include <Eigen/Dense>

namespace kanesens::sim {

struct Modes {
  // Sorted by decreasing real part (least stable first); equal real parts (a complex-conjugate
  // pair) by decreasing imaginary part.
  Eigen::VectorXcd values;
  // Column k: a right eigenvector of values[k], unit 2-norm, scaled so that its largest
  // component (the first of equal ones) is real and positive.
  Eigen::MatrixXcd vectors;
};

// Eigen's EigenSolver (real Schur form). Throws std::runtime_error if it does not converge.
Modes modes(const Eigen::MatrixXd& A);

}  // namespace kanesens::sim
