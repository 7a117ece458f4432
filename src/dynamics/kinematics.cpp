// Position and velocity stages of Kane's equations (see dynamics/equations.hpp).
#include <algorithm>
#include <type_traits>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/joint_angles.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics {

using math::axis_angle;
using math::motion_to_child;
using math::quaternion_rotation;
using math::rotate_inertia;

template <class S>
void evaluate_state_expressions(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u) {
  ws.time = t;
  expr::Inputs<S> in;
  in.parameters = ws.parameters.data();
  in.coordinates = q;
  in.speeds = u;
  in.time = t;
  for (Slot s : m.state_slots) ws.values[s] = m.expressions[s].evaluate(in);
}

namespace {
// The spatial inertia of body C in world-aligned components at its rotation R_C.
template <class S>
void rotate_body_inertia(Workspace<S>& ws, int C, const Mat3<S>& R_C) {
  if (!std::is_same_v<S, double> && ws.inertia_constant[static_cast<std::size_t>(C)])
    math::rotate_constant_inertia<S>(ws.inertia_local[C], R_C, ws.spatial_inertia[C]);
  else if (ws.inertia_diagonal[static_cast<std::size_t>(C)])
    math::rotate_diagonal_inertia<S>(ws.inertia_local[C], R_C, ws.spatial_inertia[C],
                                     ws.inertia_h_axis[static_cast<std::size_t>(C)]);
  else
    rotate_inertia<S>(ws.inertia_local[C], R_C, ws.spatial_inertia[C]);
}
}  // namespace

