#include "sim/eigenvalue_outputs.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "sim/linearize.hpp"
#include "sim/modes.hpp"
#include "util/error.hpp"

namespace kanesens::sim {

void evaluate_eigenvalues(const OutputNode& node, KaneProblem& problem, double* values, double* tangents) {
  const model::Model& m = problem.model();
  const int ns = problem.num_sensitivities();
  const double t0 = problem.initial_time();
  const std::size_t nint = static_cast<std::size_t>(problem.size()), nstate = static_cast<std::size_t>(m.nstate());
  std::vector<double> y0(nint), y(nstate), s0(nint);
  problem.initial_state(y0.data());
  problem.full_state(t0, y0.data(), y.data());
  std::vector<LinearizeDirection> directions(static_cast<std::size_t>(ns));
  for (int i = 0; i < ns; ++i) {
    LinearizeDirection& d = directions[static_cast<std::size_t>(i)];
    d.state.assign(nstate, 0.0);
    d.parameters.assign(static_cast<std::size_t>(m.nparam()), 0.0);
    problem.initial_sensitivity(i, s0.data());
    problem.full_sensitivity(t0, y0.data(), i, s0.data(), d.state.data());
    const InputRef& ref = problem.sensitivities()[static_cast<std::size_t>(i)];
    if (ref.kind == InputRef::Kind::parameter) d.parameters[static_cast<std::size_t>(ref.index)] = 1.0;
  }
  LinearizeOptions options;
  options.coordinates = node.linear_coordinates;
  options.speeds = node.linear_speeds;
  std::vector<Eigen::MatrixXd> dA;
  Linearization lin;
  try {
    lin = linearize(m, problem.workspaces().parameters(), t0, y, options, directions, dA);
  } catch (const InputError& e) {
    throw std::runtime_error("outputs." + node.name + ": cannot linearize at this sample's initial state: " + e.detail());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("outputs." + node.name + ": " + e.what());
  }
  const Modes md = modes(lin.A);
  const Eigen::MatrixXcd dl = eigenvalue_derivatives(md, dA);
  for (int k = 0; k < node.eigenvalue_count; ++k) {
    const std::size_t re = static_cast<std::size_t>(2 * k), im = re + 1;
    values[re] = md.values[k].real();
    values[im] = md.values[k].imag();
    for (int i = 0; i < ns; ++i) {
      tangents[re * static_cast<std::size_t>(ns) + static_cast<std::size_t>(i)] = dl(k, i).real();
      tangents[im * static_cast<std::size_t>(ns) + static_cast<std::size_t>(i)] = dl(k, i).imag();
    }
  }
}

}  // namespace kanesens::sim
