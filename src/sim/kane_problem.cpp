#include "sim/kane_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kane/equations.hpp"
#include "model/build_model.hpp"
#include "sim/initial_checks.hpp"
#include "util/error.hpp"

namespace kanesens {

KaneProblem::KaneProblem(const Model& model, std::vector<InputRef> sensitivities, ConstraintOptions constraints)
    : options_(constraints),
      model_(model),
      sens_(std::move(sensitivities)),
      inputs_(model),
      ws_(model),
      ws_jacobian_(model),
      ws_sens_(sens_.size()),
      parameters_(model.nparam()),
      dq_parameters_(model.nparam() + sens_.size()),
      y_dual_(model.nstate()),
      ydot_dual_(model.nstate()) {
  for (std::size_t i = 0; i < sens_.size(); ++i)
    if (sens_[i].kind == InputRef::Kind::parameter) ws_sens_[i] = std::make_unique<Workspace<Dual>>(model);
  for (const Constraint& c : model.constraints)
    for (int r = 0; r < c.nrows; ++r)
      if (c.holonomic[r]) holonomic_rows_.push_back(c.row_offset + r);
  if (model.nconstraint_rows > 0) ws_project_ = std::make_unique<Workspace<Dual>>(model);
  identity_kinematics_ = std::all_of(model.joints.begin(), model.joints.end(),
                                     [](const Joint& j) { return j.quaternion_offset < 0; });
  projection_.zero_u = Eigen::VectorXd::Zero(model.nu);
  projection_.g.resize(static_cast<Eigen::Index>(holonomic_rows_.size()));
  projection_.G.resize(static_cast<Eigen::Index>(holonomic_rows_.size()), model.nq);
  embedded_ = model.nconstraint_rows > 0 && options_.formulation == ConstraintOptions::Formulation::embedding;
  if (options_.stabilization == ConstraintOptions::Stabilization::baumgarte) {
    // The same Baumgarte terms in every workspace, so Jacobian and sensitivities differentiate
    // the equations that are integrated.
    auto set = [&](auto& ws) {
      ws.baumgarte_alpha = options_.alpha;
      ws.baumgarte_beta = options_.beta;
    };
    set(ws_);
    set(ws_jacobian_);
    for (auto& w : ws_sens_)
      if (w) set(*w);
  }
  set_sample(inputs_);
}

void KaneProblem::set_sample(const SampleInputs& inputs) {
  const std::string why = check_parameters(model_, inputs.parameters.data());
  if (!why.empty()) throw InputError({}, "parameters", why);
  inputs_ = inputs;
  parameters_ = inputs.parameters;
  set_parameters(model_, ws_, parameters_.data());
  std::vector<Dual> p(parameters_.begin(), parameters_.end());
  set_parameters(model_, ws_jacobian_, p.data());
  for (std::size_t i = 0; i < sens_.size(); ++i) {
    if (!ws_sens_[i]) continue;
    p[sens_[i].index].d = 1;
    set_parameters(model_, *ws_sens_[i], p.data());
    p[sens_[i].index].d = 0;
  }
  if (ws_project_) set_parameters(model_, *ws_project_, std::vector<Dual>(parameters_.begin(), parameters_.end()).data());
  if (embedded_) {
    // Independent speeds from A at the (consistent) initial state.
    std::vector<double> y0(static_cast<std::size_t>(model_.nstate()));
    initial_state_full(y0.data());
    std::vector<double> zero(static_cast<std::size_t>(model_.nu), 0.0);
    evaluate_state_expressions(model_, ws_, initial_time_, y0.data(), zero.data());
    compute_position(model_, ws_, y0.data());
    compute_velocity(model_, ws_, zero.data());
    compute_kinematic_derivatives(model_, ws_, y0.data(), zero.data());
    compute_constraints(model_, ws_, y0.data(), zero.data());
    sets_ = choose_embedding(ws_.constraint_matrix);
    sc_ = std::make_unique<EmbeddingScratch<double>>(model_, sets_);
    sc_dual_ = std::make_unique<EmbeddingScratch<Dual>>(model_, sets_);
  }
  std::copy(parameters_.begin(), parameters_.end(), dq_parameters_.begin());
  for (std::size_t i = 0; i < sens_.size(); ++i)
    dq_parameters_[model_.nparam() + i] = sens_[i].kind == InputRef::Kind::parameter ? 0.0 : 1.0;
}

void KaneProblem::set_initial_time(double t0) {
  initial_time_ = t0;
  set_sample(inputs_);  // the embedding's sets depend on t0
}

// y0 as duals: tangent of sensitivity i (i < 0: no tangent).
void KaneProblem::initial_state_dual(int i, std::vector<Dual>& y0) const {
  const bool param = i >= 0 && sens_[i].kind == InputRef::Kind::parameter;
  const Workspace<Dual>& ws = param ? *ws_sens_[i] : ws_jacobian_;
  int k = 0;
  for (const Joint& j : model_.joints)
    for (Slot s : j.q0) y0[k++] = ws.values[s];
  for (const Joint& j : model_.joints)
    for (Slot s : j.u0) y0[k++] = ws.values[s];
  for (int s = 0; s < model_.nstate(); ++s)
    if (inputs_.initial_set[s]) y0[s] = Dual(inputs_.initial_values[s], 0);
  if (i >= 0 && sens_[i].kind == InputRef::Kind::initial_condition) y0[sens_[i].index].d = 1;
  for (std::size_t ji = 0; ji < model_.joints.size(); ++ji) {
    const Joint& j = model_.joints[ji];
    if (j.quaternion_offset < 0) continue;
    Dual* e = y0.data() + j.quaternion_offset;
    const JointSpec& js = model_.spec.joints[ji];
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
  if (model_.nconstraint_rows > 0 && options_.correct_initial) make_consistent(y0, ws);
}

void KaneProblem::position_constraints(double t, const double* q, Eigen::VectorXd& g, Eigen::MatrixXd* G) const {
  const int nq = model_.nq, nu = model_.nu, mh = static_cast<int>(holonomic_rows_.size());
  Workspace<Dual>& ws = *ws_project_;
  std::vector<Dual> qd(q, q + nq), ud(nu, Dual(0));
  g.resize(mh);
  if (G) G->resize(mh, nq);
  const int columns = G ? nq : 1;
  for (int i = 0; i < columns; ++i) {
    if (G) qd[i].d = 1;
    evaluate_state_expressions(model_, ws, Dual(t), qd.data(), ud.data());
    compute_position(model_, ws, qd.data());
    compute_velocity(model_, ws, ud.data());
    compute_kinematic_derivatives(model_, ws, qd.data(), ud.data());
    compute_constraints(model_, ws, qd.data(), ud.data());
    for (int r = 0; r < mh; ++r) {
      g[r] = ws.position_residual[holonomic_rows_[r]].v;
      if (G) (*G)(r, i) = ws.position_residual[holonomic_rows_[r]].d;
    }
    if (G) qd[i].d = 0;
  }
}

// Dependent columns of J (rank(J) of them), tried in the order `order`: a column is taken if it
// is not negligible against J's largest column and raises the rank of those taken.
static std::vector<int> choose_dependent(const Eigen::MatrixXd& J, const std::vector<int>& order) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> full(J);
  full.setThreshold(1e-10);
  const Eigen::Index rank = full.rank();
  const double scale = J.colwise().norm().maxCoeff();
  std::vector<int> dep;
  for (std::size_t o = 0; o < order.size() && static_cast<Eigen::Index>(dep.size()) < rank; ++o) {
    const int i = order[o];
    if (!(J.col(i).norm() > 1e-10 * scale)) continue;
    std::vector<int> trial = dep;
    trial.push_back(i);
    Eigen::MatrixXd Jd(J.rows(), static_cast<Eigen::Index>(trial.size()));
    for (std::size_t c = 0; c < trial.size(); ++c) Jd.col(static_cast<Eigen::Index>(c)) = J.col(trial[c]);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jd);
    qr.setThreshold(1e-10);
    if (qr.rank() == static_cast<Eigen::Index>(trial.size())) dep = trial;
  }
  return dep;
}

