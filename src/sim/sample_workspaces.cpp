#include "sim/sample_workspaces.hpp"

#include <algorithm>

namespace kanesens::sim {

using dynamics::Workspace;
using math::Dual;

SampleWorkspaces::SampleWorkspaces(const model::Model& model, const std::vector<InputRef>& sensitivities)
    : model_(model),
      sensitivities_(sensitivities),
      parameters_(model.nparam()),
      dq_parameters_(model.nparam() + sensitivities.size()),
      values_(model),
      jacobian_(model),
      tangent_(sensitivities.size()) {
  for (std::size_t i = 0; i < sensitivities_.size(); ++i)
    if (sensitivities_[i].kind == InputRef::Kind::parameter) tangent_[i] = std::make_unique<Workspace<Dual>>(model);
}

void SampleWorkspaces::set_parameters(const std::vector<double>& parameters) {
  parameters_ = parameters;
  dynamics::set_parameters(model_, values_, parameters_.data());
  std::vector<Dual> p(parameters_.begin(), parameters_.end());
  dynamics::set_parameters(model_, jacobian_, p.data());
  for (std::size_t i = 0; i < sensitivities_.size(); ++i) {
    if (!tangent_[i]) continue;
    p[sensitivities_[i].index].d = 1;
    dynamics::set_parameters(model_, *tangent_[i], p.data());
    p[sensitivities_[i].index].d = 0;
  }
  std::copy(parameters_.begin(), parameters_.end(), dq_parameters_.begin());
  for (std::size_t i = 0; i < sensitivities_.size(); ++i)
    dq_parameters_[model_.nparam() + i] = sensitivities_[i].kind == InputRef::Kind::parameter ? 0.0 : 1.0;
}

Workspace<double>& SampleWorkspaces::values() {
  // CVODES's difference-quotient sensitivities perturb dq_parameters_ in place.
  for (int k = 0; k < model_.nparam(); ++k) {
    if (dq_parameters_[k] != parameters_[k]) {
      std::copy(dq_parameters_.begin(), dq_parameters_.begin() + model_.nparam(), parameters_.begin());
      dynamics::set_parameters(model_, values_, parameters_.data());
      break;
    }
  }
  return values_;
}

std::vector<int> SampleWorkspaces::dq_parameter_list() const {
  std::vector<int> plist;
  for (std::size_t i = 0; i < sensitivities_.size(); ++i)
    plist.push_back(sensitivities_[i].kind == InputRef::Kind::parameter ? sensitivities_[i].index
                                                                        : model_.nparam() + static_cast<int>(i));
  return plist;
}

}  // namespace kanesens::sim
