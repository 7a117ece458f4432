// Kane's equations of a planar scene (Model::planar) with 3-component spatial vectors
// (math/planar.hpp): the same recursion as kinematics.cpp/equations.cpp, where a body's rotation
// is a rotation about z by its angle (cos, sin), a speed's partial velocity is (Ω_z, v_x, v_y)
// at its body's reference point and an inertia is 4 numbers. Bodies keep constant z offsets;
// R, joint_offset, tree_anchor, tree_position and the 6-D velocity are still filled for force
// elements and energies.
#include <cmath>
#include <type_traits>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/joint_angles.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics::detail {

using math::cross_force_planar;
using math::cross_motion_planar;
using math::force_to_parent_planar;
using math::motion_to_child_planar;

template <class S>
void compute_position_planar(const Model& m, Workspace<S>& ws, const S* q) {
  compute_joint_angles(ws, q);
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    // Parent rotation about z (c_P, s_P).
    S cP = S(1), sP = S(0);
    if (P >= 0) {
      cP = ws.R[P](0, 0);
      sP = ws.R[P](1, 0);
    }
    const S* qj = q + J.q_offset;
    const Vec3<S>& a = ws.joint_axis[ji];  // ±z (revolute, planar) or in-plane (prismatic)
    S cq = S(1), sq = S(0);                // joint rotation about z
    Vec3<S> r = ws.joint_lever[ji];        // Q_C − Q_P in the parent frame
    switch (J.type) {
      case JointType::revolute:
        joint_angle(ws, q, J.q_offset, cq, sq);
        sq = a[2] * sq;
        break;
      case JointType::prismatic: r += qj[0] * a; break;
      case JointType::planar:
        r += qj[0] * ws.plane_e1[ji] + qj[1] * ws.plane_e2[ji];
        joint_angle(ws, q, J.q_offset + 2, cq, sq);
        sq = a[2] * sq;
        break;
      default: break;  // weld (Model::planar admits nothing else)
    }
    if (P >= 0) {
      Vec3<S>& o = ws.joint_offset[ji];
      o = Vec3<S>(cP * r[0] - sP * r[1], sP * r[0] + cP * r[1], r[2]);
      ws.tree_position[C] = ws.tree_position[P] + o;
    } else {
      ws.tree_anchor[ji] = r;
      ws.tree_position[C].setZero();
    }
    const S cC = cP * cq - sP * sq, sC = sP * cq + cP * sq;
    Mat3<S>& R = ws.R[C];
    R << cC, -sC, S(0), sC, cC, S(0), S(0), S(0), S(1);

    for (int k = 0; k < J.nu; ++k) {
      PVec<S>& s = ws.partial_planar[J.u_offset + k];
      if (J.speeds[k].rotation) {  // Ω = σ z about the axis through Q_C: (σ, 0, 0), σ = ±1
        s = PVec<S>(a[2], S(0), S(0));
      } else {  // translation along R_P e, e in the plane
        const Vec3<S>& e = J.type == JointType::planar ? (k == 0 ? ws.plane_e1[ji] : ws.plane_e2[ji]) : a;
        s = PVec<S>(S(0), cP * e[0] - sP * e[1], sP * e[0] + cP * e[1]);
      }
    }
    // At Q_C: c − Q_C = −R p; I_zz of the body is the same in the world (a rotation about z keeps it).
    const S mC = ws.mass[C];
    const Vec3<S>& p = ws.reference_point[C];
    const S ox = -(cC * p[0] - sC * p[1]), oy = -(sC * p[0] + cC * p[1]);
    PlanarInertia<S>& I = ws.inertia_planar[C];
    I.m = mC;
    I.hx = mC * ox;
    I.hy = mC * oy;
    I.I = ws.inertia_body[C](2, 2) + I.hx * ox + I.hy * oy;
  }
}

template <class S>
void compute_velocity_planar(const Model& m, Workspace<S>& ws, const S* u) {
  PVec<S> prefix[4];  // V_P + Σ_{k<c} s_k u_k (a planar scene's joints have ≤ 3 speeds)
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    PVec<S> A;
    if (P >= 0) {
      const Vec3<S>& r = ws.joint_offset[ji];
      prefix[0] = motion_to_child_planar<S>(ws.velocity_planar[P], r[0], r[1]);
      A = motion_to_child_planar<S>(ws.bias_planar[P], r[0], r[1]);
    } else {
      prefix[0].setZero();
      A.setZero();
    }
    const S* uj = u + J.u_offset;
    const PVec<S>* s = ws.partial_planar.data() + J.u_offset;
    if (double sg; J.nu == 1 && constant_planar_rotation(m, ws, J.u_offset, sg)) {
      const S w = times_sign(uj[0], sg);
      prefix[1] = PVec<S>(prefix[0][0] + w, prefix[0][1], prefix[0][2]);
      const PVec<S>& a = prefix[J.speeds[0].carriers];
      A[1] += a[2] * w;
      A[2] -= a[1] * w;
    } else {
      for (int k = 0; k < J.nu; ++k) prefix[k + 1] = prefix[k] + s[k] * uj[k];
      for (int k = 0; k < J.nu; ++k) A += cross_motion_planar<S>(prefix[J.speeds[k].carriers], s[k]) * uj[k];
    }
    const PVec<S>& V = prefix[J.nu];
    ws.velocity_planar[C] = V;
    ws.bias_planar[C] = A;
    ws.velocity[C] << S(0), S(0), V[0], V[1], V[2], S(0);
  }
}

