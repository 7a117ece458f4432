// The residual's derivatives in closed form (dynamics/residual_derivatives.hpp).
#include "dynamics/residual_derivatives.hpp"

#include <algorithm>
#include <cmath>

namespace kanesens::dynamics {

namespace {
using V3 = Vec3<double>;
using V6 = Vec6<double>;
using M3 = Mat3<double>;

// The spatial inertia about Q (SpatialInertia's convention: h = m (c − Q), I about Q) moved to
// O = Q − p: h_O = h + m p, I_O = I_Q + (2 h·p + m p·p) 1 − (h pᵀ + p hᵀ + m p pᵀ).
SpatialInertia<double> about_anchor(const SpatialInertia<double>& X, const V3& p) {
  SpatialInertia<double> Y;
  Y.m = X.m;
  Y.h = X.h + X.m * p;
  const V3 k = X.h + 0.5 * X.m * p;  // h pᵀ + p hᵀ + m p pᵀ = k pᵀ + p kᵀ
  Y.I = X.I - (k * p.transpose() + p * k.transpose());
  Y.I.diagonal().array() += 2 * k.dot(p);
  return Y;
}

// B's upper-left block for a body of inertia (m, h, J) about O moving with v = (ω, v0):
// B = (v×*) I − I (v×) + X(I v), with X(n, f) m = m ×* (n, f), is [B11 0; −2 p× 0] (p = m v0 −
// h × ω the linear momentum): the off-diagonal products cancel in pairs (ω× h× − h× ω× =
// (ω × h)×), and B11 = ω× J − J ω× − (h v0ᵀ + v0 hᵀ) + 2 (v0·h) 1 − n× with n = J ω + h × v0.
M3 b11(const SpatialInertia<double>& X, const V3& w, const V3& v0, const V3& n) {
  const M3 Wx = math::skew<double>(w);
  M3 B = Wx * X.I - X.I * Wx;
  B -= X.h * v0.transpose() + v0 * X.h.transpose();
  B.diagonal().array() += 2 * v0.dot(X.h);
  B -= math::skew<double>(n);
  return B;
}
}  // namespace

bool ResidualDerivatives::applies(const Model& m) {
  if (m.evaluate_planar() || m.has_quaternions || !m.forces.empty() || m.nconstraint_rows > 0 ||
      !m.state_slots.empty())
    return false;
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
      f_abs_(static_cast<std::size_t>(m.nbody())) {}

void ResidualDerivatives::evaluate(const Model& m, const Workspace<double>& ws, const double* q, const double* u,
                                   const double* udot, double* r, double* r_scale, double* dr) {
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
    const SpatialInertia<double>& I = inertia_[bi] = about_anchor(ws.spatial_inertia[bi], ws.tree_position[bi]);
    const V6 Iv = I * v, Ig = I * a0, Ia = I * V6(a - a0), vIv = math::cross_force(v, Iv);
    f_[bi] = Ia + Ig + vIv;
    f_abs_[bi] = Ia.cwiseAbs() + Ig.cwiseAbs() + vIv.cwiseAbs();
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

}  // namespace kanesens::dynamics
