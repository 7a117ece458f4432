#include "sim/linearize.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dynamics/equations.hpp"
#include "sim/holonomic.hpp"
#include "util/did_you_mean.hpp"
#include "util/error.hpp"

namespace kanesens::sim {
namespace {

using dynamics::Workspace;
using math::Dual;
using model::Constraint;
using model::Joint;
using model::JointType;
using model::Model;

// The chart: for speed k, the coordinate it moves (scalar joints), or the first speed of the
// rotation vector it belongs to (quaternion joints).
struct Chart {
  std::vector<int> coordinate;  // nu: index in q, or -1
  std::vector<int> rotation;    // nu: first speed of the rotation triple, or -1
  std::vector<int> quaternion;  // nu: index in q of the quaternion's w (with `rotation`)
  std::vector<unsigned char> floating;  // nu: 1 a free joint's translation, 2 a free or spherical joint's rotation
  std::vector<std::string> names;

  explicit Chart(const Model& m) {
    const std::size_t nu = static_cast<std::size_t>(m.nu);
    coordinate.assign(nu, -1);
    rotation.assign(nu, -1);
    quaternion.assign(nu, -1);
    floating.assign(nu, 0);
    names.assign(nu, "");
    for (const Joint& J : m.joints) {
      const bool fl = J.type == JointType::free || J.type == JointType::spherical;
      const int lin = J.quaternion_offset < 0 ? J.nu : (J.type == JointType::free ? 3 : 0);
      for (int k = 0; k < J.nu; ++k) {
        const std::size_t c = static_cast<std::size_t>(J.u_offset + k);
        floating[c] = !fl ? 0 : k < lin ? 1 : 2;
        if (k < lin) {
          coordinate[c] = J.q_offset + k;
          names[c] = m.coordinate_names[static_cast<std::size_t>(J.q_offset + k)];
        } else {
          rotation[c] = J.u_offset + lin;
          quaternion[c] = J.quaternion_offset;
          names[c] = J.name + (k - lin == 0 ? ".rx" : k - lin == 1 ? ".ry" : ".rz");
        }
      }
    }
  }

