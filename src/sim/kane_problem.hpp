// Kane's equations as an ODE problem for the solvers (sim/solve/ode_problem.hpp): state
// y = [q; u] (with the embedding formulation [q; u_i], the independent speeds), exact Jacobian and
// sensitivity right-hand sides from forward-mode dual numbers through the same templated code.
//
// Sensitivity i is with respect to a scene parameter or an initial condition (InputRef).
//   Jacobian column j:      the tangent e_j on y, 0 on parameters, through Kane's equations as a
//                           residual at the current accelerations (DerivativeMethod below) or
//                           through the whole right-hand side.
//   sensitivity rhs i:      the right-hand side on Dual with tangent s_i on y and e_p on
//                           parameter p (0 for an initial condition) = J s_i + ∂f/∂p.
//   initial sensitivity i:  the tangent of the consistent initial state (sim/initial_state.hpp).
//
// The parts: the sample's workspaces (sim/sample_workspaces.hpp), its consistent initial state,
// computed once per sample with every tangent (sim/initial_state.hpp), the projection onto the
// constraints (sim/projector.hpp) and the recorded outputs (sim/outputs.hpp).
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "dynamics/embedding.hpp"
#include "dynamics/inverse_dynamics.hpp"
#include "dynamics/residual_derivatives.hpp"
#include "dynamics/options.hpp"
#include "math/dual.hpp"
#include "sim/constraint_options.hpp"
#include "sim/holonomic.hpp"
#include "sim/initial_state.hpp"
#include "sim/inputs.hpp"
#include "sim/projector.hpp"
#include "sim/sample_workspaces.hpp"
#include "sim/solve/ode_problem.hpp"
#include "sim/tangent_blocks.hpp"
#include "util/error.hpp"

namespace kanesens::sim {

class KaneProblem final : public OdeProblem {
 public:
  // t0: the time of the initial state (the study's first output time), where time-dependent
  // constraints are made consistent and the embedding's independent speeds are chosen. Loads the
  // nominal sample; should its initial state be inconsistent, initial_state() reports it (a
  // later sample may be valid).
  KaneProblem(const model::Model& model, std::vector<InputRef> sensitivities, ConstraintOptions constraints = {},
              double t0 = 0);

  // Loads one sample: its parameters and its consistent initial state. Throws InputError if the
  // parameters are physically invalid (mass ≤ 0, ...) or the initial state cannot be made
  // consistent; the problem then reports that failure until the next set_sample.
  void set_sample(const SampleInputs& inputs);
  double initial_time() const { return t0_; }

