// Body, point and joint queries (dynamics/queries.hpp).
#include "dynamics/queries.hpp"

#include <cmath>

#include "dynamics/equations.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/frames.hpp"
#include "math/dual.hpp"
#include "math/dual2.hpp"

namespace kanesens::dynamics {

using math::cross_force;
using math::force_to_parent;
using math::wrench_at;

namespace {

// (ω_z, v_x, v_y) → the 6-D motion vector it stands for (the other components are 0).
template <class S>
Vec6<S> lift(const PVec<S>& p) {
  Vec6<S> v;
  v << S(0), S(0), p[0], p[1], p[2], S(0);
  return v;
}

// Spatial acceleration (α, a_Q) of body b at its reference point Q_b: the bias (u̇ = 0) plus
// Σ_k s_k u̇_k, each speed's partial velocity (at the Q of its joint's child: (Ω_k, 0) for a
// rotation, (0, L_k) for a translation) carried to Q_b joint by joint.
template <class S>
Vec6<S> body_acceleration(const Model& m, const Workspace<S>& ws, int b) {
  const bool planar = m.evaluate_planar();
  Vec6<S> a = planar ? lift(ws.bias_planar[b]) : ws.bias_acceleration[b];
  Vec3<S> o = Vec3<S>::Zero();  // Q_b − Q of the current joint's child
  for (int x = b; x >= 0; x = m.bodies[x].parent) {
    const Joint& J = m.joints[m.bodies[x].joint];
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) {
      const Vec6<S> s = planar ? lift(ws.partial_planar[k]) : ws.partial[k];
      const S ud = ws.udot[k];
      if (J.speeds[k - J.u_offset].rotation) {
        a.template head<3>() += s.template head<3>() * ud;
        a.template tail<3>() += s.template head<3>().cross(o) * ud;
      } else {
        a.template tail<3>() += s.template tail<3>() * ud;
      }
    }
    o += ws.joint_offset[m.bodies[x].joint];
  }
  return a;
}

template <class S>
Vec3<S> slot3(const Workspace<S>& ws, const Slot3& s) {
  return {ws.values[s[0]], ws.values[s[1]], ws.values[s[2]]};
}

// Adds the constraint forces λ to the per-body external wrenches (at the body's Q) in `ext`,
// indexed by the body's joint.
template <class S>
void add_constraint_wrenches(const Model& m, const Workspace<S>& ws, std::vector<JointLoad<S>>& ext) {
  auto add = [&](const BodyPoint<S>& p, const Vec3<S>& F) {
    if (p.body < 0) return;
    JointLoad<S>& e = ext[m.bodies[p.body].joint];
    e.force += F;
    e.moment += p.offset.cross(F);
  };
  for (const Constraint& c : m.constraints) {
    const int r0 = c.row_offset;
    switch (c.kind) {
      case Constraint::Kind::coincident: {
        Vec3<S> F = Vec3<S>::Zero();
        for (int i = 0; i < c.nrows; ++i) F[c.components[i]] = ws.multipliers[r0 + i];
        add(body_point(m, ws, c.body_a, slot3(ws, c.point_a)), F);
        add(body_point(m, ws, c.body_b, slot3(ws, c.point_b)), (-F).eval());
        break;
      }
      case Constraint::Kind::distance: {
        const BodyPoint<S> pa = body_point(m, ws, c.body_a, slot3(ws, c.point_a));
        const BodyPoint<S> pb = body_point(m, ws, c.body_b, slot3(ws, c.point_b));
        using std::sqrt;
        const Vec3<S> d = separation(pa, pb);
        const Vec3<S> F = ws.multipliers[r0] * d / sqrt(d.squaredNorm());
        add(pb, F);
        add(pa, (-F).eval());
        break;
      }
      case Constraint::Kind::rolling: {
        // The contact point as dynamics/constraints.cpp defines it: c − r ŵ, w = n − (n·a) a;
        // λ in the plane's basis (t1, t2, n).
        using std::sqrt;
        const int b = c.body;
        const Vec3<S> a = (ws.R[b] * slot3(ws, c.axis)).normalized();
        const Vec3<S> n = slot3(ws, c.normal).normalized();
        const Vec3<S> w = n - n.dot(a) * a;
        BodyPoint<S> P = body_point(m, ws, b, Vec3<S>::Zero().eval());
        P.offset -= ws.values[c.radius] * w / sqrt(w.squaredNorm());
        Vec3<S> t1, t2;
        rolling_plane_basis(n, t1, t2);
        add(P, (ws.multipliers[r0] * t1 + ws.multipliers[r0 + 1] * t2 + ws.multipliers[r0 + 2] * n).eval());
        break;
      }
      case Constraint::Kind::coupler:
      case Constraint::Kind::general:
        break;  // generalized forces on joint speeds: part of those joints' loads
    }
  }
}

}  // namespace