template <class S>
void compute_position(const Model& m, Workspace<S>& ws, const S* q) {
  if (m.evaluate_planar()) return detail::compute_position_planar(m, ws, q);
  detail::compute_joint_angles(ws, q);
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    const Mat3<S>& R_P = P >= 0 ? ws.R[P] : ws.identity;
    const S* qj = q + J.q_offset;
    const Vec3<S>& a = ws.joint_axis[ji];
    Mat3<S>& R_C = ws.R[C];
    if (const int i = ws.joint_axis_index[ji]; J.type == JointType::revolute && i >= 0) {
      // The common case in straight-line code: a revolute about a coordinate axis e_i of the
      // parent (and of the child: column i is shared) with no travel.
      S cos_q, sin_q;
      detail::joint_angle(ws, q, J.q_offset, cos_q, sin_q);
      math::rotate_about_coordinate_axis<S>(R_P, i, cos_q, sin_q, R_C);
      if (P >= 0) {
        Vec3<S>& r = ws.joint_offset[ji];
        if (const int k = ws.joint_lever_axis[ji]; k >= 0)
          r = R_P.col(k) * ws.joint_lever[ji][k];
        else
          r.noalias() = R_P * ws.joint_lever[ji];
        ws.tree_position[C] = ws.tree_position[P] + r;
      } else {
        ws.tree_anchor[ji] = ws.joint_lever[ji];
        ws.tree_position[C].setZero();
      }
      Vec6<S>& s = ws.partial[J.u_offset];
      s.template head<3>() = R_P.col(i);
      s.template tail<3>().setZero();
      rotate_body_inertia(ws, C, R_C);
      continue;
    }
    auto rotate = [&](const Mat3<S>& R_PC) {  // R_C = R_P R_PC
      if (P >= 0) R_C.noalias() = R_P * R_PC;
      else R_C = R_PC;
    };
    Vec3<S> d = Vec3<S>::Zero();         // the joint's translation, parent frame
    Vec3<S> second_axis = Vec3<S>::Zero();  // universal: the second axis, world components
    switch (J.type) {
      case JointType::revolute: rotate(axis_angle<S>(a, qj[0])); break;  // (about e_i: above)
      case JointType::prismatic:
        R_C = R_P;
        d = qj[0] * a;
        break;
      case JointType::cylindrical:
        rotate(axis_angle<S>(a, qj[0]));
        d = qj[1] * a;
        break;
      case JointType::universal: {
        const int i1 = ws.joint_axis_index[ji], i2 = ws.joint_axis2_index[ji];
        if (i1 >= 0 && i2 >= 0) {
          // Both axes coordinate axes: R_P R_first and then R_C, each rotating two columns.
          S cos_q, sin_q;
          Mat3<S> R_mid;
          detail::joint_angle(ws, q, J.q_offset, cos_q, sin_q);
          math::rotate_about_coordinate_axis<S>(P >= 0 ? R_P : ws.identity, i1, cos_q, sin_q, R_mid);
          detail::joint_angle(ws, q, J.q_offset + 1, cos_q, sin_q);
          math::rotate_about_coordinate_axis<S>(R_mid, i2, cos_q, sin_q, R_C);
          second_axis = R_mid.col(i2);
          break;
        }
        const Mat3<S> R_first = axis_angle<S>(a, qj[0]);
        const Vec3<S> first_a2 = R_first * ws.joint_axis2[ji];
        second_axis.noalias() = R_P * first_a2;
        rotate((R_first * axis_angle<S>(ws.joint_axis2[ji], qj[1])).eval());
        break;
      }
      case JointType::planar:
        d = qj[0] * ws.plane_e1[ji] + qj[1] * ws.plane_e2[ji];
        rotate(axis_angle<S>(a, qj[2]));
        break;
      case JointType::spherical: rotate(quaternion_rotation<S>(qj[0], qj[1], qj[2], qj[3])); break;
      case JointType::free:
        d = Vec3<S>(qj[0], qj[1], qj[2]);
        rotate(quaternion_rotation<S>(qj[3], qj[4], qj[5], qj[6]));
        break;
      case JointType::weld: R_C = R_P; break;
    }
    // Q_C − Q_P = R_P (lever + d): the joint's parent point from Q_P, then the joint's travel.
    if (P >= 0) {
      Vec3<S>& r = ws.joint_offset[ji];
      r.noalias() = R_P * (ws.joint_lever[ji] + d);
      ws.tree_position[C] = ws.tree_position[P] + r;
    } else {
      ws.tree_anchor[ji] = ws.joint_lever[ji] + d;
      ws.tree_position[C].setZero();
    }

    for (int k = 0; k < J.nu; ++k) {
      const SpeedAxis& sp = J.speeds[k];
      Vec6<S>& s = ws.partial[J.u_offset + k];
      auto dir = sp.rotation ? s.template head<3>() : s.template tail<3>();
      if (sp.in_child_frame) dir = R_C.col(sp.child_axis);
      else if (J.type == JointType::universal && k == 1) dir = second_axis;
      else if (J.type == JointType::planar && k < 2) dir.noalias() = R_P * (k == 0 ? ws.plane_e1[ji] : ws.plane_e2[ji]);
      else if (J.type == JointType::free && k < 3) dir = R_P.col(k);
      else if (ws.joint_axis_index[ji] >= 0) dir = R_P.col(ws.joint_axis_index[ji]);
      else dir.noalias() = R_P * a;
      if (sp.rotation) s.template tail<3>().setZero();
      else s.template head<3>().setZero();
    }
    rotate_body_inertia(ws, C, R_C);
  }
}

