// The constraints of a scene: names, bodies, points, components, couplers, general constraints
// (position or velocity form) and rolling contacts, as constraint rows of the Model; then the
// check that the nominal parameters make a valid model.
#include <set>

#include "model/builder.hpp"
#include "model/joint_types.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::model::detail {

int Builder::joint_ref(const std::string& name, const SourceLocation& w, const std::string& key) {
  if (const auto it = joint_index_.find(name); it != joint_index_.end()) return it->second;
  std::vector<std::string> names;
  for (const Joint& j : m_.joints) names.push_back(j.name);
  fail(w, key, "'" + name + "' is not a joint" + did_you_mean(name, names) + "; joints are: " + join_names(names));
}

void Builder::build_constraints() {
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
        std::vector<int> position_coordinate(static_cast<std::size_t>(m_.nu), -1);  // speed k → its coordinate
        for (const Joint& J : m_.joints) {
          const int rates = J.quaternion_offset < 0 ? J.nu : J.quaternion_offset - J.q_offset;
          for (int k = 0; k < rates; ++k) position_coordinate[static_cast<std::size_t>(J.u_offset + k)] = J.q_offset + k;
          for (int k = rates; k < J.nq; ++k)
            if (c.position.uses(expr::VarKind::coordinate, J.q_offset + k))
              fail(cs.position->where, cs.position->key,
                   "'" + m_.coordinate_names[J.q_offset + k] + "' is a quaternion component of " +
                       joint_type_name(J.type) + " joint '" + J.name +
                       "'; a position function may use only coordinates whose rates are speeds (u = q̇); use a "
                       "coincident or distance constraint, or the velocity form 'a'");
        }
        for (int i : c.position.variables(expr::VarKind::coordinate))
          for (int k = 0; k < m_.nu; ++k)
            if (position_coordinate[static_cast<std::size_t>(k)] == i) c.position_reads.emplace_back(i, k);
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

void Builder::check_nominal() {
  const std::vector<double> p = m_.nominal_parameters();
  if (const auto problem = find_parameter_problem(m_, p.data()))
    throw InputError(problem->where, problem->key, problem->message);
}

}  // namespace kanesens::model::detail
