// Dynamics stage of Kane's equations: mass matrix, forcing, energies, the solve for u̇.
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "math/cholesky.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/frames.hpp"
#include "dynamics/planar_stages.hpp"
#include "dynamics/tree_factor.hpp"

namespace kanesens::dynamics {

using math::cross_force;
using math::add_force_to_parent;

namespace {
// ws.speed_offset[k] for the first speed k of each joint: its body's reference point minus that
// of the nearest ancestor body whose joint has speeds (0 for a root); the other speeds of a joint
// share its body, so their offsets stay 0.
template <class S>
void compute_speed_offsets(const Model& m, Workspace<S>& ws) {
  const int* parent = m.speed_parent.data();
  for (const Joint& J : m.joints) {
    if (J.nu == 0) continue;
    Vec3<S>& r0 = ws.speed_offset[J.u_offset];
    r0.setZero();
    if (parent[J.u_offset] >= 0)  // to the nearest ancestor body whose joint has speeds
      for (int b = J.child;;) {
        const int jb = m.bodies[b].joint;
        r0 += ws.joint_offset[jb];
        b = m.joints[jb].parent;
        if (m.joints[m.bodies[b].joint].nu > 0) break;
      }
  }
}

}  // namespace

template <class S>
void compute_mass_matrix(const Model& m, Workspace<S>& ws) {
  compute_speed_offsets(m, ws);
  if (m.evaluate_planar()) return detail::compute_mass_matrix_planar(m, ws);
  // Composite rigid bodies (Featherstone 2008 §6.2), each at its own reference point.
  const int nb = m.nbody();
  for (int b = 0; b < nb; ++b) ws.composite_inertia[b] = ws.spatial_inertia[b];
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    if (J.parent >= 0) ws.composite_inertia[J.child].add_to_parent(ws.joint_offset[*it], ws.composite_inertia[J.parent]);
  }
  // M_kl = s_k · (I^c_C s_l) for every speed k moving C (the ancestors of l along
  // Model::speed_parent), the momentum I^c_C s_l = (τ, f) carried from Q_C to each ancestor's
  // reference point on the way to the root: f stays, τ gains r × f for each offset r passed.
  const int* parent = m.speed_parent.data();
  S* M = ws.mass_matrix.data();
  const std::ptrdiff_t ld = ws.mass_matrix.rows();
  const Vec3<S>* offset = ws.speed_offset.data();
  const Vec6<S>* s = ws.partial.data();
  const unsigned char* rotation = m.speed_rotation.data();
  // I^c s_l at l's body, and its power with s_l.
  auto momentum = [&](int l) -> Vec6<S> {
    const SpatialInertia<S>& Ic = ws.composite_inertia[m.speed_body[l]];
    return rotation[l] ? Ic.times_rotation(s[l].template head<3>()) : Ic.times_translation(s[l].template tail<3>());
  };
  auto power = [&](int k, const S& tx, const S& ty, const S& tz, const S& fx, const S& fy, const S& fz) -> S {
    const S* sk = s[k].data();
    return rotation[k] ? S(sk[0] * tx + sk[1] * ty + sk[2] * tz) : S(sk[3] * fx + sk[4] * fy + sk[5] * fz);
  };
  using P2 = Eigen::Array<S, 2, 1>;  // columns l, l2 side by side (vector operations on double)
  for (const auto& [l, l2] : ws.mass_matrix_columns) {
    const Vec6<S> F = momentum(l);
    M[l * ld + l] = power(l, F[0], F[1], F[2], F[3], F[4], F[5]);
    if (l2 < 0) {
      const S fx = F[3], fy = F[4], fz = F[5];
      S tx = F[0], ty = F[1], tz = F[2];
      for (int kp = l, k = parent[l]; k >= 0; kp = k, k = parent[k]) {
        const Vec3<S>& r = offset[kp];
        tx += r[1] * fz - r[2] * fy;
        ty += r[2] * fx - r[0] * fz;
        tz += r[0] * fy - r[1] * fx;
        const S Mkl = power(k, tx, ty, tz, fx, fy, fz);
        M[l * ld + k] = Mkl;
        M[k * ld + l] = Mkl;
      }
      continue;
    }
    Vec6<S> F2 = momentum(l2);
    M[l2 * ld + l2] = power(l2, F2[0], F2[1], F2[2], F2[3], F2[4], F2[5]);
    {
      const Vec3<S>& r = offset[l2];
      F2[0] += r[1] * F2[5] - r[2] * F2[4];
      F2[1] += r[2] * F2[3] - r[0] * F2[5];
      F2[2] += r[0] * F2[4] - r[1] * F2[3];
      const S Mll2 = power(l, F2[0], F2[1], F2[2], F2[3], F2[4], F2[5]);
      M[l2 * ld + l] = Mll2;
      M[l * ld + l2] = Mll2;
    }
    const P2 fx(F[3], F2[3]), fy(F[4], F2[4]), fz(F[5], F2[5]);
    P2 tx(F[0], F2[0]), ty(F[1], F2[1]), tz(F[2], F2[2]);
    for (int kp = l, k = parent[l]; k >= 0; kp = k, k = parent[k]) {
      const Vec3<S>& r = offset[kp];
      tx += r[1] * fz - r[2] * fy;
      ty += r[2] * fx - r[0] * fz;
      tz += r[0] * fy - r[1] * fx;
      const S* sk = s[k].data();
      const P2 Mk = rotation[k] ? P2(sk[0] * tx + sk[1] * ty + sk[2] * tz) : P2(sk[3] * fx + sk[4] * fy + sk[5] * fz);
      M[l * ld + k] = Mk[0];
      M[l2 * ld + k] = Mk[1];
      M[k * ld + l] = Mk[0];
      M[k * ld + l2] = Mk[1];
    }
  }
}