// Corrects y0 onto the constraints, in dual arithmetic so the initial sensitivities are those of
// the corrected state: positions by Newton on the dependent coordinates (chosen from the last
// coordinate backwards, so the first ones — the user's driving coordinates — are kept;
// quaternion components are never moved), speeds likewise on dependent speeds chosen from the
// last backwards (the first, driving speeds are kept).
void KaneProblem::make_consistent(std::vector<Dual>& y0, const Workspace<Dual>& ws_params) const {
  const int nq = model_.nq, nu = model_.nu, mh = static_cast<int>(holonomic_rows_.size());
  Workspace<Dual> ws = ws_params;
  Dual* q = y0.data();
  Dual* u = y0.data() + nq;
  std::vector<double> qv(nq);
  auto values = [&] { for (int i = 0; i < nq; ++i) qv[i] = q[i].v; };
  const double t0 = initial_time_;
  double dq_max = 0, du_max = 0;
  // Which initial values the user gave: 0 not given, 1 in the scene's q0/u0, 2 set for this
  // sample or a sensitivity parameter. Dependents are tried in that order (lowest first), each
  // tier from the last value backwards, so given values — and the first, driving coordinates
  // and speeds — are kept when others can absorb the correction.
  std::vector<unsigned char> given(static_cast<std::size_t>(model_.nstate()), 0);
  for (std::size_t j = 0; j < model_.joints.size(); ++j) {
    const Joint& J = model_.joints[j];
    const JointSpec& js = model_.spec.joints[j];
    for (int k = 0; k < J.nq; ++k) given[static_cast<std::size_t>(J.q_offset + k)] = !js.q0.empty();
    for (int k = 0; k < J.nu; ++k) given[static_cast<std::size_t>(nq + J.u_offset + k)] = !js.u0.empty();
  }
  // Values set for this sample (--set, vary) or differentiated with respect to rank above the
  // scene's: they are what the user is asking about.
  for (int s = 0; s < model_.nstate(); ++s)
    if (inputs_.initial_set[static_cast<std::size_t>(s)]) given[static_cast<std::size_t>(s)] = 2;
  for (const InputRef& r : sens_)
    if (r.kind == InputRef::Kind::initial_condition) given[static_cast<std::size_t>(r.index)] = 2;
  // A constraint that constrains nothing here (or is not finite) has no dependent coordinate
  // to correct: name it instead of decomposing an empty matrix.
  {
    std::vector<Dual> ud(u, u + nu);
    evaluate_state_expressions(model_, ws, Dual(t0), q, ud.data());
    compute_position(model_, ws, q);
    compute_velocity(model_, ws, ud.data());
    compute_kinematic_derivatives(model_, ws, q, ud.data());
    compute_constraints(model_, ws, q, ud.data());
    check_constraint_rows(model_, ws, t0);
  }
  auto dependent_order = [&](int offset, int count, const std::vector<int>& excluded) {
    std::vector<int> order;
    for (int pass = 0; pass < 3; ++pass)
      for (int i = count - 1; i >= 0; --i)
        if (!excluded[static_cast<std::size_t>(i)] && given[static_cast<std::size_t>(offset + i)] == pass) order.push_back(i);
    return order;
  };
  if (mh > 0) {
    Eigen::VectorXd g;
    Eigen::MatrixXd G;
    values();
    position_constraints(t0, qv.data(), g, &G);
    std::vector<int> quaternion(nq, 0);
    for (const Joint& J : model_.joints)
      if (J.quaternion_offset >= 0)
        for (int c = 0; c < 4; ++c) quaternion[J.quaternion_offset + c] = 1;
    const std::vector<int> dep = choose_dependent(G, dependent_order(0, nq, quaternion));
    std::vector<Dual> gd(mh);
    for (int iter = 0, converged = 0; iter < 50 && converged < 2; ++iter) {
      // Residual in duals (carries the parameter and initial-condition tangents).
      std::vector<Dual> ud(nu, Dual(0));
      evaluate_state_expressions(model_, ws, Dual(t0), q, ud.data());
      compute_position(model_, ws, q);
      compute_velocity(model_, ws, ud.data());
      compute_kinematic_derivatives(model_, ws, q, ud.data());
      compute_constraints(model_, ws, q, ud.data());
      double gmax = 0;
      for (int r = 0; r < mh; ++r) {
        gd[r] = ws.position_residual[holonomic_rows_[r]];
        gmax = std::max(gmax, std::abs(gd[r].v));
      }
      if (gmax < 1e-13) ++converged;  // one more step after convergence settles the tangents
      if (dep.empty()) {  // no coordinate moves the constraints: nothing to correct
        if (gmax < 1e-13) break;
        throw InputError(model_.spec.where, "scene.constraints",
                         "the position constraints are violated at t0 (residual " + std::to_string(gmax) +
                             ") and no coordinate changes them");
      }
      values();
      position_constraints(t0, qv.data(), g, &G);
      Eigen::MatrixXd Gd(mh, static_cast<Eigen::Index>(dep.size()));
      for (std::size_t c = 0; c < dep.size(); ++c) Gd.col(static_cast<Eigen::Index>(c)) = G.col(dep[c]);
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Gd);
      Eigen::VectorXd gv(mh), gt(mh);
      for (int r = 0; r < mh; ++r) {
        gv[r] = gd[r].v;
        gt[r] = gd[r].d;
      }
      const Eigen::VectorXd dv = cod.solve(gv), dt = cod.solve(gt);
      for (std::size_t c = 0; c < dep.size(); ++c) {
        q[dep[c]].v -= dv[static_cast<Eigen::Index>(c)];
        q[dep[c]].d -= dt[static_cast<Eigen::Index>(c)];
        dq_max = std::max(dq_max, std::abs(dv[static_cast<Eigen::Index>(c)]));
      }
      if (iter == 49)
        throw InputError(model_.spec.where, "scene.constraints",
                         "cannot satisfy the position constraints at t0 from the given initial coordinates (Newton did "
                         "not converge; residual " + std::to_string(gmax) + "): constraints that contradict each other, or "
                         "initial values too far from any assembly?");
    }
  }
  // Speeds: the velocity residual A u + a0 is linear in u. Dependent speeds are chosen like the
  // dependent coordinates, from the last speed backwards (any speed may be one, quaternion
  // joints' too), so the first speeds — the user's driving speeds — keep their given values.
  std::vector<int> dep_u;
  for (int iter = 0; iter < 3; ++iter) {
    evaluate_state_expressions(model_, ws, Dual(t0), q, u);
    compute_position(model_, ws, q);
    compute_velocity(model_, ws, u);
    compute_kinematic_derivatives(model_, ws, q, u);
    compute_constraints(model_, ws, q, u);
    const int m = model_.nconstraint_rows;
    Eigen::MatrixXd A(m, nu);
    Eigen::VectorXd rv(m), rt(m);
    for (int r = 0; r < m; ++r) {
      for (int k = 0; k < nu; ++k) A(r, k) = ws.constraint_matrix(r, k).v;
      rv[r] = ws.velocity_residual[r].v;
      rt[r] = ws.velocity_residual[r].d;
    }
    if (iter == 0) dep_u = choose_dependent(A, dependent_order(nq, nu, std::vector<int>(static_cast<std::size_t>(nu), 0)));
    if (dep_u.empty()) break;  // A vanishes (a redundant, all-zero system): nothing to correct
    Eigen::MatrixXd Ad(m, static_cast<Eigen::Index>(dep_u.size()));
    for (std::size_t c = 0; c < dep_u.size(); ++c) Ad.col(static_cast<Eigen::Index>(c)) = A.col(dep_u[c]);
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Ad);
    const Eigen::VectorXd dv = cod.solve(rv), dt = cod.solve(rt);
    for (std::size_t c = 0; c < dep_u.size(); ++c) {
      const int k = dep_u[c];
      u[k].v -= dv[static_cast<Eigen::Index>(c)];
      u[k].d -= dt[static_cast<Eigen::Index>(c)];
      du_max = std::max(du_max, std::abs(dv[static_cast<Eigen::Index>(c)]));
    }
  }
  initial_dq_ = dq_max;
  initial_du_ = du_max;
}

