// The residual's derivatives in closed form (dynamics/residual_derivatives.hpp).
#include "dynamics/residual_derivatives.hpp"

#include <algorithm>
#include <cmath>

#include "dynamics/equations.hpp"
#include "dynamics/force_elements.hpp"
#include "math/multi_dual.hpp"

namespace kanesens::dynamics {

namespace {
using V3 = Vec3<double>;
using V6 = Vec6<double>;
using M3 = Mat3<double>;

// B's upper-left block for a body of inertia (m, h, J) about O moving with v = (ω, v0):
// B = (v×*) I − I (v×) + X(I v), with X(n, f) m = m ×* (n, f), is [B11 0; −2 p× 0] (p = m v0 −
// h × ω the linear momentum): the off-diagonal products cancel in pairs (ω× h× − h× ω× =
// (ω × h)×), and B11 = ω× J − J ω× − (h v0ᵀ + v0 hᵀ) + 2 (v0·h) 1 − n× with n = J ω + h × v0.
M3 b11(const SpatialInertia<double>& X, const V3& w, const V3& v0, const V3& n) {
  // ω× J − J ω× is symmetric (J is): its upper triangle from T = ω× J, C_ij = T_ij + T_ji.
  const M3& J = X.I;
  M3 T;
  for (int j = 0; j < 3; ++j) T.col(j) = w.cross(J.col(j));
  const double hv = 2 * v0.dot(X.h);
  M3 B;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i <= j; ++i) {
      const double c = T(i, j) + T(j, i) - (X.h[i] * v0[j] + v0[i] * X.h[j]) + (i == j ? hv : 0.0);
      B(i, j) = c;
      B(j, i) = c;
    }
  // − n×
  B(0, 1) += n[2];
  B(1, 0) -= n[2];
  B(0, 2) -= n[1];
  B(2, 0) += n[1];
  B(1, 2) += n[0];
  B(2, 1) -= n[0];
  return B;
}
}  // namespace

bool ResidualDerivatives::applies(const Model& m) {
  if (m.evaluate_planar() || m.has_quaternions || m.nconstraint_rows > 0) return false;
  for (const Joint& J : m.joints) {
    switch (J.type) {
      case JointType::revolute:
      case JointType::prismatic:
      case JointType::cylindrical:  // its translation is along its rotation's axis: they commute
      case JointType::universal:    // the second axis is carried by the first rotation
      case JointType::planar:       // two translations (commute), then a rotation carried by both
      case JointType::weld: break;
      default: return false;
    }
    if (J.nq != J.nu || J.q_offset != J.u_offset) return false;
  }
  return true;
}

ResidualDerivatives::ResidualDerivatives(const Model& m)
    : speeds_(static_cast<std::size_t>(m.nu)),
      inertia_(static_cast<std::size_t>(m.nbody())),
      b11_(static_cast<std::size_t>(m.nbody())),
      momentum_(static_cast<std::size_t>(m.nbody())),
      f_(static_cast<std::size_t>(m.nbody())),
      f_abs_(static_cast<std::size_t>(m.nbody())),
      kinematic_tangents_(static_cast<std::size_t>(m.nu)),
      applied_wrench_(static_cast<std::size_t>(m.nu)) {
  std::vector<unsigned char> loaded(static_cast<std::size_t>(m.nbody()), 0);
  for (const Force& f : m.forces)
    for (int b : {f.body_a, f.body_b, f.body})
      if (b >= 0) loaded[static_cast<std::size_t>(b)] = 1;
  for (int b = 0; b < m.nbody(); ++b)
    if (loaded[static_cast<std::size_t>(b)]) loaded_.push_back(b);
}

