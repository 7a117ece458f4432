// The embedding formulation of constrained systems (Kane's equations with nonholonomic partial
// velocities, Kane & Levinson, Dynamics: Theory and Applications, 1985): only the independent
// speeds u_i are states. With the constraint rows split by a pivoted factorisation of A into
// dependent speeds u_d (A_d square, invertible) and u_i,
//     u   = C u_i + c,        C = [I; −A_d⁻¹ A_i],  c = [0; −A_d⁻¹ a0]      (permuted)
//     u̇   = C u̇_i + d,        d = [0;  A_d⁻¹ b],    b = −(Ȧu + ȧ0)
//     Cᵀ M C u̇_i = Cᵀ (f − M d)
// i.e. Kane's equations with the constrained partial velocities V C. The state is [q; u_i];
// q̇ = N(q) u with the full u. Templated on the scalar like the rest of the model, so exact
// Jacobians and sensitivities come from the same code.
#pragma once
#include <vector>

#include "dynamics/options.hpp"
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics {

struct EmbeddingSets {
  std::vector<int> independent;  // speeds that are states (ni)
  std::vector<int> dependent;    // speeds solved from the constraints (nd)
  std::vector<int> rows;         // constraint rows used (nd, independent rows of A)
};

template <class S>
struct EmbeddingScratch {
  EmbeddingScratch(const Model& m, const EmbeddingSets& sets);
  // A_d's columns ordered by the first row that can reach them (ConstraintSparsity): loops that
  // follow one another (a chain of loops) then give a band, lower_band rows below and upper_band
  // columns right of the diagonal; the LU with partial pivoting keeps L within lower_band and U within
  // lower_band + upper_band, so a chain of loops costs O(nd). (The full band is the dense LU.)
  std::vector<int> dependent_speed;  // nd: the speed of each column of Ad
  int lower_band = 0, upper_band = 0;
  // Orders A_d's columns and finds the band for `sets` (the constructor's, or a repartition's of
  // the same size: reconstruct_speeds calls it when the sets change; it allocates nothing then).
  void arrange(const EmbeddingSets& sets);
  bool arranged_for(const EmbeddingSets& sets) const {
    return sets.rows == arranged_rows && sets.dependent == arranged_dependent;
  }
  MatX<S> Ad;       // nd×nd, LU factors in place (within the band)
  std::vector<int> pivots;
  MatX<S> C;        // nu×ni
  MatX<S> Mt;       // ni×ni
  VecX<S> u, d, tmp;  // nu
  VecX<S> r;        // nd
  VecX<S> ft;       // ni
  double conditioning = 1;  // |largest| / |smallest| pivot of A_d at the last factorisation
  // max |(A_d⁻¹ A_i)_jk| at the last reconstruct_speeds: how strongly the dependent speeds follow
  // the independent ones. It grows without bound as the partition degrades (a dependent speed's
  // coefficients vanish), however A_d is scaled.
  double amplification = 0;
  // What arrange works from and on.
  ConstraintSparsity sparsity;
  std::vector<int> first_row, column;  // nu: scratch of arrange
  std::vector<int> arranged_rows, arranged_dependent;
};

// Picks the sets at (t, q) from A (doubles): rows by a rank-revealing QR of Aᵀ, dependent
// speeds by a column-pivoted QR of those rows (the best-conditioned A_d).
EmbeddingSets choose_embedding(const Eigen::MatrixXd& A);

// The amplification (see EmbeddingScratch) of the partition `sets` of A (doubles): infinity if
// its A_d is singular.
double embedding_amplification(const Eigen::MatrixXd& A, const EmbeddingSets& sets);

// Full speeds u (nu) from q and u_i at t. Leaves positions evaluated in ws. False if A_d is
// singular.
template <class S>
bool reconstruct_speeds(const Model& m, Workspace<S>& ws, EmbeddingScratch<S>& sc, const EmbeddingSets& sets,
                        const S& t, const S* q, const S* ui, S* u);

// ydot = [q̇; u̇_i] for y = [q; u_i]. False if M or A_d is singular.
template <class S>
bool embedded_rhs(const Model& m, Workspace<S>& ws, EmbeddingScratch<S>& sc, const EmbeddingSets& sets,
                  const S& t, const S* y, S* ydot, const DynamicsOptions& options = {});

}  // namespace kanesens::dynamics
