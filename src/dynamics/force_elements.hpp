// Applied forces shared by the 3-D and planar evaluations (dynamics/equations.cpp, dynamics/planar.cpp):
// spring-dampers, forces and torques as wrenches at the body's reference point Q_b (world-aligned
// components), and 1-DOF joint springs/dampers as generalized forces. Internal to dynamics/.
#pragma once
#include <cmath>

#include "math/dual.hpp"
#include "dynamics/frames.hpp"
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics::detail {

using math::wrench_at;

template <class S>
Vec3<S> slot_vec3(const Workspace<S>& ws, const Slot3& s) {
  return {ws.values[s[0]], ws.values[s[1]], ws.values[s[2]]};
}

// Calls add(body, wrench at its Q) for each force element's action on a body (not ground).
template <class S, class Add>
void for_each_force_element(const Model& m, const Workspace<S>& ws, Add&& add) {
  for (const Force& f : m.forces) {
    switch (f.kind) {
      case Force::Kind::spring_damper: {
        const BodyPoint<S> pa = body_point(m, ws, f.body_a, slot_vec3(ws, f.point_a));
        const BodyPoint<S> pb = body_point(m, ws, f.body_b, slot_vec3(ws, f.point_b));
        const Vec3<S> d = separation(pa, pb);
        using std::sqrt;
        const S L = sqrt(d.squaredNorm());
        if (!(value_of(L) > 0)) break;  // coincident points: direction undefined, no force
        const Vec3<S> e = d / L;
        const S Ldot = e.dot(velocity_of(ws, pb) - velocity_of(ws, pa));
        const S tension = ws.values[f.k] * (L - ws.values[f.rest]) + ws.values[f.c] * Ldot;
        const Vec3<S> Fa = tension * e;
        if (f.body_a >= 0) add(f.body_a, wrench_at<S>(pa.offset, Fa));
        if (f.body_b >= 0) add(f.body_b, wrench_at<S>(pb.offset, (-Fa).eval()));
        break;
      }
      case Force::Kind::force: {
        const int b = f.body;
        Vec3<S> F = slot_vec3(ws, f.vector);
        if (f.body_frame) F = ws.R[b] * F;
        add(b, wrench_at<S>(point_offset(ws, b, slot_vec3(ws, f.point)), F));
        break;
      }
      case Force::Kind::torque: {
        const int b = f.body;
        Vec3<S> T = slot_vec3(ws, f.vector);
        if (f.body_frame) T = ws.R[b] * T;
        Vec6<S> w;
        w << T, Vec3<S>::Zero();
        add(b, w);
        break;
      }
    }
  }
}

// Joint springs and dampers: f_k −= k (q − rest) + c u on the joint's (single) speed.
template <class S>
void add_joint_spring_dampers(const Model& m, Workspace<S>& ws, const S* q, const S* u) {
  for (const Joint& J : m.joints) {
    if (J.spring_k >= 0)
      ws.forcing[J.u_offset] -= ws.values[J.spring_k] * (q[J.q_offset] - ws.values[J.spring_rest]);
    if (J.damper_c >= 0) ws.forcing[J.u_offset] -= ws.values[J.damper_c] * u[J.u_offset];
  }
}

}  // namespace kanesens::dynamics::detail
