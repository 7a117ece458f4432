// Kane's equations as a residual at given accelerations, and the tangent solve of the forward
// dynamics from it (dynamics/inverse_dynamics.hpp).
#include "dynamics/inverse_dynamics.hpp"

#include <algorithm>
#include <type_traits>

#include "math/cholesky.hpp"
#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/force_elements.hpp"
#include "dynamics/tree_factor.hpp"

namespace kanesens::dynamics {

namespace {
// The bodies' accelerations from u̇ alone (3-D path), into a[body]: carried from parent to child
// as a velocity is, plus each joint's Σ s_k u̇_k.
template <class S, class Slots>
void accelerations_of(const Model& m, const Workspace<S>& ws, const double* udot, Slots& a) {
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    Vec6<S>& ac = a[J.child];
    if (J.parent >= 0) ac = math::motion_to_child<S>(a[J.parent], ws.joint_offset[ji]);
    else ac.setZero();
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) {
      if (J.speeds[k - J.u_offset].rotation) ac.template head<3>() += ws.partial[k].template head<3>() * udot[k];
      else ac.template tail<3>() += ws.partial[k].template tail<3>() * udot[k];
    }
  }
}

// The bias accelerations of compute_velocity (u̇ = 0) plus the part of u̇: the accelerations of the
// bodies at u̇. That part is carried from parent to child as a velocity is; the wrench arrays,
// which compute_forcing overwrites, hold it on the way.
template <class S>
void add_acceleration(const Model& m, Workspace<S>& ws, const double* udot) {
  if (m.evaluate_planar()) {
    for (int ji : m.joint_order) {
      const Joint& J = m.joints[ji];
      PVec<S>& a = ws.wrench_planar[J.child];
      if (J.parent >= 0) {
        const Vec3<S>& r = ws.joint_offset[ji];
        a = math::motion_to_child_planar<S>(ws.wrench_planar[J.parent], r[0], r[1]);
      } else {
        a.setZero();
      }
      for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) a += ws.partial_planar[k] * udot[k];
    }
    for (int b = 0; b < m.nbody(); ++b) ws.bias_planar[b] += ws.wrench_planar[b];
    return;
  }
  accelerations_of(m, ws, udot, ws.wrench);
  for (int b = 0; b < m.nbody(); ++b) ws.bias_acceleration[b] += ws.wrench[b];
}

// The stages that do not depend on u̇: state expressions, positions, velocities, q̇ and the
// constraint rows (which read the bias accelerations at u̇ = 0).
template <class S>
void stages_at_rest(const Model& m, Workspace<S>& ws, const S& t, const S* q, const S* u, const DynamicsOptions& options) {
  evaluate_state_expressions(m, ws, t, q, u);
  compute_position(m, ws, q);
  compute_velocity(m, ws, u);
  compute_kinematic_derivatives(m, ws, q, u);
  if (m.nconstraint_rows > 0) compute_constraints(m, ws, q, u, options);
}
}  // namespace

template <class S>
void evaluate_residual(const Model& m, Workspace<S>& ws, const S& t, const S* y, const double* udot,
                       const double* multipliers, const DynamicsOptions& options, S* out, S* constraint_out) {
  const S* q = y;
  const S* u = y + m.nq;
  stages_at_rest(m, ws, t, q, u, options);
  const int nc = m.nconstraint_rows;
  add_acceleration(m, ws, udot);
  compute_forcing(m, ws, q, u);  // f − M u̇
  for (int i = 0; i < m.nq; ++i) out[i] = ws.qdot[i];
  S* r = out + m.nq;
  for (int k = 0; k < m.nu; ++k) r[k] = ws.forcing[k];
  for (int j = 0; j < nc; ++j) {
    S c = -ws.constraint_bias[j];
    for (int k = 0; k < m.nu; ++k) c += ws.constraint_matrix(j, k) * udot[k];
    constraint_out[j] = c;
    if (multipliers)
      for (int k = 0; k < m.nu; ++k) r[k] += ws.constraint_matrix(j, k) * multipliers[j];
  }
}

