#include "sim/correction_directions.hpp"

#include "dynamics/equations.hpp"
#include "dynamics/frames.hpp"

namespace kanesens::sim {
namespace {

using dynamics::Workspace;
using model::Constraint;
using model::Joint;
using model::JointType;
using model::Model;
using V3 = Eigen::Vector3d;

struct Wheel {
  int body = -1;
  V3 normal, axle, centre;  // world, at q
};

// The rolling wheels at q (the position stage of `ws` evaluated there).
std::vector<Wheel> wheels_at(const Model& m, Workspace<double>& ws, double t, const double* q) {
  const std::vector<double> zero(static_cast<std::size_t>(m.nu), 0.0);
  dynamics::evaluate_constraints(m, ws, t, q, zero.data());
  std::vector<Wheel> w;
  for (const Constraint& c : m.constraints) {
    if (c.kind != Constraint::Kind::rolling) continue;
    Wheel x;
    x.body = c.body;
    x.normal = V3(ws.values[c.normal[0]], ws.values[c.normal[1]], ws.values[c.normal[2]]).normalized();
    x.axle = (ws.R[c.body] * V3(ws.values[c.axis[0]], ws.values[c.axis[1]], ws.values[c.axis[2]])).normalized();
    x.centre = dynamics::world_point(m, ws, c.body, V3::Zero().eval());
    w.push_back(x);
  }
  return w;
}

bool carries(const Model& m, const Joint& J, int body) { return m.moves[static_cast<std::size_t>(body)][static_cast<std::size_t>(J.u_offset)] != 0; }

// Joints between J's child and `body` (J carries it).
int hops(const Model& m, const Joint& J, int body) {
  int n = 0;
  for (int x = body; x >= 0 && x != J.child; x = m.bodies[static_cast<std::size_t>(x)].parent) ++n;
  return n;
}

// The free joints that carry a wheel, each with its nearest wheel (fewest joints in between,
// then the first declared).
std::vector<std::pair<int, int>> free_joints_with_wheels(const Model& m, const std::vector<Wheel>& wheels) {
  std::vector<std::pair<int, int>> r;
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& J = m.joints[j];
    if (J.type != JointType::free) continue;
    int best = -1;
    for (std::size_t w = 0; w < wheels.size(); ++w)
      if (carries(m, J, wheels[w].body) &&
          (best < 0 || hops(m, J, wheels[w].body) < hops(m, J, wheels[static_cast<std::size_t>(best)].body)))
        best = static_cast<int>(w);
    if (best >= 0) r.emplace_back(static_cast<int>(j), best);
  }
  return r;
}

// Speed direction of free joint J: its joint point moves with v, its child turns with ω (both
// world components, relative to the parent).
Eigen::VectorXd free_motion(const Model& m, const Workspace<double>& ws, const Joint& J, const V3& v, const V3& w) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(m.nu);
  const Eigen::Matrix3d RP = J.parent >= 0 ? ws.R[static_cast<std::size_t>(J.parent)] : Eigen::Matrix3d::Identity();
  u.segment<3>(J.u_offset) = RP.transpose() * v;
  u.segment<3>(J.u_offset + 3) = ws.R[static_cast<std::size_t>(J.child)].transpose() * w;
  return u;
}

// A rotation about the axis `axis` through the point X: ω = axis, v_Q = axis × (Q − X).
Eigen::VectorXd free_rotation(const Model& m, const Workspace<double>& ws, int j, const V3& axis, const V3& X) {
  const Joint& J = m.joints[static_cast<std::size_t>(j)];
    const V3 Q = dynamics::world_point(m, ws, J.child, ws.reference_point[static_cast<std::size_t>(J.child)]);
  return free_motion(m, ws, J, axis.cross(Q - X), axis);
}

