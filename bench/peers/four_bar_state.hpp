// The four-bar of configs/four_bar.yaml for the peer programs (simbody_fourbar_bench,
// mujoco_fourbar_bench): link lengths, masses, and the consistent initial state in kanesens's
// coordinates, by the YAML's closed-form "elbow-up" assembly (its derived parameters Lpb, phi0,
// th30, w2, w3), so the peers start where `kanesens simulate` starts without a Newton correction.
//
//   q = (crank absolute angle, coupler angle relative to the crank, rocker absolute angle), u = q̇.
#pragma once

#include <array>
#include <cmath>

namespace four_bar {

constexpr double crank = 0.2, coupler = 0.7, rocker = 0.5, ground = 0.6;  // r, c, b, a (m)
constexpr double crank_mass = 1.0, coupler_mass = 2.0, rocker_mass = 1.5;  // m1, m2, m3 (kg)
constexpr double gravity_y = -9.81;
constexpr double t_end = 10.0;  // docs/peers.md: error at t = 10

struct State {
  std::array<double, 3> q, u;
};

// th1 = π/2, w1 = 6 rad/s as in the YAML; the other angles and rates close the loop exactly.
inline State initial_state(double th1 = M_PI / 2, double w1 = 6.0) {
  const double r = crank, c = coupler, b = rocker, a = ground;
  const double lpb = std::hypot(a - r * std::cos(th1), r * std::sin(th1));
  const double phi0 = std::atan2(-r * std::sin(th1), a - r * std::cos(th1)) +
                      std::acos((c * c + lpb * lpb - b * b) / (2 * c * lpb));
  const double th30 = std::atan2(r * std::sin(th1) + c * std::sin(phi0), r * std::cos(th1) + c * std::cos(phi0) - a);
  // Velocity closure r w1 e⊥(th1) + c w2 e⊥(phi0) = b w3 e⊥(th30); w2 is the coupler's absolute rate.
  const double w2 = -r * w1 * std::sin(th1 - th30) / (c * std::sin(phi0 - th30));
  const double w3 = r * w1 * std::sin(th1 - phi0) / (b * std::sin(th30 - phi0));
  return {{th1, phi0 - th1, th30}, {w1, w2 - w1, w3}};
}

}  // namespace four_bar