  // nq + nu, or with the embedding formulation nq + (number of independent speeds).
  int size() const override {
    return embedded_ ? model_.nq + static_cast<int>(sets_.independent.size()) : model_.nstate();
  }
  void initial_state(double* y0) const override;
  // Checks the current sample at t0 as validation does before a run (sim/initial_checks.cpp):
  // its consistent initial state exists (no constraint vanishes or is non-finite there, the
  // correction converges) and Kane's equations give finite values there with a positive
  // definite mass matrix. Throws InputError naming what is wrong and where it was written.
  void validate_initial_state() const;
  void rhs(double t, const double* y, double* ydot) override;
  bool has_jacobian() const override { return true; }
  void jacobian(double t, const double* y, const double* ydot, double* J) override;
  // How jacobian() differentiates u̇ = M⁻¹(f + Aᵀλ):
  //   residual   (the default) one multi-tangent pass of Kane's equations as a residual at the
  //              accelerations of ydot (= f(t, y), as the contract says: inverse dynamics,
  //              dynamics/inverse_dynamics.hpp), then solves with M's and A M⁻¹ Aᵀ's factors on
  //              values; the mass matrix is never formed on the tangent scalar. With the
  //              multipliers formulation (or no constraint) where the constraint rows are
  //              independent and ydot is consistent with y (checked: the residual's value
  //              vanishes); otherwise whole_rhs.
  //   whole_rhs  multi-tangent passes of the whole right-hand side: the embedding formulation,
  //              redundant constraint rows, and tests comparing the two.
  //   closed_form (the default for the Jacobian) the residual's derivatives in closed form
  //              (dynamics/residual_derivatives.hpp) where they apply: unconstrained 3-D trees of
  //              one-axis joints (force elements on dual numbers, on the bodies they load);
  //              otherwise residual, as above.
  // All are exact and agree to round-off. The sensitivity right-hand sides choose between
  // residual and whole_rhs (set_sensitivity_method; closed_form is for the Jacobian only).
  enum class DerivativeMethod { residual, whole_rhs, closed_form };
  void set_jacobian_method(DerivativeMethod method) { jacobian_method_ = method; }
  // The method the last jacobian() call took.
  DerivativeMethod last_jacobian_method() const { return last_jacobian_method_; }
  // Whether rhs() takes the value half of the fused residual pass (3-D multipliers with the dense
  // constraint solve) until it next fails for this sample, rather than the general solve.
  bool rhs_by_value_pass() const { return value_rhs_ && !value_rhs_failed_; }
  // How the multi-tangent sensitivity right-hand sides (sensitivity_rhs_all,
  // rhs_with_sensitivities) are formed, under the conditions of jacobian()'s residual method
  // (else whole_rhs). The default is residual on the 3-D path, whose whole pass forms and
  // factors M on the tangent scalar (bench/results/sensitivity_cost_residual.json), and
  // whole_rhs on the planar path, where the residual passes were not measured faster. Where
  // ydot is not given (DOP853's stages) the residual method on the 3-D path takes f(t, y) from
  // its own first pass (fused_residual_sensitivities); elsewhere it first evaluates f on values.
  void set_sensitivity_method(DerivativeMethod method) { sensitivity_method_ = method; }
  DerivativeMethod last_sensitivity_method() const { return last_sensitivity_method_; }
  // Whether the last rhs_with_sensitivities took f from its residual passes (3-D path, residual
  // method, where it applies) rather than from a separate evaluation of the right-hand side.
  bool last_f_from_sensitivity_pass() const { return last_f_from_sensitivity_pass_; }
  // J v from one pass of the right-hand side on Dual with tangent v on y (no parameter tangent):
  // the same equations, constraint paths and partition as rhs(). (The residual form of
  // jacobian() does not pay here: with one tangent, forming M's value factor per product costs
  // more than the mass matrix's tangent saves.)
  bool has_jacobian_times() const override { return true; }
  // False where rhs() finds u̇ by the articulated-body recursion (O(n)) and J v's dual pass cannot:
  // 3-D chains with joints of several speeds, whose recursion runs on double only, so the dual
  // pass forms and factors M (O(n³)) and Newton–Krylov with exact products loses to the dense
  // solver (docs/explanation/solvers.md). Chains of one-speed joints take it on duals too.
  bool jacobian_times_cheap() const override { return jacobian_times_cheap_; }
  void jacobian_times(double t, const double* y, const double* ydot, const double* v, double* Jv) override;
  int num_sensitivities() const override { return static_cast<int>(sens_.size()); }
  void initial_sensitivity(int i, double* s0) const override;
  bool has_sensitivity_rhs() const override { return true; }
  void sensitivity_rhs(double t, const double* y, const double* ydot, int i, const double* s,
                       double* sdot) override;
  // All sensitivities in multi-tangent passes (blocks of up to 16), and with f from the first
  // pass (DOP853's stages); up to kSingleTangentPasses of them in single-tangent passes instead.
  void sensitivity_rhs_all(double t, const double* y, const double* ydot, int ns, const double* const* s,
                           double* const* sdot) override;
  void rhs_with_sensitivities(double t, const double* y, int ns, const double* const* s, double* ydot,
                              double* const* sdot) override;
  std::vector<double> sensitivity_scales() const override;
  double* dq_parameters() override { return workspaces_.dq_parameters(); }
  std::vector<int> dq_parameter_list() const override { return workspaces_.dq_parameter_list(); }

