#include "model/parameters.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "math/spatial.hpp"

namespace kanesens::model {

using math::Dual;
using math::unit_or_zero;

template <class S>
void evaluate_parameter_values(const Model& m, const S* given, S* parameters, S* values) {
  for (int i = 0; i < m.nparam(); ++i) parameters[i] = given[i];
  expr::Inputs<S> in;
  in.parameters = parameters;
  for (int i = 0; i < m.nparam(); ++i)
    if (m.parameters[i].derived) parameters[i] = m.parameters[i].value.evaluate(in);
  for (Slot s : m.parameter_slots) values[s] = m.expressions[s].evaluate(in);
}
#define KANESENS_INSTANTIATE(S) template void evaluate_parameter_values<S>(const Model&, const S*, S*, S*);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
KANESENS_INSTANTIATE(math::Dual2)
KANESENS_FOR_EACH_MULTI_DUAL(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

std::optional<ParameterProblem> find_parameter_problem(const Model& model, const double* parameters) {
  std::vector<double> given(parameters, parameters + model.nparam()), values(model.expressions.size(), 0.0);
  std::vector<double> params(given.size());
  evaluate_parameter_values(model, given.data(), params.data(), values.data());
  auto vec3 = [&](const Slot3& s) { return Eigen::Vector3d(values[s[0]], values[s[1]], values[s[2]]); };
  const SceneSpec& spec = model.spec;
  auto problem = [](std::string message, SourceLocation where, std::string key) {
    return std::optional<ParameterProblem>(ParameterProblem{std::move(message), std::move(where), std::move(key)});
  };
  for (int i = 0; i < model.nparam(); ++i)
    if (!std::isfinite(params[i])) {
      const std::size_t k = static_cast<std::size_t>(i);
      const SourceLocation w = k < spec.parameters.size() ? spec.parameters[k].value.where : SourceLocation{spec.file, 0, 0};
      const std::string key = k < spec.parameters.size() ? spec.parameters[k].value.key : "scene.parameters";
      return problem("parameter '" + model.parameters[i].name + "' is not finite (" + std::to_string(params[i]) +
                         "; a division by zero or a value out of range?)",
                     w, key);
    }
  for (Slot s : model.parameter_slots)
    if (!std::isfinite(values[s])) {
      const expr::Expression& e = model.expressions[s];
      return problem("expression '" + e.text() + "' is not finite (" + std::to_string(values[s]) +
                         "; a division by zero or a value out of range?)",
                     e.where(), e.key());
    }
  for (int b = 0; b < model.nbody(); ++b) {
    const std::string& name = model.bodies[b].name;
    const BodySpec& bs = spec.bodies[static_cast<std::size_t>(b)];
    const double m = values[model.bodies[b].mass];
    if (!(m > 0)) return problem("body '" + name + "': mass must be > 0, found " + std::to_string(m), bs.mass.where, bs.mass.key);
    const auto& slot = model.bodies[b].inertia;  // xx, yy, zz, xy, yz, xz
    Eigen::Matrix3d I;
    I << values[slot[0]], values[slot[3]], values[slot[5]], values[slot[3]], values[slot[1]], values[slot[4]],
        values[slot[5]], values[slot[4]], values[slot[2]];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
    const Eigen::Vector3d ev = eig.eigenvalues();
    const double scale = std::max(1e-300, ev.cwiseAbs().maxCoeff());
    if (ev.minCoeff() < -1e-12 * scale)
      return problem("body '" + name + "': inertia is not positive semi-definite (principal moments " +
                         std::to_string(ev[0]) + ", " + std::to_string(ev[1]) + ", " + std::to_string(ev[2]) + ")",
                     bs.where, bs.key + ".inertia");
    if (ev[0] + ev[1] < ev[2] - 1e-9 * scale)
      return problem("body '" + name + "': inertia violates the triangle inequality (principal moments " +
                         std::to_string(ev[0]) + " + " + std::to_string(ev[1]) + " < " + std::to_string(ev[2]) + ")",
                     bs.where, bs.key + ".inertia");
  }
  for (std::size_t ji = 0; ji < model.joints.size(); ++ji) {
    const Joint& j = model.joints[ji];
    const JointSpec& js = spec.joints[ji];
    const bool universal = j.type == JointType::universal;
    auto axis_where = [&](int which) {
      if (universal && js.axes.size() > static_cast<std::size_t>(which)) return js.axes[static_cast<std::size_t>(which)][0].where;
      if (js.axis) return (*js.axis)[0].where;
      return js.where;
    };
    const std::string axis_key = universal ? js.key + ".axes" : js.key + ".axis";
    if (j.axis[0] >= 0 && !(unit_or_zero<double>(vec3(j.axis)).norm() > 0))
      return problem("joint '" + j.name + "': axis has zero length", axis_where(0), universal ? axis_key + "[0]" : axis_key);
    if (j.axis2[0] >= 0 && !(unit_or_zero<double>(vec3(j.axis2)).norm() > 0))
      return problem("joint '" + j.name + "': second axis has zero length", axis_where(1), axis_key + "[1]");
    if (universal) {
      const Eigen::Vector3d a1 = vec3(j.axis), a2 = vec3(j.axis2);
      if (!(a1.cross(a2).norm() > 1e-9 * a1.norm() * a2.norm()))
        return problem("joint '" + j.name + "': its two axes are parallel; a universal joint needs two independent axes",
                       axis_where(1), axis_key + "[1]");
    }
  }
  // Constraint sizes that make a row vanish or divide by zero wherever the bodies are.
  for (std::size_t ci = 0; ci < model.constraints.size() && ci < spec.constraints.size(); ++ci) {
    const Constraint& c = model.constraints[ci];
    const ConstraintSpec& cs = spec.constraints[ci];
    if (c.kind == ConstraintKind::distance && !(values[c.length] > 0))
      return problem("constraint '" + c.name + "': length must be > 0, found " + std::to_string(values[c.length]) +
                         " (points that coincide: use type: coincident)",
                     cs.length.where, cs.length.key);
    if (c.kind == ConstraintKind::rolling) {
      if (!(values[c.radius] > 0))
        return problem("constraint '" + c.name + "': radius must be > 0, found " + std::to_string(values[c.radius]),
                       cs.radius.where, cs.radius.key);
      if (!(vec3(c.axis).norm() > 0))
        return problem("constraint '" + c.name + "': axis has zero length", cs.axis[0].where, cs.key + ".axis");
      if (!(vec3(c.normal).norm() > 0))
        return problem("constraint '" + c.name + "': normal has zero length", cs.normal[0].where, cs.key + ".normal");
    }
  }
  return std::nullopt;
}

std::string check_parameters(const Model& model, const double* parameters) {
  const auto p = find_parameter_problem(model, parameters);
  return p ? p->message : "";
}

}  // namespace kanesens::model
