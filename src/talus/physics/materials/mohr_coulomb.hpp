// Mohr-Coulomb elastoplasticity returned in principal stress space (de Souza Neto et al. 2008,
// ch. 8): main plane, left and right edges, and apex, with non-associated flow (dilation angle
// psi) and a Rankine tension cut-off on the major principal stress. Tension positive; principal
// stresses ordered s1 >= s2 >= s3. The planes are linear, so each return is exact to round-off.
#pragma once

#include "talus/physics/materials/plasticity.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <utility>

namespace talus {

struct MohrCoulomb : IsotropicElastic {
  MohrCoulombStrength strength;
};

namespace mc_detail {

using V3 = Eigen::Vector3d;

// Principal-space elasticity: D x = lambda tr(x) (1,1,1) + 2 G x.
inline V3 apply_elastic(double K, double G, const V3& x) {
  return V3::Constant((K - 2.0 / 3.0 * G) * x.sum()) + 2.0 * G * x;
}

// One linear yield plane a . s - b <= 0 with flow direction n (principal space).
struct Plane {
  V3 a, n;
  double b;
  double value(const V3& s) const { return a.dot(s) - b; }
};

// Multi-surface return onto the active planes (1 or 2), solving the consistency equations.
// Returns false if a multiplier is negative (wrong set of active planes).
inline bool return_to_planes(double K, double G, const Plane* planes, int n, V3& s) {
  if (n == 1) {
    const V3 Dn = apply_elastic(K, G, planes[0].n);
    const double dg = planes[0].value(s) / planes[0].a.dot(Dn);
    if (dg < 0.0) return false;
    s -= dg * Dn;
    return true;
  }
  const V3 D0 = apply_elastic(K, G, planes[0].n), D1 = apply_elastic(K, G, planes[1].n);
  Eigen::Matrix2d A;
  A << planes[0].a.dot(D0), planes[0].a.dot(D1), planes[1].a.dot(D0), planes[1].a.dot(D1);
  const Eigen::Vector2d f(planes[0].value(s), planes[1].value(s));
  const Eigen::Vector2d dg = A.partialPivLu().solve(f);
  if (dg[0] < 0.0 || dg[1] < 0.0) return false;
  s -= dg[0] * D0 + dg[1] * D1;
  return true;
}

// Principal stresses s1 >= s2 >= s3 and a way back to Cartesian stress. Plane strain (no
// out-of-plane shear) takes the closed form of the in-plane 2x2 block and needs no trigonometry:
// the in-plane eigenvalues c +- r with cos 2 theta = d / r, sin 2 theta = s_xy / r; a return
// keeps the principal directions, so new principal values a', b' (in-plane) and z' give
// s_xx, s_yy = (a' + b') / 2 +- (a' - b') / 2 cos 2 theta, s_xy = (a' - b') / 2 sin 2 theta.
// Otherwise Eigen's eigen-decomposition (columns of R).
struct Principal {
  V3 values;
  bool plane = false;
  double cos2 = 1.0, sin2 = 0.0;
  int slot[3] = {0, 1, 2}; // plane: sorted positions of (c + r, c - r, s_zz)
  Mat3 R;

  explicit Principal(const Voigt& sigma) {
    plane = sigma[4] == 0.0 && sigma[5] == 0.0;
    if (plane) {
      const double c = 0.5 * (sigma[0] + sigma[1]), d = 0.5 * (sigma[0] - sigma[1]);
      const double r = std::sqrt(d * d + sigma[3] * sigma[3]);
      if (r > 0.0) cos2 = d / r, sin2 = sigma[3] / r;
      const double v[3] = {c + r, c - r, sigma[2]};
      int order[3] = {0, 1, 2}; // order[i]: which of v is the i-th largest
      if (v[order[1]] < v[order[2]]) std::swap(order[1], order[2]);
      if (v[order[0]] < v[order[1]]) std::swap(order[0], order[1]);
      if (v[order[1]] < v[order[2]]) std::swap(order[1], order[2]);
      for (int i = 0; i < 3; ++i)
        values[i] = v[order[i]], slot[order[i]] = i;
      return;
    }
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(to_tensor(sigma));
    values = eig.eigenvalues().reverse();
    R = eig.eigenvectors().rowwise().reverse();
  }

