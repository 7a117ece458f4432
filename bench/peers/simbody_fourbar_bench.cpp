// Simbody peer of `kanesens bench rhs` and `kanesens simulate` on the four-bar of
// configs/four_bar.yaml (docs/peers.md, "Four-bar: Simbody and MuJoCo"). The tree is kanesens's:
// MobilizedBody::Pin ground→crank (at O), crank→coupler (at the crank tip, angle relative to the
// crank), ground→rocker (at B = (a, 0)); body frames at the rod middles, rods along body x,
// central inertia diag(0, m L²/12, m L²/12); Force::Gravity (0, −9.81, 0). So Simbody's q and u
// are kanesens's coordinates and speeds, with no conversion.
//
// The loop is closed by two Constraint::PointInPlane on the rocker: the coupler's far end lies in
// the rocker plane normal to its x axis at height b/2 and in the plane normal to its y axis at
// height 0, i.e. at the rocker tip in x and y. That is exactly the 2 rows of kanesens's planar
// `coincident` constraint; a Constraint::Ball would add a third (z) row that is identically
// satisfied in this planar tree and makes the constraint matrix rank deficient.
//
//   simbody_fourbar_bench [--repeat R] [--batch-seconds B]
//       times realize(Stage::Acceleration) after writing q and u (invalidating every stage from
//       Position on) at the consistent initial state: kinematics, articulated-body forward
//       dynamics, and the constraint multipliers (Simbody solves for them in the same realize),
//       median over batches → JSON with q, u, udot, multipliers and the force on the coupler end.
//   simbody_fourbar_bench --integrate NAME --accuracy A [--repeat R]
//       integrates t in [0, 10] from the initial state with the Simbody integrator NAME
//       (simbody_integrators.hpp) at setAccuracy(A) and setConstraintTolerance(A); median wall
//       time of R integrations → JSON with y(10), steps, realizations, projections and the final
//       constraint residuals.
#include <Simbody.h>

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
#include "four_bar_options.hpp"
#include "four_bar_state.hpp"
#include "simbody_integrators.hpp"

namespace {

struct FourBar {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::MobilizedBody::Pin crank, coupler, rocker;

  FourBar() {
    using namespace SimTK;
    using namespace four_bar;
    // A uniform thin rod along body x, frame at its middle: no inertia about its own axis.
    auto rod = [](double m, double L) {
      return Body::Rigid(MassProperties(m, Vec3(0), Inertia(0, m * L * L / 12, m * L * L / 12)));
    };
    crank = MobilizedBody::Pin(matter.Ground(), Transform(), rod(crank_mass, four_bar::crank),
                               Transform(Vec3(-four_bar::crank / 2, 0, 0)));
    coupler = MobilizedBody::Pin(crank, Transform(Vec3(four_bar::crank / 2, 0, 0)), rod(coupler_mass, four_bar::coupler),
                                 Transform(Vec3(-four_bar::coupler / 2, 0, 0)));
    rocker = MobilizedBody::Pin(matter.Ground(), Transform(Vec3(ground, 0, 0)), rod(rocker_mass, four_bar::rocker),
                                Transform(Vec3(-four_bar::rocker / 2, 0, 0)));
    const Vec3 coupler_end(four_bar::coupler / 2, 0, 0);
    Constraint::PointInPlane(rocker, UnitVec3(1, 0, 0), four_bar::rocker / 2, coupler, coupler_end);
    Constraint::PointInPlane(rocker, UnitVec3(0, 1, 0), 0.0, coupler, coupler_end);
    Force::Gravity(forces, matter, Vec3(0, gravity_y, 0));
    system.realizeTopology();
  }

  SimTK::State initial_state() const {
    SimTK::State s = system.getDefaultState();
    const auto y0 = four_bar::initial_state();
    for (int i = 0; i < 3; ++i) {
      s.updQ()[i] = y0.q[i];
      s.updU()[i] = y0.u[i];
    }
    return s;
  }