template <class S>
void compute_body_wrenches(const Model& m, Workspace<S>& ws) {
  // Applied minus inertial wrench of each body at its Q: gravity m g at the mass center
  // (moment h × g), then −(I A₀ + V ×* I V).
  // In scalars: Eigen's 3-vectors of doubles go through two-lane packets and their leftovers.
  const S g0 = ws.gravity[0], g1 = ws.gravity[1], g2 = ws.gravity[2];
  for (int b = 0; b < m.nbody(); ++b) {
    const SpatialInertia<S>& I = ws.spatial_inertia[b];
    const S* V = ws.velocity[b].data();
    const S* A0 = ws.bias_acceleration[b].data();
    const S w0 = V[0], w1 = V[1], w2 = V[2], v0 = V[3], v1 = V[4], v2 = V[5];
    const S l0 = A0[0], l1 = A0[1], l2 = A0[2];
    const S e0 = g0 - A0[3], e1 = g1 - A0[4], e2 = g2 - A0[5];
    const S mass = I.m, h0 = I.h[0], h1 = I.h[1], h2 = I.h[2];
    const S Ixx = I.I(0, 0), Iyy = I.I(1, 1), Izz = I.I(2, 2), Ixy = I.I(0, 1), Ixz = I.I(0, 2), Iyz = I.I(1, 2);
    // Momentum I V = (L, p), then (τ, F) = (h × g, m g) − I A − V ×* (L, p), with
    // V ×* (L, p) = (ω × L + v × p, ω × p).
    S IV[6];
    math::momentum(I, V, IV);
    const S L0 = IV[0], L1 = IV[1], L2 = IV[2], p0 = IV[3], p1 = IV[4], p2 = IV[5];
    S* W = ws.wrench[b].data();
    W[0] = (h1 * e2 - h2 * e1) - (Ixx * l0 + Ixy * l1 + Ixz * l2) - (w1 * L2 - w2 * L1) - (v1 * p2 - v2 * p1);
    W[1] = (h2 * e0 - h0 * e2) - (Ixy * l0 + Iyy * l1 + Iyz * l2) - (w2 * L0 - w0 * L2) - (v2 * p0 - v0 * p2);
    W[2] = (h0 * e1 - h1 * e0) - (Ixz * l0 + Iyz * l1 + Izz * l2) - (w0 * L1 - w1 * L0) - (v0 * p1 - v1 * p0);
    W[3] = mass * e0 + (h1 * l2 - h2 * l1) - (w1 * p2 - w2 * p1);
    W[4] = mass * e1 + (h2 * l0 - h0 * l2) - (w2 * p0 - w0 * p2);
    W[5] = mass * e2 + (h0 * l1 - h1 * l0) - (w0 * p1 - w1 * p0);
  }
  detail::for_each_force_element(m, ws, [&](int b, const Vec6<S>& w) { ws.wrench[b] += w; });
}

template <class S>
void compute_forcing(const Model& m, Workspace<S>& ws, const S* q, const S* u) {
  if (m.evaluate_planar()) {
    detail::compute_forcing_planar(m, ws);
  } else {
    compute_body_wrenches(m, ws);
    detail::sum_over_subtrees(m, ws);
    for (const Joint& J : m.joints)
      for (int k = J.u_offset; k < J.u_offset + J.nu; ++k)
        ws.forcing[k] = detail::power(ws.partial[k], J.speeds[k - J.u_offset].rotation, ws.wrench[J.child]);
  }
  detail::add_joint_spring_dampers(m, ws, q, u);
}

