// Kane's equations of a planar scene (Model::planar) with 3-component spatial vectors
// (math/planar.hpp): the same recursion as kinematics.cpp/equations.cpp, where a body's rotation
// is a rotation about z by its angle (cos, sin), a speed's partial velocity is (Ω_z, v_x, v_y)
// at O and an inertia is 4 numbers. Bodies keep constant z offsets; R, com, joint_point and the
// 6-D velocity are still filled for force elements and energies.
#include <cmath>

#include "math/dual.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics::detail {

using math::cross_force_planar;
using math::cross_motion_planar;

template <class S>
void compute_position_planar(const Model& m, Workspace<S>& ws, const S* q) {
  using std::cos, std::sin;
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    // Parent rotation about z (c_P, s_P) and mass center.
    S cP = S(1), sP = S(0);
    Vec3<S> c_P = Vec3<S>::Zero();
    if (P >= 0) {
      cP = ws.R[P](0, 0);
      sP = ws.R[P](1, 0);
      c_P = ws.com[P];
    }
    const S* qj = q + J.q_offset;
    const Vec3<S>& a = ws.joint_axis[ji];  // ±z (revolute, planar) or in-plane (prismatic)
    S cq = S(1), sq = S(0);                // joint rotation about z
    Vec3<S> d = Vec3<S>::Zero();           // child point relative to parent point, parent frame
    switch (J.type) {
      case JointType::revolute:
        cq = cos(qj[0]);
        sq = a[2] * sin(qj[0]);
        break;
      case JointType::prismatic: d = qj[0] * a; break;
      case JointType::planar:
        d = qj[0] * ws.plane_e1[ji] + qj[1] * ws.plane_e2[ji];
        cq = cos(qj[2]);
        sq = a[2] * sin(qj[2]);
        break;
      default: break;  // weld (Model::planar admits nothing else)
    }
    const Vec3<S> r = ws.parent_point[ji] + d;
    const Vec3<S> Q(c_P[0] + cP * r[0] - sP * r[1], c_P[1] + sP * r[0] + cP * r[1], c_P[2] + r[2]);
    ws.joint_point[ji] = Q;
    const S cC = cP * cq - sP * sq, sC = sP * cq + cP * sq;
    Mat3<S>& R = ws.R[C];
    R << cC, -sC, S(0), sC, cC, S(0), S(0), S(0), S(1);
    const Vec3<S>& p = ws.child_point[ji];
    ws.com[C] = Vec3<S>(Q[0] - (cC * p[0] - sC * p[1]), Q[1] - (sC * p[0] + cC * p[1]), Q[2] - p[2]);

    for (int k = 0; k < J.nu; ++k) {
      PVec<S>& s = ws.partial_planar[J.u_offset + k];
      if (J.speeds[k].rotation) {  // Ω = σ z: (σ, σ Q_y, −σ Q_x), σ = ±1
        const S sigma = a[2];
        s = PVec<S>(sigma, sigma * Q[1], -sigma * Q[0]);
      } else {  // translation along R_P e, e in the plane
        const Vec3<S>& e = J.type == JointType::planar ? (k == 0 ? ws.plane_e1[ji] : ws.plane_e2[ji]) : a;
        s = PVec<S>(S(0), cP * e[0] - sP * e[1], sP * e[0] + cP * e[1]);
      }
    }
    // I_zz of the body is the same in the world (a rotation about z keeps it).
    const S mC = ws.mass[C];
    const Vec3<S>& c = ws.com[C];
    PlanarInertia<S>& I = ws.inertia_planar[C];
    I.m = mC;
    I.hx = mC * c[0];
    I.hy = mC * c[1];
    I.I = ws.inertia_body[C](2, 2) + I.hx * c[0] + I.hy * c[1];
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
      prefix[0] = ws.velocity_planar[P];
      A = ws.bias_planar[P];
    } else {
      prefix[0].setZero();
      A.setZero();
    }
    const S* uj = u + J.u_offset;
    const PVec<S>* s = ws.partial_planar.data() + J.u_offset;
    for (int k = 0; k < J.nu; ++k) prefix[k + 1] = prefix[k] + s[k] * uj[k];
    for (int k = 0; k < J.nu; ++k) A += cross_motion_planar<S>(prefix[J.speeds[k].carriers], s[k]) * uj[k];
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
    if (J.parent >= 0) ws.composite_planar[J.parent] += ws.composite_planar[J.child];
  }
  ws.mass_matrix.setZero();
  for (const Joint& J : m.joints) {
    const std::vector<int>& moved_by = m.ancestor_speeds[J.child];
    for (int l = J.u_offset; l < J.u_offset + J.nu; ++l) {
      const PVec<S> F = ws.composite_planar[J.child] * ws.partial_planar[l];
      for (int k : moved_by) {
        const PVec<S>& sk = ws.partial_planar[k];
        const S Mkl = sk[0] * F[0] + sk[1] * F[1] + sk[2] * F[2];
        ws.mass_matrix(k, l) = Mkl;
        ws.mass_matrix(l, k) = Mkl;
      }
    }
  }
}

template <class S>
void compute_forcing_planar(const Model& m, Workspace<S>& ws) {
  const int nb = m.nbody();
  const S gx = ws.gravity[0], gy = ws.gravity[1];
  // Applied minus inertial wrench of each body at O: gravity m g at the mass center (its z
  // component does no work in the plane), then −(I A₀ + V ×* I V).
  for (int b = 0; b < nb; ++b) {
    const PlanarInertia<S>& I = ws.inertia_planar[b];
    const PVec<S>& V = ws.velocity_planar[b];
    const S Fx = ws.mass[b] * gx, Fy = ws.mass[b] * gy;
    const Vec3<S>& c = ws.com[b];
    ws.wrench_planar[b] = PVec<S>(c[0] * Fy - c[1] * Fx, Fx, Fy) -
                          (I * ws.bias_planar[b] + cross_force_planar<S>(V, I * V));
  }
  for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) { ws.wrench_planar[b] += PVec<S>(w[2], w[3], w[4]); });
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) ws.wrench_planar[J.parent] += ws.wrench_planar[J.child];
  }
  for (const Joint& J : m.joints)
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) ws.forcing[k] = ws.partial_planar[k].dot(ws.wrench_planar[J.child]);
}

#define KANESENS_INSTANTIATE(S)                                                         \
  template void compute_position_planar<S>(const Model&, Workspace<S>&, const S*);     \
  template void compute_velocity_planar<S>(const Model&, Workspace<S>&, const S*);     \
  template void compute_mass_matrix_planar<S>(const Model&, Workspace<S>&);            \
  template void compute_forcing_planar<S>(const Model&, Workspace<S>&);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics::detail