template <class S>
void evaluate_residual_at_rest(const Model& m, Workspace<S>& ws, const S& t, const S* y,
                               const DynamicsOptions& options, S* out, S* constraint_out) {
  const S* q = y;
  const S* u = y + m.nq;
  stages_at_rest(m, ws, t, q, u, options);
  compute_body_wrenches(m, ws);
  for (int k = 0; k < m.nu; ++k) ws.forcing[k] = S(0);
  detail::add_joint_spring_dampers(m, ws, q, u);
  for (int i = 0; i < m.nq; ++i) out[i] = ws.qdot[i];
  for (int j = 0; j < m.nconstraint_rows; ++j) constraint_out[j] = -ws.constraint_bias[j];
}

template <class S>
void forcing_values(const Model& m, const Workspace<S>& ws, Workspace<double>& wd, double* f) {
  for (int b = 0; b < m.nbody(); ++b)
    for (int i = 0; i < 6; ++i) wd.wrench[b][i] = value_of(ws.wrench[b][i]);
  detail::sum_over_subtrees(m, wd);
  for (const Joint& J : m.joints)
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k)
      f[k] = detail::power(wd.partial[k], J.speeds[k - J.u_offset].rotation, wd.wrench[J.child]) + value_of(ws.forcing[k]);
}

template <class S>
void residual_from_rest(const Model& m, Workspace<S>& ws, const double* udot, S* r, S* constraint_out) {
  // The bodies' accelerations from u̇ alone, in the bias accelerations' slots (the stages that
  // read those are done).
  accelerations_of(m, ws, udot, ws.bias_acceleration);
  for (int b = 0; b < m.nbody(); ++b) {
    // W − I a (the inertia applied to the acceleration as to a velocity: its momentum form).
    S Ia[6];
    math::momentum(ws.spatial_inertia[b], ws.bias_acceleration[b].data(), Ia);
    for (int i = 0; i < 6; ++i) ws.wrench[b][i] -= Ia[i];
  }
  detail::sum_over_subtrees(m, ws);
  for (const Joint& J : m.joints)
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k)
      r[k] = detail::power(ws.partial[k], J.speeds[k - J.u_offset].rotation, ws.wrench[J.child]) + ws.forcing[k];
  for (int j = 0; j < m.nconstraint_rows; ++j)
    for (int k = 0; k < m.nu; ++k) constraint_out[j] += ws.constraint_matrix(j, k) * udot[k];
}

template <class S>
bool factor_mass_matrix_values(const Model& m, const Workspace<S>& ws, Workspace<double>& wd) {
  for (std::size_t j = 0; j < m.joints.size(); ++j)
    for (int i = 0; i < 3; ++i) wd.joint_offset[j][i] = value_of(ws.joint_offset[j][i]);
  if (m.evaluate_planar()) {
    for (int k = 0; k < m.nu; ++k)
      for (int i = 0; i < 3; ++i) wd.partial_planar[k][i] = value_of(ws.partial_planar[k][i]);
    for (int b = 0; b < m.nbody(); ++b) {
      const PlanarInertia<S>& I = ws.inertia_planar[b];
      wd.inertia_planar[b] = {value_of(I.m), value_of(I.hx), value_of(I.hy), value_of(I.I)};
    }
  } else {
    for (int k = 0; k < m.nu; ++k)
      for (int i = 0; i < 6; ++i) wd.partial[k][i] = value_of(ws.partial[k][i]);
    for (int b = 0; b < m.nbody(); ++b) {
      const SpatialInertia<S>& I = ws.spatial_inertia[b];
      SpatialInertia<double>& Id = wd.spatial_inertia[b];
      Id.m = value_of(I.m);
      for (int i = 0; i < 3; ++i) {
        Id.h[i] = value_of(I.h[i]);
        for (int k = 0; k < 3; ++k) Id.I(i, k) = value_of(I.I(i, k));
      }
    }
  }
  for (int j = 0; j < m.nconstraint_rows; ++j)
    for (int k = 0; k < m.nu; ++k) wd.constraint_matrix(j, k) = value_of(ws.constraint_matrix(j, k));
  compute_mass_matrix(m, wd);
  return factor_mass_matrix(m, wd);
}

AccelerationTangents::AccelerationTangents(const Model& m)
    : minv_at_(m.nu, m.nconstraint_rows),
      schur_(m.nconstraint_rows, m.nconstraint_rows),
      schur_inverse_pivots_(m.nconstraint_rows),
      g_(m.nconstraint_rows),
      x_(m.nu) {}