// Holonomic residual g and G = ∂g/∂q at q, on doubles. With q̇ = u for every joint (no
// quaternions), ġ = G q̇ = G u gives G = the holonomic rows of A, from one evaluation; with
// quaternions (q̇ = N(q) u, nq > nu) G comes from nq dual evaluations (position_constraints).
void KaneProblem::holonomic_residual(double t, const double* q, bool jacobian) {
  ProjectionScratch& s = projection_;
  const int mh = static_cast<int>(holonomic_rows_.size());
  if (!identity_kinematics_) {
    position_constraints(t, q, s.g, jacobian ? &s.G : nullptr);
    return;
  }
  evaluate_state_expressions(model_, ws_, t, q, s.zero_u.data());
  compute_position(model_, ws_, q);
  compute_velocity(model_, ws_, s.zero_u.data());
  compute_kinematic_derivatives(model_, ws_, q, s.zero_u.data());
  compute_constraints(model_, ws_, q, s.zero_u.data());
  for (int r = 0; r < mh; ++r) {
    s.g[r] = ws_.position_residual[holonomic_rows_[r]];
    if (jacobian) s.G.row(r) = ws_.constraint_matrix.row(holonomic_rows_[r]);
  }
}

// CVODES projection (cvsPendulum_dns.c): the nearest consistent state, positions by Newton on
// g(q) = 0 with minimum-norm steps, then speeds by the minimum-norm correction of A u + a0 = 0;
// the error estimate is projected onto the tangent space too. Runs after every step, so its
// storage is allocated once (ProjectionScratch) and G comes from A where it can.
int KaneProblem::project(double t, const double* y, double* corr, double, double* err) {
  const int nq = model_.nq, nu = model_.nu;
  const int mh = static_cast<int>(holonomic_rows_.size());
  ProjectionScratch& s = projection_;
  s.q = Eigen::Map<const Eigen::VectorXd>(y, nq);
  if (mh > 0) {
    holonomic_residual(t, s.q.data(), true);
    s.position.compute(s.G);
    for (int iter = 0; iter < 4 && s.g.lpNorm<Eigen::Infinity>() > 1e-14; ++iter) {
      s.position.solve(s.g, s.dq);
      s.q -= s.dq;
      holonomic_residual(t, s.q.data(), false);
    }
    if (!s.g.allFinite()) return 1;
  }
  for (int i = 0; i < nq; ++i) corr[i] = s.q[i] - y[i];
  if (embedded_) {
    // Velocities satisfy the constraints by construction; only positions drift.
    for (int k = nq; k < size(); ++k) corr[k] = 0;
    if (err && mh > 0) s.position.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err, nq));
    return 0;
  }
  evaluate_state_expressions(model_, ws_, t, s.q.data(), y + nq);
  compute_position(model_, ws_, s.q.data());
  compute_velocity(model_, ws_, y + nq);
  compute_kinematic_derivatives(model_, ws_, s.q.data(), y + nq);
  compute_constraints(model_, ws_, s.q.data(), y + nq);
  s.velocity.compute(ws_.constraint_matrix);
  s.velocity.solve(ws_.velocity_residual, s.du);
  for (int k = 0; k < nu; ++k) corr[nq + k] = -s.du[k];
  if (!s.du.allFinite()) return 1;
  if (err) {
    // e ← e − G⁺G e (positions), e_u ← e_u − A⁺A e_u (speeds).
    if (mh > 0) s.position.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err, nq));
    s.velocity.remove_normal_component(Eigen::Map<Eigen::VectorXd>(err + nq, nu));
  }
  return 0;
}

