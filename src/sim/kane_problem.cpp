#include "sim/kane_problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "dynamics/equations.hpp"
#include "model/parameters.hpp"
#include "sim/outputs.hpp"

namespace kanesens::sim {

using dynamics::Workspace;
using math::Dual;

KaneProblem::KaneProblem(const model::Model& model, std::vector<InputRef> sensitivities, ConstraintOptions constraints,
                         double t0)
    : model_(model),
      sens_(std::move(sensitivities)),
      options_(constraints),
      t0_(t0),
      workspaces_(model, sens_),
      holonomic_(model),
      projector_(model, holonomic_),
      y_dual_(model.nstate()),
      ydot_dual_(model.nstate()),
      sensitivity_blocks_(model, static_cast<int>(sens_.size())),
      jacobian_values_(model),
      acceleration_tangents_(model),
      residual_value_(static_cast<std::size_t>(model.nu)),
      jacobian_multipliers_(static_cast<std::size_t>(model.nconstraint_rows)),
      fused_constraint_value_(static_cast<std::size_t>(model.nconstraint_rows)),
      value_out_(static_cast<std::size_t>(model.nstate())),
      value_constraint_(static_cast<std::size_t>(model.nconstraint_rows)),
      u_full_(static_cast<std::size_t>(model.nu)),
      s_full_(static_cast<std::size_t>(model.nstate())),
      recorded_rate_(static_cast<std::size_t>(model.nstate())) {
  embedded_ = model.nconstraint_rows > 0 && options_.formulation == ConstraintOptions::Formulation::embedding;
  if (!model.evaluate_planar()) sensitivity_method_ = DerivativeMethod::residual;
  value_rhs_ = !embedded_ && model.nconstraint_rows > 0 && !model.evaluate_planar() &&
               !workspaces_.values().sparse_constraints;
  if (dynamics::ResidualDerivatives::applies(model)) {
    const std::size_t nu = static_cast<std::size_t>(model.nu);
    closed_form_ = std::make_unique<dynamics::ResidualDerivatives>(model);
    closed_r_.resize(nu);
    closed_scale_.resize(nu);
    closed_dr_.resize(2 * nu * nu);
  }
  // J v's dual pass takes the recursion for joints of one speed only (dynamics/workspace.hpp).
  jacobian_times_cheap_ = !dynamics::uses_articulated_body(model, workspaces_.values()) ||
                          dynamics::uses_articulated_body(model, workspaces_.jacobian());
  if (options_.stabilization == ConstraintOptions::Stabilization::baumgarte) {
    dynamics_.baumgarte_alpha = options_.alpha;
    dynamics_.baumgarte_beta = options_.beta;
  }
  try {
    set_sample(SampleInputs(model));
  } catch (const InputError&) {
    // Kept in failure_: initial_state() reports it unless another sample is loaded.
  }
}

void KaneProblem::set_sample(const SampleInputs& inputs) {
  try {
    failure_.reset();
    value_rhs_failed_ = false;
    const std::string why = model::check_parameters(model_, inputs.parameters.data());
    if (!why.empty()) throw InputError({}, "parameters", why);
    workspaces_.set_parameters(inputs.parameters);
    dynamics::set_parameters(model_, jacobian_values_, inputs.parameters.data());
    holonomic_.set_parameters(inputs.parameters);
    initial_ = consistent_initial_state(model_, inputs, sens_, options_, t0_, workspaces_, holonomic_);
    if (embedded_) {
      // Independent speeds from A at the (consistent) initial state.
      Workspace<double>& ws = workspaces_.values();
      const std::vector<double> zero(static_cast<std::size_t>(model_.nu), 0.0);
      dynamics::evaluate_constraints(model_, ws, t0_, initial_.y.data(), zero.data());
      sets0_ = sets_ = dynamics::choose_embedding(ws.constraint_matrix);
      amplification0_ = amplification_ref_ = dynamics::embedding_amplification(ws.constraint_matrix, sets_);
      sc_ = std::make_unique<dynamics::EmbeddingScratch<double>>(model_, sets_);
      sc_dual_ = std::make_unique<dynamics::EmbeddingScratch<Dual>>(model_, sets_);
    }
    // Jacobian blocks cover size() columns, which the embedding's sets decide.
    if (jacobian_blocks_size_ != size()) {
      jacobian_blocks_ = TangentBlocks(model_, size());
      jacobian_blocks_size_ = size();
    }
    auto load = [&](auto& b, bool with_sensitivities) {
      using MD = typename std::decay_t<decltype(b)>::Scalar;
      std::vector<MD> p(inputs.parameters.begin(), inputs.parameters.end());
      if (with_sensitivities)
        for (int i = 0; i < b.count; ++i) {
          const InputRef& in = sens_[static_cast<std::size_t>(b.first + i)];
          if (in.kind == InputRef::Kind::parameter) p[static_cast<std::size_t>(in.index)].set_d(i, 1.0);
        }
      dynamics::set_parameters(model_, b.ws, p.data());
      b.embedding.reset();
      if (embedded_) b.embedding = std::make_unique<dynamics::EmbeddingScratch<MD>>(model_, sets_);
    };
    jacobian_blocks_.for_each([&](auto& b) { load(b, false); });
    sensitivity_blocks_.for_each([&](auto& b) { load(b, true); });
  } catch (const InputError& e) {
    failure_ = e;
    throw;
  }
}

void KaneProblem::check_initial_state() const {
  if (failure_) throw *failure_;
}

void KaneProblem::initial_state(double* y0) const {
  check_initial_state();
  sets_ = sets0_;
  amplification_ref_ = amplification0_;
  failure_cause_.clear();
  const int nq = model_.nq;
  std::copy(initial_.y.begin(), initial_.y.begin() + nq, y0);
  if (!embedded_) {
    std::copy(initial_.y.begin() + nq, initial_.y.end(), y0 + nq);
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c)
    y0[nq + static_cast<int>(c)] = initial_.y[static_cast<std::size_t>(nq + sets_.independent[c])];
}

void KaneProblem::initial_sensitivity(int i, double* s0) const {
  check_initial_state();
  const int nq = model_.nq;
  const dynamics::EmbeddingSets& sets_ = sets0_;
  const std::vector<double>& s = initial_.s[static_cast<std::size_t>(i)];
  std::copy(s.begin(), s.begin() + nq, s0);
  if (!embedded_) {
    std::copy(s.begin() + nq, s.end(), s0 + nq);
    return;
  }
  for (std::size_t c = 0; c < sets_.independent.size(); ++c)
    s0[nq + static_cast<int>(c)] = s[static_cast<std::size_t>(nq + sets_.independent[c])];
}

template <class S>
void KaneProblem::evaluate(Workspace<S>& ws, const S& t, const S* y, S* ydot) {
  if (!embedded_) {
    dynamics::RhsFailure why = dynamics::RhsFailure::none;
    if (!dynamics::evaluate_rhs(model_, ws, t, y, ydot, dynamics_, &why)) throw RecoverableError(dynamics::describe(why));
    return;
  }
  if constexpr (std::is_same_v<S, double>) {
    if (!dynamics::embedded_rhs(model_, ws, *sc_, sets_, t, y, ydot, dynamics_)) throw_embedding_failure(*sc_, t);
  } else {
    if (!dynamics::embedded_rhs(model_, ws, *sc_dual_, sets_, t, y, ydot, dynamics_))
      throw_embedding_failure(*sc_dual_, math::value_of(t));
  }
}

template <class Scratch>
void KaneProblem::throw_embedding_failure(const Scratch& sc, double t) const {
  if (!(sc.conditioning <= 1e10) || !(sc.amplification <= 1e12)) throw RecoverableError(embedding_failure(t, "have lost rank"));
  throw RecoverableError("embedding: the mass matrix is not positive definite");
}

std::string KaneProblem::embedding_failure(double t, const char* what) const {
  // The earliest since the last accepted step: where the trouble begins.
  if (!failure_cause_.empty() && failure_t_ <= t) return failure_cause_;
  failure_t_ = t;
  std::string rows;
  for (int r : sets_.rows) rows += (rows.empty() ? "" : ", ") + model_.constraint_row_names[static_cast<std::size_t>(r)];
  char when[48];
  std::snprintf(when, sizeof when, "%.10g", t);
  failure_cause_ = std::string("embedding: at t = ") + when + " the constraint rows " + rows + " " + what +
                   ": no choice of independent speeds parameterises the motion there (a singular position of "
                   "the constraints); use formulation: multipliers";
  return failure_cause_;
}

void KaneProblem::rhs(double t, const double* y, double* ydot) {
  // The multipliers' equations by the value half of the fused pass where it applies. Where it
  // cannot evaluate (redundant rows, not finite) the general solve decides and says why, and
  // takes over for the rest of the sample: redundant rows are usually so everywhere.
  if (value_rhs_ && !value_rhs_failed_) {
    if (value_pass(workspaces_.values(), t, y, ydot, value_out_.data(), value_constraint_.data())) return;
    value_rhs_failed_ = true;
  }
  evaluate(workspaces_.values(), t, y, ydot);
  // A partition that degrades is re-chosen between steps (after_step); one this bad means every
  // partition is (the re-choice keeps the best). A trial point there is rejected (a smaller step
  // may stay short of it).
  if (embedded_ && (sc_->conditioning > 1e10 || sc_->amplification > 1e12))
    throw RecoverableError(embedding_failure(t, "have (nearly) lost rank"));
}

template <int W>
void KaneProblem::evaluate_block(TangentBlock<W>& b, double t) {
  using MD = math::MultiDual<W>;
  if (embedded_) {
    if (!dynamics::embedded_rhs(model_, b.ws, *b.embedding, sets_, MD(t), b.y.data(), b.ydot.data(), dynamics_))
      throw_embedding_failure(*b.embedding, t);
    return;
  }
  dynamics::RhsFailure why = dynamics::RhsFailure::none;
  if (!dynamics::evaluate_rhs(model_, b.ws, MD(t), b.y.data(), b.ydot.data(), dynamics_, &why))
    throw RecoverableError(dynamics::describe(why));
}

// Columns in blocks: a block seeds e_c on y_c for each of its columns c and reads them all from
// one pass.

bool KaneProblem::after_step(double t, double* y, double* const* s) {
  if (!embedded_) return false;
  if (!failure_cause_.empty()) {
    // A trial point failed: forget it once a step got past it; steps crowding against it mean
    // the constraints do lose rank there.
    if (failure_t_ - t <= 1e-8 * std::max(1.0, std::abs(t))) throw std::runtime_error(failure_cause_);
    if (t > failure_t_) failure_cause_.clear();
  }
  const int nq = model_.nq;
  Workspace<double>& ws = workspaces_.values();
  if (!dynamics::reconstruct_speeds(model_, ws, *sc_, sets_, t, y, y + nq, u_full_.data()))
    throw std::runtime_error(embedding_failure(t, "have lost rank"));
  const double kappa = sc_->amplification;
  if (!(kappa > kRepartitionGrowth * std::max(amplification_ref_, 1.0))) return false;
  // reconstruct_speeds evaluated the rows at (t, q, u = 0): constraint_matrix is A at q.
  const Eigen::MatrixXd A = ws.constraint_matrix;
  const dynamics::EmbeddingSets next = dynamics::choose_embedding(A);
  if (next.rows.size() < sets_.rows.size()) throw std::runtime_error(embedding_failure(t, "have lost rank"));
  const double kappa_next = dynamics::embedding_amplification(A, next);
  if (!(2 * kappa_next < kappa) || next.independent == sets_.independent) {
    amplification_ref_ = kappa;  // no better partition here: look again after a further growth
    return false;
  }
  // The full speeds (and their sensitivities) are those of the old partition; the new state is
  // their new independent components.
  const std::size_t nn = next.independent.size();
  for (int i = 0; s && i < num_sensitivities(); ++i) {
    full_sensitivity(t, y, i, s[i], s_full_.data());
    for (std::size_t c = 0; c < nn; ++c) s[i][nq + static_cast<int>(c)] = s_full_[static_cast<std::size_t>(nq + next.independent[c])];
  }
  for (std::size_t c = 0; c < nn; ++c) y[nq + static_cast<int>(c)] = u_full_[static_cast<std::size_t>(next.independent[c])];
  sets_ = next;
  amplification_ref_ = kappa_next;
  return true;
}

void KaneProblem::jacobian(double t, const double* y, const double* ydot, double* J) {
  last_jacobian_method_ = DerivativeMethod::closed_form;
  if (jacobian_method_ == DerivativeMethod::closed_form && closed_form_ && closed_form_jacobian(t, y, ydot, J)) return;
  last_jacobian_method_ = DerivativeMethod::residual;
  if (!embedded_ && jacobian_method_ != DerivativeMethod::whole_rhs && residual_jacobian(t, y, ydot, J)) return;
  last_jacobian_method_ = DerivativeMethod::whole_rhs;
  const int n = size();
  jacobian_blocks_.for_each([&](auto& b) {
    for (int r = 0; r < n; ++r) {
      b.y[r].v = y[r];
      b.y[r].set_tangents([&](int i) { return b.first + i == r ? 1.0 : 0.0; }, b.count);
    }
    evaluate_block(b, t);
    for (int i = 0; i < b.count; ++i) {
      double* column = J + static_cast<std::ptrdiff_t>(b.first + i) * n;
      for (int r = 0; r < n; ++r) column[r] = b.ydot[r].d(i);
    }
  });
}

bool KaneProblem::closed_form_jacobian(double t, const double* y, const double* ydot, double* J) {
  // q̇ = u here (ResidualDerivatives::applies): J = [0 1; M⁻¹ ∂r/∂q M⁻¹ ∂r/∂u].
  Workspace<double>& wd = jacobian_values_;
  const int nq = model_.nq, nu = model_.nu, n = size();
  const double *q = y, *u = y + nq, *udot = ydot + nq;
  dynamics::evaluate_state_expressions(model_, wd, t, q, u);
  dynamics::compute_position(model_, wd, q);
  dynamics::compute_velocity(model_, wd, u);
  double* dr = closed_dr_.data();
  double* r = closed_r_.data();
  double* r_scale = closed_scale_.data();
  const bool applied = dynamics::ResidualDerivatives::needs_applied_pass(model_);
  closed_form_->evaluate(model_, wd, q, u, udot, !applied, r, r_scale, dr, wd.mass_matrix.data());
  if (!dynamics::factor_mass_matrix(model_, wd)) return false;
  if (applied) {
    // The force elements and the joints' spring-dampers, per block of up to 16 directions: their
    // values complete r, their tangents ∂r.
    jacobian_blocks_.for_each([&](auto& b) {
      for (int row = 0; row < n; ++row) {
        b.y[static_cast<std::size_t>(row)].v = y[row];
        b.y[static_cast<std::size_t>(row)].set_tangents([&](int i) { return b.first + i == row ? 1.0 : 0.0; }, b.count);
      }
      closed_form_->add_applied_forces(model_, wd, b.ws, t, b.y.data(), b.first, b.count, r, r_scale, dr);
    });
  }
  // ydot must solve the equations at y (it is f(t, y) by the contract): r = f − M u̇ vanishes to
  // round-off of its terms.
  constexpr double tol = 1e-8;
  for (int k = 0; k < nu; ++k) {
    double scale = r_scale[k];
    for (int l = 0; l < nu; ++l) scale = std::max(scale, std::abs(wd.mass_matrix(k, l) * udot[l]));
    if (!(std::abs(r[k]) <= tol * scale + 1e-300)) return false;
  }
  dynamics::apply_mass_inverse_rows(model_, wd, dr, n, n);  // nq = nu: dr is nu×n
  for (int c = 0; c < n; ++c) {
    double* column = J + static_cast<std::ptrdiff_t>(c) * n;
    std::fill(column, column + nq, 0.0);
    if (c >= nq) column[c - nq] = 1.0;
    for (int k = 0; k < nu; ++k) column[nq + k] = dr[static_cast<std::ptrdiff_t>(k) * n + c];
  }
  return true;
}

bool KaneProblem::residual_jacobian(double t, const double* y, const double* ydot, double* J) {
  const int n = size();
  return residual_blocks(
      jacobian_blocks_, t, y, ydot, [](int direction, int r) { return direction == r ? 1.0 : 0.0; },
      [&](int direction, int r, double d) { J[static_cast<std::ptrdiff_t>(direction) * n + r] = d; });
}

// Residual passes of every block: direction k's tangent on y_r is seed(k, r), and store(k, r, d)
// takes u̇'s (and q̇'s) tangent d. The first block forms the value factors, the others reuse them.
template <class Seed, class Store>
bool KaneProblem::residual_blocks(TangentBlocks& blocks, double t, const double* y, const double* ydot, Seed seed,
                                  Store store) {
  return blocked_passes(blocks, y, seed, store, [&](auto& b, bool first) {
    return residual_pass(b.ws, t, b.y.data(), ydot, b.ydot.data(), b.constraint_residual.data(), first);
  });
}

template <class Seed, class Store, class Pass>
bool KaneProblem::blocked_passes(TangentBlocks& blocks, const double* y, Seed seed, Store store, Pass pass) {
  const int n = size();
  bool first = true, ok = true;
  blocks.for_each([&](auto& b) {
    if (!ok) return;
    for (int r = 0; r < n; ++r) {
      b.y[r].v = y[r];
      b.y[r].set_tangents([&](int i) { return seed(b.first + i, r); }, b.count);
    }
    ok = pass(b, first);
    first = false;
    if (!ok) return;
    for (int i = 0; i < b.count; ++i)
      for (int r = 0; r < n; ++r) store(b.first + i, r, b.ydot[r].d(i));
  });
  return ok;
}

// The pass is at u̇ of ydot with λ = 0: r = f − M u̇, whose value is −Aᵀλ (which gives λ); the
// tangent of Aᵀλ is added on values, then every tangent is solved at once.
template <class S>
bool KaneProblem::residual_pass(Workspace<S>& ws, double t, const S* y, const double* ydot, S* out, S* c,
                                bool factor) {
  Workspace<double>& wd = jacobian_values_;
  const int nq = model_.nq;
  const double* udot = ydot + nq;
  dynamics::evaluate_residual(model_, ws, S(t), y, udot, nullptr, dynamics_, out, c);
  if (factor && (!dynamics::factor_mass_matrix_values(model_, ws, wd) || !acceleration_tangents_.prepare(model_, wd)))
    return false;
  return solve_residual_tangents(ws, udot, out + nq, c, factor);
}

template <class S>
bool KaneProblem::solve_residual_tangents(Workspace<S>& ws, const double* udot, S* du, S* c, bool first) {
  Workspace<double>& wd = jacobian_values_;
  const int nu = model_.nu, nc = model_.nconstraint_rows;
  double* lambda = jacobian_multipliers_.data();
  if (first) {
    for (int k = 0; k < nu; ++k) residual_value_[static_cast<std::size_t>(k)] = math::value_of(du[k]);
    acceleration_tangents_.multipliers(model_, wd, residual_value_.data(), lambda);
    if (!residual_vanishes(c, udot)) return false;
  }
  for (int j = 0; j < nc; ++j)
    for (int k = 0; k < nu; ++k) du[k] += ws.constraint_matrix(j, k) * lambda[j];
  acceleration_tangents_.solve(model_, wd, du, c);
  return true;
}

// Whether u̇ (and the λ found) solve the equations at the pass's state (ydot is f(t, y)):
// f − M u̇ + Aᵀλ and A u̇ − b vanish to round-off relative to the largest of their terms.
template <class S>
bool KaneProblem::residual_vanishes(const S* c, const double* udot) const {
  const Workspace<double>& wd = jacobian_values_;
  const int nu = model_.nu, nc = model_.nconstraint_rows;
  constexpr double tol = 1e-8;
  const double* lambda = jacobian_multipliers_.data();
  double scale = 0, worst = 0;
  for (int k = 0; k < nu; ++k) {
    double Mu = 0, At = 0;
    for (int l = 0; l < nu; ++l) {
      Mu += wd.mass_matrix(k, l) * udot[l];
      scale = std::max(scale, std::abs(wd.mass_matrix(k, l) * udot[l]));
    }
    for (int j = 0; j < nc; ++j) {
      At += wd.constraint_matrix(j, k) * lambda[j];
      scale = std::max(scale, std::abs(wd.constraint_matrix(j, k) * lambda[j]));
    }
    const double r = residual_value_[static_cast<std::size_t>(k)];  // f − M u̇
    scale = std::max(scale, std::abs(r + Mu));
    worst = std::max(worst, std::abs(r + At));
  }
  if (!(worst <= tol * scale)) return false;
  scale = worst = 0;
  for (int j = 0; j < nc; ++j) {
    double Au = 0;
    for (int k = 0; k < nu; ++k) {
      Au += wd.constraint_matrix(j, k) * udot[k];
      scale = std::max(scale, std::abs(wd.constraint_matrix(j, k) * udot[k]));
    }
    const double cj = math::value_of(c[j]);  // A u̇ − b
    scale = std::max(scale, std::abs(Au - cj));
    worst = std::max(worst, std::abs(cj));
  }
  return worst <= tol * scale;
}

void KaneProblem::jacobian_times(double t, const double* y, const double*, const double* v, double* Jv) {
  const int n = size();
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], v[r]);
  evaluate(workspaces_.jacobian(), Dual(t), y_dual_.data(), ydot_dual_.data());
  for (int r = 0; r < n; ++r) Jv[r] = ydot_dual_[r].d;
}