template <class S>
Vec3<S> body_position(const Model& m, const Workspace<S>& ws, int b) {
  return world_point(m, ws, b, Vec3<S>::Zero().eval());
}

template <class S>
Mat3<S> body_rotation(const Model&, const Workspace<S>& ws, int b) {
  return ws.R[b];
}

template <class S>
Eigen::Matrix<S, 4, 1> rotation_quaternion(const Mat3<S>& R) {
  // Shepperd's method: start from the largest of 4w², 4x², 4y², 4z² (well conditioned).
  using std::sqrt;
  const S tr = R(0, 0) + R(1, 1) + R(2, 2);
  const double c[4] = {value_of(tr), value_of(R(0, 0)), value_of(R(1, 1)), value_of(R(2, 2))};
  int k = 0;
  for (int i = 1; i < 4; ++i)
    if (c[i] > c[k]) k = i;
  Eigen::Matrix<S, 4, 1> q;
  if (k == 0) {
    const S s = sqrt(S(1) + tr) * S(2);  // 4w
    q << S(0.25) * s, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s;
  } else if (k == 1) {
    const S s = sqrt(S(1) + R(0, 0) - R(1, 1) - R(2, 2)) * S(2);  // 4x
    q << (R(2, 1) - R(1, 2)) / s, S(0.25) * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
  } else if (k == 2) {
    const S s = sqrt(S(1) + R(1, 1) - R(0, 0) - R(2, 2)) * S(2);  // 4y
    q << (R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, S(0.25) * s, (R(1, 2) + R(2, 1)) / s;
  } else {
    const S s = sqrt(S(1) + R(2, 2) - R(0, 0) - R(1, 1)) * S(2);  // 4z
    q << (R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, S(0.25) * s;
  }
  if (value_of(q[0]) < 0) q = -q;
  return q;
}

template <class S>
Vec3<S> point_position(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r) {
  return world_point(m, ws, b, r);
}

template <class S>
Vec3<S> angular_velocity(const Model&, const Workspace<S>& ws, int b) {
  return ws.velocity[b].template head<3>();
}

template <class S>
Vec3<S> point_velocity(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r) {
  return velocity_of(ws, body_point(m, ws, b, r));
}

template <class S>
Vec3<S> angular_acceleration(const Model& m, const Workspace<S>& ws, int b) {
  return body_acceleration(m, ws, b).template head<3>();
}

template <class S>
Vec3<S> point_acceleration(const Model& m, const Workspace<S>& ws, int b, const Vec3<S>& r) {
  // a_P = a_Q + α × o + ω × v_P, (α, a_Q) the spatial acceleration at Q_b, o = P − Q_b.
  const Vec6<S> a = body_acceleration(m, ws, b);
  const Vec3<S> o = point_offset(ws, b, r);
  const Vec3<S> w = ws.velocity[b].template head<3>();
  const Vec3<S> v = ws.velocity[b].template tail<3>() + w.cross(o);
  return a.template tail<3>() + a.template head<3>().cross(o) + w.cross(v);
}

template <class S>
void joint_loads(const Model& m, const Workspace<S>& ws, std::vector<JointLoad<S>>& loads) {
  // Per body (stored at its joint): external forces first, as (force, moment about Q_b).
  loads.resize(m.joints.size());
  for (JointLoad<S>& l : loads) {
    l.force.setZero();
    l.moment.setZero();
  }
  for (int b = 0; b < m.nbody(); ++b) {
    const Vec6<S> g = wrench_at<S>(point_offset(ws, b, Vec3<S>::Zero().eval()), (ws.mass[b] * ws.gravity).eval());
    loads[m.bodies[b].joint].moment = g.template head<3>();
    loads[m.bodies[b].joint].force = g.template tail<3>();
  }
  detail::for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) {
    loads[m.bodies[b].joint].moment += w.template head<3>();
    loads[m.bodies[b].joint].force += w.template tail<3>();
  });
  if (m.nconstraint_rows > 0) add_constraint_wrenches(m, ws, loads);
  // Rate of change of momentum minus the external forces, per body, at Q_b: I a + v ×* I v − f_ext.
  for (int b = 0; b < m.nbody(); ++b) {
    math::SpatialInertia<S> I;
    math::rotate_inertia<S>(ws.inertia_local[b], ws.R[b], I);
    const Vec6<S>& v = ws.velocity[b];
    const Vec6<S> h = I * body_acceleration(m, ws, b) + cross_force<S>(v, I * v);
    JointLoad<S>& l = loads[m.bodies[b].joint];
    l.moment = h.template head<3>() - l.moment;
    l.force = h.template tail<3>() - l.force;
  }
  // Subtree sums, children before parents, each moved from the child's Q to the parent's
  // (Q_parent = Q_child − r_J). A joint's load is then about its joint point, the child's Q.
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const model::Joint& J = m.joints[*it];
    if (J.parent < 0) continue;
    Vec6<S> f;
    f << loads[*it].moment, loads[*it].force;
    const Vec6<S> up = force_to_parent<S>(f, ws.joint_offset[*it]);
    JointLoad<S>& p = loads[m.bodies[J.parent].joint];
    p.moment += up.template head<3>();
    p.force += up.template tail<3>();
  }
}

