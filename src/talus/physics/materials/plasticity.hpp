// Shared pieces of the Mohr-Coulomb family: strength parameters in engineers' terms, their
// optional linear softening with equivalent plastic strain (eq. 47), and the plastic strain
// measure.
#pragma once

#include "talus/physics/materials/linear_elastic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace talus {

struct MohrCoulombStrength {
  double friction_angle = 0.0; // phi, radians
  double dilation_angle = 0.0; // psi, radians
  double cohesion = 0.0;       // c, Pa
  double tension_cutoff =
      std::numeric_limits<double>::infinity(); // on the mean stress (DP) or the major principal
                                               // stress (MC), Pa
  // Linear softening (eq. 47): c and phi move to their residual values as the equivalent
  // plastic strain goes from 0 to softening_strain. softening_strain = 0: no softening.
  double residual_cohesion = 0.0;
  double residual_friction_angle = 0.0;
  double softening_strain = 0.0;

  // With no softening the angles never change: prepare() takes their sines and cosines once
  // (the solver prepares every body's material), and current_trig() uses them.
  struct Trig {
    double sin_phi, cos_phi, sin_psi;
    double tension_limit; // Mohr-Coulomb's: tension_limit(cohesion, sin_phi, cos_phi)
  };
  std::optional<Trig> fixed;
  void prepare() { // call last: it snapshots the current angles
    fixed.reset();
    if (softening_strain <= 0.0) {
      const double sp = std::sin(friction_angle), cp = std::cos(friction_angle);
      fixed = Trig{sp, cp, std::sin(dilation_angle), tension_limit(cohesion, sp, cp)};
    }
  }

  // The largest major principal stress Mohr-Coulomb allows: the cut-off, or the apex of the
  // pyramid (c cos(phi) / sin(phi)) if that is lower.
  double tension_limit(double c, double sp, double cp) const {
    return std::min(tension_cutoff, sp > 0.0 ? c * cp / sp : tension_cutoff);
  }

  // The cohesion c, sin(phi), cos(phi) and sin(psi) at equivalent plastic strain eps_p.
  void current_trig(double eps_p, double& c, double& sp, double& cp, double& sd) const {
    if (fixed) {
      c = cohesion, sp = fixed->sin_phi, cp = fixed->cos_phi, sd = fixed->sin_psi;
      return;
    }
    double phi;
    current(eps_p, c, phi);
    sp = std::sin(phi), cp = std::cos(phi), sd = std::sin(dilation_angle);
  }

  // The cohesion and friction angle at equivalent plastic strain eps_p.
  void current(double eps_p, double& c, double& phi) const {
    if (softening_strain <= 0.0) {
      c = cohesion, phi = friction_angle;
      return;
    }
    const double s = std::min(1.0, eps_p / softening_strain);
    c = cohesion + (residual_cohesion - cohesion) * s;
    phi = friction_angle + (residual_friction_angle - friction_angle) * s;
  }
};

// Equivalent plastic strain increment sqrt(2/3 deps_p : deps_p), with deps_p = C^-1 (sigma_trial -
// sigma) the part of the strain increment the return took out of the elastic strain.
inline double plastic_strain_increment(double K, double G, const Voigt& sigma_trial,
                                       const Voigt& sigma) {
  const Voigt ds = sigma_trial - sigma;
  const double dp = mean_stress(ds);
  const Voigt dev = deviator(ds);
  Voigt de = dev / (2.0 * G);
  for (int i = 0; i < 3; ++i)
    de[i] += dp / (3.0 * K);
  const double sq = de[0] * de[0] + de[1] * de[1] + de[2] * de[2] +
                    2.0 * (de[3] * de[3] + de[4] * de[4] + de[5] * de[5]);
  return std::sqrt(2.0 / 3.0 * sq);
}

// Elastoplastic stress update shared by the Mohr-Coulomb family: Jaumann rotation and elastic
// trial (eq. 27-28), then the model's return mapping, which reports the plastic strain increment.
template <class Model, class Return>
void update_plastic_stress(const Model& mat, Voigt& sigma, double& eps_p, const Mat3& D,
                           const Mat3& W, double dt, Return&& return_to_surface) {
  sigma += trial_increment(mat.bulk_modulus(), mat.shear_modulus(), sigma, D, W, dt);
  eps_p += return_to_surface(mat, sigma, eps_p);
}

} // namespace talus
