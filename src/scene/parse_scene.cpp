#include "scene/parse_scene.hpp"

#include <algorithm>

#include "scene/yaml_util.hpp"

namespace kanesens {
namespace {

using namespace kanesens::yaml;

std::string idx(const std::string& key, std::size_t i) { return key + "[" + std::to_string(i) + "]"; }

Vec3Text zero_vec3() { return {ExprText{}, ExprText{}, ExprText{}}; }

int read_axis_name(const YAML::Node& n, const std::string& file, const std::string& key) {
  const std::string a = read_string(n, file, key);
  if (a == "x") return 0;
  if (a == "y") return 1;
  if (a == "z") return 2;
  fail(n, file, key, "expected x, y or z, found '" + a + "'");
}

InertiaSpec parse_inertia(const YAML::Node& n, const std::string& file, const std::string& key) {
  require_map(n, file, key);
  InertiaSpec s;
  if (!n["shape"]) {
    check_keys(n, file, key, {"xx", "yy", "zz", "xy", "yz", "xz"});
    s.kind = InertiaSpec::Kind::entries;
    auto get = [&](const char* k, ExprText& dst) {
      if (n[k]) dst = read_expr(n[k], file, key + "." + k);
      else dst = ExprText{"0", location(n, file), key + "." + k};
    };
    get("xx", s.xx); get("yy", s.yy); get("zz", s.zz);
    get("xy", s.xy); get("yz", s.yz); get("xz", s.xz);
    return s;
  }
  const std::string shape = read_string(n["shape"], file, key + ".shape");
  if (shape == "rod") {
    check_keys(n, file, key, {"shape", "length", "axis"});
    s.kind = InertiaSpec::Kind::rod;
    s.length = read_expr(required(n, "length", file, key), file, key + ".length");
    s.axis = read_axis_name(required(n, "axis", file, key), file, key + ".axis");
  } else if (shape == "box") {
    check_keys(n, file, key, {"shape", "size"});
    s.kind = InertiaSpec::Kind::box;
    s.size = read_vec3(required(n, "size", file, key), file, key + ".size");
  } else if (shape == "cylinder") {
    check_keys(n, file, key, {"shape", "radius", "length", "axis"});
    s.kind = InertiaSpec::Kind::cylinder;
    s.radius = read_expr(required(n, "radius", file, key), file, key + ".radius");
    s.length = read_expr(required(n, "length", file, key), file, key + ".length");
    s.axis = read_axis_name(required(n, "axis", file, key), file, key + ".axis");
  } else if (shape == "sphere") {
    check_keys(n, file, key, {"shape", "radius"});
    s.kind = InertiaSpec::Kind::sphere;
    s.radius = read_expr(required(n, "radius", file, key), file, key + ".radius");
  } else if (shape == "point") {
    check_keys(n, file, key, {"shape"});
    s.kind = InertiaSpec::Kind::point;
  } else {
    fail(n["shape"], file, key + ".shape",
         "unknown shape '" + shape + "'; shapes are: rod, box, cylinder, sphere, point");
  }
  return s;
}

BodySpec parse_body(const YAML::Node& n, const std::string& file, const std::string& key) {
  check_keys(n, file, key, {"name", "mass", "inertia"});
  BodySpec b;
  b.where = location(n, file);
  b.key = key;
  b.name = read_string(required(n, "name", file, key), file, key + ".name");
  b.mass = read_expr(required(n, "mass", file, key), file, key + ".mass");
  b.inertia = parse_inertia(required(n, "inertia", file, key), file, key + ".inertia");
  return b;
}

JointSpec parse_joint(const YAML::Node& n, const std::string& file, const std::string& key) {
  check_keys(n, file, key,
             {"name", "type", "parent", "child", "axis", "axes", "parent_point", "child_point", "q0",
              "u0", "spring", "damper"});
  JointSpec j;
  j.where = location(n, file);
  j.key = key;
  j.name = read_string(required(n, "name", file, key), file, key + ".name");
  j.type = read_string(required(n, "type", file, key), file, key + ".type");
  j.parent = read_string(required(n, "parent", file, key), file, key + ".parent");
  j.child = read_string(required(n, "child", file, key), file, key + ".child");
  if (n["axis"]) j.axis = read_vec3(n["axis"], file, key + ".axis");
  if (n["axes"]) {
    require_sequence(n["axes"], file, key + ".axes");
    for (std::size_t i = 0; i < n["axes"].size(); ++i)
      j.axes.push_back(read_vec3(n["axes"][i], file, idx(key + ".axes", i)));
  }
  j.parent_point = n["parent_point"] ? read_vec3(n["parent_point"], file, key + ".parent_point") : zero_vec3();
  j.child_point = n["child_point"] ? read_vec3(n["child_point"], file, key + ".child_point") : zero_vec3();
  if (n["q0"]) j.q0 = read_expr_list(n["q0"], file, key + ".q0");
  if (n["u0"]) j.u0 = read_expr_list(n["u0"], file, key + ".u0");
  if (const YAML::Node s = n["spring"]) {
    check_keys(s, file, key + ".spring", {"k", "rest"});
    j.spring_k = read_expr(required(s, "k", file, key + ".spring"), file, key + ".spring.k");
    j.spring_rest = s["rest"] ? read_expr(s["rest"], file, key + ".spring.rest")
                              : ExprText{"0", location(s, file), key + ".spring.rest"};
  }
  if (const YAML::Node d = n["damper"]) {
    check_keys(d, file, key + ".damper", {"c"});
    j.damper_c = read_expr(required(d, "c", file, key + ".damper"), file, key + ".damper.c");
  }
  return j;
}

ForceSpec parse_force(const YAML::Node& n, const std::string& file, const std::string& key) {
  require_map(n, file, key);
  ForceSpec f;
  f.where = location(n, file);
  f.key = key;
  f.type = read_string(required(n, "type", file, key), file, key + ".type");
  if (f.type == "spring_damper") {
    check_keys(n, file, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "k", "c", "rest"});
    f.body_a = read_string(required(n, "body_a", file, key), file, key + ".body_a");
    f.body_b = read_string(required(n, "body_b", file, key), file, key + ".body_b");
    f.point_a = n["point_a"] ? read_vec3(n["point_a"], file, key + ".point_a") : zero_vec3();
    f.point_b = n["point_b"] ? read_vec3(n["point_b"], file, key + ".point_b") : zero_vec3();
    f.k = n["k"] ? read_expr(n["k"], file, key + ".k") : ExprText{"0", f.where, key + ".k"};
    f.c = n["c"] ? read_expr(n["c"], file, key + ".c") : ExprText{"0", f.where, key + ".c"};
    f.rest = n["rest"] ? read_expr(n["rest"], file, key + ".rest") : ExprText{"0", f.where, key + ".rest"};
  } else if (f.type == "force" || f.type == "torque") {
    if (f.type == "force") check_keys(n, file, key, {"type", "name", "body", "point", "vector", "frame"});
    else check_keys(n, file, key, {"type", "name", "body", "vector", "frame"});
    f.body = read_string(required(n, "body", file, key), file, key + ".body");
    f.point = n["point"] ? read_vec3(n["point"], file, key + ".point") : zero_vec3();
    f.vector = read_vec3(required(n, "vector", file, key), file, key + ".vector");
    if (n["frame"]) {
      f.frame = read_string(n["frame"], file, key + ".frame");
      if (f.frame != "world" && f.frame != "body")
        fail(n["frame"], file, key + ".frame", "expected 'world' or 'body', found '" + f.frame + "'");
    }
  } else {
    fail(n["type"], file, key + ".type",
         "unknown force type '" + f.type + "'; types are: spring_damper, force, torque");
  }
  f.name = n["name"] ? read_string(n["name"], file, key + ".name") : f.type + std::to_string(0);
  return f;
}

ConstraintSpec parse_constraint(const YAML::Node& n, const std::string& file, const std::string& key) {
  require_map(n, file, key);
  ConstraintSpec c;
  c.where = location(n, file);
  c.key = key;
  c.type = read_string(required(n, "type", file, key), file, key + ".type");
  c.name = n["name"] ? read_string(n["name"], file, key + ".name") : "";
  auto vec_or_zero = [&](const char* k) { return n[k] ? read_vec3(n[k], file, key + "." + k) : zero_vec3(); };
  if (c.type == "coincident" || c.type == "distance") {
    if (c.type == "coincident") check_keys(n, file, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "components"});
    else check_keys(n, file, key, {"type", "name", "body_a", "point_a", "body_b", "point_b", "length"});
    c.body_a = read_string(required(n, "body_a", file, key), file, key + ".body_a");
    c.body_b = read_string(required(n, "body_b", file, key), file, key + ".body_b");
    c.point_a = vec_or_zero("point_a");
    c.point_b = vec_or_zero("point_b");
    if (c.type == "distance") c.length = read_expr(required(n, "length", file, key), file, key + ".length");
    if (const YAML::Node comp = n["components"]) {
      require_sequence(comp, file, key + ".components");
      if (comp.size() == 0) fail(comp, file, key + ".components", "expected 1 to 3 of x, y, z; found an empty list");
      for (std::size_t i = 0; i < comp.size(); ++i) {
        const std::string x = read_string(comp[i], file, key + ".components[" + std::to_string(i) + "]");
        if (x != "x" && x != "y" && x != "z") fail(comp[i], file, key + ".components", "expected x, y or z, found '" + x + "'");
        if (std::find(c.components.begin(), c.components.end(), x) != c.components.end())
          fail(comp[i], file, key + ".components", "component '" + x + "' is given twice");
        c.components.push_back(x);
      }
    }
  } else if (c.type == "coupler") {
    check_keys(n, file, key, {"type", "name", "joint_a", "joint_b", "ratio", "offset"});
    c.joint_a = read_string(required(n, "joint_a", file, key), file, key + ".joint_a");
    c.joint_b = read_string(required(n, "joint_b", file, key), file, key + ".joint_b");
    c.ratio.text = "1";
    if (n["ratio"]) c.ratio = read_expr(n["ratio"], file, key + ".ratio");
    if (n["offset"]) c.offset = read_expr(n["offset"], file, key + ".offset");
  } else if (c.type == "general") {
    check_keys(n, file, key, {"type", "name", "a", "a0", "position"});
    if (const YAML::Node a = n["a"]) {
      require_map(a, file, key + ".a");
      for (const auto& kv : a) {
        if (!kv.first.IsScalar()) fail(kv.first, file, key + ".a", "expected a speed name, found a map or list");
        const std::string speed = kv.first.Scalar();
        for (const auto& entry : c.a)
          if (entry.first == speed) fail(kv.first, file, key + ".a." + speed, "speed '" + speed + "' is given twice");
        c.a.emplace_back(speed, read_expr(kv.second, file, key + ".a." + speed));
      }
    }
    if (n["a0"]) c.a0 = read_expr(n["a0"], file, key + ".a0");
    if (n["position"]) c.position = read_expr(n["position"], file, key + ".position");
    if (c.position && (!c.a.empty() || c.a0))
      fail(n, file, key, "give either 'position' (a holonomic g(q, t) = 0; its velocity form is derived) or 'a' and 'a0', not both");
    if (!c.position && c.a.empty()) fail(n, file, key, "a general constraint needs 'a' (coefficients per speed) or 'position'");
  } else if (c.type == "rolling") {
    check_keys(n, file, key, {"type", "name", "body", "radius", "axis", "normal", "height"});
    c.body = read_string(required(n, "body", file, key), file, key + ".body");
    c.radius = read_expr(required(n, "radius", file, key), file, key + ".radius");
    c.axis = read_vec3(required(n, "axis", file, key), file, key + ".axis");
    if (n["normal"]) {
      c.normal = read_vec3(n["normal"], file, key + ".normal");
    } else {
      c.normal = zero_vec3();
      c.normal[2].text = "1";
    }
    if (n["height"]) c.height = read_expr(n["height"], file, key + ".height");
  } else {
    fail(n["type"], file, key + ".type",
         "unknown constraint type '" + c.type + "'; types are: coincident, distance, coupler, rolling, general");
  }
  return c;
}

}  // namespace

