// Kane's M, f and u̇ on six scenes at seeded random states, against values recorded in
// tests/data/kane_golden.txt from the straightforward implementation (commit 0f6f635, before
// the speed work). Guards optimisations of dynamics/: results may change by round-off only.
// Regenerate (only when the equations themselves change, never to hide a difference):
//   KANESENS_WRITE_GOLDEN=1 build/tests/test_kane_golden
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include "dynamics/equations.hpp"
#include "model/build_model.hpp"
#include "model/scene/parse_scene.hpp"
#include "test_scenes.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

using namespace kanesens::testing;

namespace {

const char* kGoldenPath = KANESENS_SOURCE_DIR "/tests/data/kane_golden.txt";
const char* kGoldenHeader =
    "# Kane's mass matrix M, forcing f and u' of five scenes (tests/support/test_scenes.hpp) at seeded\n"
    "# random states, recorded from kanesens itself (commit 0f6f635, before the speed work) by\n"
    "# tests/unit/test_kane_golden.cpp (KANESENS_WRITE_GOLDEN=1). A guard against changes beyond\n"
    "# round-off, not an independent reference. One line per state: scene, index, y, M\n"
    "# (row-major), f, u'.\n";

std::vector<std::pair<std::string, std::string>> scenes() {
  return {{"chain5", test_scenes::chain_scene(5)},
          {"chain5_tilted", test_scenes::chain_scene(5, 0.2)},
          {"spherical", test_scenes::kSphericalScene},
          {"free", test_scenes::kFreeScene},
          {"forces", test_scenes::kForcesScene}};
}

// One line per (scene, state): name, then y, M (row-major), f, u̇ as %.17g numbers.
std::vector<std::string> compute_lines() {
  std::vector<std::string> lines;
  for (const auto& [name, text] : scenes()) {
    const Model m = build_model(parse_scene_text(text, name + ".yaml"));
    Workspace<double> ws(m);
    const std::vector<double> p = m.nominal_parameters();
    set_parameters(m, ws, p.data());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(-1.5, 1.5);
    for (int s = 0; s < 3; ++s) {
      std::vector<double> y(m.nstate()), ydot(m.nstate());
      for (double& v : y) v = uni(rng);
      evaluate_rhs(m, ws, 0.7, y.data(), ydot.data());
      // M and f as the mass-matrix path forms them (the RHS may find u̇ without them).
      evaluate_mass_matrix_and_forcing(m, ws, 0.7, y.data(), y.data() + m.nq);
      std::ostringstream o;
      char buf[40];
      auto put = [&](double v) {
        std::snprintf(buf, sizeof buf, " %.17g", v);
        o << buf;
      };
      o << name << " " << s;
      for (double v : y) put(v);
      for (int r = 0; r < m.nu; ++r)
        for (int c = 0; c < m.nu; ++c) put(ws.mass_matrix(r, c));
      for (int r = 0; r < m.nu; ++r) put(ws.forcing[r]);
      for (double v : ydot) put(v);
      lines.push_back(o.str());
    }
  }
  return lines;
}

}  // namespace

TEST(KaneGolden, MatchesRecordedValues) {
  const std::vector<std::string> now = compute_lines();
  if (std::getenv("KANESENS_WRITE_GOLDEN")) {
    std::ofstream out(kGoldenPath);
    out << kGoldenHeader;
    for (const auto& l : now) out << l << "\n";
    GTEST_SKIP() << "wrote " << kGoldenPath;
  }
  std::ifstream in(kGoldenPath);
  ASSERT_TRUE(in) << kGoldenPath;
  std::string line;
  std::size_t i = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;  // the header
    ASSERT_LT(i, now.size());
    std::istringstream a(line), b(now[i]);
    std::string na, nb;
    int sa, sb;
    a >> na >> sa;
    b >> nb >> sb;
    ASSERT_EQ(na, nb);
    double x, z;
    int k = 0;
    while (a >> x) {
      ASSERT_TRUE(b >> z) << na << " state " << sa;
      EXPECT_NEAR(z, x, 1e-12 * std::max(1.0, std::abs(x))) << na << " state " << sa << " number " << k;
      ++k;
    }
    ++i;
  }
  EXPECT_EQ(i, now.size());
}

}  // namespace KANESENS_UNITY_ID