  // The embedding re-chooses its independent speeds (coordinate partitioning with re-selection,
  // docs/explanation/constraints.md): after every step it measures the amplification κ = max |A_d⁻¹ A_i|;
  // once κ has grown kRepartitionGrowth-fold (from max(κ at the last choice, 1)), it picks the
  // best-conditioned partition at the current state and, if that halves κ, maps the state and
  // the sensitivities to it (the full speeds and their sensitivities are the same in both).
  // Throws, naming the rows and the time, when A has lost rank (no partition exists).
  static constexpr double kRepartitionGrowth = 4;
  bool has_step_check() const override { return embedded_; }
  bool after_step(double t, double* y, double* const* s) override;

  bool has_projection() const override {
    return model_.nconstraint_rows > 0 && options_.stabilization == ConstraintOptions::Stabilization::projection;
  }
  int project(double t, const double* y, double* corr, double eps_proj, double* err) override;
  // Whether simulate() projects the recorded sensitivities (projection + project_sensitivities).
  bool projects_sensitivities() const { return has_projection() && options_.project_sensitivities; }

  // The cause of this run's failure when the problem knows it better than the integrator's flag
  // (the embedding's constraints losing rank); "" otherwise. simulate() puts it first.
  const std::string& failure_cause() const { return failure_cause_; }

  bool embedded() const { return embedded_; }
  const dynamics::EmbeddingSets& embedding_sets() const { return sets_; }
  // The full state [q; u] (nstate) from the integrator's state y (size()), and the full state
  // sensitivity from the integrator's s_i. Identity copies unless embedded.
  void full_state(double t, const double* y, double* y_full);
  void full_sensitivity(double t, const double* y, int i, const double* s, double* s_full);
  // The full state's time derivative d[q; u]/dt (nstate) from the integrator's y and ẏ (size()).
  void full_rate(double t, const double* y, const double* ydot, double* ydot_full);

  // Outputs at a full state (sim/outputs.hpp), with the current sample's parameters.
  double energy(double t, const double* y);
  void multipliers(double t, const double* y, double* lambda);
  // dλ/dε_i along s: row r in dlambda[r · stride].
  void multiplier_sensitivity(double t, const double* y, int i, const double* s, double* dlambda, int stride = 1);
  // Every sensitivity's dλ/dε at once (dlambda[r · ns + i], NaN where λ cannot be computed):
  // one multi-tangent pass per block of sensitivities — the stacked right-hand side's residual
  // passes where they apply, else the multiplier form's.
  void multiplier_sensitivities(double t, const double* y, const double* const* s, double* dlambda);
  // λ (m) and every dλ/dε: where the residual passes apply, λ is the one their first pass
  // solves for, not evaluated again.
  void multipliers_and_sensitivities(double t, const double* y, const double* const* s, double* lambda,
                                     double* dlambda);
  void constraint_residuals(double t, const double* y, double& position, double& velocity);
  void sensitivity_constraint_residuals(double t, const double* y, int i, const double* s, double& position,
                                        double& velocity);
  // Projects sensitivity i (s, nstate, in place) onto the constraints' tangent space at (t, y)
  // (Projector::project_sensitivity): CVODES's projection moves y only, so the integrated
  // sensitivities drift off it (docs/explanation/constraints.md); simulate() applies this to the recorded
  // ones when stabilization is projection.
  void project_sensitivity(double t, const double* y, int i, double* s);
  // All of them (s[i], nstate each), with one pass per block and stage and each of G's and A's
  // factorisations formed once.
  void project_sensitivities(double t, const double* y, double* const* s);

  // Size of the correction that made the sample's initial state consistent (max norms).
  double initial_position_correction() const { return initial_.position_correction; }
  double initial_velocity_correction() const { return initial_.velocity_correction; }
  const model::Model& model() const { return model_; }
  const std::vector<InputRef>& sensitivities() const { return sens_; }
  // The sample's workspaces (values and tangents) and the dynamics options of the integrated
  // equations, for evaluations at recorded states (sim/output_evaluator.hpp).
  SampleWorkspaces& workspaces() { return workspaces_; }
  const dynamics::DynamicsOptions& dynamics_options() const { return dynamics_; }