// Tangent i of a block is (s_i on y, e_p on its parameter — set by set_sample), so one pass gives
// J s_i + ∂f/∂p_i for all the block's sensitivities.
void KaneProblem::sensitivity_rhs_all(double t, const double* y, const double* ydot, int, const double* const* s,
                                      double* const* sdot) {
  const int n = size();
  last_sensitivity_method_ = DerivativeMethod::whole_rhs;
  if (single_tangent()) {
    for (int i = 0; i < num_sensitivities(); ++i) sensitivity_rhs(t, y, nullptr, i, s[i], sdot[i]);
    return;
  }
  if (ydot && residual_sensitivities(t, y, ydot, s, sdot)) return;
  sensitivity_blocks_.for_each([&](auto& b) {
    for (int r = 0; r < n; ++r) {
      b.y[r].v = y[r];
      b.y[r].set_tangents([&](int i) { return s[b.first + i][r]; }, b.count);
    }
    evaluate_block(b, t);
    for (int i = 0; i < b.count; ++i)
      for (int r = 0; r < n; ++r) sdot[b.first + i][r] = b.ydot[r].d(i);
  });
}

bool KaneProblem::residual_sensitivities(double t, const double* y, const double* ydot, const double* const* s,
                                         double* const* sdot) {
  if (embedded_ || sensitivity_method_ != DerivativeMethod::residual) return false;
  const bool ok = residual_blocks(
      sensitivity_blocks_, t, y, ydot, [&](int i, int r) { return s[i][r]; },
      [&](int i, int r, double d) { sdot[i][r] = d; });
  if (ok) last_sensitivity_method_ = DerivativeMethod::residual;
  return ok;
}