  // The Cartesian stress with principal values s (same order as `values`).
  Voigt stress(const V3& s) const {
    if (!plane) return to_voigt(Mat3(R * s.asDiagonal() * R.transpose()));
    const double a = s[slot[0]], b = s[slot[1]];
    const double mean = 0.5 * (a + b), radius = 0.5 * (a - b);
    Voigt out = Voigt::Zero();
    out[0] = mean + radius * cos2;
    out[1] = mean - radius * cos2;
    out[2] = s[slot[2]];
    out[3] = radius * sin2;
    return out;
  }
};

// A plane-strain stress (no out-of-plane shear) that lies clearly inside the Mohr-Coulomb surface
// and below the cut-off t, decided without the square root and the sort of Principal: with the
// in-plane mean c_m, radius r and sigma_zz = z, s1 = max(c_m + r, z) and s3 = min(c_m - r, z).
// The yield function f(s1, s3) = (1 + sp) s1 - (1 - sp) s3 grows with s1 and falls with s3, so
// f(s1, s3) <= K = 2 c cos(phi) holds iff it holds for each of the four pairings of
// {c_m + r, z} with {c_m - r, z}; each pairing with r in it bounds r from above. So: z <= t,
// 2 sp z <= K and r <= X (the least of the bounds and of t - c_m), checked as r^2 <= X^2 with a
// relative margin of 1e-9 that keeps every stress near the surface for the exact check, which
// has a looser tolerance (1e-12): a stress passed here is one the exact check also passes, so
// the result is bitwise that of the exact check alone.
inline bool clearly_elastic_plane(const Voigt& sigma, double sp, double K, double t) {
  const double cm = 0.5 * (sigma[0] + sigma[1]), d = 0.5 * (sigma[0] - sigma[1]);
  const double z = sigma[2];
  const double r2 = d * d + sigma[3] * sigma[3];
  if (!(z < t) || !(2.0 * sp * z < K)) return false;
  const double a = 1.0 + sp, b = 1.0 - sp, margin = 1.0 - 1e-9;
  // Each bound as k r <= Y with k > 0: Y > 0 and k^2 r^2 < Y^2 (no division).
  auto below = [&](double k, double Y) { return Y > 0.0 && k * k * r2 < margin * Y * Y; };
  return below(1.0, 0.5 * K - sp * cm) && below(a, K + b * z - a * cm) &&
         below(b, K - a * z + b * cm) && below(1.0, t - cm);
}

} // namespace mc_detail

namespace mc_detail {

// The return of a stress that the quick check did not pass (c, sin phi, cos phi, sin psi and the
// tension limit t at the particle's plastic strain): principal values, then the active planes.
// Kept out of line, so that return_to_mohr_coulomb, which most calls leave at the quick elastic
// check, is small enough for the compiler to inline into the stress pass.
[[gnu::noinline]] inline double return_to_surface(const MohrCoulomb& mat, Voigt& sigma, double c,
                                                  double sp, double cp, double sd, double t) {
  // Inside the main plane (sextant s1 >= s2 >= s3) and below the cut-off.
  auto inside = [&](const V3& s, double tol) {
    return (1 + sp) * s[0] - (1 - sp) * s[2] - 2 * c * cp <= tol && s[0] <= t + tol;
  };
  auto tolerance = [&](const V3& s) { return 1e-12 * (std::abs(s[0]) + std::abs(s[2]) + c + 1.0); };
  // Principal values (in plane strain: one sqrt, no trigonometry); most calls end elastic here.
  const mc_detail::Principal principal(sigma);
  const V3& trial = principal.values;
  auto admissible = [&](const V3& s) {
    const double tol = tolerance(s);
    return s[0] >= s[1] - tol && s[1] >= s[2] - tol && inside(s, tol);
  };
  if (admissible(trial)) return 0.0;

  const double K = mat.bulk_modulus(), G = mat.shear_modulus();
  // Planes of the sextant s1 >= s2 >= s3: main (s1, s3), right edge partner (s2, s3), left edge
  // partner (s1, s2), and the tension cut-offs on s1 and s2.
  const Plane main{V3(1 + sp, 0, -(1 - sp)), V3(1 + sd, 0, -(1 - sd)), 2 * c * cp};
  const Plane right{V3(0, 1 + sp, -(1 - sp)), V3(0, 1 + sd, -(1 - sd)), 2 * c * cp};
  const Plane left{V3(1 + sp, -(1 - sp), 0), V3(1 + sd, -(1 - sd), 0), 2 * c * cp};
  const Plane cut1{V3(1, 0, 0), V3(1, 0, 0), t};
  const Plane cut2{V3(0, 1, 0), V3(0, 1, 0), t};

  // Try the active sets from the simplest; the first admissible result is the return.
  V3 s;
  const Plane sets[][2] = {{main, main}, {main, right}, {main, left},
                           {cut1, cut1}, {cut1, main},  {cut1, cut2}};
  const int sizes[] = {1, 2, 2, 1, 2, 2};
  bool done = false;
  for (int i = 0; i < 6 && !done; ++i) {
    s = trial;
    done = mc_detail::return_to_planes(K, G, sets[i], sizes[i], s) && admissible(s);
  }
  if (!done) {
    // Apex: all principal stresses at the tip of the pyramid (or the cut-off), where the cone
    // of the flow directions contains the trial point.
    const double apex = std::min(t, sp > 0.0 ? c * cp / sp : t);
    s = V3::Constant(apex);
  }
  const Voigt trial_voigt = sigma;
  sigma = principal.stress(s);
  return plastic_strain_increment(K, G, trial_voigt, sigma);
}

} // namespace mc_detail

// Returns the trial stress to the Mohr-Coulomb surface with tension cut-off; returns the
// equivalent plastic strain increment (0 if elastic).
inline double return_to_mohr_coulomb(const MohrCoulomb& mat, Voigt& sigma, double eps_p) {
  double c, sp, cp, sd;
  mat.strength.current_trig(eps_p, c, sp, cp, sd);
  const double t = mat.strength.fixed ? mat.strength.fixed->tension_limit
                                      : mat.strength.tension_limit(c, sp, cp);
  // Most calls end here: clearly elastic, found without Principal's square root.
  if (sigma[4] == 0.0 && sigma[5] == 0.0 &&
      mc_detail::clearly_elastic_plane(sigma, sp, 2.0 * c * cp, t))
    return 0.0;
  return mc_detail::return_to_surface(mat, sigma, c, sp, cp, sd, t);
}

inline void update_stress(const MohrCoulomb& mat, Voigt& sigma, double& eps_p, const Mat3& D,
                          const Mat3& W, double dt) {
  update_plastic_stress(mat, sigma, eps_p, D, W, dt, return_to_mohr_coulomb);
}

} // namespace talus