 private:
  // The integrated right-hand side on scalar S, in the workspace given: the multiplier form, or
  // the embedding's. Throws solve's RecoverableError, saying why, where u̇ cannot be computed (a
  // singular M or A_d, a degenerate constraint system): the integrator retries smaller.
  template <class S>
  void evaluate(dynamics::Workspace<S>& ws, const S& t, const S* y, S* ydot);
  // The multiplier form at the full state y (nstate) in every sensitivity block, tangent i on y
  // being s[i]; then read(block, evaluated) for each block (evaluated false where u̇ and λ
  // cannot be computed).
  template <class Read>
  void full_state_sensitivity_passes(double t, const double* y, const double* const* s, Read read);
  // Throws the failure of the current sample's initial state, if any.
  void check_initial_state() const;

  const model::Model& model_;
  std::vector<InputRef> sens_;
  ConstraintOptions options_;
  dynamics::DynamicsOptions dynamics_;  // Baumgarte gains when stabilization is baumgarte
  double t0_ = 0;
  SampleWorkspaces workspaces_;
  HolonomicConstraints holonomic_;
  Projector projector_;
  InitialState initial_;
  std::optional<InputError> failure_;  // why the current sample's initial state is unavailable
  // Why the embedding cannot go on at t: A_d singular, or A of lower rank than at t0 (rows named).
  // The earliest such message since the last accepted step is kept (failure_cause).
  std::string embedding_failure(double t, const char* what) const;