SceneSpec parse_scene_node(const YAML::Node& n, const std::string& file, const std::string& text) {
  const std::string key = "scene";
  check_keys(n, file, key, {"name", "gravity", "parameters", "bodies", "joints", "forces", "constraints"});
  SceneSpec s;
  s.file = file;
  s.text = text;
  s.where = location(n, file);
  s.name = read_string(required(n, "name", file, key), file, key + ".name");
  s.gravity = n["gravity"] ? read_vec3(n["gravity"], file, key + ".gravity") : zero_vec3();
  if (const YAML::Node p = n["parameters"]) {
    if (!p.IsNull()) {
      require_map(p, file, key + ".parameters");
      for (const auto& kv : p) {
        if (!kv.first.IsScalar()) fail(kv.first, file, key + ".parameters", "expected a parameter name, found a map or list");
        const std::string name = kv.first.Scalar();
        s.parameters.push_back({name, read_expr(kv.second, file, key + ".parameters." + name)});
      }
    }
  }
  const YAML::Node bodies = required(n, "bodies", file, key);
  require_sequence(bodies, file, key + ".bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i)
    s.bodies.push_back(parse_body(bodies[i], file, idx(key + ".bodies", i)));
  const YAML::Node joints = required(n, "joints", file, key);
  require_sequence(joints, file, key + ".joints");
  for (std::size_t i = 0; i < joints.size(); ++i)
    s.joints.push_back(parse_joint(joints[i], file, idx(key + ".joints", i)));
  if (const YAML::Node f = n["forces"]; f && !f.IsNull()) {
    require_sequence(f, file, key + ".forces");
    for (std::size_t i = 0; i < f.size(); ++i) {
      s.forces.push_back(parse_force(f[i], file, idx(key + ".forces", i)));
      if (!f[i]["name"]) s.forces.back().name = s.forces.back().type + std::to_string(i);
    }
  }
  if (const YAML::Node c = n["constraints"]; c && !c.IsNull()) {
    require_sequence(c, file, key + ".constraints");
    for (std::size_t i = 0; i < c.size(); ++i) s.constraints.push_back(parse_constraint(c[i], file, idx(key + ".constraints", i)));
  }
  return s;
}

SceneSpec parse_scene_text(const std::string& text, const std::string& file) {
  const YAML::Node doc = load(text, file);
  if (!doc.IsMap()) throw InputError({file, 1, 1}, "", "expected a YAML map with keys 'kanesens' and 'scene'");
  check_keys(doc, file, "", {"kanesens", "scene"});
  const YAML::Node version = required(doc, "kanesens", file, "");
  if (!version.IsScalar() || version.Scalar() != "1")
    fail(version, file, "kanesens", "unsupported schema version '" +
                                        (version.IsScalar() ? version.Scalar() : std::string("?")) +
                                        "'; this kanesens reads version 1");
  return parse_scene_node(required(doc, "scene", file, ""), file, text);
}

SceneSpec parse_scene_file(const std::string& path) { return parse_scene_text(read_file(path), path); }

}  // namespace kanesens
