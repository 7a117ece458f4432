#include "sim/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace kanesens::sim {

Modes modes(const Eigen::MatrixXd& A) {
  Modes out;
  const Eigen::Index n = A.rows();
  out.values.resize(n);
  out.vectors.resize(n, n);
  if (n == 0) return out;
  const Eigen::EigenSolver<Eigen::MatrixXd> es(A, true);
  if (es.info() != Eigen::Success) throw std::runtime_error("linearize: the eigenvalue solver did not converge");
  const Eigen::VectorXcd values = es.eigenvalues();
  const Eigen::MatrixXcd vectors = es.eigenvectors();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index(0));
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    if (values[a].real() != values[b].real()) return values[a].real() > values[b].real();
    return values[a].imag() > values[b].imag();
  });
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index s = order[static_cast<std::size_t>(k)];
    out.values[k] = values[s];
    Eigen::VectorXcd v = vectors.col(s);
    Eigen::Index big = 0;
    for (Eigen::Index i = 1; i < n; ++i)
      if (std::abs(v[i]) > std::abs(v[big]) * (1 + 1e-12)) big = i;
    const double norm = v.norm();
    if (norm > 0) v *= std::conj(v[big]) / (std::abs(v[big]) * norm);
    out.vectors.col(k) = v;
  }
  return out;
}

Eigen::MatrixXcd eigenvalue_derivatives(const Modes& modes, const std::vector<Eigen::MatrixXd>& dA, bool* repeated) {
  const Eigen::Index n = modes.values.size(), ns = static_cast<Eigen::Index>(dA.size());
  Eigen::MatrixXcd d(n, ns);
  if (repeated) *repeated = false;
  if (n == 0) return d;
  std::vector<unsigned char> simple(static_cast<std::size_t>(n), 1);
  for (Eigen::Index k = 0; k < n; ++k)
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != k && std::abs(modes.values[k] - modes.values[j]) <=
                        kRepeatedEigenvalue * std::max(1.0, std::abs(modes.values[k]))) {
        simple[static_cast<std::size_t>(k)] = 0;
        if (repeated) *repeated = true;
      }
  // Rows of V⁻¹: left eigenvectors scaled so that wₖᴴ vₖ = 1.
  const Eigen::MatrixXcd W = modes.vectors.partialPivLu().inverse();
  for (Eigen::Index i = 0; i < ns; ++i) {
    const Eigen::MatrixXcd dAV = dA[static_cast<std::size_t>(i)].cast<std::complex<double>>() * modes.vectors;
    for (Eigen::Index k = 0; k < n; ++k)
      d(k, i) = simple[static_cast<std::size_t>(k)] ? W.row(k).transpose().cwiseProduct(dAV.col(k)).sum() : std::complex<double>(std::nan(""), std::nan(""));
  }
  return d;
}

}  // namespace kanesens::sim
