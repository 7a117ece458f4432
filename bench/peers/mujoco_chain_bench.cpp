// MuJoCo peer of `kanesens bench rhs` on the benchmark chain (tests/support/test_scenes.hpp,
// chain_scene): N uniform rods (mass 1, length 1, central inertia diag(1/12, 1e-4, 1/12)),
// hinges about z (or, with --axes, about the axes given, cycled along the chain: `--axes z,x` is
// the spatial chain of bench/common.py), gravity −y, every stage the chain does not use disabled
// (contacts, constraints, passive forces, actuation, sensors, warm start). Times mj_forward
// (positions, velocities, mass matrix and its factorisation, bias forces, the solve for qacc) at
// the same seeded random state as kanesens (q, u uniform in [-1, 1] from std::mt19937(seed)),
// median over batches.
//
//   mujoco_chain_bench N [--repeat R] [--seed S] [--axes z,x]    → JSON on stdout
//
// The JSON also carries qacc, so a script can check that both engines integrate the same
// equations (bench/bench_rhs.py compares it with `kanesens eom`).
#include <mujoco/mujoco.h>

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
#include "mujoco_peer.hpp"

namespace {

// "x", "y" or "z" as an MJCF axis; empty if none of them.
std::string axis_of(const std::string& letter) {
  if (letter == "x") return "1 0 0";
  if (letter == "y") return "0 1 0";
  if (letter == "z") return "0 0 1";
  return {};
}

// Joint i (1-based) turns about axes[(i − 1) mod size].
std::string chain_mjcf(int n, const std::vector<std::string>& axes) {
  std::string s =
      "<mujoco model=\"chain\">\n"
      // Every stage this scene does not use is off: mj_forward's best settings for it.
      "  <option gravity=\"0 -9.81 0\"><flag contact=\"disable\" constraint=\"disable\" passive=\"disable\" "
      "actuation=\"disable\" sensor=\"disable\" warmstart=\"disable\"/></option>\n"
      "  <worldbody>\n";
  std::string close;
  for (int i = 1; i <= n; ++i) {
    // Body frame at the joint; the rod hangs along −y, its mass center 0.5 below.
    s += std::string(2 * i + 2, ' ') + "<body name=\"link" + std::to_string(i) + "\" pos=\"0 " +
         (i == 1 ? "0" : "-1") + " 0\">\n";
    s += std::string(2 * i + 4, ' ') + "<joint type=\"hinge\" axis=\"" + axes[(i - 1) % axes.size()] + "\" pos=\"0 0 0\"/>\n";
    s += std::string(2 * i + 4, ' ') +
         "<inertial pos=\"0 -0.5 0\" mass=\"1\" diaginertia=\"0.083333333333333329 0.0001 "
         "0.083333333333333329\"/>\n";
    close = std::string(2 * i + 2, ' ') + "</body>\n" + close;
  }
  return s + close + "  </worldbody>\n</mujoco>\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s N [--repeat R] [--seed S] [--batch-seconds B] [--axes z,x]\n", argv[0]);
    return 2;
  }
  const int n = std::atoi(argv[1]);
  int repeat = 31;
  unsigned seed = 1;
  double batch_seconds = 2e-3;
  std::vector<std::string> axes{axis_of("z")};
  std::string axes_spec = "z";
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed")) seed = static_cast<unsigned>(std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--batch-seconds")) batch_seconds = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--axes")) {
      axes_spec = argv[i + 1];
      axes.clear();
      std::size_t start = 0;
      while (true) {
        const std::size_t comma = axes_spec.find(',', start);
        const std::string a = axis_of(axes_spec.substr(start, comma - start));
        if (a.empty()) { std::fprintf(stderr, "--axes: a comma-separated list of x, y, z\n"); return 2; }
        axes.push_back(a);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
    else { std::fprintf(stderr, "unknown option %s\n", argv[i]); return 2; }
  }
  if (n < 1 || repeat < 1) { std::fprintf(stderr, "N and --repeat must be >= 1\n"); return 2; }

  mjModel* m = mujoco_peer::load_mjcf(chain_mjcf(n, axes), "chain.xml");
  if (!m) return 1;
  mjData* d = mj_makeData(m);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = uni(rng);
  for (int i = 0; i < m->nv; ++i) d->qvel[i] = uni(rng);

  double sink = 0;
  const peers::BatchTiming timing = mujoco_peer::time_forward(m, d, repeat, batch_seconds, sink);

  std::printf("{\n  \"engine\": \"mujoco\",\n  \"mujoco_version\": %d,\n  \"n\": %d,\n  \"nq\": %d,\n  \"nv\": %d,\n",
              mj_version(), n, m->nq, m->nv);
  std::printf("  \"axes\": \"%s\",\n  \"seed\": %u,\n  \"repeat\": %d,\n", axes_spec.c_str(), seed, repeat);
  peers::print_timing("mj_forward", timing);
  peers::print_array("qpos", d->qpos, m->nq);
  peers::print_array("qvel", d->qvel, m->nv);
  peers::print_array("qacc", d->qacc, m->nv);
  std::printf("  \"checksum\": %.17g\n}\n", sink);
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
