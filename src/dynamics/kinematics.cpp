// Position and velocity stages of Kane's equations (see dynamics/equations.hpp).
#include "math/dual.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics {

using math::axis_angle;
using math::body_spatial_inertia;
using math::cross_motion;
using math::quaternion_rotation;

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

template <class S>
void compute_position(const Model& m, Workspace<S>& ws, const S* q) {
  if (m.evaluate_planar()) return detail::compute_position_planar(m, ws, q);
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    const Mat3<S> R_P = P >= 0 ? ws.R[P] : Mat3<S>::Identity();
    const Vec3<S> c_P = P >= 0 ? ws.com[P] : Vec3<S>::Zero();
    const S* qj = q + J.q_offset;
    const Vec3<S>& a = ws.joint_axis[ji];
    Mat3<S> R_PC = Mat3<S>::Identity();
    Vec3<S> d = Vec3<S>::Zero();  // child point relative to parent point, parent frame
    Mat3<S> R_first = Mat3<S>::Identity();  // universal: the first rotation
    switch (J.type) {
      case JointType::revolute: R_PC = axis_angle<S>(a, qj[0]); break;
      case JointType::prismatic: d = qj[0] * a; break;
      case JointType::cylindrical:
        R_PC = axis_angle<S>(a, qj[0]);
        d = qj[1] * a;
        break;
      case JointType::universal:
        R_first = axis_angle<S>(a, qj[0]);
        R_PC = R_first * axis_angle<S>(ws.joint_axis2[ji], qj[1]);
        break;
      case JointType::planar:
        d = qj[0] * ws.plane_e1[ji] + qj[1] * ws.plane_e2[ji];
        R_PC = axis_angle<S>(a, qj[2]);
        break;
      case JointType::spherical: R_PC = quaternion_rotation<S>(qj[0], qj[1], qj[2], qj[3]); break;
      case JointType::free:
        d = Vec3<S>(qj[0], qj[1], qj[2]);
        R_PC = quaternion_rotation<S>(qj[3], qj[4], qj[5], qj[6]);
        break;
      case JointType::weld: break;
    }
    const Vec3<S> Q = c_P + R_P * (ws.parent_point[ji] + d);
    ws.joint_point[ji] = Q;
    ws.R[C] = R_P * R_PC;
    ws.com[C] = Q - ws.R[C] * ws.child_point[ji];

    for (int k = 0; k < J.nu; ++k) {
      const SpeedAxis& sp = J.speeds[k];
      Vec3<S> dir;
      if (sp.in_child_frame) {
        dir = ws.R[C].col(sp.child_axis);
      } else if (J.type == JointType::universal && k == 1) {
        dir = R_P * (R_first * ws.joint_axis2[ji]);
      } else if (J.type == JointType::planar && k < 2) {
        dir = R_P * (k == 0 ? ws.plane_e1[ji] : ws.plane_e2[ji]);
      } else if (J.type == JointType::free && k < 3) {
        dir = R_P.col(k);
      } else {
        dir = R_P * a;
      }
      Vec6<S>& s = ws.partial[J.u_offset + k];
      if (sp.rotation) {
        s.template head<3>() = dir;
        s.template tail<3>() = Q.cross(dir);
      } else {
        s.template head<3>().setZero();
        s.template tail<3>() = dir;
      }
    }
    ws.spatial_inertia[C] =
        body_spatial_inertia<S>(ws.mass[C], ws.com[C], ws.R[C], ws.inertia_body[C], ws.inertia_world[C]);
  }
}

template <class S>
void compute_velocity(const Model& m, Workspace<S>& ws, const S* u) {
  if (m.evaluate_planar()) return detail::compute_velocity_planar(m, ws, u);
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int P = J.parent, C = J.child;
    // prefix[c] = V_P + Σ_{k<c} s_k u_k; prefix[nu] is the child's velocity.
    Vec6<S>* prefix = ws.prefix.data();
    Vec6<S> A;
    if (P >= 0) {
      prefix[0] = ws.velocity[P];
      A = ws.bias_acceleration[P];
    } else {
      prefix[0].setZero();
      A.setZero();
    }
    for (int k = 0; k < J.nu; ++k) prefix[k + 1] = prefix[k] + ws.partial[J.u_offset + k] * u[J.u_offset + k];
    // d/dt s_k = V_F × s_k, F the frame carrying axis k: the parent, moved by the first
    // `carriers` speeds of this joint (universal, planar rotation) or the child (ball, free).
    for (int k = 0; k < J.nu; ++k)
      A += cross_motion<S>(prefix[J.speeds[k].carriers], ws.partial[J.u_offset + k]) * u[J.u_offset + k];
    ws.velocity[C] = prefix[J.nu];
    ws.bias_acceleration[C] = A;
  }
}

template <class S>
void compute_kinematic_derivatives(const Model& m, Workspace<S>& ws, const S* q, const S* u) {
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
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
