// Applied forces shared by the 3-D and planar evaluations (dynamics/equations.cpp, dynamics/planar.cpp):
// spring-dampers, forces and torques as world wrenches at O, and 1-DOF joint springs/dampers as
// generalized forces. Internal to dynamics/.
#pragma once
#include <cmath>

#include "math/dual.hpp"
#include "dynamics/workspace.hpp"

namespace kanesens::dynamics::detail {

using math::wrench_at_origin;

template <class S>
Vec3<S> slot_vec3(const Workspace<S>& ws, const Slot3& s) {
  return {ws.values[s[0]], ws.values[s[1]], ws.values[s[2]]};
}

// World position and velocity of a point given in body b's frame (b = -1: ground).
template <class S>
void point_state(const Workspace<S>& ws, int b, const Vec3<S>& r, Vec3<S>& p, Vec3<S>& v) {
  if (b < 0) {
    p = r;
    v.setZero();
    return;
  }
  p = ws.com[b] + ws.R[b] * r;
  v = ws.velocity[b].template tail<3>() + ws.velocity[b].template head<3>().cross(p);
}

// Calls add(body, wrench at O) for each force element's action on a body (not ground).
template <class S, class Add>
void for_each_force_element(const Model& m, const Workspace<S>& ws, Add&& add) {
  for (const Force& f : m.forces) {
    switch (f.kind) {
      case Force::Kind::spring_damper: {
        Vec3<S> pa, va, pb, vb;
        point_state(ws, f.body_a, slot_vec3(ws, f.point_a), pa, va);
        point_state(ws, f.body_b, slot_vec3(ws, f.point_b), pb, vb);
        const Vec3<S> d = pb - pa;
        using std::sqrt;
        const S L = sqrt(d.squaredNorm());
        if (!(value_of(L) > 0)) break;  // coincident points: direction undefined, no force
        const Vec3<S> e = d / L;
        const S Ldot = e.dot(vb - va);
        const S tension = ws.values[f.k] * (L - ws.values[f.rest]) + ws.values[f.c] * Ldot;
        const Vec3<S> Fa = tension * e;
        if (f.body_a >= 0) add(f.body_a, wrench_at_origin<S>(pa, Fa));
        if (f.body_b >= 0) add(f.body_b, wrench_at_origin<S>(pb, (-Fa).eval()));
        break;
      }
      case Force::Kind::force: {
        const int b = f.body;
        Vec3<S> F = slot_vec3(ws, f.vector);
        if (f.body_frame) F = ws.R[b] * F;
        const Vec3<S> p = ws.com[b] + ws.R[b] * slot_vec3(ws, f.point);
        add(b, wrench_at_origin<S>(p, F));
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
