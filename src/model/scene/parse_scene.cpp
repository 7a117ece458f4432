#include "model/scene/parse_scene.hpp"

#include <algorithm>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "model/yaml_reader.hpp"

namespace kanesens::model {
namespace {

std::string idx(const std::string& key, std::size_t i) { return key + "[" + std::to_string(i) + "]"; }

Vec3Text zero_vec3() { return {ExprText{}, ExprText{}, ExprText{}}; }

// The optional vector `k` of map `n`; zero when it is not given.
Vec3Text vec3_or_zero(const YAML::Node& n, const YamlReader& r, const std::string& key, const char* k) {
  return n[k] ? r.read_vec3(n[k], key + "." + k) : zero_vec3();
}

// The two body points a spring-damper or a coincident/distance constraint joins.
template <class Spec>
void read_body_points(const YAML::Node& n, const YamlReader& r, const std::string& key, Spec& s) {
  s.body_a = r.read_string(r.required(n, "body_a", key), key + ".body_a");
  s.body_b = r.read_string(r.required(n, "body_b", key), key + ".body_b");
  s.point_a = vec3_or_zero(n, r, key, "point_a");
  s.point_b = vec3_or_zero(n, r, key, "point_b");
}

// The kind named by `n`, or "unknown joint type 'x' (did you mean 'y'?); types are: ...".
template <class E>
E read_kind(const YAML::Node& n, const YamlReader& r, const std::string& key, const char* what,
            std::span<const std::pair<std::string_view, E>> kinds) {
  const std::string name = r.read_string(n, key);
  std::vector<std::string_view> names;
  for (const auto& [k, v] : kinds) {
    if (k == name) return v;
    names.push_back(k);
  }
  r.fail(n, key, "unknown " + std::string(what) + " '" + name + "'" + did_you_mean(name, names) +
                     "; types are: " + join_names(names));
}

int read_axis_name(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  const std::string a = r.read_string(n, key);
  if (a == "x") return 0;
  if (a == "y") return 1;
  if (a == "z") return 2;
  r.fail(n, key, "expected x, y or z, found '" + a + "'");
}

InertiaSpec parse_inertia(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  r.require_map(n, key);
  InertiaSpec s;
  if (!n["shape"]) {
    r.check_keys(n, key, {"xx", "yy", "zz", "xy", "yz", "xz"});
    s.kind = InertiaSpec::Kind::entries;
    auto get = [&](const char* k, ExprText& dst) {
      if (n[k]) dst = r.read_expr(n[k], key + "." + k);
      else dst = ExprText{"0", r.location(n), key + "." + k};
    };
    get("xx", s.xx); get("yy", s.yy); get("zz", s.zz);
    get("xy", s.xy); get("yz", s.yz); get("xz", s.xz);
    return s;
  }
  const std::string shape = r.read_string(n["shape"], key + ".shape");
  if (shape == "rod") {
    r.check_keys(n, key, {"shape", "length", "axis"});
    s.kind = InertiaSpec::Kind::rod;
    s.length = r.read_expr(r.required(n, "length", key), key + ".length");
    s.axis = read_axis_name(r.required(n, "axis", key), r, key + ".axis");
  } else if (shape == "box") {
    r.check_keys(n, key, {"shape", "size"});
    s.kind = InertiaSpec::Kind::box;
    s.size = r.read_vec3(r.required(n, "size", key), key + ".size");
  } else if (shape == "cylinder") {
    r.check_keys(n, key, {"shape", "radius", "length", "axis"});
    s.kind = InertiaSpec::Kind::cylinder;
    s.radius = r.read_expr(r.required(n, "radius", key), key + ".radius");
    s.length = r.read_expr(r.required(n, "length", key), key + ".length");
    s.axis = read_axis_name(r.required(n, "axis", key), r, key + ".axis");
  } else if (shape == "sphere") {
    r.check_keys(n, key, {"shape", "radius"});
    s.kind = InertiaSpec::Kind::sphere;
    s.radius = r.read_expr(r.required(n, "radius", key), key + ".radius");
  } else if (shape == "point") {
    r.check_keys(n, key, {"shape"});
    s.kind = InertiaSpec::Kind::point;
  } else {
    r.fail(n["shape"], key + ".shape",
         "unknown shape '" + shape + "'; shapes are: rod, box, cylinder, sphere, point");
  }
  return s;
}

BodySpec parse_body(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  r.check_keys(n, key, {"name", "mass", "inertia"});
  BodySpec b;
  b.where = r.location(n);
  b.key = key;
  b.name = r.read_string(r.required(n, "name", key), key + ".name");
  b.mass = r.read_expr(r.required(n, "mass", key), key + ".mass");
  b.inertia = parse_inertia(r.required(n, "inertia", key), r, key + ".inertia");
  return b;
}

JointSpec parse_joint(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  r.check_keys(n, key,
             {"name", "type", "parent", "child", "axis", "axes", "parent_point", "child_point", "q0",
              "u0", "spring", "damper"});
  JointSpec j;
  j.where = r.location(n);
  j.key = key;
  j.name = r.read_string(r.required(n, "name", key), key + ".name");
  j.type = read_kind<JointType>(r.required(n, "type", key), r, key + ".type", "joint type", kJointTypes);
  j.parent = r.read_string(r.required(n, "parent", key), key + ".parent");
  j.child = r.read_string(r.required(n, "child", key), key + ".child");
  if (n["axis"]) j.axis = r.read_vec3(n["axis"], key + ".axis");
  if (n["axes"]) {
    r.require_sequence(n["axes"], key + ".axes");
    for (std::size_t i = 0; i < n["axes"].size(); ++i)
      j.axes.push_back(r.read_vec3(n["axes"][i], idx(key + ".axes", i)));
  }
  j.parent_point = vec3_or_zero(n, r, key, "parent_point");
  j.child_point = vec3_or_zero(n, r, key, "child_point");
  if (n["q0"]) j.q0 = r.read_expr_list(n["q0"], key + ".q0");
  if (n["u0"]) j.u0 = r.read_expr_list(n["u0"], key + ".u0");
  if (const YAML::Node s = n["spring"]) {
    r.check_keys(s, key + ".spring", {"k", "rest"});
    j.spring_k = r.read_expr(r.required(s, "k", key + ".spring"), key + ".spring.k");
    j.spring_rest = s["rest"] ? r.read_expr(s["rest"], key + ".spring.rest")
                              : ExprText{"0", r.location(s), key + ".spring.rest"};
  }
  if (const YAML::Node d = n["damper"]) {
    r.check_keys(d, key + ".damper", {"c"});
    j.damper_c = r.read_expr(r.required(d, "c", key + ".damper"), key + ".damper.c");
  }
  return j;
}

// A force or a constraint: a map, its kind named by `type`; where it was written, for messages.
template <class Spec, class E, std::size_t N>
Spec read_typed_map(const YAML::Node& n, const YamlReader& r, const std::string& key, const char* what,
                    const EnumName<E> (&kinds)[N]) {
  r.require_map(n, key);
  Spec s;
  s.where = r.location(n);
  s.key = key;
  s.kind = read_kind<E>(r.required(n, "type", key), r, key + ".type", what, kinds);
  return s;
}

ForceSpec parse_force(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  ForceSpec f = read_typed_map<ForceSpec>(n, r, key, "force type", kForceKinds);
  if (f.kind == ForceKind::spring_damper) {
    r.check_keys(n, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "k", "c", "rest"});
    read_body_points(n, r, key, f);
    f.k = n["k"] ? r.read_expr(n["k"], key + ".k") : ExprText{"0", f.where, key + ".k"};
    f.c = n["c"] ? r.read_expr(n["c"], key + ".c") : ExprText{"0", f.where, key + ".c"};
    f.rest = n["rest"] ? r.read_expr(n["rest"], key + ".rest") : ExprText{"0", f.where, key + ".rest"};
  } else {
    if (f.kind == ForceKind::force) r.check_keys(n, key, {"type", "name", "body", "point", "vector", "frame"});
    else r.check_keys(n, key, {"type", "name", "body", "vector", "frame"});
    f.body = r.read_string(r.required(n, "body", key), key + ".body");
    f.point = vec3_or_zero(n, r, key, "point");
    f.vector = r.read_vec3(r.required(n, "vector", key), key + ".vector");
    if (n["frame"]) {
      const std::string frame = r.read_string(n["frame"], key + ".frame");
      if (frame != "world" && frame != "body")
        r.fail(n["frame"], key + ".frame", "expected 'world' or 'body', found '" + frame + "'");
      f.body_frame = frame == "body";
    }
  }
  if (n["name"]) f.name = r.read_string(n["name"], key + ".name");
  return f;
}

ConstraintSpec parse_constraint(const YAML::Node& n, const YamlReader& r, const std::string& key) {
  ConstraintSpec c = read_typed_map<ConstraintSpec>(n, r, key, "constraint type", kConstraintKinds);
  c.name = n["name"] ? r.read_string(n["name"], key + ".name") : "";
  if (c.kind == ConstraintKind::coincident || c.kind == ConstraintKind::distance) {
    if (c.kind == ConstraintKind::coincident) r.check_keys(n, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "components"});
    else r.check_keys(n, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "length"});
    read_body_points(n, r, key, c);
    if (c.kind == ConstraintKind::distance) c.length = r.read_expr(r.required(n, "length", key), key + ".length");
    if (const YAML::Node comp = n["components"]) {
      r.require_sequence(comp, key + ".components");
      if (comp.size() == 0) r.fail(comp, key + ".components", "expected 1 to 3 of x, y, z; found an empty list");
      for (std::size_t i = 0; i < comp.size(); ++i) {
        const std::string x = r.read_string(comp[i], key + ".components[" + std::to_string(i) + "]");
        if (x != "x" && x != "y" && x != "z") r.fail(comp[i], key + ".components", "expected x, y or z, found '" + x + "'");
        const int axis = x[0] - 'x';
        if (std::find(c.components.begin(), c.components.end(), axis) != c.components.end())
          r.fail(comp[i], key + ".components", "component '" + x + "' is given twice");
        c.components.push_back(axis);
      }
    }
  } else if (c.kind == ConstraintKind::coupler) {
    r.check_keys(n, key, {"type", "name", "joint_a", "joint_b", "ratio", "offset"});
    c.joint_a = r.read_string(r.required(n, "joint_a", key), key + ".joint_a");
    c.joint_b = r.read_string(r.required(n, "joint_b", key), key + ".joint_b");
    c.ratio.text = "1";
    if (n["ratio"]) c.ratio = r.read_expr(n["ratio"], key + ".ratio");
    if (n["offset"]) c.offset = r.read_expr(n["offset"], key + ".offset");
  } else if (c.kind == ConstraintKind::general) {
    r.check_keys(n, key, {"type", "name", "a", "a0", "position"});
    if (const YAML::Node a = n["a"]) {
      r.require_map(a, key + ".a");
      for (const auto& kv : a) {
        const std::string speed = r.read_string(kv.first, key + ".a");
        for (const auto& entry : c.a)
          if (entry.first == speed) r.fail(kv.first, key + ".a." + speed, "speed '" + speed + "' is given twice");
        c.a.emplace_back(speed, r.read_expr(kv.second, key + ".a." + speed));
      }
    }
    if (n["a0"]) c.a0 = r.read_expr(n["a0"], key + ".a0");
    if (n["position"]) c.position = r.read_expr(n["position"], key + ".position");
    if (c.position && (!c.a.empty() || c.a0))
      r.fail(n, key, "give either 'position' (a holonomic g(q, t) = 0; its velocity form is derived) or 'a' and 'a0', not both");
    if (!c.position && c.a.empty()) r.fail(n, key, "a general constraint needs 'a' (coefficients per speed) or 'position'");
  } else {  // rolling
    r.check_keys(n, key, {"type", "name", "body", "radius", "axis", "normal", "height"});
    c.body = r.read_string(r.required(n, "body", key), key + ".body");
    c.radius = r.read_expr(r.required(n, "radius", key), key + ".radius");
    c.axis = r.read_vec3(r.required(n, "axis", key), key + ".axis");
    if (n["normal"]) {
      c.normal = r.read_vec3(n["normal"], key + ".normal");
    } else {
      c.normal = zero_vec3();
      c.normal[2].text = "1";
    }
    if (n["height"]) c.height = r.read_expr(n["height"], key + ".height");
  }
  return c;
}

}  // namespace