// The three below take the full state (nstate) and evaluate the multiplier form (also for the
// embedding, which gives the same λ on the constraint manifold).
void KaneProblem::multipliers(double t, const double* y, double* lambda) {
  std::vector<double> ydot(static_cast<std::size_t>(model_.nstate()));
  sync_dq_parameters();
  // Where λ cannot be determined it is recorded as NaN, never as a silent 0.
  const bool ok = evaluate_rhs(model_, ws_, t, y, ydot.data());
  for (int r = 0; r < model_.nconstraint_rows; ++r) lambda[r] = ok ? ws_.multipliers[r] : std::nan("");
}

void KaneProblem::multiplier_sensitivity(double t, const double* y, int i, const double* s, double* dlambda) {
  Workspace<Dual>& ws = dual_workspace(i);
  const int n = model_.nstate();
  std::vector<Dual> yd(static_cast<std::size_t>(n)), ydot(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) yd[static_cast<std::size_t>(r)] = Dual(y[r], s[r]);
  const bool ok = evaluate_rhs(model_, ws, Dual(t), yd.data(), ydot.data());
  for (int r = 0; r < model_.nconstraint_rows; ++r) dlambda[r] = ok ? ws.multipliers[r].d : std::nan("");
}

void KaneProblem::sensitivity_constraint_residuals(double t, const double* y, int i, const double* s,
                                                  double& position, double& velocity) {
  const int n = model_.nstate();
  Workspace<Dual>& ws = ws_sens_[i] ? *ws_sens_[i] : ws_jacobian_;
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  if (!evaluate_rhs(model_, ws, Dual(t), y_dual_.data(), ydot_dual_.data())) {
    position = velocity = std::nan("");
    return;
  }
  position = 0;
  velocity = 0;
  for (int r : holonomic_rows_) position = std::max(position, std::abs(ws.position_residual[r].d));
  for (int r = 0; r < model_.nconstraint_rows; ++r) velocity = std::max(velocity, std::abs(ws.velocity_residual[r].d));
}

