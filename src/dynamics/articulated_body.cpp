// Forward dynamics by the articulated-body algorithm (Featherstone 2008 §7.3, table 7.1), on the
// Workspace's frames: each body's quantities at its reference point Q_b with world-aligned axes,
// moved between neighbours by the joint offset r = Q_child − Q_parent (a pure shift), so, as in
// the rest of the dynamics, no large world position enters a difference.
//
// The unknowns are the bodies' accelerations less their bias accelerations (compute_velocity's,
// at u̇ = 0): δa_C = δa_P carried to Q_C + Σ_k s_k u̇_k. The textbook's velocity-product terms are
// then already in the bias, and each body's bias force is p_b = −W_b, its applied minus inertial
// wrench at u̇ = 0 (compute_body_wrenches). Three sweeps of O(1) work per joint: for a long chain
// this is cheaper than forming M (O(nu²)) and factoring it (O(nu³)).
#include <Eigen/Cholesky>

#include "dynamics/equations.hpp"

namespace kanesens::dynamics {

namespace {
using M6 = Eigen::Matrix<double, 6, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;

// parent += Xᵀ I X, X the shift of motion vectors from Q_P to Q_C = Q_P + r: an articulated
// inertia at the child's point, seen from the parent's. With I = [A B; Bᵀ C] and R = r×:
// A' = A − B R − (B R)ᵀ − R C R, B' = B + R C, C' = C. Products with R are cross products
// (row i of B R is b_i × r, column j of R C is r × c_j), formed in scalars: 3×3 temporaries
// written by rows and read by columns stall store-to-load forwarding.
void add_inertia_to_parent(const M6& I, const Eigen::Vector3d& r, M6& parent) {
  const double r0 = r[0], r1 = r[1], r2 = r[2];
  double BR[3][3], RC[3][3], RCR[3][3];
  for (int i = 0; i < 3; ++i) {
    const double b0 = I(i, 3), b1 = I(i, 4), b2 = I(i, 5);
    BR[i][0] = b1 * r2 - b2 * r1;
    BR[i][1] = b2 * r0 - b0 * r2;
    BR[i][2] = b0 * r1 - b1 * r0;
    const double c0 = I(3, 3 + i), c1 = I(4, 3 + i), c2 = I(5, 3 + i);
    RC[0][i] = r1 * c2 - r2 * c1;
    RC[1][i] = r2 * c0 - r0 * c2;
    RC[2][i] = r0 * c1 - r1 * c0;
  }
  for (int i = 0; i < 3; ++i) {
    RCR[i][0] = RC[i][1] * r2 - RC[i][2] * r1;
    RCR[i][1] = RC[i][2] * r0 - RC[i][0] * r2;
    RCR[i][2] = RC[i][0] * r1 - RC[i][1] * r0;
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      parent(i, j) += I(i, j) - BR[i][j] - BR[j][i] - RCR[i][j];
      const double b = I(i, 3 + j) + RC[i][j];
      parent(i, 3 + j) += b;
      parent(3 + j, i) += b;
      parent(3 + i, 3 + j) += I(3 + i, 3 + j);
    }
}
}  // namespace

bool articulated_body_accelerations(const Model& m, Workspace<double>& ws) {
  for (int b = 0; b < m.nbody(); ++b) {
    ws.spatial_inertia[b].to_matrix(ws.articulated_inertia[b]);
    ws.articulated_bias[b] = -ws.wrench[b];
  }
  double* x = ws.udot.data();  // u_j = τ_j − S_jᵀ p^A on the way in, u̇ on the way out
  // Leaves to roots: I^A, p^A of each body's subtree; each joint's U = I^A S, D⁻¹ = (Sᵀ U)⁻¹.
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    const int n = J.nu, k0 = J.u_offset;
    M6& IA = ws.articulated_inertia[J.child];
    V6& pA = ws.articulated_bias[J.child];
    if (n > 0) {
      const V6* s = ws.partial.data() + k0;
      V6* U = ws.articulated_columns.data() + k0;
      const unsigned char* rotation = m.speed_rotation.data() + k0;
      for (int c = 0; c < n; ++c) {  // s = (a, 0) or (0, a): half of I^A and of p^A
        if (rotation[c]) {
          U[c].noalias() = IA.leftCols<3>() * s[c].head<3>();
          x[k0 + c] = ws.forcing[k0 + c] - s[c].head<3>().dot(pA.head<3>());
        } else {
          U[c].noalias() = IA.rightCols<3>() * s[c].tail<3>();
          x[k0 + c] = ws.forcing[k0 + c] - s[c].tail<3>().dot(pA.tail<3>());
        }
      }
      M6& Dinv = ws.joint_inverse[*it];
      if (n == 1) {
        const double d = rotation[0] ? s[0].head<3>().dot(U[0].head<3>()) : s[0].tail<3>().dot(U[0].tail<3>());
        if (!(d > 0)) return false;
        Dinv(0, 0) = 1.0 / d;
      } else {
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> D(n, n);
        for (int c = 0; c < n; ++c)
          for (int d = 0; d < n; ++d) D(c, d) = s[c].dot(U[d]);
        const Eigen::LLT<decltype(D)> llt(D);
        if (llt.info() != Eigen::Success) return false;
        Dinv.topLeftCorner(n, n) = llt.solve(decltype(D)::Identity(n, n));
      }
      if (J.parent < 0) continue;
      // I^a = I^A − U D⁻¹ Uᵀ, p^a = p^A + U D⁻¹ u, in place (the child's I^A, p^A are done with).
      for (int c = 0; c < n; ++c) {
        V6 w = U[0] * Dinv(0, c);  // column c of U D⁻¹
        for (int d = 1; d < n; ++d) w += U[d] * Dinv(d, c);
        IA.noalias() -= w * U[c].transpose();
        pA += w * x[k0 + c];
      }
    }
    if (J.parent >= 0) {
      add_inertia_to_parent(IA, ws.joint_offset[*it], ws.articulated_inertia[J.parent]);
      math::add_force_to_parent<double>(pA, ws.joint_offset[*it], ws.articulated_bias[J.parent]);
    }
  }
  // Roots to leaves: u̇_j = D⁻¹ (u_j − Uᵀ δa'), δa_C = δa' + S u̇ (δa' the parent's, at Q_C). A
  // body's p^a is not needed once its joint is done, so its slot holds δa.
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int n = J.nu, k0 = J.u_offset;
    // Formed in a local (stored once at the end): a vector written in pieces and read back in
    // pairs stalls store-to-load forwarding.
    V6 a = J.parent >= 0 ? math::motion_to_child<double>(ws.articulated_bias[J.parent], ws.joint_offset[ji])
                         : V6::Zero().eval();
    if (n == 0) {
      ws.articulated_bias[J.child] = a;
      continue;
    }
    double r[6];
    for (int c = 0; c < n; ++c) r[c] = x[k0 + c] - ws.articulated_columns[k0 + c].dot(a);
    const M6& Dinv = ws.joint_inverse[ji];
    for (int c = 0; c < n; ++c) {
      double v = 0;
      for (int d = 0; d < n; ++d) v += Dinv(c, d) * r[d];
      x[k0 + c] = v;
    }
    for (int c = 0; c < n; ++c) {
      if (m.speed_rotation[k0 + c]) a.head<3>() += ws.partial[k0 + c].head<3>() * x[k0 + c];
      else a.tail<3>() += ws.partial[k0 + c].tail<3>() * x[k0 + c];
    }
    ws.articulated_bias[J.child] = a;
  }
  return true;
}

}  // namespace kanesens::dynamics
