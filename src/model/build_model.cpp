// Building a Model from a SceneSpec: parameters, bodies, joints, the tree, state names, joint
// expressions and forces (constraints: model/build_constraints.cpp).
#include "model/builder.hpp"
#include "model/joint_types.hpp"
#include "model/speed_tree.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <unordered_map>

#include "util/did_you_mean.hpp"

namespace kanesens::model {

namespace detail {

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

Model Builder::build() {
  m_.name = spec_.name;
  m_.spec = spec_;
  build_parameters();
  build_bodies();
  build_joints();
  build_topology();
  build_state_names();
  build_joint_expressions();
  build_forces();
  for (int i = 0; i < 3; ++i) m_.gravity[i] = add(spec_.gravity[i], false);
  m_.planar = is_planar();
  build_constraints();
  check_nominal();
  return std::move(m_);
}

void Builder::fail(const SourceLocation& w, const std::string& key, const std::string& what) {
  throw InputError(w, key, what);
}

void Builder::build_parameters() {
  std::set<std::string> seen;
  std::vector<double> vals;  // nominal values so far (linear in the number of parameters)
  vals.reserve(spec_.parameters.size());
  for (const auto& p : spec_.parameters) {
    if (!is_identifier(p.name) || p.name == "t" || p.name == "pi")
      fail(p.value.where, p.value.key, "'" + p.name + "' cannot be a parameter name (use letters, digits, _; not t or pi)");
    if (!seen.insert(p.name).second) fail(p.value.where, p.value.key, "duplicate parameter '" + p.name + "'");
    Parameter par;
    par.name = p.name;
    if (auto it = overrides_.find(p.name); it != overrides_.end()) {
      par.value = expr::Expression(it->second);
    } else {
      par.value = expr::compile(p.value.text, param_names_, p.value.where, p.value.key);
    }
    par.derived = !par.value.is_constant();
    expr::Inputs<double> in;
    in.parameters = vals.data();
    par.nominal = par.value.evaluate(in);
    if (!std::isfinite(par.nominal))
      fail(p.value.where, p.value.key, "value is not finite (" + std::to_string(par.nominal) +
                                           "; a division by zero or a value out of range?)");
    param_names_.add(p.name, {expr::VarKind::parameter, static_cast<int>(m_.parameters.size())});
    vals.push_back(par.nominal);
    m_.parameters.push_back(std::move(par));
  }
  for (const auto& [name, v] : overrides_) {
    if (m_.find_parameter(name) < 0) {
      std::vector<std::string> names;
      for (const auto& p : m_.parameters) names.push_back(p.name);
      throw InputError({}, "--set " + name, "no parameter '" + name + "' in scene '" + spec_.name + "'" +
                                                did_you_mean(name, names) + "; parameters are: " + join_names(names));
    }
    (void)v;
  }
}

Slot Builder::add(const ExprText& e, bool allow_state) {
  const expr::NameTable& names = allow_state ? state_names_ : param_names_;
  m_.expressions.push_back(expr::compile(e.text, names, e.where, e.key));
  const Slot s = static_cast<Slot>(m_.expressions.size() - 1);
  (m_.expressions.back().uses_state() ? m_.state_slots : m_.parameter_slots).push_back(s);
  return s;
}

Slot Builder::add_text(const std::string& text, const SourceLocation& w, const std::string& key) {
  return add(ExprText{text, w, key}, false);
}

void Builder::build_bodies() {
  if (spec_.bodies.size() > kMaxBodies)
    fail(spec_.where.file.empty() ? SourceLocation{spec_.file, 0, 0} : spec_.where, "scene.bodies",
         std::to_string(spec_.bodies.size()) + " bodies; kanesens handles at most " + std::to_string(kMaxBodies) +
             " (its mass matrix is dense)");
  for (const auto& b : spec_.bodies) {
    if (b.name == "ground") fail(b.where, b.key + ".name", "'ground' is reserved for the world frame");
    if (!is_identifier(b.name)) fail(b.where, b.key + ".name", "'" + b.name + "' is not a valid name (letters, digits, _)");
    if (!body_index_.emplace(b.name, static_cast<int>(body_index_.size())).second)
      fail(b.where, b.key + ".name", "duplicate body name '" + b.name + "'");
    Body body;
    body.name = b.name;
    body.mass = add(b.mass, false);
    const InertiaSpec& in = b.inertia;
    const std::string m = "(" + b.mass.text + ")";
    auto sq = [](const ExprText& e) { return "(" + e.text + ")^2"; };
    std::array<std::string, 6> t{"0", "0", "0", "0", "0", "0"};
    SourceLocation w = b.where;
    std::string key = b.key + ".inertia";
    switch (in.kind) {
      case InertiaSpec::Kind::entries:
        body.inertia = {add(in.xx, false), add(in.yy, false), add(in.zz, false),
                        add(in.xy, false), add(in.yz, false), add(in.xz, false)};
        m_.bodies.push_back(body);
        continue;
      case InertiaSpec::Kind::rod:
        for (int i = 0; i < 3; ++i) t[i] = i == in.axis ? "0" : m + "*" + sq(in.length) + "/12";
        w = in.length.where; key = in.length.key;
        break;
      case InertiaSpec::Kind::box:
        t[0] = m + "*(" + sq(in.size[1]) + "+" + sq(in.size[2]) + ")/12";
        t[1] = m + "*(" + sq(in.size[0]) + "+" + sq(in.size[2]) + ")/12";
        t[2] = m + "*(" + sq(in.size[0]) + "+" + sq(in.size[1]) + ")/12";
        w = in.size[0].where; key = in.size[0].key;
        break;
      case InertiaSpec::Kind::cylinder:
        for (int i = 0; i < 3; ++i)
          t[i] = i == in.axis ? m + "*" + sq(in.radius) + "/2"
                              : m + "*(3*" + sq(in.radius) + "+" + sq(in.length) + ")/12";
        w = in.radius.where; key = in.radius.key;
        break;
      case InertiaSpec::Kind::sphere:
        for (int i = 0; i < 3; ++i) t[i] = "2*" + m + "*" + sq(in.radius) + "/5";
        w = in.radius.where; key = in.radius.key;
        break;
      case InertiaSpec::Kind::point: break;
    }
    for (int i = 0; i < 6; ++i) body.inertia[i] = add_text(t[i], w, key);
    m_.bodies.push_back(body);
  }
}

int Builder::body_ref(const std::string& name, const SourceLocation& w, const std::string& key) {
  if (name == "ground") return -1;
  const auto it = body_index_.find(name);
  const int b = it == body_index_.end() ? -2 : it->second;
  if (b == -2) {
    std::vector<std::string> names{"ground"};
    for (const auto& x : m_.bodies) names.push_back(x.name);
    fail(w, key, "'" + name + "' is not a body" + did_you_mean(name, names) + "; bodies are: " + join_names(names));
  }
  return b;
}

void Builder::build_joints() {
  int q = 0, u = 0;
  for (const auto& js : spec_.joints) {
    if (!is_identifier(js.name)) fail(js.where, js.key + ".name", "'" + js.name + "' is not a valid name (letters, digits, _)");
    if (!joint_index_.emplace(js.name, static_cast<int>(joint_index_.size())).second)
      fail(js.where, js.key + ".name", "duplicate joint name '" + js.name + "'");
    Joint j;
    j.name = js.name;
    j.type = js.type;
    j.parent = body_ref(js.parent, js.where, js.key + ".parent");
    j.child = body_ref(js.child, js.where, js.key + ".child");
    if (j.child == -1) fail(js.where, js.key + ".child", "ground cannot be a joint's child; swap parent and child");
    if (j.child == j.parent) fail(js.where, js.key + ".child", "a joint cannot connect body '" + js.child + "' to itself");
    set_joint_kind(j);
    j.nq = static_cast<int>(j.coordinate_names.size());
    j.nu = static_cast<int>(j.speed_names.size());
    j.q_offset = q;
    j.u_offset = u;
    if (j.quaternion_offset >= 0) {
      j.quaternion_offset += q;
      m_.has_quaternions = true;
    }
    q += j.nq;
    u += j.nu;
    if (u > kMaxSpeeds)
      fail(js.where, js.key, "the scene has more than " + std::to_string(kMaxSpeeds) +
                                 " speeds; kanesens handles at most that many (its mass matrix is dense)");
    m_.joints.push_back(std::move(j));
  }
  m_.nq = q;
  m_.nu = u;
  if (u == 0)
    fail(spec_.where.file.empty() ? SourceLocation{spec_.file, 0, 0} : spec_.where, "scene.joints",
         "the scene has no degrees of freedom (every joint is a weld): there is nothing to integrate");
}

void Builder::build_topology() {
  const int nb = m_.nbody();
  std::vector<int> parent_joint(nb, -1);
  for (int ji = 0; ji < static_cast<int>(m_.joints.size()); ++ji) {
    const Joint& j = m_.joints[ji];
    const JointSpec& js = spec_.joints[ji];
    if (parent_joint[j.child] >= 0)
      fail(js.where, js.key + ".child",
           "body '" + js.child + "' is already the child of joint '" + m_.joints[parent_joint[j.child]].name +
               "': this closes a kinematic loop. A scene's joints must form a tree; close loops "
               "with a constraint (scene.constraints, e.g. type: coincident) instead of a second joint");
    parent_joint[j.child] = ji;
  }
  for (int b = 0; b < nb; ++b) {
    if (parent_joint[b] < 0)
      fail(spec_.bodies[b].where, spec_.bodies[b].key,
           "body '" + m_.bodies[b].name + "' is not the child of any joint; connect it (e.g. a 'free' joint to ground)");
    m_.bodies[b].joint = parent_joint[b];
    m_.bodies[b].parent = m_.joints[parent_joint[b]].parent;
  }
  // Cycle check and topological order: walk each body to ground.
  std::vector<int> depth(nb, -1);
  for (int b = 0; b < nb; ++b) {
    int steps = 0;
    for (int x = b; x >= 0; x = m_.bodies[x].parent) {
      if (++steps > nb) {
        const JointSpec& js = spec_.joints[m_.bodies[b].joint];
        fail(js.where, js.key, "the joints through body '" + m_.bodies[b].name +
                                   "' form a cycle that never reaches ground; a scene's joints must form a tree "
                                   "rooted at ground (close loops with a constraint)");
      }
    }
    depth[b] = steps;
  }
  std::vector<int> order(m_.joints.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int c) {
    return depth[m_.joints[a].child] < depth[m_.joints[c].child];
  });
  m_.joint_order = order;
  derive_speed_tree(m_);
}

void Builder::build_state_names() {
  for (const auto& j : m_.joints)
    for (const auto& c : j.coordinate_names) m_.coordinate_names.push_back(c);
  for (const auto& j : m_.joints)
    for (const auto& s : j.speed_names) m_.speed_names.push_back(s);
  m_.state_names = m_.coordinate_names;
  m_.state_names.insert(m_.state_names.end(), m_.speed_names.begin(), m_.speed_names.end());
  for (const auto& j : m_.joints) {
    if (j.nq == 1) m_.initial_condition_names.push_back(j.name + ".q0");
    else for (int i = 0; i < j.nq; ++i) m_.initial_condition_names.push_back(j.name + ".q0[" + std::to_string(i) + "]");
  }
  for (const auto& j : m_.joints) {
    if (j.nu == 1) m_.initial_condition_names.push_back(j.name + ".u0");
    else for (int i = 0; i < j.nu; ++i) m_.initial_condition_names.push_back(j.name + ".u0[" + std::to_string(i) + "]");
  }
  state_names_ = param_names_;
  state_names_.add("t", {expr::VarKind::time, 0});
  for (int i = 0; i < m_.nq; ++i) state_names_.add(m_.coordinate_names[i], {expr::VarKind::coordinate, i});
  position_names_ = state_names_;  // constraints: parameters, t and coordinates (no speeds)
  for (int i = 0; i < m_.nu; ++i) state_names_.add(m_.speed_names[i], {expr::VarKind::speed, i});
}

void Builder::build_joint_expressions() {
  for (std::size_t ji = 0; ji < m_.joints.size(); ++ji) {
    Joint& j = m_.joints[ji];
    const JointSpec& js = spec_.joints[ji];
    const bool needs_axis = j.type == JointType::revolute || j.type == JointType::prismatic ||
                            j.type == JointType::cylindrical || j.type == JointType::planar;
    if (j.type == JointType::universal) {
      if (js.axes.size() != 2) fail(js.where, js.key + ".axes", "a universal joint needs 'axes: [[..], [..]]' (two axes in the parent frame)");
      if (js.axis) fail(js.where, js.key + ".axis", "a universal joint takes 'axes' (two vectors), not 'axis'");
      j.axis = add3(js.axes[0], false);
      j.axis2 = add3(js.axes[1], false);
    } else if (needs_axis) {
      if (!js.axis) fail(js.where, js.key, std::string("missing required key 'axis' (a ") + joint_type_name(j.type) + " joint needs an axis in the parent frame)");
      if (!js.axes.empty()) fail(js.where, js.key + ".axes", "'axes' is only for universal joints; use 'axis'");
      j.axis = add3(*js.axis, false);
    } else if (js.axis || !js.axes.empty()) {
      fail(js.where, js.key + (js.axis ? ".axis" : ".axes"),
           std::string("a ") + joint_type_name(j.type) + " joint takes no axis");
    }
    // Speed directions (parent-frame slots); planar in-plane axes are derived in the workspace.
    for (auto& s : j.speeds)
      if (!s.in_child_frame) s.direction = j.axis;
    if (j.type == JointType::universal) j.speeds[1].direction = j.axis2;
    j.parent_point = add3(js.parent_point, false);
    j.child_point = add3(js.child_point, false);
    auto initial = [&](const std::vector<ExprText>& given, int n, const char* what, std::vector<Slot>& out) {
      if (given.empty()) {
        for (int i = 0; i < n; ++i) {
          const bool w = j.quaternion_offset >= 0 && std::string(what) == "q0" &&
                         i == j.quaternion_offset - j.q_offset;
          out.push_back(add_text(w ? "1" : "0", js.where, js.key + "." + what));
        }
        return;
      }
      if (static_cast<int>(given.size()) != n)
        fail(given[0].where, js.key + "." + what,
             std::string("a ") + joint_type_name(j.type) + " joint has " + std::to_string(n) + " " +
                 (what[0] == 'q' ? "coordinate" : "speed") + (n == 1 ? "" : "s") + ", found " +
                 std::to_string(given.size()) + " value" + (given.size() == 1 ? "" : "s"));
      for (const auto& g : given) out.push_back(add(g, false));
    };
    initial(js.q0, j.nq, "q0", j.q0);
    initial(js.u0, j.nu, "u0", j.u0);
    if (js.spring_k || js.damper_c) {
      if (j.nu != 1 || j.nq != 1)
        fail(js.where, js.key + (js.spring_k ? ".spring" : ".damper"),
             "joint springs and dampers are for 1-DOF joints (revolute, prismatic); use a spring_damper force");
    }
    if (js.spring_k) {
      j.spring_k = add(*js.spring_k, true);
      j.spring_rest = add(*js.spring_rest, false);
    }
    if (js.damper_c) j.damper_c = add(*js.damper_c, true);
  }
}

void Builder::build_forces() {
  std::set<std::string> seen;
  for (const auto& fs : spec_.forces) {
    if (!seen.insert(fs.name).second) fail(fs.where, fs.key + ".name", "duplicate force name '" + fs.name + "'");
    Force f;
    f.name = fs.name;
    f.kind = fs.kind;
    if (fs.kind == ForceKind::spring_damper) {
      f.body_a = body_ref(fs.body_a, fs.where, fs.key + ".body_a");
      f.body_b = body_ref(fs.body_b, fs.where, fs.key + ".body_b");
      if (f.body_a == f.body_b) fail(fs.where, fs.key + ".body_b", "a spring_damper needs two different bodies");
      f.point_a = add3(fs.point_a, false);
      f.point_b = add3(fs.point_b, false);
      f.k = add(fs.k, true);
      f.c = add(fs.c, true);
      f.rest = add(fs.rest, false);
    } else {
      f.body = body_ref(fs.body, fs.where, fs.key + ".body");
      if (f.body < 0) fail(fs.where, fs.key + ".body", "forces on ground do nothing; name a body");
      f.point = add3(fs.point, false);
      f.vector = add3(fs.vector, true);
      f.body_frame = fs.body_frame;
    }
    m_.forces.push_back(f);
  }
}

bool Builder::is_planar() const {
  auto constant = [&](Slot s, double v) {
    return m_.expressions[s].is_constant() && m_.expressions[s].constant_value() == v;
  };
  auto nonzero_constant = [&](Slot s) {
    return m_.expressions[s].is_constant() && m_.expressions[s].constant_value() != 0;
  };
  for (const Joint& j : m_.joints) {
    switch (j.type) {
      case JointType::revolute:
      case JointType::planar:
        if (!(constant(j.axis[0], 0) && constant(j.axis[1], 0) && nonzero_constant(j.axis[2]))) return false;
        break;
      case JointType::prismatic:
        if (!constant(j.axis[2], 0)) return false;
        break;
      case JointType::weld: break;
      default: return false;
    }
  }
  return true;
}

}  // namespace detail

Model build_model(const SceneSpec& spec, const std::map<std::string, double>& overrides) {
  if (spec.bodies.empty()) throw InputError(spec.where.file.empty() ? SourceLocation{spec.file, 0, 0} : spec.where, "scene.bodies", "a scene needs at least one body");
  return detail::Builder(spec, overrides).build();
}

}  // namespace kanesens::model