void KaneProblem::project_sensitivity(double t, const double* y, int i, double* s) {
  const int nq = model_.nq, nu = model_.nu, n = model_.nstate(), m = model_.nconstraint_rows;
  const int mh = static_cast<int>(holonomic_rows_.size());
  if (m == 0) return;
  Workspace<Dual>& ws = ws_sens_[i] ? *ws_sens_[i] : ws_jacobian_;
  auto evaluate = [&] {
    for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
    evaluate_rhs(model_, ws, Dual(t), y_dual_.data(), ydot_dual_.data());
  };
  evaluate();
  if (mh > 0) {
    Eigen::VectorXd g, rt(mh);
    Eigen::MatrixXd G;
    position_constraints(t, y, g, &G);
    for (int r = 0; r < mh; ++r) rt[r] = ws.position_residual[holonomic_rows_[r]].d;
    const Eigen::VectorXd dq = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(G).solve(rt);
    for (int k = 0; k < nq; ++k) s[k] -= dq[k];
    evaluate();
  }
  Eigen::MatrixXd A(m, nu);
  Eigen::VectorXd rv(m);
  for (int r = 0; r < m; ++r) {
    for (int k = 0; k < nu; ++k) A(r, k) = ws.constraint_matrix(r, k).v;
    rv[r] = ws.velocity_residual[r].d;
  }
  const Eigen::VectorXd du = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(A).solve(rv);
  for (int k = 0; k < nu; ++k) s[nq + k] -= du[k];
}

