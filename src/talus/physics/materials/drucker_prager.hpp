// Drucker-Prager elastoplasticity (eq. 42): f = sqrt(J2) + alpha I1 - k, tension positive, with the
// Mohr-Coulomb matchings of eq. 44, non-associated flow g = sqrt(J2) + alpha_psi I1, a tension
// cut-off on the mean stress and a return to the apex. The return is closed-form (the surface is
// linear in the invariants), so the stress lands on the surface to round-off.
#pragma once

#include "talus/physics/materials/plasticity.hpp"

namespace talus {

enum class DruckerPragerMatch { inner, outer, plane_strain };

struct DruckerPrager : IsotropicElastic {
  DruckerPragerMatch match = DruckerPragerMatch::inner;
  MohrCoulombStrength strength;
  // With no softening, alpha, k and alpha_psi never change: prepare() computes them once (the
  // solver prepares every body's material) instead of per particle per step.
  struct Coefficients {
    double alpha, k, alpha_psi;
  };
  std::optional<Coefficients> fixed;
  void prepare() { // call last: it snapshots the current strength and matching
    fixed.reset();
    if (strength.softening_strain > 0.0) return;
    Coefficients f{};
    double k_psi;
    match_coefficients(strength.friction_angle, strength.cohesion, f.alpha, f.k);
    match_coefficients(strength.dilation_angle, 0.0, f.alpha_psi, k_psi);
    fixed = f;
  }

  // alpha and k of eq. 44 for friction angle phi and cohesion c.
  void match_coefficients(double phi, double c, double& alpha, double& k) const {
    const double s = std::sin(phi), t = std::tan(phi);
    switch (match) {
    case DruckerPragerMatch::outer: // triaxial compression
      alpha = 2.0 * s / (std::sqrt(3.0) * (3.0 - s));
      k = 6.0 * c * std::cos(phi) / (std::sqrt(3.0) * (3.0 - s));
      break;
    case DruckerPragerMatch::inner: // triaxial extension
      alpha = 2.0 * s / (std::sqrt(3.0) * (3.0 + s));
      k = 6.0 * c * std::cos(phi) / (std::sqrt(3.0) * (3.0 + s));
      break;
    case DruckerPragerMatch::plane_strain:
      alpha = t / std::sqrt(9.0 + 12.0 * t * t);
      k = 3.0 * c / std::sqrt(9.0 + 12.0 * t * t);
      break;
    }
  }
};

// Return mapping of a trial stress onto the Drucker-Prager surface with its tension cut-off.
// Returns the equivalent plastic strain increment (0 if elastic).
inline double return_to_drucker_prager(const DruckerPrager& mat, Voigt& sigma, double eps_p) {
  double alpha = 0.0, k = 0.0, alpha_psi = 0.0, k_psi = 0.0;
  if (mat.fixed) {
    alpha = mat.fixed->alpha, k = mat.fixed->k, alpha_psi = mat.fixed->alpha_psi;
  } else {
    double c, phi;
    mat.strength.current(eps_p, c, phi);
    mat.match_coefficients(phi, c, alpha, k);
    mat.match_coefficients(mat.strength.dilation_angle, 0.0, alpha_psi, k_psi);
  }
  const double K = mat.bulk_modulus(), G = mat.shear_modulus();

  const Voigt trial = sigma;
  const double p = mean_stress(trial);
  const Voigt s = deviator(trial);
  const double q = std::sqrt(second_invariant(s)); // sqrt(J2)
  // The largest mean stress the cone can carry: the cut-off or the apex, whichever is lower.
  const double p_apex = alpha > 0.0 ? k / (3.0 * alpha) : std::numeric_limits<double>::infinity();
  const double p_max = std::min(mat.strength.tension_cutoff, p_apex);
  auto q_max = [&](double pm) { return std::max(0.0, k - 3.0 * alpha * pm); };

  const double f = q + 3.0 * alpha * p - k;
  double p_new = p, q_new = q;
  if (f > 0.0) {
    // Shear return: d_lambda from f(trial) - d_lambda (G + 9 K alpha alpha_psi) = 0.
    const double dl = f / (G + 9.0 * K * alpha * alpha_psi);
    p_new = p - 3.0 * K * alpha_psi * dl;
    q_new = q - G * dl;
  }
  if (p_new > p_max) {
    // Tension cut-off (or apex): the mean stress drops to p_max, the deviator to what fits.
    p_new = p_max;
    q_new = std::min(q, q_max(p_max));
  }
  if (p_new == p && q_new == q) return 0.0;
  Voigt out = (q > 0.0 ? q_new / q : 0.0) * s;
  for (int i = 0; i < 3; ++i)
    out[i] += p_new;
  sigma = out;
  return plastic_strain_increment(K, G, trial, sigma);
}

inline void update_stress(const DruckerPrager& mat, Voigt& sigma, double& eps_p, const Mat3& D,
                          const Mat3& W, double dt) {
  update_plastic_stress(mat, sigma, eps_p, D, W, dt, return_to_drucker_prager);
}

} // namespace talus
