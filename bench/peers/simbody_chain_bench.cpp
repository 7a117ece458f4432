// Simbody peer of `kanesens bench rhs` and `kanesens simulate` on the planar N-link chain
// (docs/peers.md): N uniform rods (mass 1, length 1, central inertia diag(1/12, YY, 1/12), YY =
// 1e-4 as in bench/bench_rhs.py's scenes, or --yy), pin joints about z (relative angles, body
// frame at the top end of the rod, mass center 0.5 below it), gravity −y (Force::Gravity).
//
//   simbody_chain_bench N [--repeat R] [--seed S] [--batch-seconds B] [--yy YY]
//       times realize(Stage::Acceleration) after writing q and u (which invalidates every stage
//       from Position on, so each evaluation does kinematics, articulated-body inertias and the
//       O(N) forward dynamics) at the seeded random state of `kanesens bench rhs` (q, u uniform
//       in [-1, 1] from std::mt19937(seed)), median over batches → JSON with q, u, udot.
//   simbody_chain_bench N --integrate NAME --accuracy A [--repeat R] [--q0 Q]
//       integrates t in [0, 10] from q = (Q, 0, ...), u = 0 (scripts/gen_chain.py's initial
//       state, Q = 0.5) with the Simbody integrator NAME (simbody_integrators.hpp: RK-Merson,
//       RK-Feldberg, RK3, Verlet, CPodes BDF or Adams) at accuracy A; median wall time of R
//       integrations → JSON with y(10).
#include <Simbody.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "batch_timing.hpp"
#include "simbody_integrators.hpp"

namespace {

struct Chain {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};

  Chain(int n, double yy) {
    using namespace SimTK;
    const double m = 1, L = 1;
    const Vec3 com(0, -L / 2, 0);  // mass center in the body frame (origin at the joint)
    const Inertia central(m * L * L / 12, yy, m * L * L / 12);
    const MassProperties mp(m, com, central.shiftFromMassCenter(-com, m));
    const Body::Rigid body(mp);
    MobilizedBody parent = matter.Ground();
    for (int i = 0; i < n; ++i) {
      const Transform X_PF(Vec3(0, i == 0 ? 0.0 : -L, 0));  // joint at the parent's bottom end
      parent = MobilizedBody::Pin(parent, X_PF, body, Transform());
    }
    Force::Gravity(forces, matter, Vec3(0, -9.81, 0));
    system.realizeTopology();
  }
};

// `  "name": [...]` of a Simbody vector (peers::print_array).
void print_array(const char* name, const SimTK::Vector& x, const char* end = ",\n") {
  peers::print_array(name, x, x.size(), end);
}

int bench_realize(int n, int repeat, unsigned seed, double batch_seconds, double yy) {
  Chain c(n, yy);
  SimTK::State s = c.system.getDefaultState();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  SimTK::Vector q(n), u(n);
  for (int i = 0; i < n; ++i) q[i] = uni(rng);
  for (int i = 0; i < n; ++i) u[i] = uni(rng);

  double sink = 0;
  const peers::BatchTiming timing = peers::time_batches(
      [&] {
        s.updQ() = q;  // invalidates Stage::Position and later
        s.updU() = u;
        c.system.realize(s, SimTK::Stage::Acceleration);
        sink += s.getUDot()[n - 1];
      },
      repeat, batch_seconds);

  int major = 0, minor = 0, build = 0;
  SimTK_version_simbody(&major, &minor, &build);
  std::printf("{\n  \"engine\": \"simbody\",\n  \"simbody_version\": \"%d.%d.%d\",\n  \"n\": %d,\n  \"nq\": %d,\n  \"nu\": %d,\n",
              major, minor, build, n, s.getNQ(), s.getNU());
  std::printf("  \"seed\": %u,\n  \"repeat\": %d,\n  \"yy\": %.17g,\n", seed, repeat, yy);
  peers::print_timing("realize_acceleration", timing);
  print_array("q", q);
  print_array("u", u);
  print_array("udot", s.getUDot());
  std::printf("  \"checksum\": %.17g\n}\n", sink);
  return 0;
}

int integrate(int n, const std::string& which, double accuracy, int repeat, double q0, double yy) {
  Chain c(n, yy);
  const double t_end = 10.0;
  std::vector<double> seconds;
  SimTK::Vector q_end, u_end;
  long long steps = 0, attempts = 0, realizations = 0;
  double t_reached = 0;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    SimTK::State s = c.system.getDefaultState();
    s.updQ() = 0;
    s.updQ()[0] = q0;
    s.updU() = 0;
    std::unique_ptr<SimTK::Integrator> integ = simbody_peer::make_integrator(c.system, which);
    if (!integ) return 2;
    integ->setAccuracy(accuracy);
    integ->setFinalTime(t_end);
    integ->initialize(s);
    if (!simbody_peer::step_to_end(*integ, t_end, "simbody_chain_bench")) return 4;
    seconds.push_back(peers::seconds_since(t0));
    const SimTK::State& e = integ->getState();
    q_end = e.getQ();
    u_end = e.getU();
    t_reached = e.getTime();
    steps = integ->getNumStepsTaken();
    attempts = integ->getNumStepsAttempted();
    realizations = integ->getNumRealizations();
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf("{\n  \"engine\": \"simbody\",\n  \"integrator\": \"%s\",\n  \"n\": %d,\n  \"accuracy\": %.6g,\n"
              "  \"t_end\": %.17g,\n  \"wall_seconds\": %.9g,\n  \"min_seconds\": %.9g,\n  \"repeat\": %d,\n"
              "  \"steps\": %lld,\n  \"steps_attempted\": %lld,\n  \"realizations\": %lld,\n",
              which.c_str(), n, accuracy, t_reached, seconds[seconds.size() / 2], seconds.front(), repeat, steps,
              attempts, realizations);
  print_array("q", q_end);
  print_array("u", u_end, "\n}\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s N [--repeat R] [--seed S] [--batch-seconds B] [--yy YY]\n"
                 "       %s N --integrate NAME --accuracy A [--repeat R] [--q0 Q] [--yy YY]\n",
                 argv[0], argv[0]);
    return 2;
  }
  const int n = std::atoi(argv[1]);
  int repeat = 31;
  unsigned seed = 1;
  double batch_seconds = 2e-3, accuracy = 1e-3, q0 = 0.5, yy = 1e-4;
  std::string which;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed")) seed = static_cast<unsigned>(std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--batch-seconds")) batch_seconds = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--integrate")) which = argv[i + 1];
    else if (!std::strcmp(argv[i], "--accuracy")) accuracy = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--q0")) q0 = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--yy")) yy = std::atof(argv[i + 1]);
    else { std::fprintf(stderr, "unknown option %s\n", argv[i]); return 2; }
  }
  if (n < 1 || repeat < 1) { std::fprintf(stderr, "N and --repeat must be >= 1\n"); return 2; }
  try {
    return which.empty() ? bench_realize(n, repeat, seed, batch_seconds, yy)
                         : integrate(n, which, accuracy, repeat, q0, yy);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simbody_chain_bench: %s\n", e.what());
    return 1;
  }
}