SceneSpec parse_scene_node(const YAML::Node& n, const std::string& file, const std::string& text) {
  const std::string key = "scene";
  const YamlReader r(file);
  r.check_keys(n, key, {"name", "gravity", "parameters", "bodies", "joints", "forces", "constraints"});
  SceneSpec s;
  s.file = file;
  s.text = text;
  s.where = r.location(n);
  s.name = r.read_string(r.required(n, "name", key), key + ".name");
  s.gravity = vec3_or_zero(n, r, key, "gravity");
  if (const YAML::Node p = n["parameters"]) {
    if (!p.IsNull()) {
      r.require_map(p, key + ".parameters");
      for (const auto& kv : p) {
        if (!kv.first.IsScalar()) r.fail(kv.first, key + ".parameters", "expected a parameter name, found a map or list");
        const std::string name = kv.first.Scalar();
        s.parameters.push_back({name, r.read_expr(kv.second, key + ".parameters." + name)});
      }
    }
  }
  const YAML::Node bodies = r.required(n, "bodies", key);
  r.require_sequence(bodies, key + ".bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i)
    s.bodies.push_back(parse_body(bodies[i], r, idx(key + ".bodies", i)));
  const YAML::Node joints = r.required(n, "joints", key);
  r.require_sequence(joints, key + ".joints");
  for (std::size_t i = 0; i < joints.size(); ++i)
    s.joints.push_back(parse_joint(joints[i], r, idx(key + ".joints", i)));
  if (const YAML::Node f = n["forces"]; f && !f.IsNull()) {
    r.require_sequence(f, key + ".forces");
    for (std::size_t i = 0; i < f.size(); ++i) {
      s.forces.push_back(parse_force(f[i], r, idx(key + ".forces", i)));
      if (!f[i]["name"]) s.forces.back().name = force_kind_name(s.forces.back().kind) + std::to_string(i);
    }
  }
  if (const YAML::Node c = n["constraints"]; c && !c.IsNull()) {
    r.require_sequence(c, key + ".constraints");
    for (std::size_t i = 0; i < c.size(); ++i) s.constraints.push_back(parse_constraint(c[i], r, idx(key + ".constraints", i)));
  }
  return s;
}

SceneSpec parse_scene_text(const std::string& text, const std::string& file) {
  const YAML::Node doc = load_yaml(text, file);
  if (!doc.IsMap()) throw InputError({file, 1, 1}, "", "expected a YAML map with keys 'kanesens' and 'scene'");
  const YamlReader r(file);
  r.check_keys(doc, "", {"kanesens", "scene"});
  const YAML::Node version = r.required(doc, "kanesens", "");
  if (!version.IsScalar() || version.Scalar() != "1")
    r.fail(version, "kanesens", "unsupported schema version '" +
                                        (version.IsScalar() ? version.Scalar() : std::string("?")) +
                                        "'; this kanesens reads version 1");
  return parse_scene_node(r.required(doc, "scene", ""), file, text);
}

SceneSpec parse_scene_file(const std::string& path) { return parse_scene_text(read_text_file(path), path); }

}  // namespace kanesens::model
