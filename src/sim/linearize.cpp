#include "sim/linearize.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dynamics/equations.hpp"
#include "math/dual2.hpp"
#include "sim/holonomic.hpp"
#include "util/did_you_mean.hpp"
#include "util/error.hpp"

namespace kanesens::sim {
namespace {

using dynamics::Workspace;
using math::Dual;
using math::DualT;
using math::value_of;
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
  template <class S>
  void displace(const Model& m, const std::vector<S>& y, const std::vector<DualT<S>>& dxi,
                std::vector<DualT<S>>& q) const {
    using D = DualT<S>;
    for (int i = 0; i < m.nq; ++i) q[static_cast<std::size_t>(i)] = D(y[static_cast<std::size_t>(i)]);
    for (int c = 0; c < m.nu; ++c) {
      const std::size_t k = static_cast<std::size_t>(c);
      if (coordinate[k] >= 0) q[static_cast<std::size_t>(coordinate[k])] += dxi[k];
      if (rotation[k] != c) continue;
      const std::size_t w = static_cast<std::size_t>(quaternion[k]);
      const D e0(y[w]), e1(y[w + 1]), e2(y[w + 2]), e3(y[w + 3]);
      const D h1 = 0.5 * dxi[k], h2 = 0.5 * dxi[k + 1], h3 = 0.5 * dxi[k + 2];
      D r[4] = {e0 - e1 * h1 - e2 * h2 - e3 * h3, e0 * h1 + e1 + e2 * h3 - e3 * h2,
                   e0 * h2 - e1 * h3 + e2 + e3 * h1, e0 * h3 + e1 * h2 - e2 * h1 + e3};
      const D n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
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
template <class D>
void position_constraints(const Model& m, Workspace<D>& ws, double t, const std::vector<D>& q,
                          const std::vector<D>& u, std::vector<D>& h) {
  dynamics::evaluate_constraints(m, ws, D(t), q.data(), u.data());
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

template <class M>
M columns(const M& J, const std::vector<int>& cols) {
  M Jc(J.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c) Jc.col(static_cast<Eigen::Index>(c)) = J.col(cols[c]);
  return Jc;
}

template <class S>
using MatS = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using VecS = Eigen::Matrix<S, Eigen::Dynamic, 1>;

Eigen::MatrixXd values_of(const Eigen::MatrixXd& M) { return M; }
Eigen::MatrixXd values_of(const MatS<Dual>& M) { return M.unaryExpr([](const Dual& x) { return x.v; }); }

// x = M⁺ b with the decomposition of M's values; on duals, the tangent of the solution
// (M ẋ = ḃ − Ṁ x), exact where M has full column rank (the dependent columns are chosen so).
Eigen::VectorXd solve_with(const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>& cod, const Eigen::MatrixXd&,
                           const Eigen::VectorXd& b) {
  return cod.solve(b);
}
VecS<Dual> solve_with(const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>& cod, const MatS<Dual>& M,
                      const VecS<Dual>& b) {
  const Eigen::VectorXd bv = b.unaryExpr([](const Dual& x) { return x.v; });
  const Eigen::VectorXd bd = b.unaryExpr([](const Dual& x) { return x.d; });
  const Eigen::MatrixXd Md = M.unaryExpr([](const Dual& x) { return x.d; });
  const Eigen::VectorXd xv = cod.solve(bv);
  const Eigen::VectorXd xd = cod.solve(bd - Md * xv);
  VecS<Dual> x(xv.size());
  for (Eigen::Index i = 0; i < xv.size(); ++i) x[i] = Dual(xv[i], xd[i]);
  return x;
}

// The independent states' rates and their derivatives before ignorable ones are dropped: Z
// (nz × (nz + inputs)) on the outer scalar S (double, or Dual for ∂Z along one outer direction).
template <class S>
struct Reduced {
  std::vector<int> dep_q, dep_u, ind_q, ind_u, named_q, named_u;
  std::vector<unsigned char> keep_q, keep_u;
  MatS<S> Z;
  Eigen::VectorXd rates;
  double position_residual = 0, velocity_residual = 0;
};

template <class S>
Reduced<S> reduce(const Model& m, const Chart& chart, const std::vector<S>& parameters, double t,
                  const std::vector<S>& y, const LinearizeOptions& options) {
  using D = DualT<S>;
  const int nq = m.nq, nu = m.nu, nc = m.nconstraint_rows, np = m.nparam();
  const std::size_t unu = static_cast<std::size_t>(nu);
  Workspace<D> ws(m);
  std::vector<D> p(parameters.begin(), parameters.end());
  dynamics::set_parameters(m, ws, p.data());
  Reduced<S> out;

  // The state as duals without tangent, and the constraint Jacobians at it.
  const int mh = count_position_constraints(m);
  std::vector<D> q(static_cast<std::size_t>(nq)), u(unu), dxi(unu, D(0)), h(static_cast<std::size_t>(mh));
  for (int k = 0; k < nu; ++k) u[static_cast<std::size_t>(k)] = D(y[static_cast<std::size_t>(nq + k)]);
  MatS<S> G(mh, nu), Av(nc, nu);
  for (int c = 0; c < nu; ++c) {
    dxi[static_cast<std::size_t>(c)].d = S(1);
    chart.displace(m, y, dxi, q);
    position_constraints(m, ws, t, q, u, h);
    for (int r = 0; r < mh; ++r) G(r, c) = h[static_cast<std::size_t>(r)].d;
    dxi[static_cast<std::size_t>(c)].d = S(0);
  }
  for (int r = 0; r < mh; ++r)
    out.position_residual = std::max(out.position_residual, std::abs(value_of(h[static_cast<std::size_t>(r)])));
  for (int r = 0; r < nc; ++r) {
    out.velocity_residual = std::max(out.velocity_residual, std::abs(value_of(ws.velocity_residual[r])));
    for (int k = 0; k < nu; ++k) Av(r, k) = ws.constraint_matrix(r, k).v;
  }
  const Eigen::MatrixXd Gv = values_of(G), Avv = values_of(Av);

  // Dependent coordinates and speeds (the named ones never), chosen on the values.
  out.named_q = find_names(options.coordinates, chart.names, "--coordinates");
  out.named_u = find_names(options.speeds, m.speed_names, "--speeds");
  out.keep_q = flags(out.named_q, nu);
  out.keep_u = flags(out.named_u, nu);
  std::vector<int>& dep_q = out.dep_q;
  std::vector<int>& dep_u = out.dep_u;
  if (mh > 0) {
    dep_q = choose_dependent_columns(Gv, dependent_order(chart, {}, out.keep_q));
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Gv);
    qr.setThreshold(1e-10);
    if (static_cast<Eigen::Index>(dep_q.size()) < qr.rank())
      throw InputError({}, "--coordinates", "the position constraints cannot be solved for the coordinates not named");
  }
  if (nc > 0) {
    // The speeds of dependent coordinates are dependent first.
    dep_u = choose_dependent_columns(Avv, dependent_order(chart, flags(dep_q, nu), out.keep_u));
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Avv);
    qr.setThreshold(1e-10);
    if (static_cast<Eigen::Index>(dep_u.size()) < qr.rank())
      throw InputError({}, "--speeds", "the velocity constraints cannot be solved for the speeds not named");
  }
  const std::vector<unsigned char> is_dep_q = flags(dep_q, nu), is_dep_u = flags(dep_u, nu);
  for (int k = 0; k < nu; ++k) {
    if (!is_dep_q[static_cast<std::size_t>(k)]) out.ind_q.push_back(k);
    if (!is_dep_u[static_cast<std::size_t>(k)]) out.ind_u.push_back(k);
  }
  const std::vector<int>& ind_q = out.ind_q;
  const std::vector<int>& ind_u = out.ind_u;
  const int niq = static_cast<int>(ind_q.size()), nz = niq + static_cast<int>(ind_u.size());
  const int nin = static_cast<int>(options.inputs.size());
  const MatS<S> Gd = columns(G, dep_q), Ad = columns(Av, dep_u);
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_q, cod_u;
  if (!dep_q.empty()) cod_q.compute(values_of(Gd));
  if (!dep_u.empty()) cod_u.compute(values_of(Ad));

  // One dual evaluation per state direction (A) and per input (B).
  MatS<S>& Z = out.Z;
  Z.resize(nz, nz + nin);
  out.rates.resize(nz);
  std::vector<D> yd(static_cast<std::size_t>(nq + nu)), ydot(static_cast<std::size_t>(nq + nu));
  VecS<S> rhs_v(nc), rhs_d(nc), hd(mh);
  for (int col = 0; col < nz + nin; ++col) {
    for (int i = 0; i < np; ++i) p[static_cast<std::size_t>(i)] = D(parameters[static_cast<std::size_t>(i)]);
    if (col >= nz) p[static_cast<std::size_t>(options.inputs[static_cast<std::size_t>(col - nz)])].d = S(1);
    dynamics::set_parameters(m, ws, p.data());
    std::fill(dxi.begin(), dxi.end(), D(0));
    if (col < niq) dxi[static_cast<std::size_t>(ind_q[static_cast<std::size_t>(col)])].d = S(1);
    // Dependent coordinates: first order of h(q) = 0.
    for (int k = 0; k < nu; ++k) u[static_cast<std::size_t>(k)] = D(y[static_cast<std::size_t>(nq + k)]);
    if (!dep_q.empty()) {
      chart.displace(m, y, dxi, q);
      position_constraints(m, ws, t, q, u, h);
      for (int r = 0; r < mh; ++r) hd[r] = h[static_cast<std::size_t>(r)].d;
      const VecS<S> dq = solve_with(cod_q, Gd, hd);
      for (std::size_t c = 0; c < dep_q.size(); ++c) dxi[static_cast<std::size_t>(dep_q[c])].d = -dq[static_cast<Eigen::Index>(c)];
    }
    chart.displace(m, y, dxi, q);
    // Dependent speeds: A u + a0 = 0 is linear in u, so one correction in duals is exact.
    if (col >= niq && col < nz) u[static_cast<std::size_t>(ind_u[static_cast<std::size_t>(col - niq)])].d = S(1);
    if (!dep_u.empty()) {
      dynamics::evaluate_constraints(m, ws, D(t), q.data(), u.data());
      MatS<S> Add(nc, static_cast<Eigen::Index>(dep_u.size()));
      for (int r = 0; r < nc; ++r) {
        rhs_v[r] = ws.velocity_residual[r].v;
        rhs_d[r] = ws.velocity_residual[r].d;
        for (std::size_t c = 0; c < dep_u.size(); ++c) Add(r, static_cast<Eigen::Index>(c)) = ws.constraint_matrix(r, dep_u[c]).d;
      }
      const VecS<S> xv = solve_with(cod_u, Ad, rhs_v);
      const VecS<S> xd = solve_with(cod_u, Ad, VecS<S>(rhs_d - Add * xv));
      for (std::size_t c = 0; c < dep_u.size(); ++c) {
        D& uk = u[static_cast<std::size_t>(dep_u[c])];
        uk.v -= xv[static_cast<Eigen::Index>(c)];
        uk.d -= xd[static_cast<Eigen::Index>(c)];
      }
    }
    std::copy(q.begin(), q.end(), yd.begin());
    std::copy(u.begin(), u.end(), yd.begin() + nq);
    dynamics::RhsFailure failure = dynamics::RhsFailure::none;
    if (!dynamics::evaluate_rhs(m, ws, D(t), yd.data(), ydot.data(), {}, &failure))
      throw std::runtime_error(std::string("linearize: the accelerations cannot be computed at this state: ") +
                               dynamics::describe(failure));
    for (int i = 0; i < niq; ++i) {
      const std::size_t c = static_cast<std::size_t>(ind_q[static_cast<std::size_t>(i)]);
      D rate = u[c];
      if (chart.rotation[c] >= 0) {  // δθ̇ = ω + ½ δθ × ω
        const std::size_t r0 = static_cast<std::size_t>(chart.rotation[c]), a = c - r0;
        const std::size_t b = (a + 1) % 3, d = (a + 2) % 3;
        rate += 0.5 * (dxi[r0 + b] * u[r0 + d] - dxi[r0 + d] * u[r0 + b]);
      }
      Z(i, col) = rate.d;
      out.rates[i] = value_of(rate);
    }
    for (std::size_t j = 0; j < ind_u.size(); ++j) {
      const D& a = ydot[static_cast<std::size_t>(nq + ind_u[j])];
      Z(niq + static_cast<Eigen::Index>(j), col) = a.d;
      out.rates[niq + static_cast<Eigen::Index>(j)] = value_of(a);
    }
  }
  return out;
}

// Drops the ignorable states of r (from Z's values) and fills lin; returns the kept states'
// indices in Z, in the order of lin's coordinates then speeds.
std::vector<int> assemble(const Model& m, const Chart& chart, const Reduced<double>& r, const LinearizeOptions& options,
                          Linearization& lin) {
  const std::vector<int>& ind_q = r.ind_q;
  const std::vector<int>& ind_u = r.ind_u;
  const Eigen::MatrixXd& Z = r.Z;
  const int niq = static_cast<int>(ind_q.size()), nz = niq + static_cast<int>(ind_u.size());
  const int nin = static_cast<int>(options.inputs.size());
  lin.position_residual = r.position_residual;
  lin.velocity_residual = r.velocity_residual;

  // Drop ignorable states: zero columns among the kept rows, repeatedly; named ones never.
  std::vector<unsigned char> kept(static_cast<std::size_t>(nz), 1), named(static_cast<std::size_t>(nz), 0);
  for (int i = 0; i < nz; ++i)
    named[static_cast<std::size_t>(i)] = i < niq ? r.keep_q[static_cast<std::size_t>(ind_q[static_cast<std::size_t>(i)])]
                                                 : r.keep_u[static_cast<std::size_t>(ind_u[static_cast<std::size_t>(i - niq)])];
  const double scale = nz > 0 ? Z.leftCols(nz).cwiseAbs().maxCoeff() : 0.0;
  for (bool changed = scale > 0; changed;) {
    changed = false;
    for (int k = 0; k < nz; ++k) {
      if (!kept[static_cast<std::size_t>(k)] || named[static_cast<std::size_t>(k)]) continue;
      double col_max = 0;
      for (int row = 0; row < nz; ++row)
        if (kept[static_cast<std::size_t>(row)]) col_max = std::max(col_max, std::abs(Z(row, k)));
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
        (k < niq ? !r.named_q.empty() : !r.named_u.empty()))
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
  if (!r.named_q.empty()) for (int c : r.named_q) order.push_back(position(c, true));
  else for (int k = 0; k < niq; ++k) if (kept[static_cast<std::size_t>(k)]) order.push_back(k);
  const std::size_t ncoord = order.size();
  if (!r.named_u.empty()) for (int c : r.named_u) order.push_back(position(c, false));
  else for (int k = niq; k < nz; ++k) if (kept[static_cast<std::size_t>(k)]) order.push_back(k);

  const Eigen::Index n = static_cast<Eigen::Index>(order.size());
  lin.A.resize(n, n);
  lin.B.resize(n, nin);
  lin.rates.resize(n);
  for (Eigen::Index row = 0; row < n; ++row) {
    const int zr = order[static_cast<std::size_t>(row)];
    for (Eigen::Index c = 0; c < n; ++c) lin.A(row, c) = Z(zr, order[static_cast<std::size_t>(c)]);
    for (int c = 0; c < nin; ++c) lin.B(row, c) = Z(zr, nz + c);
    lin.rates[row] = r.rates[zr];
    (static_cast<std::size_t>(row) < ncoord ? lin.coordinates : lin.speeds).push_back(name_of(zr));
  }
  for (int k : r.dep_q) lin.dependent_coordinates.push_back(chart.names[static_cast<std::size_t>(k)]);
  for (int k : r.dep_u) lin.dependent_speeds.push_back(m.speed_names[static_cast<std::size_t>(k)]);
  return order;
}

}  // namespace

std::vector<std::string> chart_coordinate_names(const Model& model) { return Chart(model).names; }

Linearization linearize(const Model& m, const std::vector<double>& parameters, double t, const std::vector<double>& y,
                        const LinearizeOptions& options) {
  const Chart chart(m);
  Linearization lin;
  assemble(m, chart, reduce<double>(m, chart, parameters, t, y, options), options, lin);
  return lin;
}

Linearization linearize(const Model& m, const std::vector<double>& parameters, double t, const std::vector<double>& y,
                        const LinearizeOptions& options, const std::vector<LinearizeDirection>& directions,
                        std::vector<Eigen::MatrixXd>& dA) {
  const Chart chart(m);
  Linearization lin;
  const Reduced<double> base = reduce<double>(m, chart, parameters, t, y, options);
  const std::vector<int> order = assemble(m, chart, base, options, lin);
  const Eigen::Index n = static_cast<Eigen::Index>(order.size());
  dA.assign(directions.size(), Eigen::MatrixXd(n, n));
  const std::size_t np = parameters.size(), ny = y.size();
  std::vector<Dual> pd(np), yd(ny);
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const LinearizeDirection& dir = directions[i];
    if (dir.parameters.size() != np || dir.state.size() != ny)
      throw std::invalid_argument("linearize: a direction needs one tangent per parameter and per state");
    for (std::size_t k = 0; k < np; ++k) pd[k] = Dual(parameters[k], dir.parameters[k]);
    for (std::size_t k = 0; k < ny; ++k) yd[k] = Dual(y[k], dir.state[k]);
    const Reduced<Dual> r = reduce<Dual>(m, chart, pd, t, yd, options);
    // The same dependent sets as at the state itself (chosen on the values, which are the same).
    if (r.dep_q != base.dep_q || r.dep_u != base.dep_u)
      throw std::runtime_error("linearize: the dependent coordinates changed along a derivative direction");
    for (Eigen::Index row = 0; row < n; ++row)
      for (Eigen::Index c = 0; c < n; ++c)
        dA[i](row, c) = r.Z(order[static_cast<std::size_t>(row)], order[static_cast<std::size_t>(c)]).d;
  }
  return lin;
}

}  // namespace kanesens::sim
