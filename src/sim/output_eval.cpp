#include "sim/output_eval.hpp"

#include "dynamics/equations.hpp"
#include "math/dual.hpp"
#include "math/dual2.hpp"

namespace kanesens::sim {

using dynamics::Vec3;
using dynamics::Workspace;

template <class S>
bool evaluate_series(const OutputPlan& plan, const OutputProgram& program, const model::Model& m, Workspace<S>& ws,
                     const dynamics::DynamicsOptions& options, const S& t, const S* y, S* values,
                     OutputScratch<S>& scratch) {
  if (program.empty()) return true;
  const S* q = y;
  const S* u = y + m.nq;
  if (program.level == Level::acceleration) {
    if (!dynamics::evaluate_rhs(m, ws, t, y, scratch.ydot.data(), options)) return false;
  } else if (program.level != Level::parameters) {
    dynamics::evaluate_state_expressions(m, ws, t, q, u);
    dynamics::compute_position(m, ws, q);
    if (program.level == Level::velocity) dynamics::compute_velocity(m, ws, u);
  }
  bool loads_done = false;
  model::expr::Inputs<S> parameters_only;
  parameters_only.parameters = ws.parameters.data();
  for (int v : program.nodes) {
    const OutputNode& n = plan.nodes[static_cast<std::size_t>(v)];
    S* out = values + n.slot;
    auto put3 = [&](const Vec3<S>& x) {
      out[0] = x[0];
      out[1] = x[1];
      out[2] = x[2];
    };
    auto point = [&] {
      return Vec3<S>(n.point[0].evaluate(parameters_only), n.point[1].evaluate(parameters_only),
                     n.point[2].evaluate(parameters_only));
    };
    switch (n.kind) {
      case OutputKind::position: put3(dynamics::point_position(m, ws, n.body, point())); break;
      case OutputKind::velocity: put3(dynamics::point_velocity(m, ws, n.body, point())); break;
      case OutputKind::acceleration: put3(dynamics::point_acceleration(m, ws, n.body, point())); break;
      case OutputKind::angular_velocity: put3(dynamics::angular_velocity(m, ws, n.body)); break;
      case OutputKind::orientation: {
        const auto e = dynamics::rotation_quaternion<S>(dynamics::body_rotation(m, ws, n.body));
        for (int i = 0; i < 4; ++i) out[i] = e[i];
        break;
      }
      case OutputKind::constraint_force: {
        const model::Constraint& c = m.constraints[static_cast<std::size_t>(n.constraint)];
        for (int r = 0; r < c.nrows; ++r) out[r] = ws.multipliers[c.row_offset + r];
        break;
      }
      case OutputKind::joint_load: {
        if (!loads_done) dynamics::joint_loads(m, ws, scratch.loads);
        loads_done = true;
        const dynamics::JointLoad<S>& l = scratch.loads[static_cast<std::size_t>(n.joint)];
        put3(l.force);
        out[3] = l.moment[0];
        out[4] = l.moment[1];
        out[5] = l.moment[2];
        break;
      }
      case OutputKind::force_element: {
        const dynamics::ForceElementState<S> f = dynamics::force_element_state(m, ws, n.force);
        out[0] = f.length;
        out[1] = f.rate;
        out[2] = f.tension;
        break;
      }
      case OutputKind::energy: {
        const S T = n.energy == EnergyKind::potential ? S(0) : dynamics::kinetic_energy(m, ws);
        const S V = n.energy == EnergyKind::kinetic ? S(0) : dynamics::potential_energy(m, ws, q);
        out[0] = T + V;
        break;
      }
      case OutputKind::expression: {
        model::expr::Inputs<S> in;
        in.parameters = ws.parameters.data();
        in.coordinates = q;
        in.speeds = u;
        in.quantities = values;
        in.time = t;
        out[0] = n.expression.evaluate(in);
        break;
      }
      case OutputKind::reduction:
      case OutputKind::eigenvalues: break;  // not a series
    }
  }
  return true;
}

template <class S>
void evaluate_scalar_expressions(const OutputPlan& plan, const S* parameters, S* values) {
  model::expr::Inputs<S> in;
  in.parameters = parameters;
  in.quantities = values;
  for (int v : plan.scalar_expressions) {
    const OutputNode& n = plan.nodes[static_cast<std::size_t>(v)];
    values[n.slot] = n.expression.evaluate(in);
  }
}

#define KANESENS_INSTANTIATE(S)                                                                            \
  template bool evaluate_series<S>(const OutputPlan&, const OutputProgram&, const model::Model&, Workspace<S>&, \
                                   const dynamics::DynamicsOptions&, const S&, const S*, S*, OutputScratch<S>&); \
  template void evaluate_scalar_expressions<S>(const OutputPlan&, const S*, S*);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(math::Dual)
KANESENS_INSTANTIATE(math::Dual2)  // the derivatives of extrema's times (sim/output_events.cpp)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::sim
