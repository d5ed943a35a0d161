// Hypoelastic linear material with the Jaumann stress rate (eq. 24-28 of the paper).
#pragma once

#include "talus/core/math.hpp"

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

// The trial increment dt (C:D + W sigma - sigma W) of eq. 27-28, any state.
inline Voigt trial_increment_general(double K, double G, const Voigt& sigma, const Mat3& D,
                                     const Mat3& W, double dt) {
  return jaumann_spin_term(sigma, W) * dt + elastic_increment(K, G, to_voigt(D * dt));
}

// The same, with plane strain's zeros (no out-of-plane shear in D, W or sigma) written out: the
// spin is the single w = W_xy and the increment has four components. W must be skew (the solver
// passes (L - L^T) / 2). Equal to the general form to round-off (a unit test checks), at a
// fraction of its 3x3 products.
inline Voigt trial_increment(double K, double G, const Voigt& sigma, const Mat3& D, const Mat3& W,
                             double dt) {
  const bool plane = sigma[4] == 0.0 && sigma[5] == 0.0 && D(0, 2) == 0.0 && D(1, 2) == 0.0 &&
                     D(2, 0) == 0.0 && D(2, 1) == 0.0 && W(0, 2) == 0.0 && W(1, 2) == 0.0;
  if (!plane) return trial_increment_general(K, G, sigma, D, W, dt);
  const double w = W(0, 1) * dt;
  const double exx = D(0, 0) * dt, eyy = D(1, 1) * dt, ezz = D(2, 2) * dt;
  const double exy = 0.5 * (D(0, 1) + D(1, 0)) * dt;
  const double lv = (K - 2.0 / 3.0 * G) * (exx + eyy + ezz);
  Voigt ds;
  ds[0] = 2.0 * w * sigma[3] + lv + 2.0 * G * exx;
  ds[1] = -2.0 * w * sigma[3] + lv + 2.0 * G * eyy;
  ds[2] = lv + 2.0 * G * ezz;
  ds[3] = w * (sigma[1] - sigma[0]) + 2.0 * G * exy;
  ds[4] = ds[5] = 0.0;
  return ds;
}

// sigma^{n+1} = sigma^n + dt (C:D + W sigma - sigma W), eq. 27-28.
inline void update_stress(const LinearElastic& mat, Voigt& sigma, double& /*eps_p*/, const Mat3& D,
                          const Mat3& W, double dt) {
  sigma += trial_increment(mat.bulk_modulus(), mat.shear_modulus(), sigma, D, W, dt);
}

} // namespace talus