  // The force the rocker exerts on the coupler end, world x and y (kanesens's `coincident`
  // multipliers). Simbody reports constraint forces with the sign opposite to applied forces.
  SimTK::Vec2 coupler_end_force(const SimTK::State& s) const {
    SimTK::Vec3 f(0);
    for (SimTK::ConstraintIndex i(0); i < matter.getNumConstraints(); ++i) {
      const SimTK::Constraint& con = matter.getConstraint(i);
      const SimTK::Vector_<SimTK::SpatialVec> body_forces = con.getConstrainedBodyForcesAsVector(s);
      for (SimTK::ConstrainedBodyIndex b(0); b < con.getNumConstrainedBodies(); ++b)
        if (con.getMobilizedBodyFromConstrainedBody(b).getMobilizedBodyIndex() == coupler.getMobilizedBodyIndex())
          f -= body_forces[b][1];
    }
    return {f[0], f[1]};
  }
};

// `  "name": [...]` of a Simbody vector (peers::print_array).
void print_array(const char* name, const SimTK::Vector& x, const char* end = ",\n") {
  peers::print_array(name, x, x.size(), end);
}

double max_abs(const SimTK::Vector& x) { return x.size() ? SimTK::max(SimTK::abs(x)) : 0.0; }

int bench_realize(int repeat, double batch_seconds) {
  FourBar fb;
  SimTK::State s = fb.initial_state();
  const SimTK::Vector q = s.getQ(), u = s.getU();

  double sink = 0;
  const peers::BatchTiming timing = peers::time_batches(
      [&] {
        s.updQ() = q;  // invalidates Stage::Position and later
        s.updU() = u;
        fb.system.realize(s, SimTK::Stage::Acceleration);
        sink += s.getUDot()[2];
      },
      repeat, batch_seconds);

  int major = 0, minor = 0, build = 0;
  SimTK_version_simbody(&major, &minor, &build);
  const SimTK::Vec2 f = fb.coupler_end_force(s);
  std::printf("{\n  \"engine\": \"simbody\",\n  \"simbody_version\": \"%d.%d.%d\",\n  \"scene\": \"four_bar\",\n"
              "  \"nq\": %d,\n  \"nu\": %d,\n  \"constraint_rows\": %d,\n",
              major, minor, build, s.getNQ(), s.getNU(), s.getNMultipliers());
  std::printf("  \"repeat\": %d,\n", repeat);
  peers::print_timing("realize_acceleration", timing);
  print_array("q", q);
  print_array("u", u);
  print_array("udot", s.getUDot());
  print_array("multipliers", s.getMultipliers());
  std::printf("  \"coupler_end_force\": [%.17g, %.17g],\n", f[0], f[1]);
  std::printf("  \"position_residual\": %.3g,\n  \"velocity_residual\": %.3g,\n", max_abs(s.getQErr()),
              max_abs(s.getUErr()));
  std::printf("  \"checksum\": %.17g\n}\n", sink);
  return 0;
}

int integrate(const std::string& which, double accuracy, int repeat) {
  FourBar fb;
  std::vector<double> seconds;
  SimTK::State end;
  long long steps = 0, attempts = 0, realizations = 0, projections = 0;
  double constraint_tolerance = 0;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<SimTK::Integrator> integ = simbody_peer::make_integrator(fb.system, which);
    if (!integ) return 2;
    integ->setAccuracy(accuracy);
    // Simbody projects q and u back onto the constraint manifold after every step whenever the
    // residual exceeds this tolerance; tying it to the accuracy keeps the drift at the level of
    // the integration error (kanesens's projection likewise uses the integrator's tolerances).
    integ->setConstraintTolerance(accuracy);
    // CPODES stops (and prints an error) after 500 internal steps per stepTo() by default.
    integ->setInternalStepLimit(100000000);
    integ->setFinalTime(four_bar::t_end);
    integ->initialize(fb.initial_state());
    if (!simbody_peer::step_to_end(*integ, four_bar::t_end, "simbody_fourbar_bench")) return 4;
    seconds.push_back(peers::seconds_since(t0));
    end = integ->getState();
    steps = integ->getNumStepsTaken();
    attempts = integ->getNumStepsAttempted();
    realizations = integ->getNumRealizations();
    projections = integ->getNumProjections();
    constraint_tolerance = integ->getConstraintToleranceInUse();
  }
  fb.system.realize(end, SimTK::Stage::Velocity);
  std::sort(seconds.begin(), seconds.end());
  std::printf("{\n  \"engine\": \"simbody\",\n  \"integrator\": \"%s\",\n  \"accuracy\": %.6g,\n"
              "  \"constraint_tolerance\": %.6g,\n  \"t_end\": %.17g,\n  \"wall_seconds\": %.9g,\n"
              "  \"min_seconds\": %.9g,\n  \"repeat\": %d,\n  \"steps\": %lld,\n  \"steps_attempted\": %lld,\n"
              "  \"realizations\": %lld,\n  \"projections\": %lld,\n  \"position_residual\": %.3g,\n"
              "  \"velocity_residual\": %.3g,\n",
              which.c_str(), accuracy, constraint_tolerance, end.getTime(), seconds[seconds.size() / 2],
              seconds.front(), repeat, steps, attempts, realizations, projections, max_abs(end.getQErr()),
              max_abs(end.getUErr()));
  print_array("q", end.getQ());
  print_array("u", end.getU(), "\n}\n");
  return 0;
}

// A printf format: the program's name twice.
constexpr const char* kUsage =
    "usage: %s [--repeat R] [--batch-seconds B]\n"
    "       %s --integrate NAME --accuracy A [--repeat R]\n";

}  // namespace

int main(int argc, char** argv) {
  four_bar::Options o;
  if (!four_bar::parse_options(argc, argv, "--accuracy", kUsage, o)) return 2;
  if (o.repeat < 1) { std::fprintf(stderr, "--repeat must be >= 1\n"); return 2; }
  try {
    return o.which.empty() ? bench_realize(o.repeat, o.batch_seconds) : integrate(o.which, o.step, o.repeat);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simbody_fourbar_bench: %s\n", e.what());
    return 1;
  }
}
