// Dynamics stage of Kane's equations: mass matrix, forcing, energies, the solve for u̇.
#include <cmath>

#include "ad/dual.hpp"
#include "kane/equations.hpp"

namespace kanesens {
namespace {

template <class S>
Vec3<S> vec3(const Workspace<S>& ws, const Slot3& s) {
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

}  // namespace

template <class S>
void compute_mass_matrix(const Model& m, Workspace<S>& ws) {
  const int nb = m.nbody();
  for (int b = 0; b < nb; ++b) ws.composite_inertia[b] = ws.spatial_inertia[b];
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) ws.composite_inertia[J.parent] += ws.composite_inertia[J.child];
  }
  ws.mass_matrix.setZero();
  for (const Joint& J : m.joints) {
    const std::vector<int>& moved_by = m.ancestor_speeds[J.child];
    for (int l = J.u_offset; l < J.u_offset + J.nu; ++l) {
      const Vec6<S> F = ws.composite_inertia[J.child] * ws.partial[l];
      for (int k : moved_by) {
        const S Mkl = ws.partial[k].dot(F);
        ws.mass_matrix(k, l) = Mkl;
        ws.mass_matrix(l, k) = Mkl;
      }
    }
  }
}

template <class S>
void compute_forcing(const Model& m, Workspace<S>& ws, const S* q, const S* u) {
  const int nb = m.nbody();
  // Applied minus inertial wrench of each body at O: gravity, then −(I A₀ + V ×* I V).
  for (int b = 0; b < nb; ++b) {
    const Vec6<S>& V = ws.velocity[b];
    const Mat6<S>& I = ws.spatial_inertia[b];
    ws.wrench[b] = wrench_at_origin<S>(ws.com[b], ws.mass[b] * ws.gravity) -
                   (I * ws.bias_acceleration[b] + cross_force<S>(V, I * V));
  }
  for (const Force& f : m.forces) {
    switch (f.kind) {
      case Force::Kind::spring_damper: {
        Vec3<S> pa, va, pb, vb;
        point_state(ws, f.body_a, vec3(ws, f.point_a), pa, va);
        point_state(ws, f.body_b, vec3(ws, f.point_b), pb, vb);
        const Vec3<S> d = pb - pa;
        using std::sqrt;
        const S L = sqrt(d.squaredNorm());
        if (!(value_of(L) > 0)) break;  // coincident points: direction undefined, no force
        const Vec3<S> e = d / L;
        const S Ldot = e.dot(vb - va);
        const S tension = ws.values[f.k] * (L - ws.values[f.rest]) + ws.values[f.c] * Ldot;
        const Vec3<S> Fa = tension * e;
        if (f.body_a >= 0) ws.wrench[f.body_a] += wrench_at_origin<S>(pa, Fa);
        if (f.body_b >= 0) ws.wrench[f.body_b] -= wrench_at_origin<S>(pb, Fa);
        break;
      }
      case Force::Kind::force: {
        const int b = f.body;
        Vec3<S> F = vec3(ws, f.vector);
        if (f.body_frame) F = ws.R[b] * F;
        const Vec3<S> p = ws.com[b] + ws.R[b] * vec3(ws, f.point);
        ws.wrench[b] += wrench_at_origin<S>(p, F);
        break;
      }
      case Force::Kind::torque: {
        const int b = f.body;
        Vec3<S> T = vec3(ws, f.vector);
        if (f.body_frame) T = ws.R[b] * T;
        ws.wrench[b].template head<3>() += T;
        break;
      }
    }
  }
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) ws.wrench[J.parent] += ws.wrench[J.child];
  }
  for (const Joint& J : m.joints) {
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) ws.forcing[k] = ws.partial[k].dot(ws.wrench[J.child]);
    if (J.spring_k >= 0)
      ws.forcing[J.u_offset] -= ws.values[J.spring_k] * (q[J.q_offset] - ws.values[J.spring_rest]);
    if (J.damper_c >= 0) ws.forcing[J.u_offset] -= ws.values[J.damper_c] * u[J.u_offset];
  }
}