bool KaneProblem::fused_residual_sensitivities(double t, const double* y, const double* const* s, double* ydot,
                                               double* const* sdot) {
  if (model_.evaluate_planar()) return false;
  const bool ok = blocked_passes(
      sensitivity_blocks_, y, [&](int i, int r) { return s[i][r]; }, [&](int i, int r, double d) { sdot[i][r] = d; },
      [&](auto& b, bool first) {
        return first ? fused_residual_pass(b.ws, t, b.y.data(), ydot, b.ydot.data(), b.constraint_residual.data())
                     : residual_pass(b.ws, t, b.y.data(), ydot, b.ydot.data(), b.constraint_residual.data(), false);
      });
  if (ok) last_sensitivity_method_ = DerivativeMethod::residual;
  return ok;
}

template <class S>
bool KaneProblem::value_pass(Workspace<S>& ws, double t, const S* y, double* ydot, S* out, S* c) {
  Workspace<double>& wd = jacobian_values_;
  const int nq = model_.nq, nc = model_.nconstraint_rows;
  double* udot = ydot + nq;
  double* b = fused_constraint_value_.data();
  dynamics::evaluate_residual_at_rest(model_, ws, S(t), y, dynamics_, out, c);  // c = −b
  if (!dynamics::factor_mass_matrix_values(model_, ws, wd) || !acceleration_tangents_.prepare(model_, wd)) return false;
  // M u̇ − Aᵀλ = f, A u̇ = b on values.
  dynamics::forcing_values(model_, ws, wd, udot);
  for (int j = 0; j < nc; ++j) b[j] = math::value_of(c[j]);
  acceleration_tangents_.solve(model_, wd, udot, b);
  // The solve leaves −λ in b. u̇ and λ solve the equations at y by construction, so of
  // residual_pass's check only finiteness is left (where it fails, rhs() reports why).
  double* lambda = jacobian_multipliers_.data();
  bool finite = true;
  for (int j = 0; j < nc; ++j) finite = std::isfinite(lambda[j] = -b[j]) && finite;
  for (int k = 0; k < model_.nu; ++k) finite = std::isfinite(udot[k]) && finite;
  if (!finite) return false;
  for (int i = 0; i < nq; ++i) ydot[i] = math::value_of(out[i]);
  return true;
}

