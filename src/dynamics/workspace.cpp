#include "dynamics/workspace.hpp"

#include <algorithm>
#include <type_traits>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "model/parameters.hpp"

namespace kanesens::dynamics {

using math::unit_or_zero;

namespace {
// Whether every joint has at most one speed (the articulated-body recursion's fused case, and
// the only one on the planar path).
bool joints_of_one_speed(const Model& m) {
  for (const Joint& J : m.joints)
    if (J.nu > 1) return false;
  return true;
}
}  // namespace

template <class S>
Workspace<S>::Workspace(const Model& m)
    : parameters(m.nparam()),
      values(m.expressions.size()),
      mass(m.nbody()),
      inertia_body(m.nbody()),
      reference_point(m.nbody()),
      inertia_local(m.nbody()),
      inertia_constant(static_cast<std::size_t>(m.nbody()), 1),
      inertia_diagonal(static_cast<std::size_t>(m.nbody()), 0),
      inertia_h_axis(static_cast<std::size_t>(m.nbody()), -1),
      joint_axis(m.joints.size(), Vec3<S>::Zero()),
      joint_axis2(m.joints.size(), Vec3<S>::Zero()),
      plane_e1(m.joints.size(), Vec3<S>::Zero()),
      plane_e2(m.joints.size(), Vec3<S>::Zero()),
      joint_axis_index(m.joints.size(), -1),
      joint_axis2_index(m.joints.size(), -1),
      parent_point(m.joints.size()),
      child_point(m.joints.size()),
      joint_lever(m.joints.size()),
      joint_lever_axis(m.joints.size(), -1),
      gravity(Vec3<S>::Zero()),
      identity(Mat3<S>::Identity()),
      R(m.nbody()),
      angle_cos(static_cast<std::size_t>(m.nq)),
      angle_sin(static_cast<std::size_t>(m.nq)),
      joint_offset(m.joints.size(), Vec3<S>::Zero()),
      tree_anchor(m.joints.size(), Vec3<S>::Zero()),
      tree_position(m.nbody()),
      partial(m.nu),
      spatial_inertia(m.nbody()),
      velocity(m.nbody()),
      bias_acceleration(m.nbody()),
      composite_inertia(m.nbody()),
      speed_offset(m.nu, Vec3<S>::Zero()),
      wrench(m.nbody()),
      mass_matrix(m.nu, m.nu),
      forcing(m.nu),
      cholesky(m.nu, m.nu),
      inverse_pivots(static_cast<std::size_t>(m.nu)),
      value_factor(m.nu, m.nu),
      value_solution(m.nu),
      udot(m.nu),
      qdot(m.nq),
      constraint_matrix(m.nconstraint_rows, m.nu),
      constraint_bias(m.nconstraint_rows),
      velocity_residual(m.nconstraint_rows),
      position_residual(m.nconstraint_rows),
      multipliers(m.nconstraint_rows),
      minv_at(m.nu, m.nconstraint_rows),
      schur(m.nconstraint_rows, m.nconstraint_rows),
      schur_factor(m.nconstraint_rows, m.nconstraint_rows),
      schur_rhs(m.nconstraint_rows),
      nullspace(m.nconstraint_rows, m.nconstraint_rows),
      scratch_m(m.nconstraint_rows),
      scratch_nu(m.nu),
      schur_pivots(m.nconstraint_rows),
      constraint_sparsity(m),

