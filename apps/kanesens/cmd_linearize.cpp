// `kanesens linearize SCENE [--q ..] [--u ..] [--t T] [--set NAME=VALUE] [--inputs P,..]
// [--coordinates ..] [--speeds ..] [--json]`: the linearized equations ẋ = A x + B w about a
// state made consistent with the constraints, and the eigenvalues and eigenvectors of A
// (sim/linearize.hpp, docs/linearization.md).
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "model/build_model.hpp"
#include "model/parameters.hpp"
#include "model/scene/parse_scene.hpp"
#include "sim/holonomic.hpp"
#include "sim/initial_state.hpp"
#include "sim/linearize.hpp"
#include "sim/modes.hpp"
#include "sim/sample_workspaces.hpp"
#include "util/did_you_mean.hpp"
#include "util/json_writer.hpp"
#include "util/parse_number.hpp"

namespace kanesens::cli {

using namespace kanesens::model;
using namespace kanesens::sim;

namespace {
struct LinearizeCliOptions {
  std::string scene, q, u, inputs, coordinates, speeds;
  double t = 0;
  std::vector<std::string> set;
  bool json = false;
};

// "a,b" → {"a", "b"}; "" → {}.
std::vector<std::string> split_names(const std::string& text, const std::string& what) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  for (;;) {
    const auto c = text.find(',', start);
    out.push_back(text.substr(start, c == std::string::npos ? std::string::npos : c - start));
    if (out.back().empty()) throw InputError({}, what, "empty name in '" + text + "'");
    if (c == std::string::npos) return out;
    start = c + 1;
  }
}

void check_count(const std::vector<double>& v, int n, const std::vector<std::string>& names, const std::string& what) {
  if (static_cast<int>(v.size()) != n)
    throw InputError({}, what, "expected " + std::to_string(n) + " values (" + join_names(names) + "), found " +
                                   std::to_string(v.size()));
}

void matrix(JsonWriter& j, const Eigen::MatrixXd& M) {
  j.begin_array();
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    j.begin_array();
    for (Eigen::Index c = 0; c < M.cols(); ++c) j.value(M(r, c));
    j.end_array();
  }
  j.end_array();
}
void complex(JsonWriter& j, std::complex<double> z) { j.begin_array().value(z.real()).value(z.imag()).end_array(); }

void print_json(const Model& m, double t, const std::vector<double>& y, const InitialState& init,
                const std::vector<std::string>& inputs, const Linearization& lin, const Modes& md) {
  JsonWriter j(std::cout);
  j.begin_object();
  j.key("scene").value(m.name);
  j.key("t").value(t);
  j.key("q").array(y.data(), static_cast<std::size_t>(m.nq));
  j.key("u").array(y.data() + m.nq, static_cast<std::size_t>(m.nu));
  j.key("coordinates").array(lin.coordinates);
  j.key("speeds").array(lin.speeds);
  j.key("dependent_coordinates").array(lin.dependent_coordinates);
  j.key("dependent_speeds").array(lin.dependent_speeds);
  j.key("dropped").array(lin.dropped);
  j.key("inputs").array(inputs);
  j.key("A");
  matrix(j, lin.A);
  j.key("B");
  matrix(j, lin.B);
  j.key("rates").array(lin.rates.data(), static_cast<std::size_t>(lin.rates.size()));
  j.key("eigenvalues").begin_array();
  for (Eigen::Index k = 0; k < md.values.size(); ++k) complex(j, md.values[k]);
  j.end_array();
  j.key("eigenvectors").begin_array();
  for (Eigen::Index k = 0; k < md.vectors.cols(); ++k) {
    j.begin_array();
    for (Eigen::Index r = 0; r < md.vectors.rows(); ++r) complex(j, md.vectors(r, k));
    j.end_array();
  }
  j.end_array();
  j.key("constraint_residuals").begin_object();
  j.key("position").value(lin.position_residual);
  j.key("velocity").value(lin.velocity_residual);
  j.end_object();
  j.key("initial_correction").begin_object();
  j.key("position").value(init.position_correction);
  j.key("velocity").value(init.velocity_correction);
  j.end_object();
  j.end_object();
  std::cout << "\n";
}

void print_text(const Linearization& lin, const Modes& md) {
  auto list = [](const std::vector<std::string>& v) { return v.empty() ? std::string("(none)") : join_names(v); };
  std::cout << "coordinates: " << list(lin.coordinates) << "\nspeeds: " << list(lin.speeds)
            << "\ndependent: " << list(lin.dependent_coordinates) << "; " << list(lin.dependent_speeds)
            << "\ndropped (ignorable): " << list(lin.dropped) << "\nA =\n";
  char buf[64];
  for (Eigen::Index r = 0; r < lin.A.rows(); ++r) {
    for (Eigen::Index c = 0; c < lin.A.cols(); ++c) {
      std::snprintf(buf, sizeof buf, " %22.15g", lin.A(r, c));
      std::cout << buf;
    }
    std::cout << "\n";
  }
  std::cout << "eigenvalues:\n";
  for (Eigen::Index k = 0; k < md.values.size(); ++k) {
    std::snprintf(buf, sizeof buf, "  %22.15g %+22.15gi\n", md.values[k].real(), md.values[k].imag());
    std::cout << buf;
  }
}