void ResidualDerivatives::evaluate(const Model& m, const Workspace<double>& ws, const double* q, const double* u,
                                   const double* udot, bool joint_forces, double* r, double* r_scale, double* dr,
                                   double* mass_matrix) {
  const int nu = m.nu;
  const std::ptrdiff_t ld = 2 * static_cast<std::ptrdiff_t>(nu);
  const int* parent = m.speed_parent.data();
  V6 a0;
  a0 << 0, 0, 0, -ws.gravity[0], -ws.gravity[1], -ws.gravity[2];
  // Forward: each speed's axis about its tree's anchor, the velocity and acceleration after it,
  // Ψ̇ and Ψ̈ (speeds parents first).
  for (int k : m.speed_order) {
    Speed& s = speeds_[static_cast<std::size_t>(k)];
    const V6& sk = ws.partial[static_cast<std::size_t>(k)];  // (Ω, L) at the body's Q
    const V3& p = ws.tree_position[static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)])];
    s.S.head<3>() = sk.head<3>();
    s.S.tail<3>() = sk.tail<3>() + p.cross(sk.head<3>().eval());
    const int pk = parent[k];
    const V6 v_before = pk >= 0 ? speeds_[static_cast<std::size_t>(pk)].v : V6::Zero();
    const V6 a_before = pk >= 0 ? speeds_[static_cast<std::size_t>(pk)].a : a0;
    s.dS = math::cross_motion(v_before, s.S);
    s.ddS = math::cross_motion(a_before, s.S) + math::cross_motion(v_before, s.dS);
    s.v = v_before + s.S * u[k];
    s.a = a_before + s.S * udot[k] + s.dS * u[k];
  }
  // Each body's inertia about its anchor, f = I a + v ×* I v, B's blocks (b11).
  const int nb = m.nbody();
  for (int b = 0; b < nb; ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const std::vector<int>& moving = m.ancestor_speeds[bi];
    const V6 v = moving.empty() ? V6::Zero() : speeds_[static_cast<std::size_t>(moving.back())].v;
    const V6 a = moving.empty() ? a0 : speeds_[static_cast<std::size_t>(moving.back())].a;
    // The inertia about Q moved to the anchor O = Q − tree_position (the parallel-axis shift).
    SpatialInertia<double>& I = inertia_[bi];
    I = SpatialInertia<double>();
    ws.spatial_inertia[bi].add_to_parent(ws.tree_position[bi], I);
    const V6 Iv = I * v, Ia = I * a, vIv = math::cross_force(v, Iv);
    V6 Ig;  // I a0 = (h × a0_v, m a0_v): gravity's part of I a
    Ig.head<3>() = I.h.cross(a0.tail<3>().eval());
    Ig.tail<3>() = I.m * a0.tail<3>();
    f_[bi] = Ia + vIv;
    f_abs_[bi] = (Ia - Ig).cwiseAbs() + Ig.cwiseAbs() + vIv.cwiseAbs();
    b11_[bi] = b11(I, v.head<3>(), v.tail<3>(), Iv.head<3>());
    momentum_[bi] = Iv.tail<3>();
  }
  // Sums over subtrees (about a common anchor within each tree: plain sums).
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[static_cast<std::size_t>(*it)];
    if (J.parent < 0) continue;
    const std::size_t c = static_cast<std::size_t>(J.child), pb = static_cast<std::size_t>(J.parent);
    inertia_[pb] += inertia_[c];
    b11_[pb] += b11_[c];
    momentum_[pb] += momentum_[c];
    f_[pb] += f_[c];
    f_abs_[pb] += f_abs_[c];
  }
  // Per speed: I^C S and B^Cᵀ S = (B11ᵀ S_ω + 2 p × S_v, 0), r and its scale.
  for (int k = 0; k < nu; ++k) {
    Speed& s = speeds_[static_cast<std::size_t>(k)];
    const std::size_t body = static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)]);
    s.IS = inertia_[body] * s.S;
    s.BS = b11_[body].transpose() * s.S.head<3>() + 2 * momentum_[body].cross(s.S.tail<3>().eval());
    r[k] = -s.S.dot(f_[body]);
    r_scale[k] = s.S.cwiseAbs().dot(f_abs_[body]);
  }
  std::fill(dr, dr + ld * nu, 0.0);
  std::fill(mass_matrix, mass_matrix + static_cast<std::ptrdiff_t>(nu) * nu, 0.0);
  for (int k = 0; k < nu; ++k) {
    const Speed& sk = speeds_[static_cast<std::size_t>(k)];
    const std::size_t body = static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)]);
    // The vectors speed k's derivatives give its ancestors' τ: ∂f^C/∂y_k over the bodies k moves,
    // with B^C x = (B11 x_ω, −2 p × x_ω).
    const SpatialInertia<double>& Ic = inertia_[body];
    const M3& B = b11_[body];
    const V3& pc = momentum_[body];
    V6 zeta_u = 2 * (Ic * sk.dS), zeta_q = math::cross_force(sk.S, f_[body]) + Ic * sk.ddS;
    const V3 Bs = B * sk.S.head<3>(), Bd = B * sk.dS.head<3>();
    zeta_u.head<3>() += Bs;
    zeta_u.tail<3>() -= 2 * pc.cross(sk.S.head<3>().eval());
    zeta_q.head<3>() += Bd;
    zeta_q.tail<3>() -= 2 * pc.cross(sk.dS.head<3>().eval());
    double* row_k = dr + k * ld;
    for (int j = k; j >= 0; j = parent[j]) {
      const Speed& sj = speeds_[static_cast<std::size_t>(j)];
      // M_kj = S_j · I^C_k S_k (the composite inertia of what both move).
      mass_matrix[static_cast<std::ptrdiff_t>(j) * nu + k] = mass_matrix[static_cast<std::ptrdiff_t>(k) * nu + j] =
          sk.IS.dot(sj.S);
      // τ_k with respect to speed j at or before k.
      row_k[nu + j] -= 2 * sk.IS.dot(sj.dS) + sk.BS.dot(sj.S.head<3>());
      row_k[j] -= sk.IS.dot(sj.ddS) + sk.BS.dot(sj.dS.head<3>());
      if (j == k) continue;
      double* row_j = dr + j * ld;
      row_j[nu + k] -= sj.S.dot(zeta_u);
      row_j[k] -= sj.S.dot(zeta_q);
    }
  }
  // The joints' own spring-dampers (on their first speed, as add_joint_spring_dampers).
  if (!joint_forces) return;
  for (const Joint& J : m.joints) {
    const std::ptrdiff_t k = J.u_offset;
    if (J.spring_k >= 0) {
      const double K = ws.values[static_cast<std::size_t>(J.spring_k)];
      const double x = q[J.q_offset] - ws.values[static_cast<std::size_t>(J.spring_rest)];
      r[k] -= K * x;
      r_scale[k] = std::max(r_scale[k], std::abs(K * x));
      dr[k * ld + J.q_offset] -= K;
    }
    if (J.damper_c >= 0) {
      const double C = ws.values[static_cast<std::size_t>(J.damper_c)];
      r[k] -= C * u[k];
      r_scale[k] = std::max(r_scale[k], std::abs(C * u[k]));
      dr[k * ld + nu + k] -= C;
    }
  }
}

