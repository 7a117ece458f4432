// The Simbody integrators the peer programs offer, by name (docs/peers.md): every error-controlled
// integrator Simbody 3.7 ships, so each tolerance's comparison can take Simbody's best.
#pragma once

#include <Simbody.h>

#include <cstdio>
#include <memory>
#include <string>

namespace simbody_peer {

inline constexpr const char* integrator_names =
    "rkm, rkf, rk3, verlet, cpodes (BDF/Newton), cpodes-adams (Adams/functional), cpodes-adams-newton";

// nullptr, with the known names on stderr, for an unknown name.
inline std::unique_ptr<SimTK::Integrator> make_integrator(const SimTK::System& system, const std::string& which) {
  using SimTK::CPodes;
  if (which == "rkm") return std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
  if (which == "rkf") return std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system);
  if (which == "rk3") return std::make_unique<SimTK::RungeKutta3Integrator>(system);
  if (which == "verlet") return std::make_unique<SimTK::VerletIntegrator>(system);
  if (which == "cpodes") return std::make_unique<SimTK::CPodesIntegrator>(system, CPodes::BDF, CPodes::Newton);
  if (which == "cpodes-adams")
    return std::make_unique<SimTK::CPodesIntegrator>(system, CPodes::Adams, CPodes::Functional);
  if (which == "cpodes-adams-newton")
    return std::make_unique<SimTK::CPodesIntegrator>(system, CPodes::Adams, CPodes::Newton);
  std::fprintf(stderr, "unknown integrator %s (%s)\n", which.c_str(), integrator_names);
  return nullptr;
}

// Steps an initialized integrator to t_end (its first stepTo only starts the continuous
// interval). False, with Simbody's reason on stderr after `program: `, if the simulation ends
// before t_end.
inline bool step_to_end(SimTK::Integrator& integ, double t_end, const char* program) {
  while (integ.getTime() < t_end) {
    const auto status = integ.stepTo(t_end, t_end);
    if (status == SimTK::Integrator::EndOfSimulation && integ.getTime() < t_end) {
      std::fprintf(stderr, "%s: %s at t = %.17g\n", program,
                   SimTK::Integrator::getTerminationReasonString(integ.getTerminationReason()).c_str(), integ.getTime());
      return false;
    }
  }
  return true;
}

}  // namespace simbody_peer
