// The inputs of one sample: parameter values and initial conditions. Names resolve to either a
// scene parameter ("m2") or an initial condition ("elbow.q0", "ball.q0[1]", "cart.u0").
#pragma once
#include <string>
#include <vector>

#include "model/model.hpp"

namespace kanesens::sim {

using model::Model;

struct InputRef {
  enum class Kind { parameter, initial_condition };
  Kind kind = Kind::parameter;
  int index = 0;  // parameter index, or state index (position in y = [q; u]) of the initial value
  std::string name;
};

// Throws InputError (key `context`) with a did-you-mean when `name` is neither.
InputRef resolve_input(const Model& model, const std::string& name, const std::string& context);
// True if `name` is a parameter or initial-condition name of the model.
bool is_input_name(const Model& model, const std::string& name);

struct SampleInputs {
  std::vector<double> parameters;         // np
  std::vector<double> initial_values;     // nstate: explicit initial conditions...
  std::vector<unsigned char> initial_set; // ...used where set (else the scene's q0/u0)

  explicit SampleInputs(const Model& model);  // nominal parameters, scene initial conditions
  void set(const InputRef& ref, double value);
  double get(const Model& model, const InputRef& ref) const;  // initial condition: value if set, else NaN
};

}  // namespace kanesens::sim
