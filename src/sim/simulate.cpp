#include "sim/simulate.hpp"

#include <cmath>
#include <memory>

namespace kanesens::sim {

using namespace kanesens::dynamics;

void resize_trajectory(Trajectory& traj, const KaneProblem& problem, std::size_t ntimes, const RecordFlags& flags) {
  const std::size_t n = static_cast<std::size_t>(problem.model().nstate());
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  traj.states.assign(flags.states ? ntimes * n : 0, std::nan(""));
  traj.sensitivities.assign(flags.sensitivities ? ntimes * n * ns : 0, std::nan(""));
  traj.energy.assign(flags.energy ? ntimes : 0, std::nan(""));
  const std::size_t m = static_cast<std::size_t>(problem.model().nconstraint_rows);
  traj.multipliers.assign(flags.multipliers ? ntimes * m : 0, std::nan(""));
  traj.multiplier_sensitivities.assign(flags.multipliers && flags.sensitivities ? ntimes * m * ns : 0, std::nan(""));
  traj.position_residual.assign(flags.constraint_residual ? ntimes : 0, std::nan(""));
  traj.velocity_residual.assign(flags.constraint_residual ? ntimes : 0, std::nan(""));
}

RecordFn make_recorder(KaneProblem& problem, const RecordFlags& flags, Trajectory& traj) {
  const std::size_t n = static_cast<std::size_t>(problem.model().nstate());
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  // Scratch shared by the calls (the recorder is called once per output, never concurrently).
  auto yfull = std::make_shared<std::vector<double>>(n);
  auto s_full = std::make_shared<std::vector<std::vector<double>>>(ns, std::vector<double>(n));
  auto s_ptr = std::make_shared<std::vector<const double*>>(ns);
  const std::size_t nint = static_cast<std::size_t>(problem.size());
  auto y_projected = std::make_shared<std::vector<double>>(nint);
  auto correction = std::make_shared<std::vector<double>>(nint);
  return [&problem, &traj, flags, n, ns, nint, yfull, s_full, s_ptr, y_projected, correction](
             int k, double t, const double* yint, const double* const* sint) {
    const std::size_t kk = static_cast<std::size_t>(k);
    // With projection, CVODES projects the state at the end of each step, but an output between
    // step ends is interpolated and may sit off the constraints (far off when the error test,
    // projected onto the tangent space, leaves the steps long: a fully driven coordinate).
    // Record the projected state; the integrator's own copy is left as it is.
    if (problem.has_projection() && problem.project(t, yint, correction->data(), 0.0, nullptr) == 0) {
      for (std::size_t j = 0; j < nint; ++j) (*y_projected)[j] = yint[j] + (*correction)[j];
      yint = y_projected->data();
    }
    // Outputs are always the full state [q; u] (the embedding integrates [q; u_i]).
    problem.full_state(t, yint, yfull->data());
    const double* y = yfull->data();
    for (std::size_t i = 0; sint && i < ns; ++i) {
      problem.full_sensitivity(t, yint, static_cast<int>(i), sint[i], (*s_full)[i].data());
      // CVODES projects y only: record the sensitivities projected onto the tangent space
      // (the integrator's own copies are left as they are).
      if (problem.projects_sensitivities()) problem.project_sensitivity(t, y, static_cast<int>(i), (*s_full)[i].data());
      (*s_ptr)[i] = (*s_full)[i].data();
    }
    const double* const* s = sint ? s_ptr->data() : nullptr;
    if (flags.states) std::copy(y, y + n, traj.states.begin() + static_cast<std::ptrdiff_t>(kk * n));
    if (flags.sensitivities && s)
      for (std::size_t r = 0; r < n; ++r)
        for (std::size_t i = 0; i < ns; ++i) traj.sensitivities[(kk * n + r) * ns + i] = s[i][r];
    if (flags.energy) traj.energy[kk] = problem.energy(t, y);
    const std::size_t m = static_cast<std::size_t>(problem.model().nconstraint_rows);
    if (flags.multipliers && m > 0) {
      problem.multipliers(t, y, &traj.multipliers[kk * m]);
      if (flags.sensitivities && s) {
        std::vector<double> dl(m);
        for (std::size_t i = 0; i < ns; ++i) {
          problem.multiplier_sensitivity(t, y, static_cast<int>(i), s[i], dl.data());
          for (std::size_t r = 0; r < m; ++r) traj.multiplier_sensitivities[(kk * m + r) * ns + i] = dl[r];
        }
      }
    }
    if (flags.constraint_residual && m > 0)
      problem.constraint_residuals(t, y, traj.position_residual[kk], traj.velocity_residual[kk]);
  };
}

void simulate(KaneProblem& problem, Integrator& integrator, std::span<const double> times,
              const RecordFlags& flags, Trajectory& traj) {
  resize_trajectory(traj, problem, times.size(), flags);
  traj.result = integrator.integrate(problem, times, make_recorder(problem, flags, traj));
}

}  // namespace kanesens::sim
