// Eigenvalues and eigenvectors of a linearized system ẋ = A x (sim/linearize.hpp): its modes.
#pragma once
#include <Eigen/Dense>
#include <vector>

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

// Two eigenvalues closer than this times max(1, |λ|) count as repeated.
inline constexpr double kRepeatedEigenvalue = 1e-8;

// The derivatives of modes.values along each dA[i] (the derivative of A along a direction):
// column i, entry k = wₖᴴ dA[i] vₖ / (wₖᴴ vₖ), with wₖᴴ the k-th row of V⁻¹ (the left
// eigenvectors). Exact for a simple eigenvalue; a repeated one (kRepeatedEigenvalue) has no
// derivative in general: NaN in its row, and `repeated` (if not null) is set.
Eigen::MatrixXcd eigenvalue_derivatives(const Modes& modes, const std::vector<Eigen::MatrixXd>& dA,
                                        bool* repeated = nullptr);

}  // namespace kanesens::sim