template <class S>
void compute_mass_matrix_planar(const Model& m, Workspace<S>& ws) {
  const int nb = m.nbody();
  for (int b = 0; b < nb; ++b) ws.composite_planar[b] = ws.inertia_planar[b];
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) {
      const Vec3<S>& r = ws.joint_offset[*it];
      ws.composite_planar[J.child].add_to_parent(r[0], r[1], ws.composite_planar[J.parent]);
    }
  }
  // As the 3-D stage (dynamics/equations.cpp): M_kl = s_k · (I^c s_l) for the speeds k on l's
  // walk along Model::speed_parent, the momentum (τ, f) carried by ws.speed_offset (τ gains
  // r × f); columns paired with a child column share the walk, two at a time.
  const int* parent = m.speed_parent.data();
  const unsigned char* rotation = m.speed_rotation.data();
  const PVec<S>* s = ws.partial_planar.data();
  const Vec3<S>* offset = ws.speed_offset.data();
  S* M = ws.mass_matrix.data();
  const std::ptrdiff_t ld = ws.mass_matrix.rows();
  auto power = [&](int k, const auto& t, const auto& fx, const auto& fy) {
    using R = std::decay_t<decltype(t)>;
    return rotation[k] ? R(s[k][0] * t) : R(s[k][1] * fx + s[k][2] * fy);
  };
  using P2 = Eigen::Array<S, 2, 1>;  // columns l, l2 side by side
  for (const auto& [l, l2] : ws.mass_matrix_columns) {
    const PVec<S> F = ws.composite_planar[m.speed_body[l]] * s[l];
    M[l * ld + l] = power(l, F[0], F[1], F[2]);
    if (l2 < 0) {
      const S fx = F[1], fy = F[2];
      S t = F[0];
      for (int kp = l, k = parent[l]; k >= 0; kp = k, k = parent[k]) {
        t += offset[kp][0] * fy - offset[kp][1] * fx;
        const S Mkl = power(k, t, fx, fy);
        M[l * ld + k] = Mkl;
        M[k * ld + l] = Mkl;
      }
      continue;
    }
    PVec<S> F2 = ws.composite_planar[m.speed_body[l2]] * s[l2];
    M[l2 * ld + l2] = power(l2, F2[0], F2[1], F2[2]);
    F2[0] += offset[l2][0] * F2[2] - offset[l2][1] * F2[1];
    const S Mll2 = power(l, F2[0], F2[1], F2[2]);
    M[l2 * ld + l] = Mll2;
    M[l * ld + l2] = Mll2;
    const P2 fx(F[1], F2[1]), fy(F[2], F2[2]);
    P2 t(F[0], F2[0]);
    for (int kp = l, k = parent[l]; k >= 0; kp = k, k = parent[k]) {
      t += offset[kp][0] * fy - offset[kp][1] * fx;
      const P2 Mk = power(k, t, fx, fy);
      M[l * ld + k] = Mk[0];
      M[l2 * ld + k] = Mk[1];
      M[k * ld + l] = Mk[0];
      M[k * ld + l2] = Mk[1];
    }
  }
}

template <class S>
void compute_body_wrenches_planar(const Model& m, Workspace<S>& ws) {
  const int nb = m.nbody();
  const S gx = ws.gravity[0], gy = ws.gravity[1];
  // Applied minus inertial wrench of each body at its Q: gravity m g at the mass center (its z
  // component does no work in the plane; moment h × g), then −(I A₀ + V ×* I V).
  for (int b = 0; b < nb; ++b) {
    const PlanarInertia<S>& I = ws.inertia_planar[b];
    const PVec<S>& V = ws.velocity_planar[b];
    ws.wrench_planar[b] = PVec<S>(I.hx * gy - I.hy * gx, I.m * gx, I.m * gy) -
                          (I * ws.bias_planar[b] + cross_force_planar<S>(V, I * V));
  }
  for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) { ws.wrench_planar[b] += PVec<S>(w[2], w[3], w[4]); });
}

template <class S>
void compute_forcing_planar(const Model& m, Workspace<S>& ws) {
  compute_body_wrenches_planar(m, ws);
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) {
      const Vec3<S>& r = ws.joint_offset[*it];
      ws.wrench_planar[J.parent] += force_to_parent_planar<S>(ws.wrench_planar[J.child], r[0], r[1]);
    }
  }
  for (const Joint& J : m.joints)
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) ws.forcing[k] = ws.partial_planar[k].dot(ws.wrench_planar[J.child]);
}

#define KANESENS_INSTANTIATE(S)                                                         \
  template void compute_position_planar<S>(const Model&, Workspace<S>&, const S*);     \
  template void compute_velocity_planar<S>(const Model&, Workspace<S>&, const S*);     \
  template void compute_mass_matrix_planar<S>(const Model&, Workspace<S>&);            \
  template void compute_forcing_planar<S>(const Model&, Workspace<S>&);                \
  template void compute_body_wrenches_planar<S>(const Model&, Workspace<S>&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics::detail