template <class S>
bool factor_mass_matrix(const Model& m, Workspace<S>& ws) {
  // On a multi-tangent scalar only M's value is factored (ws.value_factor).
  const int n = m.nu;
  if constexpr (math::is_multi_dual_v<S>) {
    double* U = ws.value_factor.data();
    if (ws.tree_factor) {
      tree::copy_pattern(m, ws.mass_matrix.data(), n, U, n, [](const S& x) { return x.v; });
      if (!tree::factor(m, U, n)) return false;
    } else {
      for (int j = 0; j < n; ++j)
        for (int i = 0; i <= j; ++i) U[j * n + i] = ws.mass_matrix(i, j).v;
      if (!math::cholesky_factor(U, n, U, n, n)) return false;
    }
  } else if (ws.tree_factor) {
    tree::copy_pattern(m, ws.mass_matrix.data(), n, ws.cholesky.data(), n, [](const S& x) { return x; });
    if (!tree::factor(m, ws.cholesky.data(), n)) return false;
  } else if constexpr (std::is_same_v<S, double>) {
    if (!math::cholesky_factor(ws.mass_matrix.data(), n, ws.cholesky.data(), n, n, ws.inverse_pivots.data()))
      return false;
  } else {
    if (!math::cholesky_factor(ws.mass_matrix.data(), n, ws.cholesky.data(), n, n)) return false;
  }
  return true;
}

template <class S>
bool solve_accelerations(const Model& m, Workspace<S>& ws) {
  // M's factor is kept (solve_constrained_accelerations reuses it), u̇ = M⁻¹ f.
  if (!factor_mass_matrix(m, ws)) return false;
  ws.udot = ws.forcing;
  apply_mass_inverse(m, ws, ws.udot.data());
  return true;
}

template <class S>
void apply_mass_inverse(const Model& m, Workspace<S>& ws, S* x) {
  const int n = m.nu;
  if (ws.tree_factor) return apply_mass_inverse(m, ws, x, m.speed_order.data(), n);
  if constexpr (math::is_multi_dual_v<S>) {
    // x0 = M0⁻¹ b0, then M0 x_i = b_i − M_i x0 for every tangent i, with M0's factor.
    const double* U = ws.value_factor.data();
    double* x0 = ws.value_solution.data();
    for (int i = 0; i < n; ++i) x0[i] = x[i].v;
    math::cholesky_solve(U, n, n, x0);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) x[i].subtract_tangents(ws.mass_matrix(i, k), x0[k]);
    math::cholesky_solve_with_value_factor(U, n, n, x);
    for (int i = 0; i < n; ++i) x[i].v = x0[i];
  } else if constexpr (std::is_same_v<S, double>) {
    math::cholesky_solve(ws.cholesky.data(), n, n, ws.inverse_pivots.data(), x);
  } else {
    math::cholesky_solve(ws.cholesky.data(), n, n, x);
  }
}

template <class S>
void apply_mass_inverse(const Model& m, Workspace<S>& ws, S* x, const int* support, int ns) {
  const int n = m.nu;
  if constexpr (math::is_multi_dual_v<S>) {
    // As the dense path: M0 x_i = b_i − M_i x0, M_i x0 formed on M's tree pattern.
    const double* F = ws.value_factor.data();
    double* x0 = ws.value_solution.data();
    for (int s = 0; s < ns; ++s) x0[support[s]] = x[support[s]].v;
    tree::solve(m, F, n, support, ns, x0);
    const int* parent = m.speed_parent.data();
    for (int s = 0; s < ns; ++s) {
      const int k = support[s];
      x[k].subtract_tangents(ws.mass_matrix(k, k), x0[k]);
      for (int i = parent[k]; i >= 0; i = parent[i]) {
        x[k].subtract_tangents(ws.mass_matrix(k, i), x0[i]);
        x[i].subtract_tangents(ws.mass_matrix(i, k), x0[k]);
      }
    }
    tree::solve(m, F, n, support, ns, x);
    for (int s = 0; s < ns; ++s) x[support[s]].v = x0[support[s]];
  } else {
    tree::solve(m, ws.cholesky.data(), n, support, ns, x);
  }
}

