#include "sim/initial_checks.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "dynamics/equations.hpp"
#include "math/dual.hpp"
#include "sim/kane_problem.hpp"
#include "util/error.hpp"

namespace kanesens::sim {
namespace {

using dynamics::Workspace;
using math::value_of;
using model::Constraint;
using model::Model;

template <class S>
Eigen::Matrix3d value_of_matrix(const Eigen::Matrix<S, 3, 3>& R) {
  Eigen::Matrix3d v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v(i, j) = value_of(R(i, j));
  return v;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// Where the scene was written (file:line:column of `scene:`), for problems of the whole scene.
SourceLocation scene_where(const Model& m) {
  return m.spec.where.file.empty() ? SourceLocation{m.spec.file, 0, 0} : m.spec.where;
}

}  // namespace

template <class S>
void check_constraint_rows(const Model& m, const Workspace<S>& ws, double t) {
  double scale = 1;
  for (int r = 0; r < m.nconstraint_rows; ++r)
    for (int k = 0; k < m.nu; ++k) scale = std::max(scale, std::abs(value_of(ws.constraint_matrix(r, k))));
  for (std::size_t ci = 0; ci < m.constraints.size(); ++ci) {
    const Constraint& c = m.constraints[ci];
    const SourceLocation where = ci < m.spec.constraints.size() ? m.spec.constraints[ci].where : scene_where(m);
    const std::string key = ci < m.spec.constraints.size() ? m.spec.constraints[ci].key : "scene.constraints";
    if (c.kind == Constraint::Kind::rolling) {
      // The contact point is the wheel point nearest the plane, c − r unit(n − (n·a) a): undefined
      // when the axle is along the normal (the wheel lies flat), and ill-conditioned near it.
      using V3 = Eigen::Vector3d;
      const V3 a = (value_of_matrix(ws.R[c.body]) *
                    V3(value_of(ws.values[c.axis[0]]), value_of(ws.values[c.axis[1]]), value_of(ws.values[c.axis[2]])))
                       .normalized();
      const V3 n = V3(value_of(ws.values[c.normal[0]]), value_of(ws.values[c.normal[1]]), value_of(ws.values[c.normal[2]]))
                       .normalized();
      if (!((n - n.dot(a) * a).norm() > 1e-6))
        throw InputError(where, key,
                         "the wheel of rolling constraint '" + c.name + "' lies flat on its plane at the initial state (t = " +
                             number(t) + "): its axle is along the plane's normal, where the contact point is undefined");
    }
    double largest = 0;
    for (int r = c.row_offset; r < c.row_offset + c.nrows; ++r) {
      const double values[] = {value_of(ws.position_residual[r]), value_of(ws.velocity_residual[r]),
                               value_of(ws.constraint_bias[r])};
      bool finite = std::isfinite(values[0]) && std::isfinite(values[1]) && std::isfinite(values[2]);
      for (int k = 0; k < m.nu; ++k) {
        const double a = value_of(ws.constraint_matrix(r, k));
        finite = finite && std::isfinite(a);
        largest = std::max(largest, std::abs(a));
      }
      if (!finite)
        throw InputError(where, key,
                         "constraint '" + c.name + "' is not finite at the initial state (t = " + number(t) + ", row '" +
                             m.constraint_row_names[static_cast<std::size_t>(r)] +
                             "'): a zero-length direction, or points that coincide where a distance is measured?");
    }
    if (c.nrows > 0 && !(largest > 1e-12 * scale))
      throw InputError(where, key,
                       "constraint '" + c.name + "' constrains nothing at the initial state (t = " + number(t) +
                           "): every coefficient of its " + (c.nrows == 1 ? "row" : std::to_string(c.nrows) + " rows") +
                           " is zero there (no speed moves what it constrains: a welded or unmoved body, a "
                           "component out of the scene's plane, a function of no coordinate?)");
  }
}

template void check_constraint_rows<double>(const Model&, const Workspace<double>&, double);
template void check_constraint_rows<math::Dual>(const Model&, const Workspace<math::Dual>&, double);

void KaneProblem::validate_initial_state() const {
  check_initial_state();  // degenerate constraints, a zero quaternion, Newton, ... (set_sample)
  const Model& m = model_;
  const std::vector<double>& y0 = initial_.y;
  Workspace<double> ws(m);
  dynamics::set_articulated_body(m, ws, false);  // M and f are checked below
  dynamics::set_parameters(m, ws, workspaces_.parameters().data());
  std::vector<double> ydot(y0.size());
  dynamics::RhsFailure why = dynamics::RhsFailure::none;
  const bool ok = dynamics::evaluate_rhs(m, ws, t0_, y0.data(), ydot.data(), dynamics_, &why);
  const std::string at = "at the initial state (t = " + number(t0_) + ")";
  auto not_finite = [&](const std::string& what, double value) {
    throw InputError(scene_where(m), "scene",
                     at + " " + what + " is " + number(value) +
                         ": masses, inertias, lengths, forces or initial values out of range?");
  };
  for (int i = 0; i < m.nstate(); ++i)
    if (!std::isfinite(y0[static_cast<std::size_t>(i)])) not_finite("the state " + m.state_names[static_cast<std::size_t>(i)], y0[static_cast<std::size_t>(i)]);
  for (int r = 0; r < m.nu; ++r)
    for (int c = 0; c < m.nu; ++c)
      if (!std::isfinite(ws.mass_matrix(r, c)))
        not_finite("mass matrix entry (" + m.speed_names[static_cast<std::size_t>(r)] + ", " +
                       m.speed_names[static_cast<std::size_t>(c)] + ")",
                   ws.mass_matrix(r, c));
  for (int r = 0; r < m.nu; ++r)
    if (!std::isfinite(ws.forcing[r])) not_finite("the forcing of " + m.speed_names[static_cast<std::size_t>(r)], ws.forcing[r]);
  if (!ok) throw InputError(scene_where(m), "scene", at + ": " + dynamics::describe(why));
  for (int i = 0; i < m.nstate(); ++i)
    if (!std::isfinite(ydot[static_cast<std::size_t>(i)]))
      not_finite("the rate of " + m.state_names[static_cast<std::size_t>(i)], ydot[static_cast<std::size_t>(i)]);
}

}  // namespace kanesens::sim
