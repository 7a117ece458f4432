// The immutable Model: topology, coordinates, speeds, parameters and compiled expressions of a
// scene. Built once by build_model(); evaluated through Workspace<Scalar> (dynamics/workspace.hpp).
//
// Notation (docs/reference/scene.md): nq coordinates q, nu speeds u, state y = [q; u].
// Every number of the scene is an expression stored in `expressions`; a "slot" is an index into
// it and into Workspace::values. Slots whose expression reads t, q or u are re-evaluated each
// right-hand side (state_slots); the rest once per parameter set (parameter_slots).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "model/expr/expression.hpp"
#include "model/scene/scene_spec.hpp"

namespace kanesens::model {


using Slot = int;
using Slot3 = std::array<Slot, 3>;

// One generalized speed's motion: a rotation about, or translation along, a unit direction.
// The direction is a parent-frame vector (slot), or a child-frame unit vector e_m (spherical and
// free rotations). `carriers` = how many preceding speeds of the same joint move the axis
// (0: fixed in the parent; universal's 2nd axis: 1; planar rotation: 2; spherical/free: all).
struct SpeedAxis {
  bool rotation = true;
  bool in_child_frame = false;
  Slot3 direction{-1, -1, -1};  // parent-frame direction (when !in_child_frame), normalised
  int child_axis = 0;           // 0, 1, 2 for e_x, e_y, e_z (when in_child_frame)
  int carriers = 0;
};

struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  int parent = -1;  // body index, -1 = ground
  int child = -1;
  int q_offset = 0, nq = 0, u_offset = 0, nu = 0;
  int quaternion_offset = -1;  // index in q of the quaternion's w, or -1
  std::vector<SpeedAxis> speeds;
  Slot3 axis{-1, -1, -1};   // first axis (revolute, prismatic, cylindrical, planar normal, universal a1)
  Slot3 axis2{-1, -1, -1};  // universal a2
  Slot3 parent_point{-1, -1, -1}, child_point{-1, -1, -1};
  Slot spring_k = -1, spring_rest = -1, damper_c = -1;
  std::vector<Slot> q0, u0;  // one slot per coordinate / speed
  std::vector<std::string> coordinate_names, speed_names;
};

struct Body {
  std::string name;
  Slot mass = -1;
  std::array<Slot, 6> inertia{};  // xx, yy, zz, xy, yz, xz of the central tensor, body frame
  int joint = -1;                 // the joint whose child this body is
  int parent = -1;                // parent body, -1 = ground
  int root_joint = -1;            // the joint of its tree's root body (whose parent is ground)
};

struct Force {
  using Kind = ForceKind;
  std::string name;
  Kind kind = Kind::force;
  int body_a = -1, body_b = -1;  // spring_damper (-1 = ground)
  Slot3 point_a{}, point_b{};
  Slot k = -1, c = -1, rest = -1;
  int body = -1;  // force, torque
  Slot3 point{}, vector{};
  bool body_frame = false;
};

// A constraint contributes `nrows` rows of A u + a0 = 0 (A: m×nu), starting at row_offset.
// Multiplier convention (M u̇ = f + Aᵀλ): coincident λ = force on body_a at point_a from
// body_b, world components; distance λ = force on body_b along e_ab (a→b), positive pushing
// the points apart; coupler λ = generalized force on joint_a's speed; rolling λ = contact force
// on the wheel at the contact point, world components; general λ = generalized force Aᵀλ.
struct Constraint {
  using Kind = ConstraintKind;
  std::string name;
  Kind kind = Kind::coincident;
  int row_offset = 0, nrows = 0;
  std::vector<unsigned char> holonomic;  // per row: has a position-level residual
  // coincident, distance
  int body_a = -1, body_b = -1;
  Slot3 point_a{}, point_b{};
  std::array<int, 3> components{0, 1, 2};  // coincident: kept world components (first nrows)
  Slot length = -1;
  // coupler (1-DOF joints): speeds and coordinates
  int speed_a = -1, speed_b = -1, coord_a = -1, coord_b = -1;
  Slot ratio = -1, offset = -1;
  // general: coefficients of speeds (or a position function), expressions of q, t, parameters
  std::vector<std::pair<int, expr::Expression>> a;  // (speed index, a_k)
  expr::Expression a0;
  bool has_position = false;
  expr::Expression position;
  std::vector<std::pair<int, int>> position_reads;  // (coordinate, its speed) for each coordinate it reads
  // rolling
  int body = -1;
  Slot radius = -1, height = -1;
  Slot3 axis{}, normal{};
};

struct Parameter {
  std::string name;
  expr::Expression value;  // constant, or derived from earlier parameters
  bool derived = false;
  double nominal = 0;
};

struct Model {
  std::string name;
  SceneSpec spec;  // what it was built from (text kept for provenance)
  std::vector<Parameter> parameters;
  std::vector<Body> bodies;         // ground excluded
  std::vector<Joint> joints;        // declaration order (= order of q and u)
  std::vector<int> joint_order;     // topological: parents before children
  std::vector<std::vector<int>> ancestor_speeds;  // per body: speeds moving it, root first
  // The speeds' tree (Featherstone 2008 §6.5): speed_parent[k] is the speed next to k on the
  // way to the root (the previous speed of k's joint, else the last speed of the nearest
  // ancestor joint that has speeds; −1 on a root), speed_order lists the speeds parents first.
  std::vector<int> speed_parent;  // nu
  std::vector<int> speed_order;   // nu
  std::vector<unsigned char> speed_rotation;  // nu: 1 if the speed's partial velocity is a rotation
  std::vector<int> speed_body;    // nu: the body the speed's joint moves (its child)
  std::vector<Force> forces;
  std::vector<Constraint> constraints;
  int nconstraint_rows = 0;                      // m
  std::vector<std::string> constraint_row_names;  // m, e.g. "tip.x", "rod.length"
  std::vector<std::vector<unsigned char>> moves;  // [body][speed]: speed moves body
  Slot3 gravity{};
  int nq = 0, nu = 0;
  std::vector<std::string> coordinate_names, speed_names, state_names;
  std::vector<std::string> initial_condition_names;  // "J.q0", "J.q0[2]", "J.u0", ...
  std::vector<expr::Expression> expressions;
  std::vector<Slot> parameter_slots, state_slots;
  bool has_quaternions = false;
  // Planar scene: every joint's motion keeps bodies in planes parallel to the world x–y plane,
  // whatever the parameters: revolute axes and planar-joint normals are constant ±z, prismatic
  // axes have a constant zero z component, welds are allowed, other joint types are not. (At
  // q = 0 frames are parallel, so every body then rotates about z only.) Points, gravity, forces
  // and inertias may be anything: a planar motion's power sees only ω_z, v_x, v_y and τ_z, F_x,
  // F_y, so out-of-plane components cannot change M or f. Planar scenes are evaluated with
  // 3-component spatial vectors (math/planar.hpp): a planar scene pays planar work.
  bool planar = false;
  // Evaluate with the general 3-D code even when `planar` (tests and benchmarks compare both).
  bool force_general_3d = false;
  bool evaluate_planar() const { return planar && !force_general_3d; }

  int nbody() const { return static_cast<int>(bodies.size()); }
  int nstate() const { return nq + nu; }
  int nparam() const { return static_cast<int>(parameters.size()); }
  int find_parameter(const std::string& name) const;  // -1 if absent
  int find_body(const std::string& name) const;       // -1 ground, -2 absent
  std::vector<double> nominal_parameters() const;
};

}  // namespace kanesens::model
