// MuJoCo peer of `kanesens bench rhs` and `kanesens simulate` on the four-bar of
// configs/four_bar.yaml (docs/peers.md, "Four-bar: Simbody and MuJoCo"). The tree is kanesens's:
// hinges about z, world→crank (at O), crank→coupler (at the crank tip, angle relative to the
// crank), world→rocker (at B = (a, 0)), so qpos and qvel are kanesens's q and u. Uniform rods:
// inertia m L²/12 about y and z; MuJoCo rejects a zero principal inertia, so the axial one is
// 1e-4 of that (it does not enter planar motion). Gravity (0, −9.81, 0); no geoms, no contacts.
//
// The loop is closed by an equality `connect` (3 rows, world x, y, z; the z row is identically
// satisfied in this planar tree, and MuJoCo's regularised solver takes the redundant row without
// trouble). MuJoCo computes the anchor on the second body at qpos0, so the bodies are written at
// the assembled initial configuration (euler = the initial angles, hinge ref = the same angles,
// which keeps qpos equal to kanesens's angles). MuJoCo's equality constraints are soft:
//   solimp = "0.9999 0.9999 0.001 0.5 2": impedance d = 0.9999 = mjMAXIMP, the hardest allowed;
//   solref = "2·dt 1": time constant 2·dt, critically damped. MuJoCo's `refsafe` clamps the time
//     constant to ≥ 2·dt anyway (stiffer would be unstable), so this is the stiffest usable value:
//     the loop is a spring of stiffness ~1/(d·2dt)² on the closure error, and its residual and
//     the error it leaves shrink with dt.
//
//   mujoco_fourbar_bench [--repeat R] [--batch-seconds B] [--dt DT]
//       times mj_forward at the consistent initial state (positions, velocities, mass matrix and
//       its factorisation, bias forces, the constraint Jacobian and the constraint solve for
//       qacc), median over batches → JSON with qpos, qvel, qacc, efc_force of the connect rows.
//   mujoco_fourbar_bench --integrate rk4|euler|implicit --dt DT [--repeat R]
//       fixed-step mj_step (RK4 or semi-implicit Euler) from the initial state to t = 10: there is
//       no error control; median wall time of R runs → JSON with y(10) and the loop residual.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "batch_timing.hpp"
#include "mujoco_peer.hpp"
#include "four_bar_options.hpp"
#include "four_bar_state.hpp"