template <class S>
bool KaneProblem::fused_residual_pass(Workspace<S>& ws, double t, const S* y, double* ydot, S* out, S* c) {
  if (!value_pass(ws, t, y, ydot, out, c)) return false;
  dynamics::residual_from_rest(model_, ws, ydot + model_.nq, out + model_.nq, c);
  return solve_residual_tangents(ws, ydot + model_.nq, out + model_.nq, c, false);
}

// f is the value part of the first whole sensitivity pass, or the residual passes' own f.
void KaneProblem::rhs_with_sensitivities(double t, const double* y, int ns, const double* const* s, double* ydot,
                                         double* const* sdot) {
  last_f_from_sensitivity_pass_ = false;
  if (ns == 0) {
    rhs(t, y, ydot);
    return;
  }
  if (!single_tangent() && !embedded_ && sensitivity_method_ == DerivativeMethod::residual) {
    last_f_from_sensitivity_pass_ = fused_residual_sensitivities(t, y, s, ydot, sdot);
    if (last_f_from_sensitivity_pass_) return;
    rhs(t, y, ydot);
    last_sensitivity_method_ = DerivativeMethod::whole_rhs;
    if (residual_sensitivities(t, y, ydot, s, sdot)) return;
  }
  sensitivity_rhs_all(t, y, nullptr, ns, s, sdot);
  if (single_tangent()) {
    for (int r = 0; r < size(); ++r) ydot[r] = ydot_dual_[r].v;
    if (embedded_ && (sc_dual_->conditioning > 1e10 || sc_dual_->amplification > 1e12))
      throw RecoverableError(embedding_failure(t, "have (nearly) lost rank"));
    return;
  }
  bool first = true;
  sensitivity_blocks_.for_each([&](auto& b) {
    if (!first) return;
    first = false;
    for (int r = 0; r < size(); ++r) ydot[r] = b.ydot[r].v;
    if (embedded_ && (b.embedding->conditioning > 1e10 || b.embedding->amplification > 1e12))
      throw RecoverableError(embedding_failure(t, "have (nearly) lost rank"));
  });
}

