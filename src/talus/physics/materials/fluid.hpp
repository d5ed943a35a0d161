// A weakly compressible Newtonian fluid (water as a body): the pressure is a state function of
// the particle's volume ratio J = V / V_0 = det F (V_0: its volume at zero pressure), the
// deviatoric stress is viscous,
//   sigma = -p I + 2 mu dev(D),   p = K (1 / J - 1),  p >= -tension.
// (A hydrostatic start seeds the compressed volume with mass rho_0 V, so the density there is
// rho_0, not rho_0 / J: a difference of p / K, about 1 %.)
// The law is linear in density (Tait's equation with exponent 1): with an artificial sound
// speed c = sqrt(K / rho_0) ten times the flow's speed the density varies by about 1 %, where
// Tait's exponent 7 would change the pressure by a few percent and is not the physics being
// resolved (the real c of water, 1,480 m/s, would make the time step tens of times shorter).
// Below -tension (default 0) the pressure is cut: the fluid separates at a free surface instead
// of pulling. A fluid keeps no shape: its F is reset to J^(1/D) I every step.
#pragma once

#include "talus/core/math.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

struct Fluid {
  double density = 0.0;   // rho_0, kg/m^3
  double bulk = 0.0;      // K, Pa
  double viscosity = 0.0; // mu, Pa s
  double tension = 0.0;   // the largest tension (Pa) the fluid carries before it separates
  // Hydrostatic: the earth-pressure coefficient of [initial_state] k0 is 1 (nu / (1 - nu)).
  static constexpr double poisson_ratio = 0.5;

  double bulk_modulus() const { return bulk; }
  double shear_modulus() const { return 0.0; }
  // The pressure wave's modulus, which sets the CFL step: K (no shear stiffness).
  double p_wave_modulus() const { return bulk; }
  // p(J) = K (1 / J - 1), cut at -tension.
  double pressure(double J) const { return std::max(bulk * (1.0 / J - 1.0), -tension); }
  // The volume ratio at pressure p: J = 1 / (1 + p / K).
  double volume_ratio(double p) const { return 1.0 / (1.0 + p / bulk); }
  // The energy stored per unit reference volume, W(J) with p = -dW/dJ:
  // K (J - 1 - ln J) up to J_t = volume_ratio(-tension), then W(J_t) + tension (J - J_t).
  double stored_energy(double J) const {
    const double Jt = tension > 0.0 ? volume_ratio(-tension) : 1.0;
    const double j = std::min(J, Jt);
    return bulk * (j - 1.0 - std::log(j)) + tension * std::max(J - Jt, 0.0);
  }
};

// sigma = -p I + 2 mu dev(D) (D the rate of deformation, 3x3: plane strain has D_zz = 0).
inline Voigt fluid_stress(const Fluid& f, double p, const Mat3& D) {
  const double third = D.trace() / 3.0;
  Voigt s;
  for (int i = 0; i < 3; ++i)
    s[i] = -p + 2.0 * f.viscosity * (D(i, i) - third);
  s[3] = 2.0 * f.viscosity * D(0, 1);
  s[4] = 2.0 * f.viscosity * D(1, 2);
  s[5] = 2.0 * f.viscosity * D(0, 2);
  return s;
}

} // namespace talus
