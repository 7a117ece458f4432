#include "sim/output_plan.hpp"

#include <algorithm>
#include <functional>

namespace kanesens::sim {

using model::expr::VarKind;

std::vector<std::string> output_component_suffixes(OutputKind kind, const model::Model& m, int constraint) {
  switch (kind) {
    case OutputKind::position:
    case OutputKind::velocity:
    case OutputKind::acceleration:
    case OutputKind::angular_velocity: return {"x", "y", "z"};
    case OutputKind::orientation: return {"qw", "qx", "qy", "qz"};
    case OutputKind::joint_load: return {"fx", "fy", "fz", "mx", "my", "mz"};
    case OutputKind::force_element: return {"length", "rate", "tension"};
    case OutputKind::constraint_force: {
      const model::Constraint& c = m.constraints[static_cast<std::size_t>(constraint)];
      std::vector<std::string> out;
      for (int r = 0; r < c.nrows; ++r) {
        const std::string& row = m.constraint_row_names[static_cast<std::size_t>(c.row_offset + r)];
        const auto dot = row.rfind('.');
        if (dot == std::string::npos || row.substr(0, dot) != c.name) return {};  // one unnamed row
        out.push_back(row.substr(dot + 1));
      }
      return out;
    }
    case OutputKind::energy:
    case OutputKind::expression:
    case OutputKind::reduction:
    case OutputKind::eigenvalues: return {};
  }
  return {};
}

Level kind_level(OutputKind kind, EnergyKind energy) {
  switch (kind) {
    case OutputKind::position:
    case OutputKind::orientation: return Level::position;
    case OutputKind::velocity:
    case OutputKind::angular_velocity:
    case OutputKind::force_element: return Level::velocity;
    case OutputKind::acceleration:
    case OutputKind::constraint_force:
    case OutputKind::joint_load: return Level::acceleration;
    case OutputKind::energy: return energy == EnergyKind::potential ? Level::position : Level::velocity;
    case OutputKind::expression:
    case OutputKind::reduction:
    case OutputKind::eigenvalues: return Level::parameters;  // from what they read; eigenvalues: not a series
  }
  return Level::acceleration;
}

int OutputPlan::node_of_slot(int slot) const {
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const OutputNode& n = nodes[i];
    if (slot >= n.slot && slot < n.slot + static_cast<int>(n.components.size())) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> order_outputs(const std::vector<std::vector<int>>& depends, std::vector<int>& cycle) {
  // Depth-first, in index order; a node met again while on the stack closes a cycle.
  const std::size_t n = depends.size();
  enum class Mark : unsigned char { none, active, done };
  std::vector<Mark> mark(n, Mark::none);
  std::vector<int> order, stack;
  cycle.clear();
  std::function<bool(int)> visit = [&](int v) {
    if (mark[static_cast<std::size_t>(v)] == Mark::done) return true;
    if (mark[static_cast<std::size_t>(v)] == Mark::active) {
      cycle.assign(std::find(stack.begin(), stack.end(), v), stack.end());
      cycle.push_back(v);
      return false;
    }
    mark[static_cast<std::size_t>(v)] = Mark::active;
    stack.push_back(v);
    for (int d : depends[static_cast<std::size_t>(v)])
      if (!visit(d)) return false;
    stack.pop_back();
    mark[static_cast<std::size_t>(v)] = Mark::done;
    order.push_back(v);
    return true;
  };
  for (std::size_t v = 0; v < n; ++v)
    if (!visit(static_cast<int>(v))) return {};
  return order;
}

namespace {

// The series nodes `starts` read, directly or not, with themselves, in evaluation order.
OutputProgram program_of(const OutputPlan& plan, const std::vector<int>& starts) {
  std::vector<unsigned char> in(plan.nodes.size(), 0);
  std::function<void(int)> add = [&](int v) {
    const OutputNode& node = plan.nodes[static_cast<std::size_t>(v)];
    if (!node.series || in[static_cast<std::size_t>(v)]) return;
    in[static_cast<std::size_t>(v)] = 1;
    for (int d : node.depends) add(d);
  };
  for (int v : starts) add(v);
  OutputProgram p;
  for (std::size_t v = 0; v < plan.nodes.size(); ++v)
    if (in[v]) {
      p.nodes.push_back(static_cast<int>(v));
      p.level = std::max(p.level, plan.nodes[v].level);
    }
  return p;
}

}  // namespace

void finish_output_plan(OutputPlan& plan, const std::vector<int>& user_order) {
  std::vector<int> record_starts, at_starts, integrand_starts, event_starts, extremum_starts, at_event_starts;
  plan.event_nodes.clear();
  plan.event_occurrences = 0;
  plan.extremum_nodes.clear();
  plan.at_event_nodes.clear();
  plan.at_times.clear();
  plan.quadrature_nodes.clear();
  plan.scalar_expressions.clear();
  for (std::size_t v = 0; v < plan.nodes.size(); ++v) {
    OutputNode& node = plan.nodes[v];
    Level level = kind_level(node.kind, node.energy);
    if (node.kind == OutputKind::expression) {
      const auto& e = node.expression;
      if (!e.variables(VarKind::time).empty() || !e.variables(VarKind::coordinate).empty())
        level = std::max(level, Level::position);
      if (!e.variables(VarKind::speed).empty()) level = std::max(level, Level::velocity);
    }
    for (int d : node.depends) level = std::max(level, plan.nodes[static_cast<std::size_t>(d)].level);
    node.level = level;
    if (node.series && node.recorded) record_starts.push_back(static_cast<int>(v));
    if (node.kind == OutputKind::reduction) {
      if (node.reduce == Reduction::at) {
        at_starts.push_back(node.of);
        plan.at_times.push_back(node.at);
      } else if (node.reduce == Reduction::event) {
        event_starts.push_back(node.of);
        plan.event_nodes.push_back(static_cast<int>(v));
        plan.event_occurrences = std::max(plan.event_occurrences, node.recorded_times);
      } else if (is_extremum(node.reduce)) {
        extremum_starts.push_back(node.of);
        plan.extremum_nodes.push_back(static_cast<int>(v));
      } else if (node.reduce == Reduction::at_event) {
        at_event_starts.push_back(node.of);
        plan.at_event_nodes.push_back(static_cast<int>(v));
      } else {
        integrand_starts.push_back(node.of);
        node.quadrature = static_cast<int>(plan.quadrature_nodes.size());
        plan.quadrature_nodes.push_back(static_cast<int>(v));
      }
    }
    if (!node.series && node.kind == OutputKind::expression) plan.scalar_expressions.push_back(static_cast<int>(v));
  }
  std::sort(plan.at_times.begin(), plan.at_times.end());
  plan.at_times.erase(std::unique(plan.at_times.begin(), plan.at_times.end()), plan.at_times.end());
  plan.record = program_of(plan, record_starts);
  plan.at = program_of(plan, at_starts);
  plan.integrands = program_of(plan, integrand_starts);
  plan.events = program_of(plan, event_starts);
  plan.extrema = program_of(plan, extremum_starts);
  plan.at_event = program_of(plan, at_event_starts);
  plan.series_slots.clear();
  plan.scalar_slots.clear();
  plan.series_names.clear();
  plan.scalar_names.clear();
  for (int v : user_order) {
    const OutputNode& node = plan.nodes[static_cast<std::size_t>(v)];
    if (!node.recorded) continue;
    for (std::size_t c = 0; c < node.components.size(); ++c) {
      (node.series ? plan.series_slots : plan.scalar_slots).push_back(node.slot + static_cast<int>(c));
      (node.series ? plan.series_names : plan.scalar_names).push_back(node.components[c]);
    }
  }
}

}  // namespace kanesens::sim
