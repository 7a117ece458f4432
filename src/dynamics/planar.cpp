// Kane's equations of a planar scene (Model::planar) with 3-component spatial vectors
// (math/planar.hpp): the same recursion as kinematics.cpp/equations.cpp, where a body's rotation
// is a rotation about z by its angle (cos, sin), a speed's partial velocity is (Ω_z, v_x, v_y)
// at its body's reference point and an inertia is 4 numbers. Bodies keep constant z offsets;
// R, joint_offset, tree_anchor, tree_position and the 6-D velocity are still filled for force
// elements and energies.
#include <cmath>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics::detail {

using math::cross_force_planar;
using math::cross_motion_planar;
using math::force_to_parent_planar;
using math::motion_to_child_planar;

template <class S>
void compute_position_planar(const Model& m, Workspace<S>& ws, const S* q) {
  using std::cos, std::sin;
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
        cq = cos(qj[0]);
        sq = a[2] * sin(qj[0]);
        break;
      case JointType::prismatic: r += qj[0] * a; break;
      case JointType::planar:
        r += qj[0] * ws.plane_e1[ji] + qj[1] * ws.plane_e2[ji];
        cq = cos(qj[2]);
        sq = a[2] * sin(qj[2]);
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
    if (J.parent >= 0) {
      const Vec3<S>& r = ws.joint_offset[*it];
      ws.composite_planar[J.child].add_to_parent(r[0], r[1], ws.composite_planar[J.parent]);
    }
  }
  auto power = [](const PVec<S>& s, bool rotation, const PVec<S>& F) {
    return rotation ? S(s[0] * F[0]) : S(s[1] * F[1] + s[2] * F[2]);
  };
  for (const Joint& J : m.joints) {
    for (int l = J.u_offset; l < J.u_offset + J.nu; ++l) {
      PVec<S> F = ws.composite_planar[J.child] * ws.partial_planar[l];
      for (int k = J.u_offset; k <= l; ++k) {
        const S Mkl = power(ws.partial_planar[k], J.speeds[k - J.u_offset].rotation, F);
        ws.mass_matrix(k, l) = Mkl;
        ws.mass_matrix(l, k) = Mkl;
      }
      for (int b = J.child; m.bodies[b].parent >= 0;) {
        const Vec3<S>& r = ws.joint_offset[m.bodies[b].joint];
        F[0] += r[0] * F[2] - r[1] * F[1];
        b = m.bodies[b].parent;
        const Joint& K = m.joints[m.bodies[b].joint];
        for (int k = K.u_offset; k < K.u_offset + K.nu; ++k) {
          const S Mkl = power(ws.partial_planar[k], K.speeds[k - K.u_offset].rotation, F);
          ws.mass_matrix(k, l) = Mkl;
          ws.mass_matrix(l, k) = Mkl;
        }
      }
    }
  }
}

template <class S>
void compute_forcing_planar(const Model& m, Workspace<S>& ws) {
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
  template void compute_forcing_planar<S>(const Model&, Workspace<S>&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics::detail