template <class S>
bool solve_accelerations(const Model& m, Workspace<S>& ws) {
  // In-place Cholesky M = L Lᵀ (lower triangle of ws.cholesky), then two triangular solves.
  const int n = m.nu;
  auto& L = ws.cholesky;
  using std::sqrt;
  for (int j = 0; j < n; ++j) {
    S d = ws.mass_matrix(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(value_of(d) > 0)) return false;
    L(j, j) = sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      S s = ws.mass_matrix(i, j);
      for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
      L(i, j) = s / L(j, j);
    }
  }
  auto& x = ws.udot;
  for (int i = 0; i < n; ++i) {
    S s = ws.forcing[i];
    for (int k = 0; k < i; ++k) s -= L(i, k) * x[k];
    x[i] = s / L(i, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    S s = x[i];
    for (int k = i + 1; k < n; ++k) s -= L(k, i) * x[k];
    x[i] = s / L(i, i);
  }
  return true;
}

template <class S>
void evaluate_mass_matrix_and_forcing(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u) {
  evaluate_state_expressions(m, ws, t, q, u);
  compute_position(m, ws, q);
  compute_velocity(m, ws, u);
  compute_mass_matrix(m, ws);
  compute_forcing(m, ws, q, u);
}

template <class S>
bool evaluate_rhs(const Model& m, Workspace<S>& ws, const S& t, const S* y, S* ydot) {
  const S* q = y;
  const S* u = y + m.nq;
  evaluate_mass_matrix_and_forcing(m, ws, t, q, u);
  compute_kinematic_derivatives(m, ws, q, u);
  bool ok = solve_accelerations(m, ws);
  if (ok && m.nconstraint_rows > 0) {
    compute_constraints(m, ws, q, u);
    solve_constrained_accelerations(m, ws);
  }
  for (int i = 0; i < m.nq; ++i) ydot[i] = ws.qdot[i];
  for (int i = 0; i < m.nu; ++i) ydot[m.nq + i] = ws.udot[i];
  return ok;
}

template <class S>
S kinetic_energy(const Model& m, const Workspace<S>& ws) {
  S T = S(0);
  for (int b = 0; b < m.nbody(); ++b) T += S(0.5) * ws.velocity[b].dot(ws.spatial_inertia[b] * ws.velocity[b]);
  return T;
}

template <class S>
S potential_energy(const Model& m, const Workspace<S>& ws, const S* q) {
  S V = S(0);
  for (int b = 0; b < m.nbody(); ++b) V -= ws.mass[b] * ws.gravity.dot(ws.com[b]);
  for (const Joint& J : m.joints)
    if (J.spring_k >= 0) {
      const S x = q[J.q_offset] - ws.values[J.spring_rest];
      V += S(0.5) * ws.values[J.spring_k] * x * x;
    }
  for (const Force& f : m.forces) {
    if (f.kind != Force::Kind::spring_damper) continue;
    Vec3<S> pa, va, pb, vb;
    point_state(ws, f.body_a, vec3(ws, f.point_a), pa, va);
    point_state(ws, f.body_b, vec3(ws, f.point_b), pb, vb);
    using std::sqrt;
    const S x = sqrt((pb - pa).squaredNorm()) - ws.values[f.rest];
    V += S(0.5) * ws.values[f.k] * x * x;
  }
  return V;
}

#define KANESENS_INSTANTIATE(S)                                                                 \
  template void compute_mass_matrix<S>(const Model&, Workspace<S>&);                            \
  template void compute_forcing<S>(const Model&, Workspace<S>&, const S*, const S*);            \
  template bool solve_accelerations<S>(const Model&, Workspace<S>&);                            \
  template void evaluate_mass_matrix_and_forcing<S>(const Model&, Workspace<S>&, const S&,      \
                                                    const S*, const S*);                        \
  template bool evaluate_rhs<S>(const Model&, Workspace<S>&, const S&, const S*, S*);           \
  template S kinetic_energy<S>(const Model&, const Workspace<S>&);                              \
  template S potential_energy<S>(const Model&, const Workspace<S>&, const S*);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens
