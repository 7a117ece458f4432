#include "sim/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
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

}  // namespace kanesens::sim