void KaneProblem::constraint_residuals(double t, const double* y, double& position, double& velocity) {
  std::vector<double> ydot(static_cast<std::size_t>(model_.nstate()));
  sync_dq_parameters();
  if (!evaluate_rhs(model_, ws_, t, y, ydot.data())) {
    position = velocity = std::nan("");
    return;
  }
  position = 0;
  velocity = 0;
  for (int r : holonomic_rows_) position = std::max(position, std::abs(ws_.position_residual[r]));
  for (int r = 0; r < model_.nconstraint_rows; ++r) velocity = std::max(velocity, std::abs(ws_.velocity_residual[r]));
}

void KaneProblem::initial_state_full(double* y0) const {
  std::vector<Dual> y(model_.nstate());
  initial_state_dual(-1, y);
  for (int s = 0; s < model_.nstate(); ++s) y0[s] = y[s].v;
}

void KaneProblem::initial_state(double* y0) const {
  std::vector<Dual> y(model_.nstate());
  initial_state_dual(-1, y);
  for (int s = 0; s < model_.nq; ++s) y0[s] = y[s].v;
  if (!embedded_) {
    for (int s = model_.nq; s < model_.nstate(); ++s) y0[s] = y[s].v;
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c) y0[model_.nq + static_cast<int>(c)] = y[model_.nq + sets_.independent[c]].v;
}

void KaneProblem::initial_sensitivity(int i, double* s0) const {
  std::vector<Dual> y(model_.nstate());
  initial_state_dual(i, y);
  for (int s = 0; s < model_.nq; ++s) s0[s] = y[s].d;
  if (!embedded_) {
    for (int s = model_.nq; s < model_.nstate(); ++s) s0[s] = y[s].d;
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c) s0[model_.nq + static_cast<int>(c)] = y[model_.nq + sets_.independent[c]].d;
}

void KaneProblem::full_state(double t, const double* y, double* y_full) {
  const int nq = model_.nq;
  std::copy(y, y + nq, y_full);
  if (!embedded_) {
    std::copy(y + nq, y + model_.nstate(), y_full + nq);
    return;
  }
  sync_dq_parameters();
  if (!reconstruct_speeds(model_, ws_, *sc_, sets_, t, y, y + nq, y_full + nq))
    throw std::runtime_error("embedding: the dependent-speed matrix is singular at t = " + std::to_string(t));
}