// q̇ = N(q) u, without the quaternions' norm term (q is on the unit sphere here).
Eigen::VectorXd coordinate_rate(const Model& m, const double* q, const Eigen::VectorXd& u) {
  Eigen::VectorXd qd(m.nq);
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) {
      for (int k = 0; k < J.nq; ++k) qd[J.q_offset + k] = u[J.u_offset + k];
      continue;
    }
    const int lin = J.type == JointType::free ? 3 : 0;
    for (int k = 0; k < lin; ++k) qd[J.q_offset + k] = u[J.u_offset + k];
    const double* e = q + J.quaternion_offset;
    const double* w = u.data() + J.u_offset + lin;
    double* ed = qd.data() + J.quaternion_offset;
    ed[0] = 0.5 * (-e[1] * w[0] - e[2] * w[1] - e[3] * w[2]);
    ed[1] = 0.5 * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1]);
    ed[2] = 0.5 * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2]);
    ed[3] = 0.5 * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0]);
  }
  return qd;
}

Eigen::MatrixXd columns(const std::vector<Eigen::VectorXd>& c, Eigen::Index rows) {
  Eigen::MatrixXd D(rows, static_cast<Eigen::Index>(c.size()));
  for (std::size_t i = 0; i < c.size(); ++i) D.col(static_cast<Eigen::Index>(i)) = c[i];
  return D;
}

}  // namespace

Eigen::MatrixXd coordinate_directions(const Model& m, Workspace<double>& ws, double t, const double* q,
                                      const std::vector<int>& fallback) {
  const std::vector<Wheel> wheels = wheels_at(m, ws, t, q);
  const auto free = free_joints_with_wheels(m, wheels);
  std::vector<Eigen::VectorXd> d;
  for (const Wheel& w : wheels)  // heights
    for (const auto& [j, nearest] : free)
      if (carries(m, m.joints[static_cast<std::size_t>(j)], w.body))
        d.push_back(coordinate_rate(m, q, free_motion(m, ws, m.joints[static_cast<std::size_t>(j)], w.normal, V3::Zero())));
  for (const auto& [j, nearest] : free) {  // pitch about the nearest wheel's axle
    const Wheel& w = wheels[static_cast<std::size_t>(nearest)];
    d.push_back(coordinate_rate(m, q, free_rotation(m, ws, j, w.axle, w.centre)));
  }
  for (int i : fallback) d.push_back(Eigen::VectorXd::Unit(m.nq, i));
  return columns(d, m.nq);
}

Eigen::MatrixXd speed_directions(const Model& m, Workspace<double>& ws, double t, const double* q,
                                 const std::vector<int>& fallback) {
  const std::vector<Wheel> wheels = wheels_at(m, ws, t, q);
  const auto free = free_joints_with_wheels(m, wheels);
  std::vector<Eigen::VectorXd> d;
  for (const auto& [j, nearest] : free)  // translational speeds
    for (int k = 0; k < 3; ++k) d.push_back(Eigen::VectorXd::Unit(m.nu, m.joints[static_cast<std::size_t>(j)].u_offset + k));
  for (const Wheel& w : wheels)  // yaw rates
    for (const auto& [j, nearest] : free)
      if (carries(m, m.joints[static_cast<std::size_t>(j)], w.body))
        d.push_back(free_motion(m, ws, m.joints[static_cast<std::size_t>(j)], V3::Zero(), w.normal));
  for (const auto& [j, nearest] : free)  // pitch rates
    d.push_back(free_motion(m, ws, m.joints[static_cast<std::size_t>(j)], V3::Zero(),
                            wheels[static_cast<std::size_t>(nearest)].axle));
  for (auto J = m.joints.rbegin(); J != m.joints.rend(); ++J)  // wheel spins, last wheel first
    if (J->type == JointType::revolute)
      for (const Wheel& w : wheels)
        if (J->child == w.body) d.push_back(Eigen::VectorXd::Unit(m.nu, J->u_offset));
  for (int k : fallback) d.push_back(Eigen::VectorXd::Unit(m.nu, k));
  return columns(d, m.nu);
}

}  // namespace kanesens::sim
