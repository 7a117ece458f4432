// The scene as written in YAML: plain structs, numbers kept as expression text with their
// source location. build_model() validates and compiles it into an immutable Model.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "util/enum_names.hpp"
#include "util/error.hpp"

namespace kanesens::model {

// The kinds a scene names, parsed from their names where the YAML is read; the rest of
// kanesens sees only these enums.
enum class JointType { revolute, prismatic, cylindrical, universal, planar, spherical, free, weld };
enum class ForceKind { spring_damper, force, torque };
enum class ConstraintKind { coincident, distance, coupler, general, rolling };
// Their names in the YAML (util/enum_names.hpp), in the order the parser's messages list them.
inline constexpr EnumName<JointType> kJointTypes[] = {
    {"revolute", JointType::revolute},   {"prismatic", JointType::prismatic}, {"cylindrical", JointType::cylindrical},
    {"universal", JointType::universal}, {"planar", JointType::planar},       {"spherical", JointType::spherical},
    {"free", JointType::free},           {"weld", JointType::weld}};
inline constexpr EnumName<ForceKind> kForceKinds[] = {
    {"spring_damper", ForceKind::spring_damper}, {"force", ForceKind::force}, {"torque", ForceKind::torque}};
inline constexpr EnumName<ConstraintKind> kConstraintKinds[] = {
    {"coincident", ConstraintKind::coincident}, {"distance", ConstraintKind::distance},
    {"coupler", ConstraintKind::coupler},       {"rolling", ConstraintKind::rolling},
    {"general", ConstraintKind::general}};
const char* joint_type_name(JointType t);
const char* force_kind_name(ForceKind k);
const char* constraint_kind_name(ConstraintKind k);

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
  std::string name;
  JointType type = JointType::revolute;
  std::string parent, child;
  std::optional<Vec3Text> axis;
  std::vector<Vec3Text> axes;  // universal
  Vec3Text parent_point, child_point;
  std::vector<ExprText> q0, u0;  // empty = defaults
  std::optional<ExprText> spring_k, spring_rest, damper_c;
  SourceLocation where;
  std::string key;
};

struct ForceSpec {
  ForceKind kind = ForceKind::force;
  std::string name;
  // spring_damper
  std::string body_a, body_b;
  Vec3Text point_a, point_b;
  ExprText k, c, rest;
  // force / torque
  std::string body;
  Vec3Text point, vector;
  bool body_frame = false;  // vector in the body's frame (frame: body), else the world's
  SourceLocation where;
  std::string key;
};

// Constraints Σ_k a_jk u_k + a_j0 = 0 (docs/reference/scene.md, "Constraints").
struct ConstraintSpec {
  std::string name;
  ConstraintKind kind = ConstraintKind::coincident;
  // coincident, distance: two body points (body "ground" allowed)
  std::string body_a, body_b;
  Vec3Text point_a, point_b;
  std::vector<int> components;  // coincident: world components kept (0 x, 1 y, 2 z); empty = default
  ExprText length;                      // distance
  // coupler: u_a − ratio u_b = 0 (q_a − ratio q_b − offset = 0)
  std::string joint_a, joint_b;
  ExprText ratio, offset;
  // general: Σ a_k u_k + a0 = 0, or from a position function g(q, t) = 0
  std::vector<std::pair<std::string, ExprText>> a;  // speed name → coefficient
  std::optional<ExprText> a0, position;
  // rolling: a wheel (body) of radius r rolling without slip on the plane n·x = height
  std::string body;
  ExprText radius, height;
  Vec3Text axis, normal;
  SourceLocation where;
  std::string key;
};

struct SceneSpec {
  std::string file;  // path of the file it came from ("" if inline text)
  std::string text;  // the exact YAML text (stored in output files)
  SourceLocation where;  // the `scene:` map (messages about the scene as a whole)
  std::string name;
  Vec3Text gravity;
  std::vector<ParameterSpec> parameters;
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  std::vector<ForceSpec> forces;
  std::vector<ConstraintSpec> constraints;
};

}  // namespace kanesens::model