void apply_mass_inverse_rows(const Model& m, Workspace<double>& ws, double* X, std::ptrdiff_t ldx, int ncols) {
  const int n = m.nu;
  if (!ws.tree_factor)
    return math::cholesky_solve_rows(ws.cholesky.data(), n, n, ws.inverse_pivots.data(), X, ldx, ncols);
  double* x = ws.value_solution.data();  // (scratch on double)
  for (int c = 0; c < ncols; ++c) {
    for (int i = 0; i < n; ++i) x[i] = X[i * ldx + c];
    apply_mass_inverse(m, ws, x);
    for (int i = 0; i < n; ++i) X[i * ldx + c] = x[i];
  }
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
  RhsFailure why = RhsFailure::none;
  if (uses_articulated_body(m, ws)) {
    // u̇ by the articulated-body algorithm: no M, no f (ws.forcing keeps the joints' own forces).
    evaluate_state_expressions(m, ws, t, q, u);
    compute_position(m, ws, q);
    compute_velocity(m, ws, u);
    if (m.evaluate_planar()) detail::compute_body_wrenches_planar(m, ws);
    else compute_body_wrenches(m, ws);
    ws.forcing.setZero();
    detail::add_joint_spring_dampers(m, ws, q, u);
    compute_kinematic_derivatives(m, ws, q, u);
    const bool ok = m.evaluate_planar() ? detail::articulated_body_accelerations_planar(m, ws)
                                        : articulated_body_accelerations(m, ws);
    if (!ok) why = RhsFailure::mass_matrix_not_positive_definite;
  } else {
    evaluate_mass_matrix_and_forcing(m, ws, t, q, u);
    compute_kinematic_derivatives(m, ws, q, u);
    if (!solve_accelerations(m, ws)) {
      why = RhsFailure::mass_matrix_not_positive_definite;
    } else if (m.nconstraint_rows > 0) {
      compute_constraints(m, ws, q, u, options);
      if (!solve_constrained_accelerations(m, ws)) why = RhsFailure::constraints_degenerate;
    }
  }
  std::copy(ws.qdot.data(), ws.qdot.data() + m.nq, ydot);
  std::copy(ws.udot.data(), ws.udot.data() + m.nu, ydot + m.nq);
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
  // Gravity: −Σ m g·c, with c = anchor + (Q − anchor) + (c − Q) formed here (world positions;
  // the anchor's part is the potential's constant for a fixed base).
  S V = S(0);
  for (int b = 0; b < m.nbody(); ++b) {
    const Vec3<S>& anchor = ws.tree_anchor[m.bodies[b].root_joint];
    const Vec3<S> c_rel = ws.tree_position[b] + ws.R[b] * (-ws.reference_point[b]);
    V -= ws.mass[b] * ws.gravity.dot(anchor) + ws.mass[b] * ws.gravity.dot(c_rel);
  }
  for (const Joint& J : m.joints)
    if (J.spring_k >= 0) {
      const S x = q[J.q_offset] - ws.values[J.spring_rest];
      V += S(0.5) * ws.values[J.spring_k] * x * x;
    }
  for (const Force& f : m.forces) {
    if (f.kind != Force::Kind::spring_damper) continue;
    const BodyPoint<S> pa = body_point(m, ws, f.body_a, detail::slot_vec3(ws, f.point_a));
    const BodyPoint<S> pb = body_point(m, ws, f.body_b, detail::slot_vec3(ws, f.point_b));
    using std::sqrt;
    const S x = sqrt(separation(pa, pb).squaredNorm()) - ws.values[f.rest];
    V += S(0.5) * ws.values[f.k] * x * x;
  }
  return V;
}

#define KANESENS_INSTANTIATE(S)                                                                 \
  template void compute_mass_matrix<S>(const Model&, Workspace<S>&);                            \
  template void compute_body_wrenches<S>(const Model&, Workspace<S>&);                          \
  template void compute_forcing<S>(const Model&, Workspace<S>&, const S*, const S*);            \
  template bool factor_mass_matrix<S>(const Model&, Workspace<S>&);                             \
  template bool solve_accelerations<S>(const Model&, Workspace<S>&);                            \
  template void apply_mass_inverse<S>(const Model&, Workspace<S>&, S*);                         \
  template void apply_mass_inverse<S>(const Model&, Workspace<S>&, S*, const int*, int);         \
  template void evaluate_mass_matrix_and_forcing<S>(const Model&, Workspace<S>&, const S&,      \
                                                    const S*, const S*);                        \
  template void evaluate_constraints<S>(const Model&, Workspace<S>&, const S&, const S*, const S*,   \
                                        const DynamicsOptions&);                                  \
  template bool evaluate_rhs<S>(const Model&, Workspace<S>&, const S&, const S*, S*,             \
                                const DynamicsOptions&, RhsFailure*);                           \
  template S kinetic_energy<S>(const Model&, const Workspace<S>&);                              \
  template S potential_energy<S>(const Model&, const Workspace<S>&, const S*);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