void KaneProblem::sensitivity_rhs(double t, const double* y, const double*, int i, const double* s, double* sdot) {
  const int n = size();
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], s[r]);
  evaluate(workspaces_.tangent(i), Dual(t), y_dual_.data(), ydot_dual_.data());
  for (int r = 0; r < n; ++r) sdot[r] = ydot_dual_[r].d;
}

std::vector<double> KaneProblem::sensitivity_scales() const {
  std::vector<double> scales;
  for (const auto& s : sens_) {
    double v = 1;
    if (s.kind == InputRef::Kind::parameter) v = std::abs(workspaces_.parameters()[static_cast<std::size_t>(s.index)]);
    scales.push_back(v > 0 ? v : 1.0);
  }
  return scales;
}

int KaneProblem::project(double t, const double* y, double* corr, double, double* err) {
  return projector_.project(workspaces_.values(), t, y, size(), !embedded_, corr, err);
}

void KaneProblem::project_sensitivity(double t, const double* y, int i, double* s) {
  projector_.project_sensitivity(workspaces_.tangent(i), dynamics_, t, y, s);
}

void KaneProblem::full_state(double t, const double* y, double* y_full) {
  const int nq = model_.nq;
  std::copy(y, y + nq, y_full);
  if (!embedded_) {
    std::copy(y + nq, y + model_.nstate(), y_full + nq);
    return;
  }
  if (!dynamics::reconstruct_speeds(model_, workspaces_.values(), *sc_, sets_, t, y, y + nq, y_full + nq))
    throw std::runtime_error(embedding_failure(t, "have lost rank"));
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
  if (!dynamics::reconstruct_speeds(model_, workspaces_.tangent(i), *sc_dual_, sets_, Dual(t), y_dual_.data(),
                                    y_dual_.data() + nq, u.data()))
    throw std::runtime_error(embedding_failure(t, "have lost rank"));
  for (int k = 0; k < model_.nu; ++k) s_full[nq + k] = u[static_cast<std::size_t>(k)].d;
}

