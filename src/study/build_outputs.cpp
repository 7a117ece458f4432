#include "study/build_outputs.hpp"

#include <algorithm>
#include <cstdio>

#include "util/did_you_mean.hpp"

namespace kanesens::study {
namespace {

using model::Model;
using model::expr::NameTable;
using model::expr::VarKind;
using sim::OutputKind;
using sim::OutputNode;

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

// The index of `name` among `names`, or an InputError listing them.
template <class Items, class Name>
int find_named(const Items& items, Name name_of, const OutputSpec& o, const char* what, const char* plural) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < items.size(); ++i) {
    names.push_back(name_of(items[i]));
    if (names.back() == o.target) return static_cast<int>(i);
  }
  throw InputError(o.target_where, o.target_key,
                   std::string("unknown ") + what + " '" + o.target + "'" + did_you_mean(o.target, names) + "; " +
                       plural + " are: " + join_names(names));
}

struct Builder {
  const std::vector<OutputSpec>& specs;
  const Model& m;
  std::span<const double> times;
  const NominalLinearization& nominal;
  sim::OutputPlan plan;
  std::vector<int> user_node;         // spec → its node
  std::vector<int> spec_of_node;      // node → the spec it comes from (−1: a constraint's λ)
  std::vector<std::string> node_key;  // where an error about the node is reported
  NameTable parameters, names;

  void add_node(OutputNode n, int spec, std::string key) {
    n.slot = plan.nvalues;
    plan.nvalues += static_cast<int>(n.components.size());
    plan.nodes.push_back(std::move(n));
    spec_of_node.push_back(spec);
    node_key.push_back(std::move(key));
  }
  const SourceLocation& where_of(int node) const {
    static const SourceLocation none;
    const int s = spec_of_node[static_cast<std::size_t>(node)];
    return s < 0 ? none : specs[static_cast<std::size_t>(s)].where;
  }

  void check_name(const OutputSpec& o, const std::vector<std::string>& components) {
    const std::string key = o.key();
    if (is_reserved_output_name(o.name))
      throw InputError(o.where, key, "'" + o.name + "' names a recorded output (record: energy, constraint_residual); choose another name");
    for (const auto& c : components) {
      const bool taken = c == "t" || c == "pi" || m.find_parameter(c) >= 0 ||
                         std::find(m.state_names.begin(), m.state_names.end(), c) != m.state_names.end();
      if (taken)
        throw InputError(o.where, key, "'" + c + "' is already a name of the scene (t, pi, a parameter or a state), which expressions read; choose another output name");
    }
  }

  // A body-frame point: three expressions of the parameters.
  void compile_point(OutputNode& n, const OutputSpec& o) {
    for (int i = 0; i < 3; ++i) {
      const model::ExprText& e = o.point[static_cast<std::size_t>(i)];
      n.point[static_cast<std::size_t>(i)] =
          model::expr::compile(e.text, parameters, e.where.file.empty() ? o.where : e.where,
                               "outputs." + o.name + ".point[" + std::to_string(i) + "]");
    }
  }

  // Kind eigenvalues: the reduced states and the number of eigenvalues, from the nominal sample.
  void add_eigenvalues(OutputNode& n, const OutputSpec& o) {
    const std::string key = o.key();
    if (!nominal) throw InputError(o.where, key, "eigenvalue outputs need the nominal sample's initial state");
    sim::LinearizeOptions lo;
    lo.coordinates = o.coordinates;
    lo.speeds = o.speeds;
    sim::Linearization lin;
    try {
      lin = nominal(lo);
    } catch (const InputError& e) {
      const bool speeds = e.key_path() == "--speeds";
      throw InputError(speeds ? o.speeds_where : o.coordinates_where, key + (speeds ? ".speeds" : ".coordinates"), e.detail());
    } catch (const std::runtime_error& e) {
      throw InputError(o.where, key, std::string("cannot linearize at the nominal initial state: ") + e.what());
    }
    const long dim = static_cast<long>(lin.A.rows());
    if (dim == 0) throw InputError(o.where, key, "the linearized system has no states at the initial state (every one is dependent or ignorable)");
    if (o.count > dim)
      throw InputError(o.where, key + ".count", "count: " + std::to_string(o.count) + " but the linearized system has " +
                                                    std::to_string(dim) + " eigenvalues");
    n.linear_coordinates = lin.coordinates;
    n.linear_speeds = lin.speeds;
    n.eigenvalue_count = static_cast<int>(o.count > 0 ? o.count : dim);
    n.series = false;
  }

