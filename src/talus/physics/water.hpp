// A hydrostatic water level (the [water] section): below it a particle weighs its buoyant
// weight and its stress is the effective stress (docs/formulation.md, "Water").
#pragma once

#include <algorithm>

namespace talus {

// The share of a particle of height l, centred at height z, that lies below the level: 0 above
// it, 1 below, linear across it, so the weight changes smoothly as the particle crosses.
inline double submerged_fraction(double level, double z, double l) {
  return std::clamp((level - z) / l + 0.5, 0.0, 1.0);
}

// The integral of submerged_fraction from z upwards: the work of the buoyancy on a particle
// that moves from z0 to z is rho_w / rho m g (H(z0) - H(z)).
inline double submerged_integral(double level, double z, double l) {
  const double top = level + 0.5 * l;
  if (z >= top) return 0.0;
  if (z >= level - 0.5 * l) return (top - z) * (top - z) / (2.0 * l);
  return level - z;
}

} // namespace talus
