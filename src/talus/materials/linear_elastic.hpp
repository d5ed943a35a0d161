// Hypoelastic linear material with the Jaumann stress rate (eq. 24-28 of the paper).
#pragma once

#include "talus/math.hpp"

#include <cmath>

namespace talus {

// Density and isotropic elasticity: every material model starts from these.
struct IsotropicElastic {
  double density = 0.0;
  double youngs_modulus = 0.0;
  double poisson_ratio = 0.0;

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double bulk_modulus() const { return youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)); }
  // P-wave modulus K + 4G/3, which sets the CFL time step.
  double p_wave_modulus() const { return bulk_modulus() + 4.0 / 3.0 * shear_modulus(); }
};

struct LinearElastic : IsotropicElastic {};

// Elastic trial increment C : D dt for an isotropic material (deps in Voigt order, engineering
// shear not used: deps[3..5] are tensor components).
inline Voigt elastic_increment(double K, double G, const Voigt& deps) {
  const double vol = deps[0] + deps[1] + deps[2];
  Voigt ds;
  const double lambda = K - 2.0 / 3.0 * G;
  for (int i = 0; i < 3; ++i)
    ds[i] = lambda * vol + 2.0 * G * deps[i];
  for (int i = 3; i < 6; ++i)
    ds[i] = 2.0 * G * deps[i];
  return ds;
}

// sigma^{n+1} = sigma^n + dt (C:D + W sigma - sigma W), eq. 27-28.
inline void update_stress(const LinearElastic& mat, Voigt& sigma, double& /*eps_p*/, const Mat3& D,
                          const Mat3& W, double dt) {
  const Voigt deps = to_voigt(D * dt);
  sigma += jaumann_spin_term(sigma, W) * dt +
           elastic_increment(mat.bulk_modulus(), mat.shear_modulus(), deps);
}

} // namespace talus