      partial_planar(m.nu),
      inertia_planar(m.nbody()),
      composite_planar(m.nbody()),
      velocity_planar(m.nbody()),
      bias_planar(m.nbody()),
      wrench_planar(m.nbody()),
      prefix(7) {
  coordinate_angles.reserve(2 * m.joints.size() + 1);  // set_parameters fills it without allocating
  {
    std::vector<unsigned char> used(static_cast<std::size_t>(m.nu), 0);
    for (int l : m.speed_order) {
      if (used[static_cast<std::size_t>(l)]) continue;
      used[static_cast<std::size_t>(l)] = 1;
      int l2 = -1;
      for (int k = 0; k < m.nu && l2 < 0; ++k)
        if (m.speed_parent[static_cast<std::size_t>(k)] == l && !used[static_cast<std::size_t>(k)]) l2 = k;
      if (l2 >= 0) used[static_cast<std::size_t>(l2)] = 1;
      mass_matrix_columns.push_back({l, l2});
    }
  }
  bool general = false;
  std::size_t longest_position = 0;
  for (const Constraint& c : m.constraints)
    if (c.kind == Constraint::Kind::general) {
      general = true;
      if (c.has_position) longest_position = std::max(longest_position, c.position.size());
    }
  if (general) {
    general_q1.resize(m.nq);
    general_p1.resize(m.nparam());
    general_gradient.resize(m.nq);
    general_tape.resize(longest_position);
  }
  for (Slot s : m.parameter_slots)
    if (m.expressions[s].is_constant()) values[s] = S(m.expressions[s].constant_value());
  // M has structural zeros only where two speeds move no common body (branches).
  std::size_t related = 0;
  for (const Joint& J : m.joints) related += static_cast<std::size_t>(J.nu) * m.ancestor_speeds[J.child].size();
  const std::size_t n = static_cast<std::size_t>(m.nu);
  std::size_t within = 0;  // pairs counted twice above: speeds of the same joint
  for (const Joint& J : m.joints) within += static_cast<std::size_t>(J.nu) * static_cast<std::size_t>(J.nu - 1) / 2;
  mass_matrix_full = related - within == n * (n + 1) / 2;
  tree_factor = !mass_matrix_full;
  // The sparse constraint solve pays for its indexing when A M⁻¹ Aᵀ or M⁻¹ Aᵀ is mostly zero.
  const auto mc = static_cast<std::size_t>(m.nconstraint_rows);
  sparse_constraints = tree_factor && mc > 0 &&
                       (2 * constraint_sparsity.envelope_entries < mc * (mc + 1) / 2 ||
                        2 * constraint_sparsity.support_entries < mc * n);
  if constexpr (std::is_same_v<S, double>) {
    if (mass_matrix_full && m.nconstraint_rows == 0 && (joints_of_one_speed(m) || m.nu >= kArticulatedBodyMinSpeeds))
      set_articulated_body(m, *this, true);
  } else if (mass_matrix_full && m.nconstraint_rows == 0 && joints_of_one_speed(m)) {
    set_articulated_body(m, *this, true);
  }
  mass_matrix.setZero();
  constraint_matrix.setZero();
}

template <class S>
void set_articulated_body(const Model& m, Workspace<S>& ws, bool on) {
  ws.articulated_body = on && m.nconstraint_rows == 0 &&
                        (joints_of_one_speed(m) || (std::is_same_v<S, double> && !m.evaluate_planar()));
  if (!ws.articulated_body) return;
  if (m.evaluate_planar()) {
    ws.articulated_inertia_planar.resize(static_cast<std::size_t>(m.nbody()));
    ws.articulated_bias_planar.resize(static_cast<std::size_t>(m.nbody()));
    ws.articulated_columns_planar.resize(static_cast<std::size_t>(m.nu));
    return;
  }
  ws.articulated_inertia.resize(static_cast<std::size_t>(m.nbody()));
  ws.articulated_bias.resize(static_cast<std::size_t>(m.nbody()));
  ws.articulated_columns.resize(static_cast<std::size_t>(m.nu));
  ws.articulated_first.assign(m.joints.size(), 0);
  ws.articulated_has_children.assign(static_cast<std::size_t>(m.nbody()), 0);
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const int P = m.joints[static_cast<std::size_t>(*it)].parent;
    if (P < 0) continue;
    unsigned char& seen = ws.articulated_has_children[static_cast<std::size_t>(P)];
    ws.articulated_first[static_cast<std::size_t>(*it)] = seen ? 0 : 1;
    seen = 1;
  }
  if constexpr (std::is_same_v<S, double>) ws.joint_inverse.assign(m.joints.size(), Mat6<double>::Zero());
}

namespace {
template <class S>
Vec3<S> vec3(const Workspace<S>& ws, const Slot3& s) {
  return {ws.values[s[0]], ws.values[s[1]], ws.values[s[2]]};
}
template <class Derived>
bool has_tangent(const Eigen::MatrixBase<Derived>& x) {
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (math::has_tangent(x.derived().coeff(i))) return true;
  return false;
}
}  // namespace

