// `kanesens check SCENE.yaml`: validate a scene and summarise it.
#include <iostream>

#include "commands.hpp"
#include <Eigen/Dense>

#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "sim/kane_problem.hpp"
#include "model/scene/parse_scene.hpp"
#include "util/did_you_mean.hpp"

namespace kanesens::cli {

using namespace kanesens::dynamics;
using namespace kanesens::model;
using namespace kanesens::sim;

CLI::App* add_check(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("check", "Validate a scene and print its bodies, joints, coordinates, speeds and parameters");
  auto path = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "Scene YAML file")->required();
  cmd->callback([&action, path] {
    action = [path] {
      const Model m = build_model(parse_scene_file(*path));
      KaneProblem problem(m, {});
      problem.validate_initial_state();  // degenerate constraints, non-finite equations at t = 0
      std::cout << "scene '" << m.name << "' (" << *path << "): valid\n";
      std::cout << "  bodies (" << m.nbody() << "):";
      for (const auto& b : m.bodies) std::cout << " " << b.name;
      std::cout << "\n  joints (" << m.joints.size() << "):";
      for (const auto& j : m.joints)
        std::cout << " " << j.name << " [" << joint_type_name(j.type) << ": "
                  << (j.parent >= 0 ? m.bodies[j.parent].name : "ground") << " -> " << m.bodies[j.child].name << "]";
      int rank = 0;
      if (m.nconstraint_rows > 0) {
        // Rank of the constraint matrix at the initial state: DOF = nu − rank(A).
        std::vector<double> y(static_cast<std::size_t>(m.nstate()));
        problem.initial_state(y.data());
        Workspace<double> ws(m);
        const std::vector<double> p = m.nominal_parameters();
        set_parameters(m, ws, p.data());
        evaluate_constraints(m, ws, 0.0, y.data(), y.data() + m.nq);
        rank = static_cast<int>(Eigen::FullPivLU<Eigen::MatrixXd>(ws.constraint_matrix).rank());
      }
      std::cout << "\n  degrees of freedom: " << m.nu - rank << " (nq = " << m.nq << ", nu = " << m.nu
                << ", independent constraint rows = " << rank << ")\n";
      std::cout << "  coordinates: " << join_names(m.coordinate_names) << "\n";
      std::cout << "  speeds: " << join_names(m.speed_names) << "\n";
      std::cout << "  constraints (" << m.constraints.size() << ", " << m.nconstraint_rows << " rows):";
      for (const auto& c : m.constraints) std::cout << " " << c.name;
      std::cout << "\n  constraint rows: " << (m.nconstraint_rows ? join_names(m.constraint_row_names) : "none") << "\n";
      std::cout << "  forces (" << m.forces.size() << "):";
      for (const auto& f : m.forces) std::cout << " " << f.name;
      std::cout << "\n  parameters (" << m.nparam() << "):";
      for (const auto& p : m.parameters)
        std::cout << " " << p.name << "=" << p.nominal << (p.derived ? " (derived)" : "");
      std::cout << "\n  initial conditions: " << join_names(m.initial_condition_names) << "\n";
      return 0;
    };
  });
  return cmd;
}

}  // namespace kanesens::cli
