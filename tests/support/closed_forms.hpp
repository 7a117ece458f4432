// Closed-form solutions the integration tests compare against (tests/unit/test_integrator.cpp,
// tests/regression/test_closed_form_trajectories.cpp). Written from the textbook formulas, not
// from src/; test_integrator.cpp and test_closed_form_trajectories.cpp check them on their own
// (complex-step derivatives, the equations of motion by finite differences).
#pragma once
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <cmath>

namespace kanesens::testing {

// Underdamped oscillator m ẍ + c ẋ + k x = 0, x(0) = x0, ẋ(0) = v0 (c² < 4 m k):
//   x(t) = e^{−a t} [x0 cos ω t + (v0 + a x0)/ω sin ω t],   a = c/(2m),  ω = √(k/m − a²).
// Templated on the scalar so a complex argument gives complex-step derivatives.
template <class T>
T damped_oscillator_x(T t, T x0, T v0, T m, T c, T k) {
  using std::cos, std::exp, std::sin, std::sqrt;
  const T a = c / (2.0 * m), w = sqrt(k / m - a * a);
  return exp(-a * t) * (x0 * cos(w * t) + (v0 + a * x0) / w * sin(w * t));
}

// x(t) and its derivatives with respect to (x0, v0, m, c, k), by hand. With E = e^{−a t},
// C = cos ω t, S = sin ω t, B = (v0 + a x0)/ω:
//   ∂x/∂x0 = E (C + a S/ω),   ∂x/∂v0 = E S/ω,
//   ∂x/∂a  = −t x + E x0 S/ω,   ∂x/∂ω = E (−x0 t S − B S/ω + B t C),
// and a, ω depend on (m, c, k) through ∂a/∂m = −c/(2m²), ∂a/∂c = 1/(2m), and 2ω dω = d(k/m) − 2a da:
//   ∂ω/∂m = (a c − k)/(2 m² ω),   ∂ω/∂c = −a/(2 m ω),   ∂ω/∂k = 1/(2 m ω).
struct OscillatorSolution {
  double x;
  double dx[5];  // ∂x/∂(x0, v0, m, c, k)
};

inline OscillatorSolution damped_oscillator(double t, double x0, double v0, double m, double c,
                                            double k) {
  const double a = c / (2 * m), w = std::sqrt(k / m - a * a);
  const double E = std::exp(-a * t), C = std::cos(w * t), S = std::sin(w * t);
  const double B = (v0 + a * x0) / w;
  OscillatorSolution s{};
  s.x = E * (x0 * C + B * S);
  const double dx_da = -t * s.x + E * x0 * S / w;
  const double dx_dw = E * (-x0 * t * S - B * S / w + B * t * C);
  const double da_dm = -c / (2 * m * m), da_dc = 1 / (2 * m);
  const double dw_dm = (a * c - k) / (2 * m * m * w), dw_dc = -a / (2 * m * w),
               dw_dk = 1 / (2 * m * w);
  s.dx[0] = E * (C + a * S / w);
  s.dx[1] = E * S / w;
  s.dx[2] = dx_da * da_dm + dx_dw * dw_dm;
  s.dx[3] = dx_da * da_dc + dx_dw * dw_dc;
  s.dx[4] = dx_dw * dw_dk;
  return s;
}

// Torque-free rigid body with principal moments I = diag(1, 2, 3) and ω(0) = (1, 0, 1) (body
// frame): 2E = 4 and |H|² = 10 make the elliptic parameter m = k² = 1/3 and the time scale 1, so
// (Landau & Lifshitz, Mechanics, §37) ω(t) = (cn(t | 1/3), sn(t | 1/3), dn(t | 1/3)).
// Boost's Jacobi functions take the modulus k.
struct Omega {
  double w1, w2, w3;
};
inline Omega torque_free_omega(double t) {
  double cn = 0, dn = 0;
  const double sn = boost::math::jacobi_elliptic(1 / std::sqrt(3.0), t, &cn, &dn);
  return {cn, sn, dn};
}

}  // namespace kanesens::testing
