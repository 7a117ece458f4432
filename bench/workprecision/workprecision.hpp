// `kanesens-workprecision STUDY [--tolerances 1e-4,1e-6,...] [--methods M1,M2,...]
//  [--repeat K] [--reference-rtol 1e-13] [--reference-method M] [--reference-file F] [--with-sens]
//  [--json]`:
// speed against accuracy. For every method and tolerance the study's nominal sample is
// integrated, compared with a reference solution at the study's output times, and timed.
//
// Methods (all on the same KaneProblem):
//   bdf-exact         CVODES BDF, Newton, exact (dual-number) Jacobian
//   bdf-dq            CVODES BDF, Newton, CVODES's difference-quotient Jacobian
//   adams-newton      CVODES Adams–Moulton, Newton, exact Jacobian
//   adams-functional  CVODES Adams–Moulton, fixed-point iteration (no Jacobian)
//   dop853            explicit adaptive Runge–Kutta 8(5,3) (sim/solve/dop853.hpp, solver.method: dop853)
//   rk4               classical fixed-step RK4 (sim/solve/rk4.hpp); tolerance tol → step
//                     h = rk4_h_scale · tol^(1/4) (its global error is O(h⁴)), or the step
//                     counts of --rk4-steps (h = (t_end − t0)/N)
//   sens-exact        bdf-exact with the study's sensitivities, exact sensitivity RHS (duals)
//   sens-dq           bdf-exact with the study's sensitivities, CVODES's DQ sensitivity RHS
// The first six integrate the states only, unless --with-sens (then all integrate the study's
// sensitivities with the exact sensitivity RHS; RK4 and DOP853 by their own stages).
// Tolerances of the error-controlled methods: rtol = tol, atol = tol · atol_ratio (all states).
//
// Reference: --reference-method (bdf-exact; dop853 for non-stiff problems, whose BDF reference
// limits the measurable error to ~1e-9) at --reference-rtol (atol = reference_rtol · atol_ratio), with the
// study's sensitivities, or --reference-file: JSON/YAML with `time` and `states` (T × n) and
// optionally `state_names` and `sensitivities` (T × n × ns) — e.g. `kanesens simulate` output or
// a published solution (only the times it lists are compared; they must be output times).
//
// Errors (d = y − y_ref, at the reference's times):
//   final_rel_error  max over components of |d_i(T)| / max(|y_ref,i(T)|, error_floor)
//   l2_error         sqrt(mean over times and components of d²) (DiffEqDevTools :l2)
//   linf_error       max over times and components of |d|
//   sens_final_rel_error  max over (i, j) of |ds_ij(T)| / max(|s_ref,ij(T)|, floor · max_i |s_ref,ij(T)|)
//   sens_l2_error    as l2_error, over all sensitivities
// and diagnostics of the run itself: energy drift max |E(t) − E(t0)|, energy error against the
// reference, max | |quaternion| − 1 |, constraint residuals (max |g|, max |A u + a0|), and the
// growth rate of the sensitivity norm ln(‖S(t)‖_F / ‖S(t0)‖_F) / (t − t0) (a Lyapunov estimate
// for chaotic systems; also the least-squares slope of ln ‖S‖ over the second half of the run).
//
// Work: wall time of the integration alone (a recorder that does nothing), median of --repeat
// runs, each with a fresh Integrator (setup included); the errors come from one more, recorded,
// run (integration is deterministic). If that recorded run takes longer than --max-seconds,
// it is the only run and its time is reported (timed_with_recording = true).
#pragma once
#include <chrono>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "sim/kane_problem.hpp"
#include "sim/simulate.hpp"
#include "study/study_spec.hpp"
#include "util/json_writer.hpp"

namespace kanesens::bench {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

struct WpOptions {
  std::string study;
  std::vector<std::string> set;
  std::string tolerances = "1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10";
  std::string methods;  // empty: the default list
  std::string rk4_steps;
  int repeat = 5;
  double reference_rtol = 1e-13;
  std::string reference_method = "bdf-exact";
  std::string reference_file;
  double atol_ratio = 1e-2;
  double error_floor = 1e-2;
  double rk4_h_scale = 0.1;
  double max_seconds = 2.0;
  long max_steps = 0;  // 0: the study's solver.max_steps
  long reference_max_steps = 100000000;
  bool with_sens = false;
  bool json = false;
};

// A solution at some output times (indices into the study's output times).
struct Solution {
  std::vector<std::size_t> index;      // output index of each time
  std::vector<double> states;          // index.size() × n
  std::vector<double> sensitivities;   // index.size() × n × ns (may be empty)
  std::vector<double> energy;          // index.size() (may be empty)
};

struct Errors {
  double final_rel = nan_value, final_abs = nan_value, l2 = nan_value, linf = nan_value;
  std::string worst_component;
  double sens_final_rel = nan_value, sens_l2 = nan_value;
  double energy_error = nan_value;
};

struct Diagnostics {
  double energy_drift = nan_value, energy_drift_final = nan_value;
  double quaternion_drift = nan_value;
  double position_residual = nan_value, velocity_residual = nan_value;
  double sens_rate = nan_value, sens_slope = nan_value, sens_norm_final = nan_value;
};

struct Row {
  std::string method;
  double tol = nan_value, rtol = nan_value, atol = nan_value, h = nan_value;
  long rk4_steps = 0;
  bool with_sens = false, ok = false, skipped = false, timed_with_recording = false;
  int status = 0;
  std::string message;
  double t_fail = nan_value;
  double wall_median = nan_value, wall_min = nan_value;
  int repeats = 0;
  sim::SolverStats stats;
  Errors err;
  Diagnostics diag;
};

struct Setup {
  const WpOptions& o;
  const study::StudySpec& study;
  const model::Model& model;
  const std::vector<double>& times;
};

double seconds_since(std::chrono::steady_clock::time_point t0);

// accuracy.cpp: the run's own diagnostics, its errors against the reference, a reference file.
Diagnostics diagnose(const model::Model& m, const std::vector<double>& times, const sim::Trajectory& tr,
                     std::size_t ns, int outputs);
Errors compare(const Setup& s, const sim::Trajectory& tr, std::size_t ns, const Solution& ref);
Solution load_reference(const Setup& s, std::size_t ns);

// measure.cpp: the methods, and one timed run of a method at a tolerance (or RK4 step h).
sim::RecordFlags flags_for(const model::Model& m, bool sens);
// Configures `opt` for an error-controlled method (CVODES or DOP853); false for an unknown name.
bool solver_method(const std::string& name, sim::SolverOptions& opt);
Row run_method(const Setup& s, sim::KaneProblem& problem, const std::string& method, double tol, double h,
               sim::Trajectory& tr);

// report.cpp: the JSON rows and the text table.
void write_row(JsonWriter& j, const Row& r);
std::string fmt(double v, const char* f = "%.2e");

}  // namespace kanesens::bench
