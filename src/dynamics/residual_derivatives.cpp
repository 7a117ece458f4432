// The residual's derivatives in closed form (dynamics/residual_derivatives.hpp).
#include "dynamics/residual_derivatives.hpp"

#include <algorithm>
#include <cmath>

namespace kanesens::dynamics {

namespace {
using V6 = Vec6<double>;
using M6 = Mat6<double>;

// m ×* h as a linear map of m: (ω × n + v × f, ω × f) = X m with X = [−n× −f×; −f× 0].
void add_force_cross_map(const V6& h, M6& X) {
  const double n0 = h[0], n1 = h[1], n2 = h[2], f0 = h[3], f1 = h[4], f2 = h[5];
  // −a× = [0 a2 −a1; −a2 0 a0; a1 −a0 0]
  const double N[3][3] = {{0, n2, -n1}, {-n2, 0, n0}, {n1, -n0, 0}};
  const double F[3][3] = {{0, f2, -f1}, {-f2, 0, f0}, {f1, -f0, 0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      X(i, j) += N[i][j];
      X(i, 3 + j) += F[i][j];
      X(3 + i, j) += F[i][j];
    }
}

// The spatial inertia about Q (SpatialInertia's convention: h = m (c − Q), I about Q) moved to
// O = Q − p: h_O = h + m p, I_O = I_Q + (2 h·p + m p·p) 1 − (h pᵀ + p hᵀ + m p pᵀ).
SpatialInertia<double> about_anchor(const SpatialInertia<double>& X, const Vec3<double>& p) {
  SpatialInertia<double> Y;
  Y.m = X.m;
  Y.h = X.h + X.m * p;
  const Vec3<double> k = X.h + 0.5 * X.m * p;  // h pᵀ + p hᵀ + m p pᵀ = k pᵀ + p kᵀ
  Y.I = X.I - (k * p.transpose() + p * k.transpose());
  Y.I.diagonal().array() += 2 * k.dot(p);
  return Y;
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
      b_(static_cast<std::size_t>(m.nbody())),
      f_(static_cast<std::size_t>(m.nbody())),
      f_abs_(static_cast<std::size_t>(m.nbody())) {}

void ResidualDerivatives::evaluate(const Model& m, const Workspace<double>& ws, const double* q, const double* u,
                                   const double* udot,
                                   double* r, double* r_scale, double* dr_dq, double* dr_du) {
  const int nu = m.nu;
  const int* parent = m.speed_parent.data();
  V6 a0;
  a0 << 0, 0, 0, -ws.gravity[0], -ws.gravity[1], -ws.gravity[2];
  // Forward: each speed's axis about its tree's anchor, the velocity and acceleration after it,
  // Ψ̇ and Ψ̈ (speeds parents first).
  for (int k : m.speed_order) {
    Speed& s = speeds_[static_cast<std::size_t>(k)];
    const V6& sk = ws.partial[static_cast<std::size_t>(k)];  // (Ω, L) at the body's Q
    const Vec3<double>& p = ws.tree_position[static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)])];
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
  // Each body's inertia about its anchor, f = I a + v ×* I v and B = (v×*) I − I (v×) + X(I v).
  const int nb = m.nbody();
  for (int b = 0; b < nb; ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const std::vector<int>& moving = m.ancestor_speeds[bi];
    const V6 v = moving.empty() ? V6::Zero() : speeds_[static_cast<std::size_t>(moving.back())].v;
    const V6 a = moving.empty() ? a0 : speeds_[static_cast<std::size_t>(moving.back())].a;
    inertia_[bi] = about_anchor(ws.spatial_inertia[bi], ws.tree_position[bi]);
    const M6 I = inertia_[bi].matrix();
    const V6 Iv = I * v, Ig = I * a0, Ia = I * (a - a0), vIv = math::cross_force(v, Iv);
    f_[bi] = Ia + Ig + vIv;
    f_abs_[bi] = Ia.cwiseAbs() + Ig.cwiseAbs() + vIv.cwiseAbs();
    M6 crm;  // v× = [ω× 0; v× ω×]
    crm.setZero();
    crm.block<3, 3>(0, 0) = math::skew<double>(v.head<3>());
    crm.block<3, 3>(3, 3) = crm.block<3, 3>(0, 0);
    crm.block<3, 3>(3, 0) = math::skew<double>(v.tail<3>());
    M6& B = b_[bi];
    B.noalias() = -crm.transpose() * I;  // v×* = −(v×)ᵀ
    B.noalias() -= I * crm;
    add_force_cross_map(Iv, B);
  }
  // Sums over subtrees (about a common anchor within each tree: plain sums).
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[static_cast<std::size_t>(*it)];
    if (J.parent < 0) continue;
    const std::size_t c = static_cast<std::size_t>(J.child), pb = static_cast<std::size_t>(J.parent);
    inertia_[pb] += inertia_[c];
    b_[pb] += b_[c];
    f_[pb] += f_[c];
    f_abs_[pb] += f_abs_[c];
  }
  for (int k = 0; k < nu; ++k) {
    Speed& s = speeds_[static_cast<std::size_t>(k)];
    const std::size_t body = static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)]);
    s.IS = inertia_[body] * s.S;
    s.BS.noalias() = b_[body].transpose() * s.S;
    r[k] = -s.S.dot(f_[body]);
    r_scale[k] = s.S.cwiseAbs().dot(f_abs_[body]);
  }
  std::fill(dr_dq, dr_dq + static_cast<std::ptrdiff_t>(nu) * nu, 0.0);
  std::fill(dr_du, dr_du + static_cast<std::ptrdiff_t>(nu) * nu, 0.0);
  for (int k = 0; k < nu; ++k) {
    const Speed& sk = speeds_[static_cast<std::size_t>(k)];
    const std::size_t body = static_cast<std::size_t>(m.speed_body[static_cast<std::size_t>(k)]);
    // The vectors speed k's derivatives give its ancestors' τ: ∂f^C_j/∂y_k for j before k.
    const M6 Ic = inertia_[body].matrix();
    const V6 zeta_u = 2 * (Ic * sk.dS) + b_[body] * sk.S;
    const V6 zeta_q = math::cross_force(sk.S, f_[body]) + Ic * sk.ddS + b_[body] * sk.dS;
    for (int j = k; j >= 0; j = parent[j]) {
      const Speed& sj = speeds_[static_cast<std::size_t>(j)];
      // τ_k with respect to speed j at or before k.
      dr_du[static_cast<std::ptrdiff_t>(j) * nu + k] -= 2 * sk.IS.dot(sj.dS) + sk.BS.dot(sj.S);
      dr_dq[static_cast<std::ptrdiff_t>(j) * nu + k] -= sk.IS.dot(sj.ddS) + sk.BS.dot(sj.dS);
      if (j == k) continue;
      dr_du[static_cast<std::ptrdiff_t>(k) * nu + j] -= sj.S.dot(zeta_u);
      dr_dq[static_cast<std::ptrdiff_t>(k) * nu + j] -= sj.S.dot(zeta_q);
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
      dr_dq[static_cast<std::ptrdiff_t>(J.q_offset) * nu + k] -= K;
    }
    if (J.damper_c >= 0) {
      const double C = ws.values[static_cast<std::size_t>(J.damper_c)];
      r[k] -= C * u[k];
      r_scale[k] = std::max(r_scale[k], std::abs(C * u[k]));
      dr_du[k * nu + k] -= C;
    }
  }
}

}  // namespace kanesens::dynamics