  void add_spec(std::size_t si) {
    const OutputSpec& o = specs[si];
    const std::string key = o.key();
    OutputNode n;
    n.name = o.name;
    n.kind = o.kind;
    n.energy = o.energy;
    switch (o.kind) {
      case OutputKind::position:
      case OutputKind::velocity:
      case OutputKind::acceleration:
      case OutputKind::orientation:
      case OutputKind::angular_velocity: {
        n.body = m.find_body(o.target);
        if (n.body == -1) throw InputError(o.target_where, o.target_key, "'ground' does not move; name a body");
        if (n.body < 0) n.body = find_named(m.bodies, [](const model::Body& b) { return b.name; }, o, "body", "bodies");
        compile_point(n, o);
        break;
      }
      case OutputKind::joint_load:
        n.joint = find_named(m.joints, [](const model::Joint& j) { return j.name; }, o, "joint", "joints");
        break;
      case OutputKind::constraint_force:
        n.constraint = find_named(m.constraints, [](const model::Constraint& c) { return c.name; }, o, "constraint", "constraints");
        break;
      case OutputKind::force_element:
        n.force = find_named(m.forces, [](const model::Force& f) { return f.name; }, o, "force", "forces");
        if (m.forces[static_cast<std::size_t>(n.force)].kind != model::ForceKind::spring_damper)
          throw InputError(o.target_where, o.target_key,
                           "'" + o.target + "' is a " + model::force_kind_name(m.forces[static_cast<std::size_t>(n.force)].kind) +
                               "; force_element outputs (length, rate, tension) are for spring_damper elements");
        break;
      case OutputKind::energy:
      case OutputKind::expression: break;
      case OutputKind::eigenvalues: add_eigenvalues(n, o); break;
      case OutputKind::reduction: {
        // The series reduced: a hidden expression node just before this one.
        OutputNode of;
        of.name = o.name + ".of";
        of.kind = OutputKind::expression;
        of.recorded = false;
        of.components = {of.name};
        add_node(std::move(of), static_cast<int>(si), key + (o.event ? ".when" : ".of"));
        n.of = static_cast<int>(plan.nodes.size()) - 1;
        n.depends = {n.of};
        n.reduce = o.reduce;
        n.series = false;
        n.direction = o.direction;
        n.stop = o.stop;
        n.max_count = o.max_count;
        n.recorded_times = o.recorded_times;
        n.occurrence = o.occurrence;
        break;
      }
    }
    const std::vector<std::string> suffixes = sim::output_component_suffixes(o.kind, m, n.constraint);
    for (const auto& s : suffixes) n.components.push_back(o.name + "." + s);
    if (suffixes.empty()) n.components = {o.name};
    if (o.event) n.components = {o.name + ".time", o.name + ".count"};
    if (o.kind == OutputKind::eigenvalues) {
      n.components.clear();
      for (int k = 0; k < n.eigenvalue_count; ++k) {
        n.components.push_back(o.name + ".re" + std::to_string(k));
        n.components.push_back(o.name + ".im" + std::to_string(k));
      }
    }
    check_name(o, n.components);
    user_node.push_back(static_cast<int>(plan.nodes.size()));
    add_node(std::move(n), static_cast<int>(si), o.kind == OutputKind::expression ? key + ".expression" : key);
  }

