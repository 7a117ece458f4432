#include "sim/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "dynamics/equations.hpp"
#include "dynamics/queries.hpp"
#include "sim/output_evaluator.hpp"

namespace kanesens::sim {

using namespace kanesens::dynamics;

namespace {

// The solver's times: the output times and the outputs' `at:` times, merged. For solver time j,
// output[j] is the output index (or −1) and at[j] says whether `at:` values are taken there.
struct Schedule {
  std::vector<double> times;
  std::vector<int> output;
  std::vector<unsigned char> at;
};

Schedule make_schedule(std::span<const double> times, const std::vector<double>& at_times) {
  Schedule s;
  std::size_t a = 0;
  for (std::size_t k = 0; k <= times.size(); ++k) {
    const double next = k < times.size() ? times[k] : INFINITY;
    for (; a < at_times.size() && at_times[a] < next; ++a) {
      s.times.push_back(at_times[a]);
      s.output.push_back(-1);
      s.at.push_back(1);
    }
    if (k == times.size()) break;
    const bool at = a < at_times.size() && at_times[a] == next;
    if (at) ++a;
    s.times.push_back(next);
    s.output.push_back(static_cast<int>(k));
    s.at.push_back(at ? 1 : 0);
  }
  return s;
}

// Position of each body frame and its quaternion (world) at the full state y.
void record_poses(KaneProblem& problem, double t, const double* y, double* out) {
  const model::Model& m = problem.model();
  Workspace<double>& ws = problem.workspaces().values();
  evaluate_state_expressions(m, ws, t, y, y + m.nq);
  compute_position(m, ws, y);
  for (int b = 0; b < m.nbody(); ++b) {
    const Vec3<double> p = body_position(m, ws, b);
    const auto e = rotation_quaternion<double>(body_rotation(m, ws, b));
    double* o = out + 7 * b;
    for (int i = 0; i < 3; ++i) o[i] = p[i];
    for (int i = 0; i < 4; ++i) o[3 + i] = e[i];
  }
}

// The recorder; with `outputs` (and its schedule), also the study's outputs.
RecordFn recorder(KaneProblem& problem, const RecordFlags& flags, Trajectory& traj, OutputEvaluator* outputs,
                  const Schedule* schedule) {
  const std::size_t n = static_cast<std::size_t>(problem.model().nstate());
  const std::size_t ns = static_cast<std::size_t>(problem.num_sensitivities());
  // Scratch shared by the calls (the recorder is called once per output, never concurrently).
  auto yfull = std::make_shared<std::vector<double>>(n);
  auto s_full = std::make_shared<std::vector<std::vector<double>>>(ns, std::vector<double>(n));
  auto s_ptr = std::make_shared<std::vector<double*>>(ns);
  const std::size_t nint = static_cast<std::size_t>(problem.size());
  auto y_projected = std::make_shared<std::vector<double>>(nint);
  auto correction = std::make_shared<std::vector<double>>(nint);
  const std::size_t ntimes =  // output times (for the [output][time] layout of the outputs)
      schedule ? static_cast<std::size_t>(std::count_if(schedule->output.begin(), schedule->output.end(),
                                                        [](int k) { return k >= 0; }))
               : 0;
  return [&problem, &traj, flags, n, ns, nint, yfull, s_full, s_ptr, y_projected, correction, outputs, schedule,
          ntimes](int j, double t, const double* yint, const double* const* sint) {
    const int k_out = schedule ? schedule->output[static_cast<std::size_t>(j)] : j;
    const bool at = schedule && schedule->at[static_cast<std::size_t>(j)];
    const std::size_t kk = static_cast<std::size_t>(k_out);
    // With projection, CVODES projects the state at the end of each step, but an output between
    // step ends is interpolated and may sit off the constraints (far off when the error test,
    // projected onto the tangent space, leaves the steps long: a fully driven coordinate).
    // Record the projected state; the integrator's own copy is left as it is.
    if (problem.has_projection() && problem.project(t, yint, correction->data(), 0.0, nullptr) == 0) {
      for (std::size_t r = 0; r < nint; ++r) (*y_projected)[r] = yint[r] + (*correction)[r];
      yint = y_projected->data();
    }
    // Outputs are always the full state [q; u] (the embedding integrates [q; u_i]).
    problem.full_state(t, yint, yfull->data());
    const double* y = yfull->data();
    for (std::size_t i = 0; sint && i < ns; ++i) {
      problem.full_sensitivity(t, yint, static_cast<int>(i), sint[i], (*s_full)[i].data());
      (*s_ptr)[i] = (*s_full)[i].data();
    }
    // CVODES projects y only: record the sensitivities projected onto the tangent space
    // (the integrator's own copies are left as they are).
    if (sint && problem.projects_sensitivities())
      problem.project_sensitivities(t, y, s_ptr->data());
    const double* const* s = sint ? s_ptr->data() : nullptr;
    if (outputs && (j == 0 || static_cast<std::size_t>(j) + 1 == schedule->times.size())) outputs->take_end_values(t, y, s);
    if (at) {
      outputs->evaluate(outputs->plan().at, t, y, s);
      outputs->take_at_values(t);
    }
    if (k_out < 0) return;
    if (flags.states) std::copy(y, y + n, traj.states.begin() + static_cast<std::ptrdiff_t>(kk * n));
    if (flags.sensitivities && s)
      for (std::size_t r = 0; r < n; ++r)
        for (std::size_t i = 0; i < ns; ++i) traj.sensitivities[(kk * n + r) * ns + i] = s[i][r];
    if (flags.energy) traj.energy[kk] = problem.energy(t, y);
    const std::size_t m = static_cast<std::size_t>(problem.model().nconstraint_rows);
    if (flags.multipliers && m > 0) {
      if (flags.sensitivities && s)
        problem.multipliers_and_sensitivities(t, y, s, &traj.multipliers[kk * m],
                                              &traj.multiplier_sensitivities[kk * m * ns]);
      else
        problem.multipliers(t, y, &traj.multipliers[kk * m]);
    }
    if (flags.constraint_residual && m > 0)
      problem.constraint_residuals(t, y, traj.position_residual[kk], traj.velocity_residual[kk]);
    if (flags.poses) {
      const std::size_t nb = static_cast<std::size_t>(problem.model().nbody());
      record_poses(problem, t, y, &traj.poses[kk * nb * 7]);
    }
    if (outputs && !outputs->plan().record.empty()) {
      const OutputPlan& plan = outputs->plan();
      outputs->evaluate(plan.record, t, y, s);
      const std::size_t T = ntimes;
      for (std::size_t v = 0; v < plan.series_slots.size(); ++v) {
        const int slot = plan.series_slots[v];
        traj.outputs[v * T + kk] = outputs->value(slot);
        for (std::size_t i = 0; s && i < ns; ++i)
          traj.output_sensitivities[(v * T + kk) * ns + i] = outputs->tangent(slot, static_cast<int>(i));
      }
    }
  };
}

}  // namespace

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
  const std::size_t nseries = flags.outputs ? flags.outputs->series_slots.size() : 0;
  const std::size_t nscalar = flags.outputs ? flags.outputs->scalar_slots.size() : 0;
  traj.outputs.assign(nseries * ntimes, std::nan(""));
  traj.output_sensitivities.assign(nseries * ntimes * ns, std::nan(""));
  traj.scalar_outputs.assign(nscalar, std::nan(""));
  traj.scalar_output_sensitivities.assign(nscalar * ns, std::nan(""));
  const std::size_t nevent = flags.outputs ? flags.outputs->event_nodes.size() : 0;
  const std::size_t W = flags.outputs ? static_cast<std::size_t>(flags.outputs->event_occurrences) : 0;
  traj.event_times.assign(nevent * W, std::nan(""));
  traj.event_time_sensitivities.assign(nevent * W * ns, std::nan(""));
  traj.event_counts.assign(nevent, std::nan(""));
  traj.poses.assign(flags.poses ? ntimes * static_cast<std::size_t>(problem.model().nbody()) * 7 : 0, std::nan(""));
}