void KaneProblem::full_rate(double t, const double* y, const double* ydot, double* ydot_full) {
  const int nq = model_.nq, n = size();
  std::copy(ydot, ydot + nq, ydot_full);
  if (!embedded_) {
    std::copy(ydot + nq, ydot + model_.nstate(), ydot_full + nq);
    return;
  }
  // d/dt of the reconstructed speeds along (1, ẏ): the Jacobian's workspace carries no ∂/∂p.
  for (int r = 0; r < n; ++r) y_dual_[r] = Dual(y[r], ydot[r]);
  std::vector<Dual> u(static_cast<std::size_t>(model_.nu));
  if (!dynamics::reconstruct_speeds(model_, workspaces_.jacobian(), *sc_dual_, sets_, Dual(t, 1.0), y_dual_.data(),
                                    y_dual_.data() + nq, u.data()))
    throw std::runtime_error(embedding_failure(t, "have lost rank"));
  for (int k = 0; k < model_.nu; ++k) ydot_full[nq + k] = u[static_cast<std::size_t>(k)].d;
}

double KaneProblem::energy(double t, const double* y) { return sim::energy(model_, workspaces_.values(), t, y); }

void KaneProblem::multipliers(double t, const double* y, double* lambda) {
  sim::multipliers(model_, workspaces_.values(), dynamics_, t, y, recorded_rate_.data(), lambda);
}

