// Minimum-norm solutions x = J⁺ r of an underdetermined constraint system J x = r (J m×n, m ≤ n):
// the projections onto a constraint manifold and its tangent space (KaneProblem::project).
//
// Full row rank, well conditioned (the usual case, every step of a projected integration):
// x = Jᵀ (J Jᵀ)⁻¹ r by Cholesky of the small m×m Gram matrix, in storage allocated once.
// Rank-deficient or ill-conditioned J (redundant constraints, a toggle position): a complete
// orthogonal decomposition, whose rank threshold drops the null directions, as before this
// fast path existed. The switch is on the Cholesky pivots: cond(J)² ≈ (max/min diag L)², so a
// ratio above 1e4 (cond(J) above ~1e4, a Gram condition above 1e8) goes the careful way.
//
// Constraint Jacobians of large mechanisms are mostly zero (a row involves the speeds of two
// bodies' paths to the root): a J with few nonzeros per column gets J Jᵀ summed from its
// nonzeros, column by column, and the Cholesky factorisation confined to J Jᵀ's envelope (for
// loops that follow one another, a band): O(nnz) instead of O(m² n). A dense J takes the dense
// product. The factorisation is hand-written (Eigen's LLT has no envelope) and allocates only
// when the size changes.
#pragma once
#include <Eigen/Dense>

namespace kanesens::math {

class MinNormSolver {
 public:
  // Factorises J. Sizes may change between calls (storage is reused when they do not).
  void compute(const Eigen::MatrixXd& J);
  // x = J⁺ r (r: m, x: n). x must not alias r.
  void solve(const Eigen::VectorXd& r, Eigen::VectorXd& x);
  // e ← e − J⁺ J e: the component of e in the null space of J (tangent to the manifold).
  void remove_normal_component(Eigen::Ref<Eigen::VectorXd> e);
  bool used_cholesky() const { return cholesky_; }

 private:
  Eigen::MatrixXd J_, gram_;  // gram_: J Jᵀ, then its factor U = Lᵀ in the upper envelope
  Eigen::VectorXi first_;      // per row of J Jᵀ: its first nonzero column (the envelope)
  Eigen::VectorXi column_rows_;  // scratch: the rows of one column of J that are nonzero
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  Eigen::VectorXd w_, x_, Je_;
  bool cholesky_ = true;
};

}  // namespace kanesens::math