template <class S>
void compute_velocity(const Model& m, Workspace<S>& ws, const S* u) {
  if (m.evaluate_planar()) return detail::compute_velocity_planar(m, ws, u);
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    // prefix[c] = V_P + Σ_{k<c} s_k u_k at Q_C; prefix[nu] is the child's velocity.
    Vec6<S>* prefix = ws.prefix.data();
    Vec6<S>& A = ws.bias_acceleration[C];
    if (J.nu == 1 && J.speeds[0].carriers == 0 && P >= 0) {
      // One speed about (along) an axis fixed in the parent: V_C = V_P at Q_C + s u,
      // A_C = A_P at Q_C + V_P at Q_C × s u, in 3-vectors.
      const Vec3<S>& r = ws.joint_offset[ji];
      const Vec6<S>& VP = ws.velocity[P];
      const Vec6<S>& AP = ws.bias_acceleration[P];
      const Vec3<S> w = VP.template head<3>();
      const Vec3<S> v = VP.template tail<3>() + w.cross(r);
      const Vec3<S> al = AP.template head<3>();
      const Vec3<S> ac = AP.template tail<3>() + al.cross(r);
      Vec6<S>& V = ws.velocity[C];
      const S uk = u[J.u_offset];
      const Vec6<S>& sk = ws.partial[J.u_offset];
      if (J.speeds[0].rotation) {
        const Vec3<S> au = sk.template head<3>() * uk;
        V.template head<3>() = w + au;
        V.template tail<3>() = v;
        A.template head<3>() = al + w.cross(au);
        A.template tail<3>() = ac + v.cross(au);
      } else {
        const Vec3<S> au = sk.template tail<3>() * uk;
        V.template head<3>() = w;
        V.template tail<3>() = v + au;
        A.template head<3>() = al;
        A.template tail<3>() = ac + w.cross(au);
      }
      continue;
    }
    if (P >= 0) {
      prefix[0] = motion_to_child<S>(ws.velocity[P], ws.joint_offset[ji]);
      A = motion_to_child<S>(ws.bias_acceleration[P], ws.joint_offset[ji]);
    } else {
      prefix[0].setZero();
      A.setZero();
    }
    const S* uj = u + J.u_offset;
    const Vec6<S>* s = ws.partial.data() + J.u_offset;
    for (int k = 0; k < J.nu; ++k) {
      prefix[k + 1] = prefix[k];
      if (J.speeds[k].rotation) prefix[k + 1].template head<3>() += s[k].template head<3>() * uj[k];
      else prefix[k + 1].template tail<3>() += s[k].template tail<3>() * uj[k];
    }
    // d/dt s_k = V_F × s_k, F the frame carrying axis k: the parent, moved by the first
    // `carriers` speeds of this joint (universal, planar rotation) or the child (ball, free).
    // (ω, v) × (a, 0) = (ω × a, v × a); (ω, v) × (0, a) = (0, ω × a).
    for (int k = 0; k < J.nu; ++k) {
      const Vec6<S>& V = prefix[J.speeds[k].carriers];
      if (J.speeds[k].rotation) {
        const Vec3<S> au = s[k].template head<3>() * uj[k];
        A.template head<3>() += V.template head<3>().cross(au);
        A.template tail<3>() += V.template tail<3>().cross(au);
      } else {
        const Vec3<S> au = s[k].template tail<3>() * uj[k];
        A.template tail<3>() += V.template head<3>().cross(au);
      }
    }
    ws.velocity[C] = prefix[J.nu];
  }
}

template <class S>
void compute_kinematic_derivatives(const Model& m, Workspace<S>& ws, const S* q, const S* u) {
  if (!m.has_quaternions) {  // q̇ = u, joint by joint in the same order
    std::copy(u, u + m.nq, ws.qdot.data());
    return;
  }
  for (const Joint& J : m.joints) {
    const S* uj = u + J.u_offset;
    S* qd = ws.qdot.data() + J.q_offset;
    if (J.quaternion_offset < 0) {
      for (int k = 0; k < J.nq; ++k) qd[k] = uj[k];
      continue;
    }
    const int lin = J.type == JointType::free ? 3 : 0;
    for (int k = 0; k < lin; ++k) qd[k] = uj[k];
    const S* e = q + J.quaternion_offset;
    const S* w = uj + lin;
    S* ed = ws.qdot.data() + J.quaternion_offset;
    // q̇ = ½ q ⊗ (0, ω) with ω in child components, plus the norm correction.
    const S corr = kQuaternionStabilization * (S(1) - (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]));
    ed[0] = S(0.5) * (-e[1] * w[0] - e[2] * w[1] - e[3] * w[2]) + corr * e[0];
    ed[1] = S(0.5) * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1]) + corr * e[1];
    ed[2] = S(0.5) * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2]) + corr * e[2];
    ed[3] = S(0.5) * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0]) + corr * e[3];
  }
}

#define KANESENS_INSTANTIATE(S)                                                              \
  template void evaluate_state_expressions<S>(const Model&, Workspace<S>&, const S&, const S*, \
                                              const S*);                                     \
  template void compute_position<S>(const Model&, Workspace<S>&, const S*);                  \
  template void compute_velocity<S>(const Model&, Workspace<S>&, const S*);                  \
  template void compute_kinematic_derivatives<S>(const Model&, Workspace<S>&, const S*, const S*);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
