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
using M3 = Eigen::Matrix3d;
using M6 = Eigen::Matrix<double, 6, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;

// parent += Xᵀ I X, X the shift of motion vectors from Q_P to Q_C = Q_P + r: an articulated
// inertia at the child's point, seen from the parent's. With I = [A B; Bᵀ C] and R = r×:
// A' = A − B R − (B R)ᵀ − R C R, B' = B + R C, C' = C. Products with R are cross products
// (row i of B R is b_i × r, column j of R C is r × c_j): two thirds of a 3×3 product's work.
void add_inertia_to_parent(const M6& I, const Eigen::Vector3d& r, M6& parent) {
  M3 BR, RC, RCR;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d b = I.block<1, 3>(i, 3).transpose();
    BR.row(i) = b.cross(r).transpose();
    RC.col(i) = r.cross(I.block<3, 1>(3, 3 + i));
  }
  for (int i = 0; i < 3; ++i) RCR.row(i) = RC.row(i).transpose().cross(r).transpose();
  const M3 B2 = I.topRightCorner<3, 3>() + RC;
  parent.topLeftCorner<3, 3>() += I.topLeftCorner<3, 3>() - BR - BR.transpose() - RCR;
  parent.topRightCorner<3, 3>() += B2;
  parent.bottomLeftCorner<3, 3>() += B2.transpose();
  parent.bottomRightCorner<3, 3>() += I.bottomRightCorner<3, 3>();
}
}  // namespace

bool articulated_body_accelerations(const Model& m, Workspace<double>& ws) {
  for (int b = 0; b < m.nbody(); ++b) {
    const SpatialInertia<double>& I = ws.spatial_inertia[b];  // [I h×; −h× m1]
    M6& IA = ws.articulated_inertia[b];
    const M3 H = math::skew<double>(I.h);
    IA.topLeftCorner<3, 3>() = I.I;
    IA.topRightCorner<3, 3>() = H;
    IA.bottomLeftCorner<3, 3>() = -H;
    IA.bottomRightCorner<3, 3>() = I.m * M3::Identity();
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
    V6& a = ws.articulated_bias[J.child];
    if (J.parent >= 0) a = math::motion_to_child<double>(ws.articulated_bias[J.parent], ws.joint_offset[ji]);
    else a.setZero();
    if (n == 0) continue;
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
  }
  return true;
}

}  // namespace kanesens::dynamics
