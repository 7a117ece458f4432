// The workspaces of one sample of a KaneProblem: per-thread scratch with the sample's parameters
// loaded. One on doubles (the integrated right-hand side, projection and outputs) and one on
// dual numbers per tangent: a parameter sensitivity's carries ∂/∂p_i on its parameters, the
// Jacobian's and the initial-condition sensitivities' carry none.
#pragma once
#include <memory>
#include <vector>

#include "dynamics/workspace.hpp"
#include "math/dual.hpp"
#include "sim/inputs.hpp"

namespace kanesens::sim {

class SampleWorkspaces {
 public:
  SampleWorkspaces(const model::Model& model, const std::vector<InputRef>& sensitivities);

  // Loads a parameter set (np) into every workspace.
  void set_parameters(const std::vector<double>& parameters);
  const std::vector<double>& parameters() const { return parameters_; }

  // The double workspace with the current parameters (see dq_parameters()).
  dynamics::Workspace<double>& values();
  // The dual workspace of the Jacobian (no parameter tangent).
  dynamics::Workspace<math::Dual>& jacobian() { return jacobian_; }
  // The dual workspace of sensitivity i: its parameter's tangent, or the Jacobian's.
  dynamics::Workspace<math::Dual>& tangent(int i) { return tangent_[i] ? *tangent_[i] : jacobian_; }

  // For CVODES's difference-quotient sensitivities: the np parameters and ns dummies (one per
  // sensitivity: what an initial-condition sensitivity perturbs), which CVODES perturbs in place
  // between right-hand sides; values() reloads the parameters when they changed.
  double* dq_parameters() { return dq_parameters_.data(); }
  std::vector<int> dq_parameter_list() const;

 private:
  const model::Model& model_;
  std::vector<InputRef> sensitivities_;
  std::vector<double> parameters_;     // as loaded in values_
  std::vector<double> dq_parameters_;  // np + ns
  dynamics::Workspace<double> values_;
  dynamics::Workspace<math::Dual> jacobian_;
  std::vector<std::unique_ptr<dynamics::Workspace<math::Dual>>> tangent_;  // parameter sensitivities
};

}  // namespace kanesens::sim
