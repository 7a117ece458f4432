#include "sim/inputs.hpp"

#include <cmath>

#include "util/did_you_mean.hpp"
#include "util/error.hpp"

namespace kanesens::sim {

using namespace kanesens::model;

bool is_input_name(const Model& m, const std::string& name) {
  if (m.find_parameter(name) >= 0) return true;
  for (const auto& n : m.initial_condition_names)
    if (n == name) return true;
  return false;
}

InputRef resolve_input(const Model& m, const std::string& name, const std::string& context) {
  if (const int p = m.find_parameter(name); p >= 0) {
    if (m.parameters[p].derived)
      throw InputError({}, context, "parameter '" + name + "' is derived from other parameters ('" +
                                        m.parameters[p].value.text() +
                                        "'); vary or differentiate with respect to those, or --set it to a number");
    return {InputRef::Kind::parameter, p, name};
  }
  for (std::size_t i = 0; i < m.initial_condition_names.size(); ++i)
    if (m.initial_condition_names[i] == name) return {InputRef::Kind::initial_condition, static_cast<int>(i), name};
  std::vector<std::string> all;
  for (const auto& p : m.parameters) all.push_back(p.name);
  all.insert(all.end(), m.initial_condition_names.begin(), m.initial_condition_names.end());
  std::string hint = did_you_mean(name, all);
  if (name.size() > 3 && name.substr(name.size() - 2) == ".q") hint += " (initial conditions end in .q0 / .u0)";
  throw InputError({}, context, "'" + name + "' is neither a parameter nor an initial condition of scene '" +
                                    m.name + "'" + hint + "; parameters: " +
                                    [&] {
                                      std::vector<std::string> p;
                                      for (const auto& x : m.parameters) p.push_back(x.name);
                                      return join_names(p);
                                    }() +
                                    "; initial conditions: " + join_names(m.initial_condition_names));
}

SampleInputs::SampleInputs(const Model& m)
    : parameters(m.nominal_parameters()), initial_values(m.nstate(), std::nan("")), initial_set(m.nstate(), 0) {}

void SampleInputs::set(const InputRef& ref, double value) {
  if (ref.kind == InputRef::Kind::parameter) {
    parameters[ref.index] = value;
  } else {
    initial_values[ref.index] = value;
    initial_set[ref.index] = 1;
  }
}

double SampleInputs::get(const Model&, const InputRef& ref) const {
  return ref.kind == InputRef::Kind::parameter ? parameters[ref.index] : initial_values[ref.index];
}

}  // namespace kanesens::sim