  // An at_event output's event, by name (events may be listed after the outputs).
  void resolve_events() {
    for (std::size_t si = 0; si < specs.size(); ++si) {
      const OutputSpec& o = specs[si];
      if (o.kind != OutputKind::reduction || o.event || o.reduce != sim::Reduction::at_event) continue;
      std::string known;
      for (std::size_t sj = 0; sj < specs.size(); ++sj) {
        if (!specs[sj].event) continue;
        if (specs[sj].name == o.at_event) plan.nodes[static_cast<std::size_t>(user_node[si])].event = user_node[sj];
        known += (known.empty() ? "" : ", ") + specs[sj].name;
      }
      if (plan.nodes[static_cast<std::size_t>(user_node[si])].event < 0)
        throw InputError(o.reduce_where, o.key() + ".at_event",
                         "no event named '" + o.at_event + "'" + (known.empty() ? " (the study has no events:)" : "; events: " + known));
    }
  }

  // The names expressions read: outputs first (they shadow a constraint's rows of the same
  // name), then t, the states and parameters, then every constraint row (its λ).
  void fill_names() {
    for (std::size_t si = 0; si < specs.size(); ++si) {
      const OutputNode& n = plan.nodes[static_cast<std::size_t>(user_node[si])];
      for (std::size_t c = 0; c < n.components.size(); ++c)
        names.add(n.components[c], {VarKind::quantity, n.slot + static_cast<int>(c)});
      if (n.components.size() > 1 || n.components[0] != n.name)
        names.refuse(n.name, "'" + n.name + "' is a vector output; name one of its components: " + join_names(n.components));
    }
    names.add("t", {VarKind::time, 0});
    for (int i = 0; i < m.nq; ++i) names.add(m.coordinate_names[static_cast<std::size_t>(i)], {VarKind::coordinate, i});
    for (int i = 0; i < m.nu; ++i) names.add(m.speed_names[static_cast<std::size_t>(i)], {VarKind::speed, i});
    for (int i = 0; i < m.nparam(); ++i) names.add(m.parameters[static_cast<std::size_t>(i)].name, {VarKind::parameter, i});
    for (std::size_t c = 0; c < m.constraints.size(); ++c) {
      OutputNode n;
      n.name = m.constraints[c].name;
      n.kind = OutputKind::constraint_force;
      n.constraint = static_cast<int>(c);
      n.recorded = false;
      for (int r = 0; r < m.constraints[c].nrows; ++r)
        n.components.push_back(m.constraint_row_names[static_cast<std::size_t>(m.constraints[c].row_offset + r)]);
      add_node(std::move(n), -1, "");
      const OutputNode& added = plan.nodes.back();
      for (std::size_t r = 0; r < added.components.size(); ++r)
        if (!names.find(added.components[r])) names.add(added.components[r], {VarKind::quantity, added.slot + static_cast<int>(r)});
    }
  }

  void compile_expressions() {
    for (std::size_t v = 0; v < plan.nodes.size(); ++v) {
      OutputNode& n = plan.nodes[v];
      if (n.kind != OutputKind::expression) continue;
      const OutputSpec& o = specs[static_cast<std::size_t>(spec_of_node[v])];
      n.expression = model::expr::compile(o.expression.text, names, o.expression.where, node_key[v]);
      for (int slot : n.expression.variables(VarKind::quantity)) {
        const int d = plan.node_of_slot(slot);
        if (std::find(n.depends.begin(), n.depends.end(), d) == n.depends.end()) n.depends.push_back(d);
      }
    }
  }

