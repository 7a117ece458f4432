#include "sim/initial_state.hpp"

#include <algorithm>
#include <cmath>

#include "dynamics/equations.hpp"
#include "sim/correction_directions.hpp"
#include "sim/initial_checks.hpp"
#include "util/error.hpp"

namespace kanesens::sim {
namespace {

using dynamics::Workspace;
using math::Dual;
using model::Joint;
using model::Model;

// Tangent 0 is the state's own (no tangent); tangent 1 + i is sensitivity i.
struct Tangents {
  std::vector<std::vector<Dual>> y;        // [tangent][nstate]
  std::vector<Workspace<Dual>*> workspace;  // [tangent]
};

// y0 as duals with the tangent of sensitivity `i` (i < 0: none), before any correction.
void unconstrained_state(const Model& m, const SampleInputs& inputs, const std::vector<InputRef>& sens, int i,
                         const Workspace<Dual>& ws, std::vector<Dual>& y0) {
  int k = 0;
  for (const Joint& j : m.joints)
    for (model::Slot s : j.q0) y0[k++] = ws.values[s];
  for (const Joint& j : m.joints)
    for (model::Slot s : j.u0) y0[k++] = ws.values[s];
  for (int s = 0; s < m.nstate(); ++s)
    if (inputs.initial_set[s]) y0[s] = Dual(inputs.initial_values[s], 0);
  if (i >= 0 && sens[i].kind == InputRef::Kind::initial_condition) y0[sens[i].index].d = 1;
  for (std::size_t ji = 0; ji < m.joints.size(); ++ji) {
    const Joint& j = m.joints[ji];
    if (j.quaternion_offset < 0) continue;
    Dual* e = y0.data() + j.quaternion_offset;
    const model::JointSpec& js = m.spec.joints[ji];
    const SourceLocation where = js.q0.empty() ? js.where : js.q0[0].where;
    // Scaled by its largest component first (a constant: the tangent of the normalised result is
    // unchanged), so that 1e200 or 1e-200 components normalise instead of overflowing.
    double largest = 0;
    for (int c = 0; c < 4; ++c) largest = std::max(largest, std::abs(e[c].v));
    if (!std::isfinite(largest))
      throw InputError(where, js.key + ".q0", "the initial quaternion of joint '" + j.name + "' is not finite");
    if (!(largest > 0)) throw InputError(where, js.key + ".q0", "the initial quaternion of joint '" + j.name + "' is zero");
    for (int c = 0; c < 4; ++c) e[c] = e[c] / largest;
    const Dual n = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    for (int c = 0; c < 4; ++c) e[c] = e[c] / n;
  }
}

// Which initial values the user gave: 0 not given, 1 in the scene's q0/u0, 2 set for this sample
// or a sensitivity parameter. Dependents are tried in that order (lowest first), each tier from
// the last value backwards, so given values — and the first, driving coordinates and speeds —
// are kept when others can absorb the correction.
std::vector<unsigned char> given_values(const Model& m, const SampleInputs& inputs, const std::vector<InputRef>& sens) {
  std::vector<unsigned char> given(static_cast<std::size_t>(m.nstate()), 0);
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& J = m.joints[j];
    const model::JointSpec& js = m.spec.joints[j];
    for (int k = 0; k < J.nq; ++k) given[static_cast<std::size_t>(J.q_offset + k)] = !js.q0.empty();
    for (int k = 0; k < J.nu; ++k) given[static_cast<std::size_t>(m.nq + J.u_offset + k)] = !js.u0.empty();
  }
  // Values set for this sample (--set, vary) or differentiated with respect to rank above the
  // scene's: they are what the user is asking about.
  for (int s = 0; s < m.nstate(); ++s)
    if (inputs.initial_set[static_cast<std::size_t>(s)]) given[static_cast<std::size_t>(s)] = 2;
  for (const InputRef& r : sens)
    if (r.kind == InputRef::Kind::initial_condition) given[static_cast<std::size_t>(r.index)] = 2;
  return given;
}

std::vector<int> dependent_order(const std::vector<unsigned char>& given, int offset, int count,
                                 const std::vector<int>& excluded) {
  std::vector<int> order;
  for (int pass = 0; pass < 3; ++pass)
    for (int i = count - 1; i >= 0; --i)
      if (!excluded[static_cast<std::size_t>(i)] && given[static_cast<std::size_t>(offset + i)] == pass) order.push_back(i);
  return order;
}

// Unit quaternions again after a Newton step (every tangent: the normalisation is part of the
// map from the inputs to the corrected state).
void normalize_quaternions(const Model& m, std::vector<Dual>& y) {
  for (const Joint& J : m.joints) {
    if (J.quaternion_offset < 0) continue;
    Dual* e = y.data() + J.quaternion_offset;
    const Dual n = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    for (int c = 0; c < 4; ++c) e[c] = e[c] / n;
  }
}

std::vector<int> all_columns(Eigen::Index n) {
  std::vector<int> order(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  return order;
}

// Positions: Newton along the chosen directions (sim/correction_directions.hpp), re-evaluated at
// every iterate; one more step after convergence to settle the tangents. Returns max |Δq|.
double correct_positions(const Model& m, const std::vector<unsigned char>& given, double t0, Tangents& tan,
                         HolonomicConstraints& holonomic, Workspace<double>& wsv) {
  const int nq = m.nq, nu = m.nu, mh = holonomic.size();
  const std::size_t T = tan.y.size();
  std::vector<double> qv(static_cast<std::size_t>(nq));
  auto values = [&] { for (int i = 0; i < nq; ++i) qv[static_cast<std::size_t>(i)] = tan.y[0][static_cast<std::size_t>(i)].v; };
  Eigen::VectorXd g;
  Eigen::MatrixXd G;
  values();
  holonomic.evaluate(t0, qv.data(), g, &G);
  std::vector<int> quaternion(static_cast<std::size_t>(nq), 0);
  for (const Joint& J : m.joints)
    if (J.quaternion_offset >= 0)
      for (int c = 0; c < 4; ++c) quaternion[static_cast<std::size_t>(J.quaternion_offset + c)] = 1;
  const std::vector<int> fallback = dependent_order(given, 0, nq, quaternion);
  Eigen::MatrixXd D = coordinate_directions(m, wsv, t0, qv.data(), fallback);
  const std::vector<int> dep = choose_dependent_columns(G * D, all_columns(D.cols()));
  const std::vector<Dual> ud(static_cast<std::size_t>(nu), Dual(0));
  std::vector<std::vector<Dual>> gd(T, std::vector<Dual>(static_cast<std::size_t>(mh)));
  Eigen::VectorXd gv(mh), gt(mh);
  Eigen::MatrixXd Dd(nq, static_cast<Eigen::Index>(dep.size()));
  const std::vector<double> start = qv;
  for (int iter = 0, converged = 0; iter < 50 && converged < 2; ++iter) {
    // Residuals in duals (they carry the parameter and initial-condition tangents); their values
    // are the same for every tangent.
    for (std::size_t k = 0; k < T; ++k) {
      Workspace<Dual>& ws = *tan.workspace[k];
      dynamics::evaluate_constraints(m, ws, Dual(t0), tan.y[k].data(), ud.data());
      for (int r = 0; r < mh; ++r) gd[k][static_cast<std::size_t>(r)] = ws.position_residual[holonomic.rows()[static_cast<std::size_t>(r)]];
    }
    double gmax = 0;
    for (int r = 0; r < mh; ++r) gmax = std::max(gmax, std::abs(gd[0][static_cast<std::size_t>(r)].v));
    if (gmax < 1e-13) ++converged;
    if (dep.empty()) {  // no coordinate moves the constraints: nothing to correct
      if (gmax < 1e-13) break;
      throw InputError(m.spec.where, "scene.constraints",
                       "the position constraints are violated at t0 (residual " + std::to_string(gmax) +
                           ") and no coordinate changes them");
    }
    values();
    holonomic.evaluate(t0, qv.data(), g, &G);
    D = coordinate_directions(m, wsv, t0, qv.data(), fallback);
    for (std::size_t c = 0; c < dep.size(); ++c) Dd.col(static_cast<Eigen::Index>(c)) = D.col(dep[c]);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(G * Dd);
    for (int r = 0; r < mh; ++r) gv[r] = gd[0][static_cast<std::size_t>(r)].v;
    Eigen::VectorXd dv = Dd * cod.solve(gv);
    // A far start: no step longer than 0.5 (m, rad, quaternion units), so the iterate stays
    // near the branch it started on.
    const double longest = dv.lpNorm<Eigen::Infinity>();
    if (longest > 0.5) dv *= 0.5 / longest;
    for (std::size_t k = 0; k < T; ++k) {
      for (int r = 0; r < mh; ++r) gt[r] = gd[k][static_cast<std::size_t>(r)].d;
      const Eigen::VectorXd dt = Dd * cod.solve(gt);
      for (int i = 0; i < nq; ++i) {
        Dual& q = tan.y[k][static_cast<std::size_t>(i)];
        q.v -= dv[i];
        q.d -= dt[i];
      }
      normalize_quaternions(m, tan.y[k]);
    }
    if (iter == 49)
      throw InputError(m.spec.where, "scene.constraints",
                       "cannot satisfy the position constraints at t0 from the given initial coordinates (Newton did "
                       "not converge; residual " + std::to_string(gmax) + "): constraints that contradict each other, or "
                       "initial values too far from any assembly?");
  }
  double dq_max = 0;
  for (int i = 0; i < nq; ++i)
    dq_max = std::max(dq_max, std::abs(tan.y[0][static_cast<std::size_t>(i)].v - start[static_cast<std::size_t>(i)]));
  return dq_max;
}

// Speeds: the velocity residual A u + a0 is linear in u; it is removed along the chosen speed
// directions (sim/correction_directions.hpp: the rolling contacts' own, then any speed from
// the last backwards), so the first speeds — the user's driving speeds — keep their given
// values. Returns max |Δu|.
double correct_speeds(const Model& m, const std::vector<unsigned char>& given, double t0, Tangents& tan,
                      Workspace<double>& wsv) {
  const int nq = m.nq, nu = m.nu, nc = m.nconstraint_rows;
  const std::size_t T = tan.y.size();
  std::vector<double> qv(static_cast<std::size_t>(nq));
  for (int i = 0; i < nq; ++i) qv[static_cast<std::size_t>(i)] = tan.y[0][static_cast<std::size_t>(i)].v;
  const Eigen::MatrixXd U =
      speed_directions(m, wsv, t0, qv.data(), dependent_order(given, nq, nu, std::vector<int>(static_cast<std::size_t>(nu), 0)));
  std::vector<int> dep;
  Eigen::MatrixXd A(nc, nu);
  Eigen::VectorXd rv(nc);
  std::vector<Eigen::VectorXd> rt(T, Eigen::VectorXd(nc));
  Eigen::MatrixXd Ud;
  std::vector<double> start(static_cast<std::size_t>(nu));
  for (int c = 0; c < nu; ++c) start[static_cast<std::size_t>(c)] = tan.y[0][static_cast<std::size_t>(nq + c)].v;
  for (int iter = 0; iter < 3; ++iter) {
    for (std::size_t k = 0; k < T; ++k) {
      Workspace<Dual>& ws = *tan.workspace[k];
      const Dual* q = tan.y[k].data();
      dynamics::evaluate_constraints(m, ws, Dual(t0), q, q + nq);
      if (k == 0) {  // A and the residual's value: the same for every tangent
        for (int r = 0; r < nc; ++r) {
          for (int c = 0; c < nu; ++c) A(r, c) = ws.constraint_matrix(r, c).v;
          rv[r] = ws.velocity_residual[r].v;
        }
      }
      for (int r = 0; r < nc; ++r) rt[k][r] = ws.velocity_residual[r].d;
    }
    if (iter == 0) {
      dep = choose_dependent_columns(A * U, all_columns(U.cols()));
      Ud.resize(nu, static_cast<Eigen::Index>(dep.size()));
      for (std::size_t c = 0; c < dep.size(); ++c) Ud.col(static_cast<Eigen::Index>(c)) = U.col(dep[c]);
    }
    if (dep.empty()) break;  // A vanishes (a redundant, all-zero system): nothing to correct
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A * Ud);
    const Eigen::VectorXd dv = Ud * cod.solve(rv);
    for (std::size_t k = 0; k < T; ++k) {
      const Eigen::VectorXd dt = Ud * cod.solve(rt[k]);
      for (int c = 0; c < nu; ++c) {
        Dual& u = tan.y[k][static_cast<std::size_t>(nq + c)];
        u.v -= dv[c];
        u.d -= dt[c];
      }
    }
  }
  double du_max = 0;
  for (int c = 0; c < nu; ++c)
    du_max = std::max(du_max, std::abs(tan.y[0][static_cast<std::size_t>(nq + c)].v - start[static_cast<std::size_t>(c)]));
  return du_max;
}

}  // namespace