bool AccelerationTangents::prepare(const Model& m, Workspace<double>& ws) {
  const int n = m.nu, nc = m.nconstraint_rows;
  if (nc == 0) return true;
  for (int j = 0; j < nc; ++j)
    for (int k = 0; k < n; ++k) minv_at_(k, j) = ws.constraint_matrix(j, k);
  if (ws.tree_factor)
    for (int j = 0; j < nc; ++j) apply_mass_inverse(m, ws, minv_at_.col(j).data());
  else
    math::cholesky_solve_columns(ws.cholesky.data(), n, n, ws.inverse_pivots.data(), minv_at_.data(), n, nc);
  for (int j = 0; j < nc; ++j)
    for (int i = 0; i <= j; ++i) {
      double s = 0;
      for (int k = 0; k < n; ++k) s += ws.constraint_matrix(i, k) * minv_at_(k, j);
      schur_(i, j) = s;
    }
  // The multipliers' rank threshold (dynamics/constraint_solve.cpp): a pivot below it means
  // redundant rows there.
  double max0 = 0;
  for (int i = 0; i < nc; ++i) max0 = std::max(max0, schur_(i, i));
  if (!math::cholesky_factor(schur_.data(), nc, schur_.data(), nc, nc, schur_inverse_pivots_.data())) return false;
  for (int i = 0; i < nc; ++i)
    if (!(schur_(i, i) * schur_(i, i) > 1e-11 * max0)) return false;
  return true;
}

void AccelerationTangents::multipliers(const Model& m, Workspace<double>& ws, const double* r0, double* lambda) {
  const int n = m.nu, nc = m.nconstraint_rows;
  if (nc == 0) return;
  for (int k = 0; k < n; ++k) x_[k] = r0[k];
  apply_mass_inverse(m, ws, x_.data());
  for (int j = 0; j < nc; ++j) {
    double s = 0;
    for (int k = 0; k < n; ++k) s += ws.constraint_matrix(j, k) * x_[k];
    lambda[j] = -s;
  }
  math::cholesky_solve(schur_.data(), nc, nc, schur_inverse_pivots_.data(), lambda);
}

template <class S>
void AccelerationTangents::solve(const Model& m, Workspace<double>& ws, S* x, S* dc) const {
  const int n = m.nu, nc = m.nconstraint_rows;
  // M⁻¹ δr with M's factor on values (the tree's, or the dense Cholesky of solve_accelerations).
  if (ws.tree_factor) tree::solve(m, ws.cholesky.data(), n, m.speed_order.data(), n, x);
  else if constexpr (std::is_same_v<S, double>) math::cholesky_solve(ws.cholesky.data(), n, n, ws.inverse_pivots.data(), x);
  else math::cholesky_solve_with_value_factor(ws.cholesky.data(), n, n, x, ws.inverse_pivots.data());
  if (nc == 0) return;
  // δλ = −(A M⁻¹ Aᵀ)⁻¹ (δc + A M⁻¹ δr); δu̇ = M⁻¹ δr + M⁻¹ Aᵀ δλ.
  for (int j = 0; j < nc; ++j)
    for (int k = 0; k < n; ++k) dc[j] += ws.constraint_matrix(j, k) * x[k];
  math::cholesky_solve_with_value_factor(schur_.data(), nc, nc, dc, schur_inverse_pivots_.data());
  for (int j = 0; j < nc; ++j)
    for (int k = 0; k < n; ++k) x[k] -= minv_at_(k, j) * dc[j];
}

#define KANESENS_INSTANTIATE(S)                                                                            \
  template void evaluate_residual<S>(const Model&, Workspace<S>&, const S&, const S*, const double*,       \
                                     const double*, const DynamicsOptions&, S*, S*);                     \
  template void evaluate_residual_at_rest<S>(const Model&, Workspace<S>&, const S&, const S*,               \
                                             const DynamicsOptions&, S*, S*);                            \
  template void forcing_values<S>(const Model&, const Workspace<S>&, Workspace<double>&, double*);      \
  template void residual_from_rest<S>(const Model&, Workspace<S>&, const double*, S*, S*);               \
  template bool factor_mass_matrix_values<S>(const Model&, const Workspace<S>&, Workspace<double>&);  \
  template void AccelerationTangents::solve<S>(const Model&, Workspace<double>&, S*, S*) const;
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