  // Puts the nodes in evaluation order (a cycle is an error) and renumbers their references.
  void order() {
    std::vector<std::vector<int>> depends;
    for (const OutputNode& n : plan.nodes) depends.push_back(n.depends);
    std::vector<int> cycle;
    const std::vector<int> order = sim::order_outputs(depends, cycle);
    if (order.empty()) {
      // The outputs' names along the cycle (an `of:` expression is its output's).
      std::vector<std::string> names;
      for (int v : cycle) {
        const int s = spec_of_node[static_cast<std::size_t>(v)];
        const std::string name = s < 0 ? plan.nodes[static_cast<std::size_t>(v)].name : specs[static_cast<std::size_t>(s)].name;
        if (names.empty() || names.back() != name) names.push_back(name);
      }
      if (names.size() == 1) names.push_back(names.front());  // reads itself
      std::string path;
      for (const auto& name : names) path += (path.empty() ? "" : " -> ") + name;
      throw InputError(where_of(cycle.front()), node_key[static_cast<std::size_t>(cycle.front())],
                       "outputs depend on each other in a cycle: " + path);
    }
    std::vector<int> position(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) position[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    std::vector<OutputNode> nodes;
    std::vector<int> spec_of;
    std::vector<std::string> keys;
    for (int v : order) {
      OutputNode n = std::move(plan.nodes[static_cast<std::size_t>(v)]);
      for (int& d : n.depends) d = position[static_cast<std::size_t>(d)];
      if (n.of >= 0) n.of = position[static_cast<std::size_t>(n.of)];
      if (n.event >= 0) n.event = position[static_cast<std::size_t>(n.event)];
      nodes.push_back(std::move(n));
      spec_of.push_back(spec_of_node[static_cast<std::size_t>(v)]);
      keys.push_back(node_key[static_cast<std::size_t>(v)]);
    }
    plan.nodes = std::move(nodes);
    spec_of_node = std::move(spec_of);
    node_key = std::move(keys);
    for (int& u : user_node) u = position[static_cast<std::size_t>(u)];
  }

  // Series (changes with time) or one number per sample, in evaluation order.
  void classify() {
    for (std::size_t v = 0; v < plan.nodes.size(); ++v) {
      OutputNode& n = plan.nodes[v];
      if (n.kind == OutputKind::reduction) {
        const OutputNode& of = plan.nodes[static_cast<std::size_t>(n.of)];
        const OutputSpec& o = specs[static_cast<std::size_t>(spec_of_node[v])];
        if (!of.series)
          throw InputError(o.expression.where, o.key() + (o.event ? ".when" : ".of"),
                           "'" + o.expression.text + "' does not change with time (it reads only parameters and outputs that are one number per sample); '" +
                               (o.event ? "when" : "of") + "' takes a quantity of time");
        if (n.reduce == sim::Reduction::at) {
          n.at = o.at_end ? times.back() : o.at;
          if (n.at < times.front() || n.at > times.back())
            throw InputError(o.reduce_where, "outputs." + o.name + ".at",
                             "t = " + number_text(n.at) + " is outside the study's time span [" + number_text(times.front()) +
                                 ", " + number_text(times.back()) + "]");
        }
        continue;
      }
      if (n.kind != OutputKind::expression) continue;
      const auto& e = n.expression;
      bool of_time = !e.variables(VarKind::time).empty() || !e.variables(VarKind::coordinate).empty() ||
                     !e.variables(VarKind::speed).empty();
      int scalar_dep = -1;
      for (int d : n.depends) {
        if (plan.nodes[static_cast<std::size_t>(d)].series) of_time = true;
        else scalar_dep = d;
      }
      n.series = of_time;
      if (of_time && scalar_dep >= 0)
        throw InputError(where_of(static_cast<int>(v)), node_key[v],
                         "mixes quantities of time with '" + plan.nodes[static_cast<std::size_t>(scalar_dep)].name +
                             "', one number per sample; an expression reads either (t, states, λ, series outputs) or (outputs that are one number per sample), with parameters");
    }
  }
};

}  // namespace

bool is_reserved_output_name(const std::string& name) {
  return name == "energy" || name == "position_residual" || name == "velocity_residual";
}

sim::OutputPlan build_output_plan(const std::vector<OutputSpec>& specs, const Model& m, std::span<const double> times,
                                  const NominalLinearization& nominal) {
  Builder b{specs, m, times, nominal, {}, {}, {}, {}, {}, {}};
  for (int i = 0; i < m.nparam(); ++i) b.parameters.add(m.parameters[static_cast<std::size_t>(i)].name, {VarKind::parameter, i});
  if (specs.empty()) return {};
  for (std::size_t si = 0; si < specs.size(); ++si) b.add_spec(si);
  b.resolve_events();
  b.fill_names();
  b.compile_expressions();
  b.order();
  b.classify();
  sim::finish_output_plan(b.plan, b.user_node);
  return std::move(b.plan);
}

}  // namespace kanesens::study
