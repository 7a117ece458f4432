#include "model/build_model.hpp"
#include "model/joint_types.hpp"
#include "model/speed_tree.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <unordered_map>

#include "util/did_you_mean.hpp"

namespace kanesens::model {

namespace {

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

class Builder {
 public:
  Builder(const SceneSpec& spec, const std::map<std::string, double>& overrides)
      : spec_(spec), overrides_(overrides) {}

  Model build() {
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

 private:
  [[noreturn]] void fail(const SourceLocation& w, const std::string& key, const std::string& what) {
    throw InputError(w, key, what);
  }

  void build_parameters() {
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

  Slot add(const ExprText& e, bool allow_state) {
    const expr::NameTable& names = allow_state ? state_names_ : param_names_;
    m_.expressions.push_back(expr::compile(e.text, names, e.where, e.key));
    const Slot s = static_cast<Slot>(m_.expressions.size() - 1);
    (m_.expressions.back().uses_state() ? m_.state_slots : m_.parameter_slots).push_back(s);
    return s;
  }
  Slot add_text(const std::string& text, const SourceLocation& w, const std::string& key) {
    return add(ExprText{text, w, key}, false);
  }
  Slot3 add3(const Vec3Text& v, bool allow_state) { return {add(v[0], allow_state), add(v[1], allow_state), add(v[2], allow_state)}; }

  void build_bodies() {
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

  int body_ref(const std::string& name, const SourceLocation& w, const std::string& key) {
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

  void build_joints() {
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

  void build_topology() {
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

  void build_state_names() {
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

  void build_joint_expressions() {
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

  void build_forces() {
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

  // Model::planar's criterion, on the expressions (not the nominal values), so that it holds for
  // every parameter set.
  bool is_planar() const {
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

  int joint_ref(const std::string& name, const SourceLocation& w, const std::string& key) {
    if (const auto it = joint_index_.find(name); it != joint_index_.end()) return it->second;
    std::vector<std::string> names;
    for (const Joint& j : m_.joints) names.push_back(j.name);
    fail(w, key, "'" + name + "' is not a joint" + did_you_mean(name, names) + "; joints are: " + join_names(names));
  }

  void build_constraints() {
    std::set<std::string> seen;
    const bool planar = m_.planar;  // rotations about z only: coincident rows x, y
    int row = 0;
    for (std::size_t ci = 0; ci < spec_.constraints.size(); ++ci) {
      const ConstraintSpec& cs = spec_.constraints[ci];
      Constraint c;
      c.name = cs.name.empty() ? constraint_kind_name(cs.kind) + std::to_string(ci) : cs.name;
      c.kind = cs.kind;
      // Row names are "<name>" or "<name>.x": a name must not contain a dot, or "pin" and
      // "pin.x" would both name a row "pin.x".
      if (!is_identifier(c.name))
        fail(cs.where, cs.key + ".name", "'" + c.name + "' is not a valid name (letters, digits, _)");
      if (!seen.insert(c.name).second) fail(cs.where, cs.key + ".name", "duplicate constraint name '" + c.name + "'");
      std::vector<std::string> rows;
      if (cs.kind == ConstraintKind::coincident || cs.kind == ConstraintKind::distance) {
        c.body_a = body_ref(cs.body_a, cs.where, cs.key + ".body_a");
        c.body_b = body_ref(cs.body_b, cs.where, cs.key + ".body_b");
        if (c.body_a == c.body_b) fail(cs.where, cs.key + ".body_b", "a constraint needs two different bodies");
        c.point_a = add3(cs.point_a, false);
        c.point_b = add3(cs.point_b, false);
        if (c.kind == Constraint::Kind::distance) {
          c.length = add(cs.length, false);
          rows = {c.name};
        } else {
          std::vector<int> comps = cs.components;
          if (comps.empty()) comps = planar ? std::vector<int>{0, 1} : std::vector<int>{0, 1, 2};
          // At most the three world components, each once (they index a 3-element array).
          if (comps.size() > 3)
            fail(cs.where, cs.key + ".components", "at most 3 components (x, y, z), found " + std::to_string(comps.size()));
          std::set<int> distinct;
          for (std::size_t i = 0; i < comps.size(); ++i) {
            if (comps[i] < 0 || comps[i] > 2)
              fail(cs.where, cs.key + ".components", "expected x, y or z, found component " + std::to_string(comps[i]));
            if (!distinct.insert(comps[i]).second)
              fail(cs.where, cs.key + ".components",
                   std::string("component '") + static_cast<char>('x' + comps[i]) + "' is given twice");
            c.components[i] = comps[i];
            rows.push_back(c.name + "." + static_cast<char>('x' + comps[i]));
          }
        }
        c.holonomic.assign(rows.size(), 1);
      } else if (cs.kind == ConstraintKind::coupler) {
        const int ja = joint_ref(cs.joint_a, cs.where, cs.key + ".joint_a");
        const int jb = joint_ref(cs.joint_b, cs.where, cs.key + ".joint_b");
        for (int j : {ja, jb})
          if (m_.joints[j].nu != 1 || m_.joints[j].nq != 1)
            fail(cs.where, cs.key, "a coupler links 1-DOF joints (revolute, prismatic); '" + m_.joints[j].name + "' is " + joint_type_name(m_.joints[j].type));
        if (ja == jb) fail(cs.where, cs.key + ".joint_b", "a coupler links two different joints; both are '" + cs.joint_a + "'");
        c.speed_a = m_.joints[ja].u_offset;
        c.speed_b = m_.joints[jb].u_offset;
        c.coord_a = m_.joints[ja].q_offset;
        c.coord_b = m_.joints[jb].q_offset;
        c.ratio = add(cs.ratio, false);
        c.offset = add(cs.offset, false);
        rows = {c.name};
        c.holonomic = {1};
      } else if (cs.kind == ConstraintKind::general) {
        if (cs.position) {
          c.has_position = true;
          c.position = expr::compile(cs.position->text, position_names_, cs.position->where, cs.position->key);
          c.holonomic = {1};
          if (!c.position.uses_any(expr::VarKind::coordinate))
            fail(cs.position->where, cs.position->key,
                 "the position function does not depend on any coordinate, so it constrains nothing");
          // The velocity form a_k = ∂g/∂q_k needs u = q̇ for every coordinate it reads: any
          // joint but a quaternion's components (the translation of a free joint is u = q̇).
          c.position_coordinate.assign(m_.nu, -1);
          for (const Joint& J : m_.joints) {
            const int rates = J.quaternion_offset < 0 ? J.nu : J.quaternion_offset - J.q_offset;
            for (int k = 0; k < rates; ++k) c.position_coordinate[J.u_offset + k] = J.q_offset + k;
            for (int k = rates; k < J.nq; ++k)
              if (c.position.uses(expr::VarKind::coordinate, J.q_offset + k))
                fail(cs.position->where, cs.position->key,
                     "'" + m_.coordinate_names[J.q_offset + k] + "' is a quaternion component of " +
                         joint_type_name(J.type) + " joint '" + J.name +
                         "'; a position function may use only coordinates whose rates are speeds (u = q̇); use a "
                         "coincident or distance constraint, or the velocity form 'a'");
          }
        } else {
          for (const auto& [speed, text] : cs.a) {
            int k = -1;
            for (int i = 0; i < m_.nu; ++i)
              if (m_.speed_names[i] == speed) k = i;
            if (k < 0)
              fail(text.where, text.key, "'" + speed + "' is not a speed" + did_you_mean(speed, m_.speed_names) +
                                             "; speeds are: " + join_names(m_.speed_names));
            for (const auto& entry : c.a)
              if (entry.first == k) fail(text.where, text.key, "speed '" + speed + "' is given twice");
            c.a.emplace_back(k, expr::compile(text.text, position_names_, text.where, text.key));
          }
          c.a0 = cs.a0 ? expr::compile(cs.a0->text, position_names_, cs.a0->where, cs.a0->key) : expr::Expression(0.0);
          c.holonomic = {0};
        }
        rows = {c.name};
      } else {  // rolling
        c.body = body_ref(cs.body, cs.where, cs.key + ".body");
        if (c.body < 0) fail(cs.where, cs.key + ".body", "the rolling body cannot be ground");
        c.radius = add(cs.radius, false);
        c.height = add(cs.height, false);
        c.axis = add3(cs.axis, false);
        c.normal = add3(cs.normal, false);
        // Contact-point velocity in the plane's basis: two no-slip rows and the normal row,
        // the derivative of the contact height (dynamics/equations.hpp).
        rows = {c.name + ".t1", c.name + ".t2", c.name + ".n"};
        c.holonomic = {0, 0, 1};
      }
      c.row_offset = row;
      c.nrows = static_cast<int>(rows.size());
      row += c.nrows;
      if (row > kMaxSpeeds)
        fail(cs.where, cs.key, "more than " + std::to_string(kMaxSpeeds) + " constraint rows; kanesens handles at most that many");
      m_.constraint_row_names.insert(m_.constraint_row_names.end(), rows.begin(), rows.end());
      m_.constraints.push_back(std::move(c));
    }
    m_.nconstraint_rows = row;
  }

  void check_nominal() {
    const std::vector<double> p = m_.nominal_parameters();
    if (const auto problem = find_parameter_problem(m_, p.data()))
      throw InputError(problem->where, problem->key, problem->message);
  }

  const SceneSpec& spec_;
  const std::map<std::string, double>& overrides_;
  Model m_;
  expr::NameTable param_names_, state_names_, position_names_;
  std::unordered_map<std::string, int> body_index_, joint_index_;  // name → index (linear build)
};

}  // namespace

Model build_model(const SceneSpec& spec, const std::map<std::string, double>& overrides) {
  if (spec.bodies.empty()) throw InputError(spec.where.file.empty() ? SourceLocation{spec.file, 0, 0} : spec.where, "scene.bodies", "a scene needs at least one body");
  return Builder(spec, overrides).build();
}

}  // namespace kanesens::model
