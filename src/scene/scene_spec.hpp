// The scene as written in YAML: plain structs, numbers kept as expression text with their
// source location. build_model() validates and compiles it into an immutable Model.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "util/error.hpp"

namespace kanesens {

// A number or expression as written, with where it was written.
struct ExprText {
  std::string text = "0";
  SourceLocation where;
  std::string key;  // key path, e.g. "scene.bodies[1].mass"
};
using Vec3Text = std::array<ExprText, 3>;

struct ParameterSpec {
  std::string name;
  ExprText value;
};

struct InertiaSpec {
  enum class Kind { entries, rod, box, cylinder, sphere, point };
  Kind kind = Kind::entries;
  ExprText xx, yy, zz, xy, yz, xz;  // entries
  ExprText length, radius;          // rod, cylinder, sphere
  Vec3Text size;                    // box
  int axis = 2;                     // rod, cylinder: 0 x, 1 y, 2 z
};

struct BodySpec {
  std::string name;
  ExprText mass;
  InertiaSpec inertia;
  SourceLocation where;
  std::string key;
};

struct JointSpec {
  std::string name, type, parent, child;
  std::optional<Vec3Text> axis;
  std::vector<Vec3Text> axes;  // universal
  Vec3Text parent_point, child_point;
  std::vector<ExprText> q0, u0;  // empty = defaults
  std::optional<ExprText> spring_k, spring_rest, damper_c;
  SourceLocation where;
  std::string key;
};

struct ForceSpec {
  std::string type, name;
  // spring_damper
  std::string body_a, body_b;
  Vec3Text point_a, point_b;
  ExprText k, c, rest;
  // force / torque
  std::string body;
  Vec3Text point, vector;
  std::string frame = "world";
  SourceLocation where;
  std::string key;
};

struct ConstraintSpec {
  std::string name, type;
  SourceLocation where;
  std::string key;
};

struct SceneSpec {
  std::string file;  // path of the file it came from ("" if inline text)
  std::string text;  // the exact YAML text (stored in output files)
  std::string name;
  Vec3Text gravity;
  std::vector<ParameterSpec> parameters;
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  std::vector<ForceSpec> forces;
  std::vector<ConstraintSpec> constraints;
};

}  // namespace kanesens
