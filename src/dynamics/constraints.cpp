// Constraints Σ_k a_jk(q,t) u_k + a_j0(q,t) = 0 (docs/explanation/constraints.md): the rows of
// A, their residuals and the bias −(Ȧu + ȧ0). The solve with multipliers is in
// dynamics/constraint_solve.cpp.
#include <array>
#include <cmath>
#include <type_traits>

#include "math/dual.hpp"
#include "math/dual2.hpp"  // the Dual2 instantiations
#include "math/multi_dual.hpp"
#include "dynamics/equations.hpp"
#include "dynamics/frames.hpp"
#include "math/planar.hpp"

namespace kanesens::dynamics {
namespace {

template <class S>
Vec3<S> vec3(const Workspace<S>& ws, const Slot3& s) {
  return {ws.values[s[0]], ws.values[s[1]], ws.values[s[2]]};
}

// Zeroes row r of A where it can be nonzero (ConstraintSparsity); the rest of A is zero from
// the workspace's construction on and never written. (Inlined: a call per row costs as much as
// the few stores it makes.)
template <class S>
[[gnu::always_inline]] inline void clear_row(Workspace<S>& ws, int r) {
  const ConstraintSparsity& sp = ws.constraint_sparsity;
  for (int s = sp.closure_start[r]; s < sp.closure_start[r + 1]; ++s) ws.constraint_matrix(r, sp.closure[s]) = S(0);
}

// A body point's velocity and bias acceleration (u̇ = 0), world components:
// v = v_Q + ω × o, a = a_Q + α × o + ω × v (o = offset from Q_b).
template <class S>
void point_motion(const Workspace<S>& ws, const BodyPoint<S>& p, Vec3<S>& v, Vec3<S>& a) {
  if (p.body < 0) {
    v.setZero();
    a.setZero();
    return;
  }
  const Vec6<S>& V = ws.velocity[p.body];
  const Vec6<S>& A = ws.bias_acceleration[p.body];
  const Vec3<S> w = V.template head<3>();
  v = V.template tail<3>() + w.cross(p.offset);
  a = A.template tail<3>() + A.template head<3>().cross(p.offset) + w.cross(v);
}

// Calls add(k, V_k) for every speed k moving body b, V_k the partial velocity of the point at
// offset o from Q_b: L_k + Ω_k × (P − Q_k), with P − Q_k carried joint by joint to the root.
template <class S, class Add>
void for_each_point_partial(const Model& m, const Workspace<S>& ws, int b, Vec3<S> o, Add&& add) {
  while (b >= 0) {
    const Joint& J = m.joints[m.bodies[b].joint];
    for (int k = J.u_offset; k < J.u_offset + J.nu; ++k) {
      const Vec6<S>& s = ws.partial[k];
      if (J.speeds[k - J.u_offset].rotation) add(k, Vec3<S>(s.template head<3>().cross(o)));
      else add(k, Vec3<S>(s.template tail<3>()));
    }
    o += ws.joint_offset[m.bodies[b].joint];
    b = m.bodies[b].parent;
  }
}

// g, the velocity form and the bias of a general position constraint g(q, t) = 0 on scalar S.
// The dual copies of q live in the workspace (nq entries: any size, no allocation here), those of
// the parameters too (set_parameters fills them).
template <class S>
void general_position(Workspace<S>& ws, const Constraint& c, int row, const S* q) {
  // One gradient of g on duals along (q̇, 1): its value is g and its ε part the velocity residual
  // ġ; the gradient's values are ∂g/∂q_i (the A row, u = q̇) and its ε parts H (q̇, 1) with H the
  // Hessian in (q, t), so the bias −g̈ at u̇ = 0 is −(q̇, 1)·H (q̇, 1).
  auto& x = ws.general_q1;
  for (const auto& [i, k] : c.position_reads) x[i] = DualT<S>(q[i], ws.qdot[i]);
  expr::Inputs<DualT<S>> in;
  in.parameters = ws.general_p1.data();
  in.coordinates = x.data();
  in.time = DualT<S>(ws.time, S(1));
  DualT<S>* grad = ws.general_gradient.data();
  for (const auto& [i, k] : c.position_reads) grad[i] = DualT<S>(S(0));
  DualT<S> d_time;
  const DualT<S> g = c.position.gradient(in, ws.general_tape, grad, d_time);
  ws.position_residual[row] = g.v;
  ws.velocity_residual[row] = g.d;
  clear_row(ws, row);
  S bias = d_time.d;
  for (const auto& [i, k] : c.position_reads) {
    ws.constraint_matrix(row, k) = grad[i].v;
    bias += grad[i].d * ws.qdot[i];
  }
  ws.constraint_bias[row] = -bias;
}

// A row, a0 and bias of a general velocity constraint Σ a_k u_k + a0 = 0.
template <class S>
void general_velocity(const Model& m, Workspace<S>& ws, const Constraint& c, int row, const S* q, const S* u) {
  auto& x = ws.general_q1;
  for (int i = 0; i < m.nq; ++i) x[i] = DualT<S>(q[i], ws.qdot[i]);
  expr::Inputs<DualT<S>> in;
  in.parameters = ws.general_p1.data();
  in.coordinates = x.data();
  in.time = DualT<S>(ws.time, S(1));
  clear_row(ws, row);
  S residual = S(0), bias = S(0);
  for (const auto& [k, a] : c.a) {
    const DualT<S> ak = a.evaluate(in);
    ws.constraint_matrix(row, k) += ak.v;
    residual += ak.v * u[k];
    bias += ak.d * u[k];
  }
  const DualT<S> a0 = c.a0.evaluate(in);
  ws.velocity_residual[row] = residual + a0.v;
  ws.constraint_bias[row] = -(bias + a0.d);
  ws.position_residual[row] = S(0);
}

// The rolling constraint's three rows in the plane's basis e = (t1, t2, n) (scalar T: S, or
// double for a fixed plane).
// Contact point P = c + r d, d = −unit(n − (n·a) a): the wheel point nearest the plane. Rows
// t1, t2 are the no-slip rows; row n is the velocity form of the contact height
// (rolling_contact_height). Offsets from the wheel's Q: c − Q = o_c, P − Q = o_c + r d.
template <class S, class T>
void rolling_rows(const Model& m, Workspace<S>& ws, const Constraint& c, const std::array<Vec3<T>, 3>& e) {
  using std::sqrt;
  const int b = c.body, r0 = c.row_offset;
  const Vec3<T>& n = e[2];
  const Vec3<S> a = (ws.R[b] * vec3(ws, c.axis)).normalized();
  const S na = a.dot(n);
  const Vec3<S> w = n - na * a;
  const S wn = sqrt(w.squaredNorm());
  const Vec3<S> wh = w / wn;
  const S radius = ws.values[c.radius];
  const Vec3<S> o_c = point_offset(ws, b, Vec3<S>::Zero().eval());
  const Vec3<S> o_P = o_c - radius * wh;
  const Vec3<S> omega = ws.velocity[b].template head<3>();
  const Vec3<S> vQ = ws.velocity[b].template tail<3>();
  const Vec3<S> vc = vQ + omega.cross(o_c);
  // Ṗ = v_c + r ḋ, with ȧ = ω × a, ẇ = −(ȧ·n) a − (a·n) ȧ, ḋ = −(ẇ − ŵ(ŵ·ẇ))/|w|.
  const Vec3<S> adot = omega.cross(a);
  const Vec3<S> wdot = -adot.dot(n) * a - na * adot;
  const Vec3<S> ddot = -(wdot - wh * wh.dot(wdot)) / wn;
  const Vec3<S> Pdot = vc + radius * ddot;
  const Vec3<S> alpha = ws.bias_acceleration[b].template head<3>();
  const Vec3<S> bias = ws.bias_acceleration[b].template tail<3>() + alpha.cross(o_P) + omega.cross(Pdot);
  const Vec3<S> vP = vQ + omega.cross(o_P);
  for (int i = 0; i < 3; ++i) clear_row(ws, r0 + i);
  for_each_point_partial(m, ws, b, o_P, [&](int k, const Vec3<S>& V) {
    for (int i = 0; i < 3; ++i) ws.constraint_matrix(r0 + i, k) = V.dot(e[i]);
  });
  for (int i = 0; i < 3; ++i) {
    ws.velocity_residual[r0 + i] = vP.dot(e[i]);
    ws.constraint_bias[r0 + i] = -bias.dot(e[i]);
    ws.position_residual[r0 + i] = S(0);
  }
  // rolling_contact_height with this case's unit vectors: |n − (n·a) a| is |w|.
  const Vec3<S> center = ws.tree_anchor[m.bodies[b].root_joint] + (ws.tree_position[b] + o_c);
  ws.position_residual[r0 + 2] = center.dot(n) - radius * wn - ws.values[c.height];
}

}  // namespace

template <class S>
void rolling_plane_basis(const Vec3<S>& n, Vec3<S>& t1, Vec3<S>& t2) {
  using std::abs;
  using std::sqrt;
  // The world axis least aligned with n (x unless n is within ~25° of ±x), projected.
  const Vec3<S> e = abs(value_of(n[0])) < 0.9 ? Vec3<S>(S(1), S(0), S(0)) : Vec3<S>(S(0), S(1), S(0));
  const Vec3<S> t = e - n.dot(e) * n;
  t1 = t / sqrt(t.squaredNorm());
  t2 = n.cross(t1);
}

template <class S>
S rolling_contact_height(const Model& m, const Workspace<S>& ws, const Constraint& c) {
  using std::sqrt;
  const int b = c.body;
  const Vec3<S> a = (ws.R[b] * vec3(ws, c.axis)).normalized();
  const Vec3<S> n = vec3(ws, c.normal).normalized();
  const S na = n.dot(a);
  // n·P = n·c − r |n − (n·a) a|, |n − (n·a) a|² = 1 − (n·a)².
  // The height is a world quantity: the wheel center's world position, formed here.
  return n.dot(world_point(m, ws, b, Vec3<S>::Zero().eval())) - ws.values[c.radius] * sqrt(S(1) - na * na) - ws.values[c.height];
}

template <class S>
void compute_constraints(const Model& m, Workspace<S>& ws, const S* q, const S* u, const DynamicsOptions& options) {
  using std::sqrt;
  if (m.evaluate_planar()) {
    // The planar path keeps (ω_z, v_x, v_y); constraints read the 6-D partial velocities and
    // bias accelerations, whose other components are zero in a planar motion.
    auto lift = [](const PVec<S>& p) {
      Vec6<S> v = Vec6<S>::Zero();
      v[2] = p[0];
      v[3] = p[1];
      v[4] = p[2];
      return v;
    };
    for (int k = 0; k < m.nu; ++k) ws.partial[k] = lift(ws.partial_planar[k]);
    for (int b = 0; b < m.nbody(); ++b) ws.bias_acceleration[b] = lift(ws.bias_planar[b]);
  }
  for (const Constraint& c : m.constraints) {
    const int r0 = c.row_offset;
    switch (c.kind) {
      case Constraint::Kind::coincident:
      case Constraint::Kind::distance: {
        const BodyPoint<S> pa = body_point(m, ws, c.body_a, vec3(ws, c.point_a));
        const BodyPoint<S> pb = body_point(m, ws, c.body_b, vec3(ws, c.point_b));
        Vec3<S> va, aa, vb, ab;
        point_motion(ws, pa, va, aa);
        point_motion(ws, pb, vb, ab);
        const Vec3<S> d = separation(pa, pb);  // pb − pa
        if (c.kind == Constraint::Kind::coincident) {
          for (int i = 0; i < c.nrows; ++i) clear_row(ws, r0 + i);
          for_each_point_partial(m, ws, c.body_a, pa.offset, [&](int k, const Vec3<S>& V) {
            for (int i = 0; i < c.nrows; ++i) ws.constraint_matrix(r0 + i, k) += V[c.components[i]];
          });
          for_each_point_partial(m, ws, c.body_b, pb.offset, [&](int k, const Vec3<S>& V) {
            for (int i = 0; i < c.nrows; ++i) ws.constraint_matrix(r0 + i, k) -= V[c.components[i]];
          });
          for (int i = 0; i < c.nrows; ++i) {
            const int comp = c.components[i];
            ws.position_residual[r0 + i] = -d[comp];
            ws.velocity_residual[r0 + i] = va[comp] - vb[comp];
            ws.constraint_bias[r0 + i] = -(aa[comp] - ab[comp]);
          }
        } else {
          const Vec3<S> dd = vb - va;
          const S L = sqrt(d.squaredNorm());
          const Vec3<S> e = d / L;
          const S ed = e.dot(dd);
          clear_row(ws, r0);
          for_each_point_partial(m, ws, c.body_b, pb.offset, [&](int k, const Vec3<S>& V) { ws.constraint_matrix(r0, k) += e.dot(V); });
          for_each_point_partial(m, ws, c.body_a, pa.offset, [&](int k, const Vec3<S>& V) { ws.constraint_matrix(r0, k) -= e.dot(V); });
          ws.position_residual[r0] = L - ws.values[c.length];
          ws.velocity_residual[r0] = ed;
          ws.constraint_bias[r0] = -(e.dot(ab - aa) + (dd.squaredNorm() - ed * ed) / L);
        }
        break;
      }
      case Constraint::Kind::coupler: {
        const S ratio = ws.values[c.ratio];
        clear_row(ws, r0);
        ws.constraint_matrix(r0, c.speed_a) += S(1);
        ws.constraint_matrix(r0, c.speed_b) -= ratio;
        ws.position_residual[r0] = q[c.coord_a] - ratio * q[c.coord_b] - ws.values[c.offset];
        ws.velocity_residual[r0] = u[c.speed_a] - ratio * u[c.speed_b];
        ws.constraint_bias[r0] = S(0);
        break;
      }
      case Constraint::Kind::general:
        if (c.has_position) general_position(ws, c, r0, q);
        else general_velocity(m, ws, c, r0, q, u);
        break;
      case Constraint::Kind::rolling: {
        auto rows_with_normal = [&](const auto& normal) {
          std::array<std::decay_t<decltype(normal)>, 3> e;
          e[2] = normal.normalized();
          rolling_plane_basis(e[2], e[0], e[1]);
          rolling_rows(m, ws, c, e);
        };
        const Vec3<S> n_given = vec3(ws, c.normal);
        // A fixed plane (the usual case): its unit normal and basis on values, so that the rows
        // are formed with products by plain numbers (half the work on a tangent scalar).
        if (!math::has_tangent(n_given[0]) && !math::has_tangent(n_given[1]) && !math::has_tangent(n_given[2]))
          rows_with_normal(Vec3<double>(value_of(n_given[0]), value_of(n_given[1]), value_of(n_given[2])));
        else
          rows_with_normal(n_given);
        break;
      }
    }
  }
  if (options.baumgarte_alpha != 0 || options.baumgarte_beta != 0) {
    const double a2 = 2 * options.baumgarte_alpha, b2 = options.baumgarte_beta * options.baumgarte_beta;
    for (int r = 0; r < m.nconstraint_rows; ++r)
      ws.constraint_bias[r] -= a2 * ws.velocity_residual[r] + b2 * ws.position_residual[r];
  }
}

#define KANESENS_INSTANTIATE(S)                                                          \
  template void rolling_plane_basis<S>(const Vec3<S>&, Vec3<S>&, Vec3<S>&);               \
  template S rolling_contact_height<S>(const Model&, const Workspace<S>&, const Constraint&);          \
  template void compute_constraints<S>(const Model&, Workspace<S>&, const S*, const S*,   \
                                       const DynamicsOptions&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