template <class S>
void set_parameters(const Model& m, Workspace<S>& ws, const S* p) {
  model::evaluate_parameter_values(m, p, ws.parameters.data(), ws.values.data());
  // The general constraints' expressions read the parameters as constants of their dual types.
  for (std::size_t i = 0; i < ws.general_p1.size(); ++i) ws.general_p1[i] = DualT<S>(ws.parameters[i]);

  for (int b = 0; b < m.nbody(); ++b) {
    const auto& I = m.bodies[b].inertia;
    ws.mass[b] = ws.values[m.bodies[b].mass];
    const S xx = ws.values[I[0]], yy = ws.values[I[1]], zz = ws.values[I[2]];
    const S xy = ws.values[I[3]], yz = ws.values[I[4]], xz = ws.values[I[5]];
    ws.inertia_body[b] << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  }
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& J = m.joints[j];
    if (J.axis[0] >= 0) ws.joint_axis[j] = unit_or_zero<S>(vec3(ws, J.axis));
    if (J.axis2[0] >= 0) ws.joint_axis2[j] = unit_or_zero<S>(vec3(ws, J.axis2));
    // A coordinate axis takes the fast paths, unless a parameter's tangent would be lost there.
    auto coordinate_index = [](const Vec3<S>& axis) {
      if (!has_tangent(axis))
        for (int i = 0; i < 3; ++i)
          if (axis == Vec3<S>::Unit(i)) return i;
      return -1;
    };
    ws.joint_axis_index[j] = coordinate_index(ws.joint_axis[j]);
    ws.joint_axis2_index[j] = J.axis2[0] >= 0 ? coordinate_index(ws.joint_axis2[j]) : -1;
    ws.parent_point[j] = vec3(ws, J.parent_point);
    ws.child_point[j] = vec3(ws, J.child_point);
    ws.reference_point[J.child] = ws.child_point[j];
    if (J.type == JointType::planar) {
      // In-plane directions: e1 = unit(x − (x·n) n) (y if n ∥ x), e2 = n × e1.
      const Vec3<S> n = ws.joint_axis[j];
      Vec3<S> x = Vec3<S>::UnitX();
      if (std::abs(value_of(n[0])) > 1 - 1e-9) x = Vec3<S>::UnitY();
      ws.plane_e1[j] = unit_or_zero<S>(x - x.dot(n) * n);
      ws.plane_e2[j] = n.cross(ws.plane_e1[j]);
    }
  }
  auto zero = [](const S& x) { return value_of(x) == 0 && !math::has_tangent(x); };
  // R v is then column k of R times v_k (the other products add exact zeros).
  auto along_axis = [&](const Vec3<S>& v) {
    for (int k = 0; k < 3; ++k)
      if (zero(v[(k + 1) % 3]) && zero(v[(k + 2) % 3])) return k;
    return -1;
  };
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& J = m.joints[j];
    ws.joint_lever[j] = J.parent >= 0 ? Vec3<S>(ws.parent_point[j] - ws.reference_point[J.parent]) : ws.parent_point[j];
    ws.joint_lever_axis[j] = along_axis(ws.joint_lever[j]);
  }
  // The angles the position stage rotates by with their cos and sin: on the planar path every
  // revolute joint's and a planar joint's rotation, on the 3-D path those about a coordinate axis
  // (a revolute's, or both of a universal joint's; a planar scene evaluated in 3-D,
  // Model::force_general_3d, has them all).
  ws.coordinate_angles.clear();
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& J = m.joints[j];
    if (J.type == JointType::revolute && (m.planar || ws.joint_axis_index[j] >= 0)) {
      ws.coordinate_angles.push_back(J.q_offset);
    } else if (J.type == JointType::universal && ws.joint_axis_index[j] >= 0 && ws.joint_axis2_index[j] >= 0) {
      ws.coordinate_angles.push_back(J.q_offset);
      ws.coordinate_angles.push_back(J.q_offset + 1);
    } else if (J.type == JointType::planar && m.planar)
      ws.coordinate_angles.push_back(J.q_offset + 2);
  }
  if (ws.coordinate_angles.size() % 2) ws.coordinate_angles.push_back(ws.coordinate_angles.back());
  for (int b = 0; b < m.nbody(); ++b) {
    const SpatialInertia<S>& I = ws.inertia_local[b] = math::body_inertia_at<S>(ws.mass[b], ws.inertia_body[b], ws.reference_point[b]);
    ws.inertia_constant[static_cast<std::size_t>(b)] =
        !math::has_tangent(I.m) && !has_tangent(I.h) && !has_tangent(I.I);
    ws.inertia_diagonal[static_cast<std::size_t>(b)] = zero(I.I(0, 1)) && zero(I.I(0, 2)) && zero(I.I(1, 2));
    ws.inertia_h_axis[static_cast<std::size_t>(b)] = along_axis(I.h);
  }
  ws.gravity = vec3(ws, m.gravity);
}

#define KANESENS_INSTANTIATE(S) \
  template struct Workspace<S>;  \
  template void set_articulated_body<S>(const Model&, Workspace<S>&, bool); \
  template void set_parameters<S>(const Model&, Workspace<S>&, const S*);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