namespace {

std::string fourbar_mjcf(const char* integrator, double dt) {
  using namespace four_bar;
  const auto y0 = four_bar::initial_state();
  char buf[4096];
  // A rod along body x from the hinge (body origin) to its tip at (L, 0, 0).
  auto inertial = [](double m, double L) {
    char s[256];
    const double i = m * L * L / 12;
    std::snprintf(s, sizeof s, "<inertial pos=\"%.17g 0 0\" mass=\"%.17g\" diaginertia=\"%.17g %.17g %.17g\"/>", L / 2,
                  m, 1e-4 * i, i, i);
    return std::string(s);
  };
  std::snprintf(
      buf, sizeof buf,
      "<mujoco model=\"four_bar\">\n"
      "  <compiler angle=\"radian\"/>\n"
      "  <option timestep=\"%.17g\" integrator=\"%s\" gravity=\"0 %.17g 0\" tolerance=\"1e-12\">\n"
      "    <flag contact=\"disable\"/>\n"
      "  </option>\n"
      "  <worldbody>\n"
      "    <body name=\"crank\" pos=\"0 0 0\" euler=\"0 0 %.17g\">\n"
      "      <joint type=\"hinge\" axis=\"0 0 1\" ref=\"%.17g\"/>\n"
      "      %s\n"
      "      <body name=\"coupler\" pos=\"%.17g 0 0\" euler=\"0 0 %.17g\">\n"
      "        <joint type=\"hinge\" axis=\"0 0 1\" ref=\"%.17g\"/>\n"
      "        %s\n"
      "      </body>\n"
      "    </body>\n"
      "    <body name=\"rocker\" pos=\"%.17g 0 0\" euler=\"0 0 %.17g\">\n"
      "      <joint type=\"hinge\" axis=\"0 0 1\" ref=\"%.17g\"/>\n"
      "      %s\n"
      "    </body>\n"
      "  </worldbody>\n"
      "  <equality>\n"
      "    <connect body1=\"coupler\" body2=\"rocker\" anchor=\"%.17g 0 0\"\n"
      "             solref=\"%.17g 1\" solimp=\"0.9999 0.9999 0.001 0.5 2\"/>\n"
      "  </equality>\n"
      "</mujoco>\n",
      dt, integrator, gravity_y, y0.q[0], y0.q[0], inertial(crank_mass, crank).c_str(), crank, y0.q[1], y0.q[1],
      inertial(coupler_mass, coupler).c_str(), ground, y0.q[2], y0.q[2], inertial(rocker_mass, rocker).c_str(), coupler,
      2 * dt);
  return buf;
}

// qpos0 is the assembled configuration (the refs); the speeds close the loop exactly.
void set_initial_state(const mjModel* m, mjData* d) {
  mj_resetData(m, d);
  const auto y0 = four_bar::initial_state();
  for (int i = 0; i < 3; ++i) d->qvel[i] = y0.u[i];
}

// Largest closure error of the connect rows: position (m) and velocity (m/s), after mj_forward.
void print_residuals(const mjData* d) {
  double pos = 0, vel = 0;
  for (int i = 0; i < d->nefc; ++i)
    if (d->efc_type[i] == mjCNSTR_EQUALITY) {
      pos = std::max(pos, std::abs(d->efc_pos[i]));
      vel = std::max(vel, std::abs(d->efc_vel[i]));
    }
  std::printf("  \"position_residual\": %.3g,\n  \"velocity_residual\": %.3g,\n", pos, vel);
}

int bench_forward(mjModel* m, mjData* d, int repeat, double batch_seconds) {
  set_initial_state(m, d);
  double sink = 0;
  const peers::BatchTiming timing = mujoco_peer::time_forward(m, d, repeat, batch_seconds, sink);

  std::printf("{\n  \"engine\": \"mujoco\",\n  \"mujoco_version\": %d,\n  \"scene\": \"four_bar\",\n  \"nq\": %d,\n"
              "  \"nv\": %d,\n  \"nefc\": %d,\n  \"timestep\": %.6g,\n",
              mj_version(), m->nq, m->nv, d->nefc, m->opt.timestep);
  std::printf("  \"repeat\": %d,\n", repeat);
  peers::print_timing("mj_forward", timing);
  peers::print_array("qpos", d->qpos, m->nq);
  peers::print_array("qvel", d->qvel, m->nv);
  peers::print_array("qacc", d->qacc, m->nv);
  // connect rows: world x, y, z of the force on body1 (the coupler end) from body2 (the rocker).
  peers::print_array("efc_force", d->efc_force, d->nefc);
  print_residuals(d);
  std::printf("  \"checksum\": %.17g\n}\n", sink);
  return 0;
}

int integrate(mjModel* m, mjData* d, const std::string& which, int repeat) {
  const double dt = m->opt.timestep;
  const long long steps = std::llround(four_bar::t_end / dt);
  std::vector<double> seconds;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    set_initial_state(m, d);
    for (long long k = 0; k < steps; ++k) mj_step(m, d);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  for (int i = 0; i < m->nv; ++i)
    if (!std::isfinite(d->qpos[i]) || !std::isfinite(d->qvel[i])) {
      std::fprintf(stderr, "mujoco_fourbar_bench: non-finite state at t = %.17g (dt %g)\n", d->time, dt);
      return 4;
    }
  mj_forward(m, d);  // efc_pos and efc_vel at the final state
  std::printf("{\n  \"engine\": \"mujoco\",\n  \"mujoco_version\": %d,\n  \"integrator\": \"%s\",\n  \"dt\": %.6g,\n"
              "  \"t_end\": %.17g,\n  \"steps\": %lld,\n  \"wall_seconds\": %.9g,\n  \"min_seconds\": %.9g,\n"
              "  \"repeat\": %d,\n",
              mj_version(), which.c_str(), dt, d->time, steps, seconds[seconds.size() / 2], seconds.front(), repeat);
  print_residuals(d);
  peers::print_array("q", d->qpos, m->nq);
  peers::print_array("u", d->qvel, m->nv, "\n}\n");
  return 0;
}

// A printf format: the program's name twice.
constexpr const char* kUsage =
    "usage: %s [--repeat R] [--batch-seconds B] [--dt DT]\n"
    "       %s --integrate rk4|euler|implicit --dt DT [--repeat R]\n";

}  // namespace

int main(int argc, char** argv) {
  four_bar::Options o;
  if (!four_bar::parse_options(argc, argv, "--dt", kUsage, o)) return 2;
  if (o.repeat < 1 || !(o.step > 0)) { std::fprintf(stderr, "--repeat must be >= 1 and --dt > 0\n"); return 2; }
  const char* integrator = o.which.empty() || o.which == "rk4" ? "RK4"
                           : o.which == "euler"                 ? "Euler"
                           : o.which == "implicit"              ? "implicit"
                                                                : nullptr;
  if (!integrator) { std::fprintf(stderr, "unknown integrator %s (rk4, euler, implicit)\n", o.which.c_str()); return 2; }
  mjModel* m = mujoco_peer::load_mjcf(fourbar_mjcf(integrator, o.step), "four_bar.xml");
  if (!m) return 1;
  mjData* d = mj_makeData(m);
  const int status = o.which.empty() ? bench_forward(m, d, o.repeat, o.batch_seconds) : integrate(m, d, o.which, o.repeat);
  mj_deleteData(d);
  mj_deleteModel(m);
  return status;
}
