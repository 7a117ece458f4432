#include "model/model.hpp"

namespace kanesens::model {

int Model::find_parameter(const std::string& n) const {
  for (int i = 0; i < nparam(); ++i)
    if (parameters[i].name == n) return i;
  return -1;
}
int Model::find_body(const std::string& n) const {
  if (n == "ground") return -1;
  for (int i = 0; i < nbody(); ++i)
    if (bodies[i].name == n) return i;
  return -2;
}
std::vector<double> Model::nominal_parameters() const {
  std::vector<double> p;
  for (const auto& par : parameters) p.push_back(par.nominal);
  return p;
}

}  // namespace kanesens::model