template <class S>
void ResidualDerivatives::add_applied_forces(const Model& m, const Workspace<double>& wd, Workspace<S>& ws, double t,
                                             const S* y, int first, int count, double* r, double* r_scale,
                                             double* dr) {
  const int nq = m.nq, nu = m.nu;
  const std::ptrdiff_t ld = 2 * static_cast<std::ptrdiff_t>(nu);
  const S* q = y;
  const S* u = y + nq;
  evaluate_state_expressions(m, ws, S(t), q, u);
  auto axis = [&](int j) -> const Speed& { return speeds_[static_cast<std::size_t>(j)]; };
  // Direction i of the block is q_j (first + i < nq) or u_j; value + the tangents tangent(j, is_q)
  // over the speeds j that move the body (0 for the others).
  auto set = [&](S& x, double value, const std::vector<unsigned char>& moves, auto&& tangent) {
    x.v = value;
    x.set_tangents(
        [&](int i) {
          const int d = first + i;
          const bool is_q = d < nq;
          const int j = is_q ? d : d - nq;
          return moves[static_cast<std::size_t>(j)] ? tangent(j, is_q) : 0.0;
        },
        count);
  };
  // The kinematics the force elements read, on the loaded bodies only.
  for (int b : loaded_) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int rj = m.bodies[bi].root_joint;
    const int root = m.joints[static_cast<std::size_t>(rj)].child;
    const std::vector<unsigned char>& moves = m.moves[bi];
    const V3 Q = wd.tree_position[bi];  // from the tree's anchor, the origin of the speeds' axes
    const Mat3<double>& R = wd.R[bi];
    const std::vector<int>& moving = m.ancestor_speeds[bi];
    const V6 V = moving.empty() ? V6::Zero() : axis(moving.back()).v;  // about the anchor
    for (int j : moving) {
      const Speed& sj = axis(j);
      KinematicTangents& k = kinematic_tangents_[static_cast<std::size_t>(j)];
      const V3 w = sj.S.head<3>(), vO = sj.S.tail<3>();
      k.dQ = vO + w.cross(Q);  // the point Q moved by S_j
      k.dR = math::skew<double>(w) * R;
      k.dAnchor = m.moves[static_cast<std::size_t>(root)][static_cast<std::size_t>(j)] ? vO : V3::Zero();
      // ∂V/∂q_j = S_j × V + Ψ̇_j about the anchor; at Q: (dω, dv + dω × Q + ω × dQ).
      const V6 dV = math::cross_motion(sj.S, V) + sj.dS;
      k.dVq.head<3>() = dV.head<3>();
      k.dVq.tail<3>() = dV.tail<3>() + dV.head<3>().cross(Q) + V.head<3>().cross(k.dQ);
    }
    auto kin = [&](int j) -> const KinematicTangents& { return kinematic_tangents_[static_cast<std::size_t>(j)]; };
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c)
        set(ws.R[bi](a, c), R(a, c), moves, [&](int j, bool is_q) { return is_q ? kin(j).dR(a, c) : 0.0; });
      set(ws.tree_position[bi][a], Q[a], moves,
          [&](int j, bool is_q) { return is_q ? kin(j).dQ[a] - kin(j).dAnchor[a] : 0.0; });
      set(ws.tree_anchor[static_cast<std::size_t>(rj)][a], wd.tree_anchor[static_cast<std::size_t>(rj)][a], moves,
          [&](int j, bool is_q) { return is_q ? kin(j).dAnchor[a] : 0.0; });
      set(ws.velocity[bi][a], wd.velocity[bi][a], moves,
          [&](int j, bool is_q) { return is_q ? kin(j).dVq[a] : axis(j).S[a]; });
      set(ws.velocity[bi][3 + a], wd.velocity[bi][3 + a], moves,
          [&](int j, bool is_q) { return is_q ? kin(j).dVq[3 + a] : kin(j).dQ[a]; });
    }
    ws.wrench[bi].setZero();
  }
  detail::for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) { ws.wrench[static_cast<std::size_t>(b)] += w; });
  // Q_k = the joints' own forces + S_k · Σ W (about the anchor, a point fixed in the world: Q's
  // tangent there is ∂Q, not tree_position's), over the loaded bodies k moves.
  for (int k = 0; k < nu; ++k) {
    ws.forcing[static_cast<std::size_t>(k)] = S(0);
    applied_wrench_[static_cast<std::size_t>(k)].setZero();
  }
  detail::add_joint_spring_dampers(m, ws, q, u);
  for (int b : loaded_) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const V3& Qv = wd.tree_position[bi];
    Vec3<S> Q;
    for (int a = 0; a < 3; ++a)
      set(Q[a], Qv[a], m.moves[bi], [&](int j, bool is_q) {
        if (!is_q) return 0.0;
        const V6& Sj = axis(j).S;
        return (Sj.tail<3>() + Sj.head<3>().cross(Qv))[a];
      });
    Vec6<S> W = ws.wrench[bi];
    const Vec3<S> F = W.template tail<3>();
    W.template head<3>() += Q.cross(F);
    V6 Wv;
    for (int a = 0; a < 6; ++a) Wv[a] = W[a].v;
    for (int j : m.ancestor_speeds[bi]) {
      S& Qj = ws.forcing[static_cast<std::size_t>(j)];
      const V6& Sj = axis(j).S;
      for (int a = 0; a < 6; ++a) Qj += W[a] * Sj[a];
      applied_wrench_[static_cast<std::size_t>(j)] += Wv;
    }
  }
  for (int k = 0; k < nu; ++k) {
    const S& Qk = ws.forcing[static_cast<std::size_t>(k)];
    if (first == 0) {
      r[k] += Qk.v;
      r_scale[k] = std::max(r_scale[k], std::abs(Qk.v));
    }
    double* row = dr + k * ld;
    for (int i = 0; i < count; ++i) row[first + i] += Qk.d(i);
    // ∂S_k/∂q_j = S_j × S_k for j before k: (S_j × S_k)·W = S_j·(S_k ×* W).
    const V6 g = math::cross_force(axis(k).S, applied_wrench_[static_cast<std::size_t>(k)]);
    for (int j = m.speed_parent[static_cast<std::size_t>(k)]; j >= 0; j = m.speed_parent[static_cast<std::size_t>(j)])
      if (j >= first && j < first + count && j < nq) row[j] += axis(j).S.dot(g);
  }
}

#define KANESENS_INSTANTIATE(S)                                                                              \
  template void ResidualDerivatives::add_applied_forces<S>(const Model&, const Workspace<double>&, Workspace<S>&, \
                                                           double, const S*, int, int, double*, double*, double*);
KANESENS_FOR_EACH_MULTI_DUAL(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