template <class S>
ForceElementState<S> force_element_state(const Model& m, const Workspace<S>& ws, int fi) {
  const model::Force& f = m.forces[fi];
  const BodyPoint<S> pa = body_point(m, ws, f.body_a, slot3(ws, f.point_a));
  const BodyPoint<S> pb = body_point(m, ws, f.body_b, slot3(ws, f.point_b));
  using std::sqrt;
  const Vec3<S> d = separation(pa, pb);
  const S L = sqrt(d.squaredNorm());
  // Coincident points: no direction, so no rate (the force element applies no force then).
  const S rate = value_of(L) > 0 ? S((d / L).dot(velocity_of(ws, pb) - velocity_of(ws, pa))) : S(0);
  return {L, rate, ws.values[f.k] * (L - ws.values[f.rest]) + ws.values[f.c] * rate};
}

#define KANESENS_INSTANTIATE(S)                                                                       \
  template Vec3<S> body_position<S>(const Model&, const Workspace<S>&, int);                          \
  template Mat3<S> body_rotation<S>(const Model&, const Workspace<S>&, int);                          \
  template Eigen::Matrix<S, 4, 1> rotation_quaternion<S>(const Mat3<S>&);                             \
  template Vec3<S> point_position<S>(const Model&, const Workspace<S>&, int, const Vec3<S>&);         \
  template Vec3<S> angular_velocity<S>(const Model&, const Workspace<S>&, int);                       \
  template Vec3<S> point_velocity<S>(const Model&, const Workspace<S>&, int, const Vec3<S>&);         \
  template Vec3<S> angular_acceleration<S>(const Model&, const Workspace<S>&, int);                   \
  template Vec3<S> point_acceleration<S>(const Model&, const Workspace<S>&, int, const Vec3<S>&);     \
  template void joint_loads<S>(const Model&, const Workspace<S>&, std::vector<JointLoad<S>>&);        \
  template ForceElementState<S> force_element_state<S>(const Model&, const Workspace<S>&, int);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
KANESENS_INSTANTIATE(math::Dual2)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
