// Dynamics stage of Kane's equations: mass matrix, forcing, energies, the solve for u̇.
#include <cmath>

#include "math/dual.hpp"
#include "math/cholesky.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/planar_stages.hpp"

namespace kanesens::dynamics {

using math::cross_force;
using math::wrench_at_origin;

template <class S>
void compute_mass_matrix(const Model& m, Workspace<S>& ws) {
  if (m.evaluate_planar()) return detail::compute_mass_matrix_planar(m, ws);
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
  if (m.evaluate_planar()) {
    detail::compute_forcing_planar(m, ws);
  } else {
    const int nb = m.nbody();
    // Applied minus inertial wrench of each body at O: gravity, then −(I A₀ + V ×* I V).
    for (int b = 0; b < nb; ++b) {
      const Vec6<S>& V = ws.velocity[b];
      const SpatialInertia<S>& I = ws.spatial_inertia[b];
      ws.wrench[b] = wrench_at_origin<S>(ws.com[b], ws.mass[b] * ws.gravity) -
                     (I * ws.bias_acceleration[b] + cross_force<S>(V, I * V));
    }
    detail::for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) { ws.wrench[b] += w; });
    for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
      const Joint& J = m.joints[*it];
      if (J.parent >= 0) ws.wrench[J.parent] += ws.wrench[J.child];
    }
    for (const Joint& J : m.joints)
      for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) ws.forcing[k] = ws.partial[k].dot(ws.wrench[J.child]);
  }
  detail::add_joint_spring_dampers(m, ws, q, u);
}

template <class S>
bool solve_accelerations(const Model& m, Workspace<S>& ws) {
  // M = Uᵀ U into ws.cholesky (kept: solve_constrained_accelerations reuses it), u̇ = M⁻¹ f.
  const int n = m.nu;
  if (!math::cholesky_factor(ws.mass_matrix.data(), n, ws.cholesky.data(), n, n)) return false;
  ws.udot = ws.forcing;
  math::cholesky_solve(ws.cholesky.data(), n, n, ws.udot.data());
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

const char* describe(RhsFailure failure) {
  switch (failure) {
    case RhsFailure::none: return "no failure";
    case RhsFailure::mass_matrix_not_positive_definite: return "mass matrix is not positive definite";
    case RhsFailure::constraints_degenerate:
      return "the constraint system is degenerate (every constraint row vanishes, or it is not finite)";
  }
  return "?";
}

template <class S>
void evaluate_constraints(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u,
                          const DynamicsOptions& options) {
  evaluate_state_expressions(m, ws, t, q, u);
  compute_position(m, ws, q);
  compute_velocity(m, ws, u);
  compute_kinematic_derivatives(m, ws, q, u);
  compute_constraints(m, ws, q, u, options);
}

template <class S>
bool evaluate_rhs(const Model& m, Workspace<S>& ws, const S& t, const S* y, S* ydot, const DynamicsOptions& options,
                  RhsFailure* failure) {
  const S* q = y;
  const S* u = y + m.nq;
  evaluate_mass_matrix_and_forcing(m, ws, t, q, u);
  compute_kinematic_derivatives(m, ws, q, u);
  RhsFailure why = RhsFailure::none;
  if (!solve_accelerations(m, ws)) {
    why = RhsFailure::mass_matrix_not_positive_definite;
  } else if (m.nconstraint_rows > 0) {
    compute_constraints(m, ws, q, u, options);
    if (!solve_constrained_accelerations(m, ws)) why = RhsFailure::constraints_degenerate;
  }
  for (int i = 0; i < m.nq; ++i) ydot[i] = ws.qdot[i];
  for (int i = 0; i < m.nu; ++i) ydot[m.nq + i] = ws.udot[i];
  if (failure) *failure = why;
  return why == RhsFailure::none;
}

template <class S>
S kinetic_energy(const Model& m, const Workspace<S>& ws) {
  S T = S(0);
  if (m.evaluate_planar()) {
    for (int b = 0; b < m.nbody(); ++b)
      T += S(0.5) * ws.velocity_planar[b].dot(ws.inertia_planar[b] * ws.velocity_planar[b]);
    return T;
  }
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
    detail::point_state(ws, f.body_a, detail::slot_vec3(ws, f.point_a), pa, va);
    detail::point_state(ws, f.body_b, detail::slot_vec3(ws, f.point_b), pb, vb);
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
  template void evaluate_constraints<S>(const Model&, Workspace<S>&, const S&, const S*, const S*,   \
                                        const DynamicsOptions&);                                  \
  template bool evaluate_rhs<S>(const Model&, Workspace<S>&, const S&, const S*, S*,             \
                                const DynamicsOptions&, RhsFailure*);                           \
  template S kinetic_energy<S>(const Model&, const Workspace<S>&);                              \
  template S potential_energy<S>(const Model&, const Workspace<S>&, const S*);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