  bool embedded_ = false;
  bool jacobian_times_cheap_ = true;
  dynamics::EmbeddingSets sets0_;  // the partition chosen at t0
  // The partition in use and κ when it was chosen: initial_state() restores sets0_ (the
  // integrator starts every run there), after_step() re-chooses.
  mutable dynamics::EmbeddingSets sets_;
  mutable double amplification_ref_ = 0, amplification0_ = 0;
  mutable std::string failure_cause_;
  mutable double failure_t_ = 0;
  std::unique_ptr<dynamics::EmbeddingScratch<double>> sc_;
  std::unique_ptr<dynamics::EmbeddingScratch<math::Dual>> sc_dual_;
  std::vector<math::Dual> y_dual_, ydot_dual_;  // the dual evaluations' state (allocated once)
  // Multi-tangent passes: the Jacobian's columns (no parameter tangent) and the sensitivities
  // (each parameter sensitivity's tangent e_p set per sample).
  TangentBlocks jacobian_blocks_, sensitivity_blocks_;
  int jacobian_blocks_size_ = -1;
  // The residual Jacobian: M's and A M⁻¹ Aᵀ's factors on values at the state, the tangent
  // solve, scratch (r's value (nu), λ (m)).
  DerivativeMethod jacobian_method_ = DerivativeMethod::closed_form, last_jacobian_method_ = DerivativeMethod::residual;
  DerivativeMethod sensitivity_method_ = DerivativeMethod::whole_rhs, last_sensitivity_method_ = DerivativeMethod::whole_rhs;
  dynamics::Workspace<double> jacobian_values_;
  dynamics::AccelerationTangents acceleration_tangents_;
  std::vector<double> residual_value_, jacobian_multipliers_;
  // False when the residual form does not apply at this state (J then holds no result).
  bool residual_jacobian(double t, const double* y, const double* ydot, double* J);
  // The closed form (when ResidualDerivatives::applies): scratch r, its scale, [∂r/∂q ∂r/∂u].
  std::unique_ptr<dynamics::ResidualDerivatives> closed_form_;
  std::vector<double> closed_r_, closed_scale_, closed_dr_;
  // False, as residual_jacobian, when ydot does not solve the equations at y or M is not
  // positive definite there.
  bool closed_form_jacobian(double t, const double* y, const double* ydot, double* J);
  // The sensitivity right-hand sides by residual passes; false (sdot then holds no result) as
  // residual_jacobian.
  bool residual_sensitivities(double t, const double* y, const double* ydot, const double* const* s,
                              double* const* sdot);
  template <class Seed, class Store>
  bool residual_blocks(TangentBlocks& blocks, double t, const double* y, const double* ydot, Seed seed, Store store);
  // Every block seeded (direction k's tangent on y_r is seed(k, r)), pass(block, first) run on it,
  // and its tangents stored (store(k, r, d)); false as soon as a pass is.
  template <class Seed, class Store, class Pass>
  bool blocked_passes(TangentBlocks& blocks, const double* y, Seed seed, Store store, Pass pass);
  // One residual pass on ws at the seeded state y (dynamics/inverse_dynamics.hpp): out (nstate)
  // gets q̇ and u̇ with their tangents, c (m) is scratch. `factor`: form the value factors from
  // this pass (else those of the last one, at the same state, are used). False when the
  // residual form does not apply.
  template <class S>
  bool residual_pass(dynamics::Workspace<S>& ws, double t, const S* y, const double* ydot, S* out, S* c, bool factor);
  // The end of every residual pass, r = f − M u̇ in du and c: on the first block λ from r's value
  // and the check that u̇ solves the equations (false if not), then Aᵀλ's tangent added and every
  // tangent solved with the value factors.
  template <class S>
  bool solve_residual_tangents(dynamics::Workspace<S>& ws, const double* udot, S* du, S* c, bool first);
  template <class S>
  bool residual_vanishes(const S* c, const double* udot) const;
  // DOP853's stages (f not given): f and the sensitivity right-hand sides from the residual
  // passes alone, the first of them at u̇ = 0 (fused_residual_pass). False (ydot and sdot then
  // hold no result) where the residual form does not apply, or on the planar path.
  bool fused_residual_sensitivities(double t, const double* y, const double* const* s, double* ydot,
                                    double* const* sdot);
  // The first pass of fused_residual_sensitivities: the stages at u̇ = 0 give f on values
  // (dynamics::forcing_values), then u̇ and λ with M's factor from the same pass;
  // residual_from_rest completes the residual at u̇, and the tangents are solved as in
  // residual_pass, with that λ (u̇ and λ solve the equations by construction: only their
  // finiteness is checked). ydot gets f(t, y).
  template <class S>
  bool fused_residual_pass(dynamics::Workspace<S>& ws, double t, const S* y, double* ydot, S* out, S* c);
  // Its first half: the stages at u̇ = 0 on ws (out, c as there), f (dynamics::forcing_values),
  // then u̇ and λ (jacobian_multipliers_) on values into ydot. False where the value solve does
  // not apply (redundant rows) or is not finite.
  template <class S>
  bool value_pass(dynamics::Workspace<S>& ws, double t, const S* y, double* ydot, S* out, S* c);
  std::vector<double> fused_constraint_value_;  // m: −b, then scratch of the value solve
  // rhs() by value_pass on doubles: 3-D multipliers with the dense constraint solve, where it
  // takes fewer operations than the general one (which handles redundant rows).
  bool value_rhs_ = false;
  bool value_rhs_failed_ = false;  // this sample's value_pass could not evaluate once
  std::vector<double> value_out_, value_constraint_;  // value_pass's out and c (nstate, m)
  bool last_f_from_sensitivity_pass_ = false;
  template <int W>
  void evaluate_block(TangentBlock<W>& b, double t);
  // One sensitivity: a Dual pass costs less than a block of the narrowest compiled width (2);
  // two take one block of width 2, which costs less than two Dual passes.
  static constexpr int kSingleTangentPasses = 1;
  bool single_tangent() const { return num_sensitivities() <= kSingleTangentPasses; }
  // The embedding could not evaluate: rank lost (the rows named) or M not positive definite.
  template <class Scratch>
  [[noreturn]] void throw_embedding_failure(const Scratch& sc, double t) const;
  std::vector<double> u_full_, s_full_;  // after_step scratch (nu, nstate)
  // multiplier_sensitivities from the fused residual passes (3-D path, multipliers): false
  // where they do not apply or cannot evaluate (the multiplier form's passes then say which).
  bool fused_multiplier_sensitivities(double t, const double* y, const double* const* s, double* dlambda);
  // The same from multi-tangent passes of the multiplier form (NaN where λ cannot be computed).
  void multiplier_form_sensitivities(double t, const double* y, const double* const* s, double* dlambda);
  std::vector<double> recorded_rate_;  // nstate: ẏ of the recording passes and multipliers (scratch)
};

}  // namespace kanesens::sim