int run_linearize(const LinearizeCliOptions& o) {
  const Model m = build_model(parse_scene_file(o.scene));
  SampleInputs inputs(m);
  for (const auto& [k, v] : parse_assignments(o.set)) inputs.set(resolve_input(m, k, "--set " + k), parse_number(v, "--set " + k));
  if (!o.q.empty()) {
    const std::vector<double> q = parse_number_list(o.q, "--q");
    check_count(q, m.nq, m.coordinate_names, "--q");
    for (int i = 0; i < m.nq; ++i) inputs.set({InputRef::Kind::initial_condition, i, ""}, q[static_cast<std::size_t>(i)]);
  }
  if (!o.u.empty()) {
    const std::vector<double> u = parse_number_list(o.u, "--u");
    check_count(u, m.nu, m.speed_names, "--u");
    for (int i = 0; i < m.nu; ++i) inputs.set({InputRef::Kind::initial_condition, m.nq + i, ""}, u[static_cast<std::size_t>(i)]);
  }
  if (const auto problem = find_parameter_problem(m, inputs.parameters.data()))
    throw InputError(problem->where, problem->key, problem->message);
  LinearizeOptions lo;
  std::vector<std::string> input_names = split_names(o.inputs, "--inputs");
  std::vector<std::string> parameter_names;
  for (const auto& p : m.parameters) parameter_names.push_back(p.name);
  for (const std::string& name : input_names) {
    const int i = m.find_parameter(name);
    if (i < 0)
      throw InputError({}, "--inputs", "unknown parameter '" + name + "'" + did_you_mean(name, parameter_names) +
                                           "; inputs are scene parameters: " + join_names(parameter_names));
    if (m.parameters[static_cast<std::size_t>(i)].derived)
      throw InputError({}, "--inputs", "parameter '" + name + "' is derived from others; name a parameter given by value");
    lo.inputs.push_back(i);
  }
  lo.coordinates = split_names(o.coordinates, "--coordinates");
  lo.speeds = split_names(o.speeds, "--speeds");

  // The state made consistent as `simulate` does (ConstraintOptions defaults).
  SampleWorkspaces workspaces(m, {});
  workspaces.set_parameters(inputs.parameters);
  HolonomicConstraints holonomic(m);
  holonomic.set_parameters(inputs.parameters);
  const InitialState init = consistent_initial_state(m, inputs, {}, ConstraintOptions{}, o.t, workspaces, holonomic);

  const Linearization lin = linearize(m, inputs.parameters, o.t, init.y, lo);
  constexpr double kConsistent = 1e-8;
  if (lin.position_residual > kConsistent || lin.velocity_residual > kConsistent)
    throw InputError({}, o.q.empty() ? "initial conditions" : "--q",
                     "the state does not satisfy the constraints (position residual " +
                         std::to_string(lin.position_residual) + ", velocity residual " +
                         std::to_string(lin.velocity_residual) + ")");
  // A describes stability only about a steady state of the kept coordinates and speeds.
  const double rate = lin.rates.size() > 0 ? lin.rates.cwiseAbs().maxCoeff() : 0.0;
  if (rate > kConsistent)
    std::cerr << "kanesens: warning: the state is not steady in the kept coordinates and speeds (max |rate| = " << rate
              << "); A is the Jacobian there, not the linearization about an equilibrium\n";
  const Modes md = modes(lin.A);
  if (o.json) print_json(m, o.t, init.y, init, input_names, lin, md);
  else print_text(lin, md);
  return 0;
}
}  // namespace

CLI::App* add_linearize(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "linearize", "Linearized equations x' = A x + B w about a consistent state, with eigenvalues and eigenvectors");
  auto o = std::make_shared<LinearizeCliOptions>();
  cmd->add_option("scene", o->scene, "Scene YAML file")->required();
  cmd->add_option("--q", o->q, "All coordinates in joint order, comma-separated (default: the scene's q0; --q=-1,2 for negatives)");
  cmd->add_option("--u", o->u, "All speeds in joint order, comma-separated (default: the scene's u0)");
  cmd->add_option("--t", o->t, "Time")->check(finite_number());
  cmd->add_option("--set", o->set, "Override a parameter (m2=0.9) or an initial condition (elbow.q0=0.3); repeatable");
  cmd->add_option("--inputs", o->inputs, "Parameters that act as inputs (the columns of B), comma-separated");
  cmd->add_option("--coordinates", o->coordinates, "Coordinates to keep, comma-separated (default: chosen automatically)");
  cmd->add_option("--speeds", o->speeds, "Speeds to keep, comma-separated (default: chosen automatically)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([&action, o] { action = [o] { return run_linearize(*o); }; });
  return cmd;
}

}  // namespace kanesens::cli
