// The Simbody integrators the peer programs offer, by name (docs/peers.md): every error-controlled
// integrator Simbody 3.7 ships, so each tolerance's comparison can take Simbody's best.
#pragma once

#include <Simbody.h>

#include <memory>
#include <string>

namespace simbody_peer {

inline constexpr const char* integrator_names =
    "rkm, rkf, rk3, verlet, cpodes (BDF/Newton), cpodes-adams (Adams/functional), cpodes-adams-newton";

// nullptr for an unknown name.
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
  return nullptr;
}

}  // namespace simbody_peer
