#include "study/setup.hpp"

#include <map>

#include "model/build_model.hpp"
#include "sim/kane_problem.hpp"
#include "sim/linearize.hpp"
#include "util/did_you_mean.hpp"
#include "study/build_outputs.hpp"

namespace kanesens::study {
namespace {

// --set values that name scene parameters (the others are initial conditions, or unknown).
std::map<std::string, double> parameter_overrides(const StudySpec& st) {
  std::map<std::string, double> out;
  for (const auto& [name, v] : st.set_inputs)
    for (const auto& p : st.scene.parameters)
      if (p.name == name) out[name] = v;
  return out;
}

// resolve_input, with the error placed where the name is written in the study file.
sim::InputRef resolve_at(const model::Model& model, const std::string& name, const std::string& key,
                         const SourceLocation& where) {
  try {
    return sim::resolve_input(model, name, key);
  } catch (const InputError& e) {
    throw InputError(where, e.key_path(), e.detail());
  }
}

}  // namespace

StudySetup setup_study(const std::string& path, const std::vector<std::string>& set) {
  StudySpec spec = parse_study_file(path, set);
  const std::map<std::string, double> overrides = parameter_overrides(spec);
  model::Model model = model::build_model(spec.scene, overrides);
  sim::SampleInputs base(model);
  Design design(spec.sampling, spec.vary);
  StudySetup s{set, std::move(spec), std::move(model), std::move(base), std::move(design), {}, {}, {}, {}};
  const StudySpec& st = s.spec;
  for (const auto& [name, v] : st.set_inputs)
    if (!overrides.count(name)) s.base.set(sim::resolve_input(s.model, name, "--set " + name), v);
  for (std::size_t d = 0; d < st.vary.size(); ++d)
    s.varied.push_back(resolve_at(s.model, st.vary[d].name, "vary." + st.vary[d].name, st.vary_where[d]));
  for (std::size_t i = 0; i < st.sensitivities.size(); ++i)
    s.sensitivities.push_back(resolve_at(s.model, st.sensitivities[i], "sensitivities[" + std::to_string(i) + "]",
                                         st.sensitivity_where[i]));

  const bool constrained = s.model.nconstraint_rows > 0;
  s.record.states = st.record.count(RecordItem::states) > 0;
  s.record.sensitivities = st.record.count(RecordItem::sensitivities) > 0 && !s.sensitivities.empty();
  s.record.energy = st.record.count(RecordItem::energy) > 0;
  s.record.multipliers = st.record.count(RecordItem::multipliers) > 0 && constrained;
  s.record.constraint_residual = st.record.count(RecordItem::constraint_residual) > 0 && constrained;
  s.record.poses = st.record.count(RecordItem::poses) > 0;
  if (st.record.count(RecordItem::sensitivities) && s.sensitivities.empty())
    throw InputError(st.record_where, "record", "'sensitivities' is recorded but the study lists no sensitivities");
  if (!st.solver.atol_per_state.empty()) {
    if (static_cast<int>(st.solver.atol_per_state.size()) != s.model.nstate())
      throw InputError(st.atol_where, "solver.atol",
                       "expected one entry per state (" + std::to_string(s.model.nstate()) + ": " +
                           join_names(s.model.state_names) + "), found " + std::to_string(st.solver.atol_per_state.size()));
    if (constrained && st.constraints.formulation == sim::ConstraintOptions::Formulation::embedding)
      throw InputError(st.atol_where, "solver.atol",
                       "a list of per-state tolerances is not supported with formulation: embedding (it integrates "
                       "fewer states); give one number");
  }
  // The nominal sample at its initial state: a constraint that constrains nothing there, equations
  // that are not finite or a mass matrix that is not positive definite are found now, not in
  // every sample after a run's file exists.
  sim::KaneProblem nominal(s.model, s.recorded_sensitivities(), st.constraints, st.output_times.front());
  nominal.set_sample(s.base);
  nominal.validate_initial_state();
  const double t0 = st.output_times.front();
  auto nominal_linearization = [&](const sim::LinearizeOptions& options) {
    std::vector<double> y0(static_cast<std::size_t>(nominal.size())), y(static_cast<std::size_t>(s.model.nstate()));
    nominal.initial_state(y0.data());
    nominal.full_state(t0, y0.data(), y.data());
    return sim::linearize(s.model, nominal.workspaces().parameters(), t0, y, options);
  };
  s.outputs = std::make_shared<const sim::OutputPlan>(
      build_output_plan(st.outputs, s.model, st.output_times, nominal_linearization));
  if (!s.outputs->empty()) s.record.outputs = s.outputs.get();
  return s;
}

std::vector<sim::InputRef> StudySetup::recorded_sensitivities() const {
  return record.sensitivities || record.outputs ? sensitivities : std::vector<sim::InputRef>{};
}

sim::SampleInputs StudySetup::sample(std::int64_t i, std::span<double> values) const {
  sim::SampleInputs in = base;
  design.sample(i, values);
  for (std::size_t d = 0; d < values.size(); ++d) in.set(varied[d], values[d]);
  return in;
}

}  // namespace kanesens::study