void KaneProblem::full_sensitivity(double t, const double* y, int i, const double* s, double* s_full) {
  const int nq = model_.nq, n = size();
  std::copy(s, s + nq, s_full);
  if (!embedded_) {
    std::copy(s + nq, s + model_.nstate(), s_full + nq);
    return;
  }
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  std::vector<Dual> u(static_cast<std::size_t>(model_.nu));
  if (!reconstruct_speeds(model_, dual_workspace(i), *sc_dual_, sets_, Dual(t), y_dual_.data(), y_dual_.data() + nq, u.data()))
    throw std::runtime_error("embedding: the dependent-speed matrix is singular at t = " + std::to_string(t));
  for (int k = 0; k < model_.nu; ++k) s_full[nq + k] = u[static_cast<std::size_t>(k)].d;
}

void KaneProblem::sync_dq_parameters() {
  // CVODES's difference-quotient sensitivities perturb dq_parameters_ in place.
  for (int k = 0; k < model_.nparam(); ++k) {
    if (dq_parameters_[k] != parameters_[k]) {
      std::copy(dq_parameters_.begin(), dq_parameters_.begin() + model_.nparam(), parameters_.begin());
      set_parameters(model_, ws_, parameters_.data());
      return;
    }
  }
}

void KaneProblem::rhs(double t, const double* y, double* ydot) {
  sync_dq_parameters();
  if (embedded_) {
    if (!embedded_rhs(model_, ws_, *sc_, sets_, t, y, ydot))
      throw solve::RecoverableError("embedding: singular mass matrix or dependent-speed matrix");
    if (sc_->conditioning > 1e10)
      throw std::runtime_error("embedding: the independent speeds chosen at t0 no longer parameterise the motion at t = " +
                               std::to_string(t) + " (dependent-speed matrix conditioning " +
                               std::to_string(sc_->conditioning) + "); use formulation: multipliers");
    return;
  }
  RhsFailure why = RhsFailure::none;
  if (!evaluate_rhs(model_, ws_, t, y, ydot, &why)) throw solve::RecoverableError(describe(why));
}

void KaneProblem::jacobian(double t, const double* y, const double*, double* J) {
  const int n = size();
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], r == c ? 1.0 : 0.0);
    RhsFailure why = RhsFailure::mass_matrix_not_positive_definite;
    const bool ok = embedded_ ? embedded_rhs(model_, ws_jacobian_, *sc_dual_, sets_, Dual(t), y_dual_.data(), ydot_dual_.data())
                              : evaluate_rhs(model_, ws_jacobian_, Dual(t), y_dual_.data(), ydot_dual_.data(), &why);
    if (!ok) throw solve::RecoverableError(describe(why));
    for (int r = 0; r < n; ++r) J[r + c * n] = ydot_dual_[r].d;
  }
}

void KaneProblem::sensitivity_rhs(double t, const double* y, const double*, int i, const double* s,
                                  double* sdot) {
  const int n = size();
  Workspace<Dual>& ws = dual_workspace(i);
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  RhsFailure why = RhsFailure::mass_matrix_not_positive_definite;
  const bool ok = embedded_ ? embedded_rhs(model_, ws, *sc_dual_, sets_, Dual(t), y_dual_.data(), ydot_dual_.data())
                            : evaluate_rhs(model_, ws, Dual(t), y_dual_.data(), ydot_dual_.data(), &why);
  if (!ok) throw solve::RecoverableError(describe(why));
  for (int r = 0; r < n; ++r) sdot[r] = ydot_dual_[r].d;
}

std::vector<double> KaneProblem::sensitivity_scales() const {
  std::vector<double> scales;
  for (const auto& s : sens_) {
    double v = 1;
    if (s.kind == InputRef::Kind::parameter) v = std::abs(parameters_[s.index]);
    scales.push_back(v > 0 ? v : 1.0);
  }
  return scales;
}

std::vector<int> KaneProblem::dq_parameter_list() const {
  std::vector<int> plist;
  for (std::size_t i = 0; i < sens_.size(); ++i)
    plist.push_back(sens_[i].kind == InputRef::Kind::parameter ? sens_[i].index
                                                               : model_.nparam() + static_cast<int>(i));
  return plist;
}

double KaneProblem::energy(double t, const double* y) {
  const double* q = y;
  const double* u = y + model_.nq;
  evaluate_state_expressions(model_, ws_, t, q, u);
  compute_position(model_, ws_, q);
  compute_velocity(model_, ws_, u);
  return kinetic_energy(model_, ws_) + potential_energy(model_, ws_, q);
}

}  // namespace kanesens