InitialState consistent_initial_state(const Model& m, const SampleInputs& inputs, const std::vector<InputRef>& sens,
                                      const ConstraintOptions& options, double t0, SampleWorkspaces& workspaces,
                                      HolonomicConstraints& holonomic) {
  const std::size_t n = static_cast<std::size_t>(m.nstate()), ns = sens.size();
  Tangents tan;
  tan.y.assign(ns + 1, std::vector<Dual>(n));
  tan.workspace.assign(ns + 1, &workspaces.jacobian());
  for (std::size_t i = 0; i < ns; ++i) tan.workspace[i + 1] = &workspaces.tangent(static_cast<int>(i));
  for (std::size_t k = 0; k <= ns; ++k)
    unconstrained_state(m, inputs, sens, static_cast<int>(k) - 1, *tan.workspace[k], tan.y[k]);

  InitialState init;
  if (m.nconstraint_rows > 0) {
    // A constraint that constrains nothing here (or is not finite) has no dependent coordinate
    // to correct and no multiplier: name it instead of decomposing an empty matrix.
    Workspace<Dual>& ws = *tan.workspace[0];
    const Dual* y = tan.y[0].data();
    dynamics::evaluate_constraints(m, ws, Dual(t0), y, y + m.nq);
    check_constraint_rows(m, ws, t0);
  }
  if (m.nconstraint_rows > 0 && options.correct_initial) {
    const std::vector<unsigned char> given = given_values(m, inputs, sens);
    if (holonomic.size() > 0)
      init.position_correction = correct_positions(m, given, t0, tan, holonomic, workspaces.values());
    init.velocity_correction = correct_speeds(m, given, t0, tan, workspaces.values());
  }
  init.y.resize(n);
  for (std::size_t r = 0; r < n; ++r) init.y[r] = tan.y[0][r].v;
  init.s.assign(ns, std::vector<double>(n));
  for (std::size_t i = 0; i < ns; ++i)
    for (std::size_t r = 0; r < n; ++r) init.s[i][r] = tan.y[i + 1][r].d;
  return init;
}

}  // namespace kanesens::sim