void KaneProblem::multiplier_sensitivity(double t, const double* y, int i, const double* s, double* dlambda,
                                         int stride) {
  sim::multiplier_sensitivity(model_, workspaces_.tangent(i), dynamics_, t, y, s, {y_dual_.data(), ydot_dual_.data()},
                              dlambda, stride);
}

template <class Read>
void KaneProblem::full_state_sensitivity_passes(double t, const double* y, const double* const* s, Read read) {
  const int n = model_.nstate();
  sensitivity_blocks_.for_each([&](auto& b) {
    using MD = typename std::decay_t<decltype(b.y)>::value_type;
    for (int r = 0; r < n; ++r) {
      b.y[r].v = y[r];
      b.y[r].set_tangents([&](int i) { return s[b.first + i][r]; }, b.count);
    }
    read(b, dynamics::evaluate_rhs(model_, b.ws, MD(t), b.y.data(), b.ydot.data(), dynamics_));
  });
}

void KaneProblem::multiplier_sensitivities(double t, const double* y, const double* const* s, double* dlambda) {
  const int ns = num_sensitivities();
  if (single_tangent()) {
    for (int i = 0; i < ns; ++i) multiplier_sensitivity(t, y, i, s[i], dlambda + i, ns);
    return;
  }
  if (!fused_multiplier_sensitivities(t, y, s, dlambda)) multiplier_form_sensitivities(t, y, s, dlambda);
}

