#include "sim/simulate.hpp"

#include <cmath>

namespace kanesens {

void resize_trajectory(Trajectory& traj, const KaneProblem& problem, std::size_t ntimes, const RecordFlags& flags) {
  const std::size_t n = static_cast<std::size_t>(problem.size());
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  traj.states.assign(flags.states ? ntimes * n : 0, std::nan(""));
  traj.sensitivities.assign(flags.sensitivities ? ntimes * n * ns : 0, std::nan(""));
  traj.energy.assign(flags.energy ? ntimes : 0, std::nan(""));
}

void simulate(KaneProblem& problem, solve::Integrator& integrator, std::span<const double> times,
              const RecordFlags& flags, Trajectory& traj) {
  resize_trajectory(traj, problem, times.size(), flags);
  const std::size_t n = static_cast<std::size_t>(problem.size());
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  traj.result = integrator.integrate(problem, times, [&](int k, double t, const double* y, const double* const* s) {
    const std::size_t kk = static_cast<std::size_t>(k);
    if (flags.states) std::copy(y, y + n, traj.states.begin() + static_cast<std::ptrdiff_t>(kk * n));
    if (flags.sensitivities && s)
      for (std::size_t r = 0; r < n; ++r)
        for (std::size_t i = 0; i < ns; ++i) traj.sensitivities[(kk * n + r) * ns + i] = s[i][r];
    if (flags.energy) traj.energy[kk] = problem.energy(t, y);
  });
}

}  // namespace kanesens
