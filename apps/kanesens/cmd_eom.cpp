// `kanesens eom SCENE --q .. --u .. [--t T] [--set NAME=VALUE]`: Kane's equations at one state,
// as JSON (mass_matrix, forcing, udot, energies...).
#include <iostream>

#include "commands.hpp"
#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "util/json_writer.hpp"
#include "util/parse_number.hpp"

namespace kanesens::cli {

using namespace kanesens::dynamics;
using namespace kanesens::model;

namespace {
struct EomOptions {
  std::string scene, q, u;
  double t = 0;
  std::vector<std::string> set;
};

int run_eom(const EomOptions& o) {
  std::map<std::string, double> overrides;
  for (const auto& [k, v] : parse_assignments(o.set)) overrides[k] = parse_number(v, "--set " + k);
  const Model m = build_model(parse_scene_file(o.scene), overrides);
  const std::vector<double> q = o.q.empty() ? std::vector<double>{} : parse_number_list(o.q, "--q");
  const std::vector<double> u = o.u.empty() ? std::vector<double>{} : parse_number_list(o.u, "--u");
  if (static_cast<int>(q.size()) != m.nq)
    throw InputError({}, "--q", "expected " + std::to_string(m.nq) + " coordinates (" +
                                    [&] { std::string s; for (auto& n : m.coordinate_names) s += (s.empty() ? "" : ", ") + n; return s; }() +
                                    "), found " + std::to_string(q.size()));
  if (static_cast<int>(u.size()) != m.nu)
    throw InputError({}, "--u", "expected " + std::to_string(m.nu) + " speeds (" +
                                    [&] { std::string s; for (auto& n : m.speed_names) s += (s.empty() ? "" : ", ") + n; return s; }() +
                                    "), found " + std::to_string(u.size()));
  Workspace<double> ws(m);
  set_articulated_body(m, ws, false);  // M and f are printed
  const std::vector<double> p = m.nominal_parameters();
  set_parameters(m, ws, p.data());
  std::vector<double> y(q);
  y.insert(y.end(), u.begin(), u.end());
  std::vector<double> ydot(y.size());
  RhsFailure why = RhsFailure::none;
  const bool ok = evaluate_rhs(m, ws, o.t, y.data(), ydot.data(), {}, &why);

  JsonWriter j(std::cout);
  j.begin_object();
  j.key("scene").value(m.name);
  j.key("t").value(o.t);
  j.key("q").array(q);
  j.key("u").array(u);
  j.key("coordinate_names").array(m.coordinate_names);
  j.key("speed_names").array(m.speed_names);
  j.key("mass_matrix").begin_array();
  for (int r = 0; r < m.nu; ++r) {
    j.begin_array();
    for (int c = 0; c < m.nu; ++c) j.value(ws.mass_matrix(r, c));
    j.end_array();
  }
  j.end_array();
  j.key("forcing").array(ws.forcing.data(), m.nu);
  j.key("qdot").array(ws.qdot.data(), m.nq);
  j.key("udot");
  if (ok) j.array(ws.udot.data(), m.nu);
  else j.value(std::nan(""));  // null: M is not positive definite, or the constraints are degenerate
  const int nc = m.nconstraint_rows;
  j.key("constraint_names").array(m.constraint_row_names);
  j.key("constraint_matrix").begin_array();
  for (int r = 0; r < nc; ++r) {
    j.begin_array();
    for (int c = 0; c < m.nu; ++c) j.value(ws.constraint_matrix(r, c));
    j.end_array();
  }
  j.end_array();
  // constraint_bias = −(Ȧu + ȧ0): the right-hand side of A u̇ = constraint_bias.
  j.key("constraint_bias").array(ws.constraint_bias.data(), static_cast<std::size_t>(nc));
  j.key("constraint_velocity_residual").array(ws.velocity_residual.data(), static_cast<std::size_t>(nc));
  j.key("constraint_position_residual").array(ws.position_residual.data(), static_cast<std::size_t>(nc));
  j.key("multipliers");
  if (ok) j.array(ws.multipliers.data(), static_cast<std::size_t>(nc));
  else j.value(std::nan(""));
  j.key("constraint_rank").value(nc > 0 ? ws.constraint_rank : 0);
  j.key("kinetic_energy").value(kinetic_energy(m, ws));
  j.key("potential_energy").value(potential_energy(m, ws, q.data()));
  j.key("mass_matrix_positive_definite").value(why != RhsFailure::mass_matrix_not_positive_definite);
  j.key("constraints_solvable").value(why != RhsFailure::constraints_degenerate);
  if (!ok) std::cerr << "kanesens: eom: " << describe(why) << " at this state\n";
  j.end_object();
  std::cout << "\n";
  return ok ? 0 : 3;
}
}  // namespace

CLI::App* add_eom(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("eom", "Evaluate Kane's equations M u' = f at one state; prints JSON");
  auto o = std::make_shared<EomOptions>();
  cmd->add_option("scene", o->scene, "Scene YAML file")->required();
  cmd->add_option("--q", o->q, "All coordinates in joint order, comma-separated (use --q=-1,2 for negatives)");
  cmd->add_option("--u", o->u, "All speeds in joint order, comma-separated");
  cmd->add_option("--t", o->t, "Time (for time-dependent forces)")->check(finite_number());
  cmd->add_option("--set", o->set, "Override a parameter: NAME=VALUE (repeatable)");
  cmd->callback([&action, o] { action = [o] { return run_eom(*o); }; });
  return cmd;
}

}  // namespace kanesens::cli