  // q = q* displaced by the chart coordinates dxi (nu): scalar coordinates added, quaternions
  // q* ⊗ (1, δθ/2) normalised (first order is all a dual number carries).
  void displace(const Model& m, const std::vector<double>& y, const std::vector<Dual>& dxi,
                std::vector<Dual>& q) const {
    for (int i = 0; i < m.nq; ++i) q[static_cast<std::size_t>(i)] = Dual(y[static_cast<std::size_t>(i)]);
    for (int c = 0; c < m.nu; ++c) {
      const std::size_t k = static_cast<std::size_t>(c);
      if (coordinate[k] >= 0) q[static_cast<std::size_t>(coordinate[k])] += dxi[k];
      if (rotation[k] != c) continue;
      const std::size_t w = static_cast<std::size_t>(quaternion[k]);
      const double e0 = y[w], e1 = y[w + 1], e2 = y[w + 2], e3 = y[w + 3];
      const Dual h1 = 0.5 * dxi[k], h2 = 0.5 * dxi[k + 1], h3 = 0.5 * dxi[k + 2];
      Dual r[4] = {e0 - e1 * h1 - e2 * h2 - e3 * h3, e0 * h1 + e1 + e2 * h3 - e3 * h2,
                   e0 * h2 - e1 * h3 + e2 + e3 * h1, e0 * h3 + e1 * h2 - e2 * h1 + e3};
      const Dual n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
      for (int i = 0; i < 4; ++i) q[w + static_cast<std::size_t>(i)] = r[i] / n;
    }
  }
};

// The position constraints h(q) at (t, q, u): the holonomic rows' residuals (a rolling contact's
// normal row among them: its contact height). Leaves the constraints evaluated in ws.
int count_position_constraints(const Model& m) {
  int n = 0;
  for (const Constraint& c : m.constraints) n += static_cast<int>(std::count(c.holonomic.begin(), c.holonomic.end(), 1));
  return n;
}
void position_constraints(const Model& m, Workspace<Dual>& ws, double t, const std::vector<Dual>& q,
                          const std::vector<Dual>& u, std::vector<Dual>& h) {
  dynamics::evaluate_constraints(m, ws, Dual(t), q.data(), u.data());
  std::size_t i = 0;
  for (const Constraint& c : m.constraints)
    for (int r = 0; r < c.nrows; ++r)
      if (c.holonomic[static_cast<std::size_t>(r)]) h[i++] = ws.position_residual[c.row_offset + r];
}

// Dependent-column preference: floating joints' translations, then their rotations, then the
// rest, each from the last backwards (contacts and closures determine where a floating base is;
// joint coordinates and body-frame rates are what one steers by and names modes in); `first`
// (if any) before everything; `excluded` never.
std::vector<int> dependent_order(const Chart& chart, const std::vector<unsigned char>& first,
                                 const std::vector<unsigned char>& excluded) {
  std::vector<int> order;
  const int n = static_cast<int>(chart.names.size());
  for (int tier = 0; tier < 4; ++tier)
    for (int i = n - 1; i >= 0; --i) {
      const std::size_t k = static_cast<std::size_t>(i);
      if (excluded[k]) continue;
      const int t = !first.empty() && first[k] ? 0 : chart.floating[k] == 1 ? 1 : chart.floating[k] == 2 ? 2 : 3;
      if (t == tier) order.push_back(i);
    }
  return order;
}

// Indices of `names` in `all` (InputError with a suggestion for an unknown one).
std::vector<int> find_names(const std::vector<std::string>& names, const std::vector<std::string>& all,
                            const std::string& key) {
  std::vector<int> idx;
  for (const std::string& n : names) {
    const auto it = std::find(all.begin(), all.end(), n);
    if (it == all.end())
      throw InputError({}, key, "unknown name '" + n + "'" + did_you_mean(n, all) + "; the names are " + join_names(all));
    if (std::find(idx.begin(), idx.end(), static_cast<int>(it - all.begin())) != idx.end())
      throw InputError({}, key, "'" + n + "' is named twice");
    idx.push_back(static_cast<int>(it - all.begin()));
  }
  return idx;
}

std::vector<unsigned char> flags(const std::vector<int>& idx, int n) {
  std::vector<unsigned char> f(static_cast<std::size_t>(n), 0);
  for (int i : idx) f[static_cast<std::size_t>(i)] = 1;
  return f;
}

Eigen::MatrixXd columns(const Eigen::MatrixXd& J, const std::vector<int>& cols) {
  Eigen::MatrixXd Jc(J.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c) Jc.col(static_cast<Eigen::Index>(c)) = J.col(cols[c]);
  return Jc;
}

}  // namespace

std::vector<std::string> chart_coordinate_names(const Model& model) { return Chart(model).names; }

Linearization linearize(const Model& m, const std::vector<double>& parameters, double t, const std::vector<double>& y,
                        const LinearizeOptions& options) {
  const int nq = m.nq, nu = m.nu, nc = m.nconstraint_rows, np = m.nparam();
  const std::size_t unu = static_cast<std::size_t>(nu);
  const Chart chart(m);
  Workspace<Dual> ws(m);
  std::vector<Dual> p(parameters.begin(), parameters.end());
  dynamics::set_parameters(m, ws, p.data());

  // The state as duals without tangent, and the constraint Jacobians at it.
  const int mh = count_position_constraints(m);
  std::vector<Dual> q(static_cast<std::size_t>(nq)), u(unu), dxi(unu, Dual(0)), h(static_cast<std::size_t>(mh));
  for (int k = 0; k < nu; ++k) u[static_cast<std::size_t>(k)] = Dual(y[static_cast<std::size_t>(nq + k)]);
  Eigen::MatrixXd G(mh, nu), Av(nc, nu);
  for (int c = 0; c < nu; ++c) {
    dxi[static_cast<std::size_t>(c)].d = 1;
    chart.displace(m, y, dxi, q);
    position_constraints(m, ws, t, q, u, h);
    for (int r = 0; r < mh; ++r) G(r, c) = h[static_cast<std::size_t>(r)].d;
    dxi[static_cast<std::size_t>(c)].d = 0;
  }
  Linearization lin;
  for (int r = 0; r < mh; ++r) lin.position_residual = std::max(lin.position_residual, std::abs(h[static_cast<std::size_t>(r)].v));
  for (int r = 0; r < nc; ++r) {
    lin.velocity_residual = std::max(lin.velocity_residual, std::abs(ws.velocity_residual[r].v));
    for (int k = 0; k < nu; ++k) Av(r, k) = ws.constraint_matrix(r, k).v;
  }

  // Dependent coordinates and speeds (the named ones never).
  const std::vector<int> named_q = find_names(options.coordinates, chart.names, "--coordinates");
  const std::vector<int> named_u = find_names(options.speeds, m.speed_names, "--speeds");
  const std::vector<unsigned char> keep_q = flags(named_q, nu), keep_u = flags(named_u, nu);
  std::vector<int> dep_q, dep_u;
  if (mh > 0) {
    dep_q = choose_dependent_columns(G, dependent_order(chart, {}, keep_q));
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G);
    qr.setThreshold(1e-10);
    if (static_cast<Eigen::Index>(dep_q.size()) < qr.rank())
      throw InputError({}, "--coordinates", "the position constraints cannot be solved for the coordinates not named");
  }
  if (nc > 0) {
    // The speeds of dependent coordinates are dependent first.
    dep_u = choose_dependent_columns(Av, dependent_order(chart, flags(dep_q, nu), keep_u));
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Av);
    qr.setThreshold(1e-10);
    if (static_cast<Eigen::Index>(dep_u.size()) < qr.rank())
      throw InputError({}, "--speeds", "the velocity constraints cannot be solved for the speeds not named");
  }
  const std::vector<unsigned char> is_dep_q = flags(dep_q, nu), is_dep_u = flags(dep_u, nu);
  std::vector<int> ind_q, ind_u;
  for (int k = 0; k < nu; ++k) {
    if (!is_dep_q[static_cast<std::size_t>(k)]) ind_q.push_back(k);
    if (!is_dep_u[static_cast<std::size_t>(k)]) ind_u.push_back(k);
  }
  const int niq = static_cast<int>(ind_q.size()), nz = niq + static_cast<int>(ind_u.size());
  const int nin = static_cast<int>(options.inputs.size());
  const Eigen::MatrixXd Gd = columns(G, dep_q), Ad = columns(Av, dep_u);
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_q, cod_u;
  if (!dep_q.empty()) cod_q.compute(Gd);
  if (!dep_u.empty()) cod_u.compute(Ad);

  // One dual evaluation per state direction (A) and per input (B).
  Eigen::MatrixXd Z(nz, nz + nin);
  Eigen::VectorXd rates(nz);
  std::vector<Dual> yd(static_cast<std::size_t>(nq + nu)), ydot(static_cast<std::size_t>(nq + nu));
  Eigen::VectorXd rhs_v(nc), rhs_d(nc), hd(mh);
  for (int col = 0; col < nz + nin; ++col) {
    for (int i = 0; i < np; ++i) p[static_cast<std::size_t>(i)] = Dual(parameters[static_cast<std::size_t>(i)]);
    if (col >= nz) p[static_cast<std::size_t>(options.inputs[static_cast<std::size_t>(col - nz)])].d = 1;
    dynamics::set_parameters(m, ws, p.data());
    std::fill(dxi.begin(), dxi.end(), Dual(0));
    if (col < niq) dxi[static_cast<std::size_t>(ind_q[static_cast<std::size_t>(col)])].d = 1;
    // Dependent coordinates: first order of h(q) = 0.
    for (int k = 0; k < nu; ++k) u[static_cast<std::size_t>(k)] = Dual(y[static_cast<std::size_t>(nq + k)]);
    if (!dep_q.empty()) {
      chart.displace(m, y, dxi, q);
      position_constraints(m, ws, t, q, u, h);
      for (int r = 0; r < mh; ++r) hd[r] = h[static_cast<std::size_t>(r)].d;
      const Eigen::VectorXd dq = cod_q.solve(hd);
      for (std::size_t c = 0; c < dep_q.size(); ++c) dxi[static_cast<std::size_t>(dep_q[c])].d = -dq[static_cast<Eigen::Index>(c)];
    }
    chart.displace(m, y, dxi, q);
    // Dependent speeds: A u + a0 = 0 is linear in u, so one correction in duals is exact.
    if (col >= niq && col < nz) u[static_cast<std::size_t>(ind_u[static_cast<std::size_t>(col - niq)])].d = 1;
    if (!dep_u.empty()) {
      dynamics::evaluate_constraints(m, ws, Dual(t), q.data(), u.data());
      Eigen::MatrixXd Add(nc, static_cast<Eigen::Index>(dep_u.size()));
      for (int r = 0; r < nc; ++r) {
        rhs_v[r] = ws.velocity_residual[r].v;
        rhs_d[r] = ws.velocity_residual[r].d;
        for (std::size_t c = 0; c < dep_u.size(); ++c) Add(r, static_cast<Eigen::Index>(c)) = ws.constraint_matrix(r, dep_u[c]).d;
      }
      const Eigen::VectorXd xv = cod_u.solve(rhs_v);
      const Eigen::VectorXd xd = cod_u.solve(rhs_d - Add * xv);
      for (std::size_t c = 0; c < dep_u.size(); ++c) {
        Dual& uk = u[static_cast<std::size_t>(dep_u[c])];
        uk.v -= xv[static_cast<Eigen::Index>(c)];
        uk.d -= xd[static_cast<Eigen::Index>(c)];
      }
    }
    std::copy(q.begin(), q.end(), yd.begin());
    std::copy(u.begin(), u.end(), yd.begin() + nq);
    dynamics::RhsFailure failure = dynamics::RhsFailure::none;
    if (!dynamics::evaluate_rhs(m, ws, Dual(t), yd.data(), ydot.data(), {}, &failure))
      throw std::runtime_error(std::string("linearize: the accelerations cannot be computed at this state: ") +
                               dynamics::describe(failure));
    for (int i = 0; i < niq; ++i) {
      const std::size_t c = static_cast<std::size_t>(ind_q[static_cast<std::size_t>(i)]);
      Dual rate = u[c];
      if (chart.rotation[c] >= 0) {  // δθ̇ = ω + ½ δθ × ω
        const std::size_t r0 = static_cast<std::size_t>(chart.rotation[c]), a = c - r0;
        const std::size_t b = (a + 1) % 3, d = (a + 2) % 3;
        rate += 0.5 * (dxi[r0 + b] * u[r0 + d] - dxi[r0 + d] * u[r0 + b]);
      }
      Z(i, col) = rate.d;
      rates[i] = rate.v;
    }
    for (std::size_t j = 0; j < ind_u.size(); ++j) {
      const Dual& a = ydot[static_cast<std::size_t>(nq + ind_u[j])];
      Z(niq + static_cast<Eigen::Index>(j), col) = a.d;
      rates[niq + static_cast<Eigen::Index>(j)] = a.v;
    }
  }

  // Drop ignorable states: zero columns among the kept rows, repeatedly; named ones never.
  std::vector<unsigned char> kept(static_cast<std::size_t>(nz), 1), named(static_cast<std::size_t>(nz), 0);
  for (int i = 0; i < nz; ++i)
    named[static_cast<std::size_t>(i)] = i < niq ? keep_q[static_cast<std::size_t>(ind_q[static_cast<std::size_t>(i)])]
                                                 : keep_u[static_cast<std::size_t>(ind_u[static_cast<std::size_t>(i - niq)])];
  const double scale = nz > 0 ? Z.leftCols(nz).cwiseAbs().maxCoeff() : 0.0;
  for (bool changed = scale > 0; changed;) {
    changed = false;
    for (int k = 0; k < nz; ++k) {
      if (!kept[static_cast<std::size_t>(k)] || named[static_cast<std::size_t>(k)]) continue;
      double col_max = 0;
      for (int r = 0; r < nz; ++r)
        if (kept[static_cast<std::size_t>(r)]) col_max = std::max(col_max, std::abs(Z(r, k)));
      if (col_max <= options.ignorable_tolerance * scale) {
        kept[static_cast<std::size_t>(k)] = 0;
        changed = true;
      }
    }
  }
  auto name_of = [&](int k) { return k < niq ? chart.names[static_cast<std::size_t>(ind_q[static_cast<std::size_t>(k)])]
                                             : m.speed_names[static_cast<std::size_t>(ind_u[static_cast<std::size_t>(k - niq)])]; };
  for (int k = 0; k < nz; ++k) {
    if (kept[static_cast<std::size_t>(k)] && !named[static_cast<std::size_t>(k)] &&
        (k < niq ? !named_q.empty() : !named_u.empty()))
      throw InputError({}, k < niq ? "--coordinates" : "--speeds",
                       "'" + name_of(k) + "' is independent and not ignorable at this state (the dynamics depend on it); name it too");
    if (!kept[static_cast<std::size_t>(k)]) lin.dropped.push_back(name_of(k));
  }
  // The kept states: named ones in the order named, the others in chart / speed order.
  std::vector<int> order;
  auto position = [&](int chart_index, bool coordinate) {
    if (coordinate) return static_cast<int>(std::find(ind_q.begin(), ind_q.end(), chart_index) - ind_q.begin());
    return niq + static_cast<int>(std::find(ind_u.begin(), ind_u.end(), chart_index) - ind_u.begin());
  };
  if (!named_q.empty()) for (int c : named_q) order.push_back(position(c, true));
  else for (int k = 0; k < niq; ++k) if (kept[static_cast<std::size_t>(k)]) order.push_back(k);
  const std::size_t ncoord = order.size();
  if (!named_u.empty()) for (int c : named_u) order.push_back(position(c, false));
  else for (int k = niq; k < nz; ++k) if (kept[static_cast<std::size_t>(k)]) order.push_back(k);

  const Eigen::Index n = static_cast<Eigen::Index>(order.size());
  lin.A.resize(n, n);
  lin.B.resize(n, nin);
  lin.rates.resize(n);
  for (Eigen::Index r = 0; r < n; ++r) {
    const int zr = order[static_cast<std::size_t>(r)];
    for (Eigen::Index c = 0; c < n; ++c) lin.A(r, c) = Z(zr, order[static_cast<std::size_t>(c)]);
    for (int c = 0; c < nin; ++c) lin.B(r, c) = Z(zr, nz + c);
    lin.rates[r] = rates[zr];
    (static_cast<std::size_t>(r) < ncoord ? lin.coordinates : lin.speeds).push_back(name_of(zr));
  }
  for (int k : dep_q) lin.dependent_coordinates.push_back(chart.names[static_cast<std::size_t>(k)]);
  for (int k : dep_u) lin.dependent_speeds.push_back(m.speed_names[static_cast<std::size_t>(k)]);
  return lin;
}

}  // namespace kanesens::sim