RecordFn make_recorder(KaneProblem& problem, const RecordFlags& flags, Trajectory& traj) {
  return recorder(problem, flags, traj, nullptr, nullptr);
}

// The problem's own account of a failure (the embedding's rows that lost rank) leads the message.
static void name_failure_cause(const KaneProblem& problem, Trajectory& traj) {
  if (!traj.result.ok() && !problem.failure_cause().empty() &&
      traj.result.message.find(problem.failure_cause()) == std::string::npos)
    traj.result.message = problem.failure_cause() + " (" + traj.result.message + ")";
}

void simulate(KaneProblem& problem, Integrator& integrator, std::span<const double> times,
              const RecordFlags& flags, Trajectory& traj) {
  resize_trajectory(traj, problem, times.size(), flags);
  if (!flags.outputs || flags.outputs->empty()) {
    traj.result = integrator.integrate(problem, times, make_recorder(problem, flags, traj));
    name_failure_cause(problem, traj);
    return;
  }
  const OutputPlan& plan = *flags.outputs;
  for (double t : plan.at_times)
    if (times.empty() || t < times.front() || t > times.back())
      throw std::invalid_argument("outputs: at time " + std::to_string(t) + " outside the output times");
  const Schedule schedule = make_schedule(times, plan.at_times);
  OutputEvaluator outputs(plan, problem);
  outputs.start();
  outputs.take_initial_eigenvalues();
  traj.result = integrator.integrate(problem, schedule.times, recorder(problem, flags, traj, &outputs, &schedule),
                                     outputs.size() > 0 ? &outputs : nullptr, outputs.events());
  outputs.finish(traj.result.ok(), times.back() - times.front(), traj.scalar_outputs.data(),
                 traj.scalar_output_sensitivities.data());
  outputs.event_records(traj.event_times.data(), traj.event_time_sensitivities.data(), traj.event_counts.data());
  if (const std::string notes = outputs.notes(); !notes.empty())
    traj.result.message += (traj.result.message.empty() ? "" : "; ") + notes;
  name_failure_cause(problem, traj);
}

}  // namespace kanesens::sim