void KaneProblem::multiplier_form_sensitivities(double t, const double* y, const double* const* s, double* dlambda) {
  const int m = model_.nconstraint_rows, ns = num_sensitivities();
  full_state_sensitivity_passes(t, y, s, [&](auto& b, bool ok) {
    for (int r = 0; r < m; ++r)
      for (int i = 0; i < b.count; ++i) dlambda[r * ns + b.first + i] = ok ? b.ws.multipliers[r].d(i) : std::nan("");
  });
}

void KaneProblem::multipliers_and_sensitivities(double t, const double* y, const double* const* s, double* lambda,
                                                double* dlambda) {
  if (single_tangent()) {
    multipliers(t, y, lambda);
    multiplier_sensitivities(t, y, s, dlambda);
  } else if (fused_multiplier_sensitivities(t, y, s, dlambda)) {
    std::copy(jacobian_multipliers_.begin(), jacobian_multipliers_.end(), lambda);  // that pass's own λ
  } else {
    multipliers(t, y, lambda);
    multiplier_form_sensitivities(t, y, s, dlambda);
  }
}

// The stacked right-hand side's passes (fused_residual_sensitivities) leave −δλ in each block's
// constraint part (AccelerationTangents::solve): dλ/dε without forming M on the tangent scalar.
bool KaneProblem::fused_multiplier_sensitivities(double t, const double* y, const double* const* s, double* dlambda) {
  if (embedded_ || sensitivity_method_ != DerivativeMethod::residual || model_.evaluate_planar()) return false;
  const int m = model_.nconstraint_rows, ns = num_sensitivities();
  return blocked_passes(
      sensitivity_blocks_, y, [&](int i, int r) { return s[i][r]; }, [](int, int, double) {},
      [&](auto& b, bool first) {
        const bool ok = first ? fused_residual_pass(b.ws, t, b.y.data(), recorded_rate_.data(), b.ydot.data(),
                                                    b.constraint_residual.data())
                              : residual_pass(b.ws, t, b.y.data(), recorded_rate_.data(), b.ydot.data(),
                                              b.constraint_residual.data(), false);
        if (ok)
          for (int r = 0; r < m; ++r)
            for (int i = 0; i < b.count; ++i) dlambda[r * ns + b.first + i] = -b.constraint_residual[r].d(i);
        return ok;
      });
}

void KaneProblem::project_sensitivities(double t, const double* y, double* const* s) {
  const int m = model_.nconstraint_rows, nu = model_.nu, ns = num_sensitivities(), mh = holonomic_.size();
  if (m == 0 || ns == 0) return;
  if (single_tangent()) {
    for (int i = 0; i < ns; ++i) project_sensitivity(t, y, i, s[i]);
    return;
  }
  if (mh > 0) {
    Eigen::MatrixXd rt(mh, ns);
    full_state_sensitivity_passes(t, y, s, [&](auto& b, bool ok) {
      Projector::check_evaluated(ok, t);
      for (int r = 0; r < mh; ++r)
        for (int i = 0; i < b.count; ++i)
          rt(r, b.first + i) = b.ws.position_residual[holonomic_.rows()[static_cast<std::size_t>(r)]].d(i);
    });
    projector_.correct_sensitivity_positions(t, y, rt, s);
  }
  Eigen::MatrixXd A(m, nu), rv(m, ns);
  full_state_sensitivity_passes(t, y, s, [&](auto& b, bool ok) {
    Projector::check_evaluated(ok, t);
    for (int r = 0; r < m; ++r) {
      for (int k = 0; k < nu; ++k) A(r, k) = b.ws.constraint_matrix(r, k).v;
      for (int i = 0; i < b.count; ++i) rv(r, b.first + i) = b.ws.velocity_residual[r].d(i);
    }
  });
  projector_.correct_sensitivity_speeds(A, rv, s);
}

void KaneProblem::constraint_residuals(double t, const double* y, double& position, double& velocity) {
  sim::constraint_residuals(model_, workspaces_.values(), dynamics_, holonomic_.rows(), t, y, position, velocity);
}

void KaneProblem::sensitivity_constraint_residuals(double t, const double* y, int i, const double* s,
                                                   double& position, double& velocity) {
  sim::sensitivity_constraint_residuals(model_, workspaces_.tangent(i), dynamics_, holonomic_.rows(), t, y, s,
                                        {y_dual_.data(), ydot_dual_.data()}, position, velocity);
}

}  // namespace kanesens::sim
