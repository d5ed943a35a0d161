// Stress-point tests of Drucker-Prager (each matching) and Mohr-Coulomb: expected values come from
// the closed-form yield conditions written out here.
#include "talus/physics/materials/drucker_prager.hpp"
#include "talus/physics/materials/mohr_coulomb.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <random>

namespace talus {
namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;

MohrCoulombStrength strength(double phi_deg, double c, double psi_deg = 0.0, double t = INFINITY) {
  MohrCoulombStrength s;
  s.friction_angle = phi_deg * deg;
  s.dilation_angle = psi_deg * deg;
  s.cohesion = c;
  s.tension_cutoff = t;
  return s;
}

DruckerPrager dp(DruckerPragerMatch m, MohrCoulombStrength s) {
  return {2000, 50e6, 0.3, m, s, {}};
}
MohrCoulomb mc(MohrCoulombStrength s) {
  return {2000, 50e6, 0.3, s};
}

double dp_yield(const DruckerPrager& m, const Voigt& s) {
  double a = 0.0, k = 0.0;
  m.match_coefficients(m.strength.friction_angle, m.strength.cohesion, a, k);
  return std::sqrt(second_invariant(deviator(s))) + a * trace(s) - k;
}

Eigen::Vector3d principal(const Voigt& s) {
  Eigen::SelfAdjointEigenSolver<Mat3> e(to_tensor(s));
  return e.eigenvalues().reverse(); // s1 >= s2 >= s3
}

double mc_yield(const MohrCoulomb& m, const Voigt& s) {
  const Eigen::Vector3d p = principal(s);
  const double sp = std::sin(m.strength.friction_angle), cp = std::cos(m.strength.friction_angle);
  return (p[0] - p[2]) + (p[0] + p[2]) * sp - 2.0 * m.strength.cohesion * cp;
}

Voigt isotropic(double p) {
  Voigt s = Voigt::Zero();
  s[0] = s[1] = s[2] = p;
  return s;
}

// Drives a material along a strain path: n increments of the strain-rate D over dt = 1.
template <class M>
Voigt drive(const M& m, Voigt sigma, const Mat3& D, int n, double* eps_p = nullptr) {
  double e = 0.0;
  for (int i = 0; i < n; ++i)
    update_stress(m, sigma, e, D, Mat3::Zero(), 1.0);
  if (eps_p) *eps_p = e;
  return sigma;
}

// Triaxial compression shape at constant mean stress: d = rate * (-2, 1, 1) (axial along x).
Mat3 triaxial_compression(double rate) {
  Mat3 D = Mat3::Zero();
  D(0, 0) = -2.0 * rate;
  D(1, 1) = D(2, 2) = rate;
  return D;
}

TEST(DruckerPrager, ElasticBelowYield) {
  const auto m = dp(DruckerPragerMatch::inner, strength(30, 10e3));
  double e = 0.0;
  Voigt s = isotropic(-100e3);
  Mat3 D = Mat3::Zero();
  D(0, 1) = D(1, 0) = 1e-5;
  update_stress(m, s, e, D, Mat3::Zero(), 1.0);
  EXPECT_DOUBLE_EQ(e, 0.0);
  EXPECT_NEAR(s[3], 2.0 * m.shear_modulus() * 1e-5, 1e-6);
  EXPECT_NEAR(mean_stress(s), -100e3, 1e-6);
}

// Peak deviator q = s1 - s3 at mean stress p on the compression meridian (s2 = s1):
// DP: q = sqrt(3) (k - 3 alpha p); MC: q = (2 c cos(phi) - 2 p sin(phi)) / (1 - sin(phi) / 3).
TEST(DruckerPrager, TriaxialCompressionReachesThePeakOfEachMatching) {
  const double phi = 30, c = 20e3, p = -200e3;
  for (auto match :
       {DruckerPragerMatch::inner, DruckerPragerMatch::outer, DruckerPragerMatch::plane_strain}) {
    const auto m = dp(match, strength(phi, c));
    double a = 0.0, k = 0.0;
    m.match_coefficients(phi * deg, c, a, k);
    const Voigt s = drive(m, isotropic(p), triaxial_compression(1e-5), 400);
    const Eigen::Vector3d pr = principal(s);
    EXPECT_NEAR(pr[0] - pr[2], std::sqrt(3.0) * (k - 3.0 * a * p), 1e-8 * std::abs(p));
    EXPECT_NEAR(mean_stress(s), p, 1e-8 * std::abs(p)); // zero dilation: p stays
  }
  // The outer cone touches Mohr-Coulomb on the compression meridian.
  double a = 0.0, k = 0.0;
  dp(DruckerPragerMatch::outer, strength(phi, c)).match_coefficients(phi * deg, c, a, k);
  const double mc_peak =
      (2 * c * std::cos(phi * deg) - 2 * p * std::sin(phi * deg)) / (1 - std::sin(phi * deg) / 3);
  EXPECT_NEAR(std::sqrt(3.0) * (k - 3.0 * a * p), mc_peak, 1e-9 * mc_peak);
}

TEST(MohrCoulomb, TriaxialCompressionReachesThePeak) {
  const double phi = 30, c = 20e3, p = -200e3;
  const auto m = mc(strength(phi, c));
  const Voigt s = drive(m, isotropic(p), triaxial_compression(1e-5), 400);
  const Eigen::Vector3d pr = principal(s);
  const double peak =
      (2 * c * std::cos(phi * deg) - 2 * p * std::sin(phi * deg)) / (1 - std::sin(phi * deg) / 3);
  EXPECT_NEAR(pr[0] - pr[2], peak, 1e-8 * peak);
  EXPECT_NEAR(pr[0], pr[1], 1e-8 * std::abs(p)); // on the edge s1 = s2 (compression meridian)
}

TEST(MohrCoulomb, ClassicTriaxialAtConstantConfiningStress) {
  // Trial states with s2 = s3 = -confining fixed and growing axial compression return to the
  // surface; at the peak, sigma_a = (sigma_c (1 + sin phi) + 2 c cos phi) / (1 - sin phi).
  const double phi = 35, c = 50e3, sc = 100e3;
  const auto m = mc(strength(phi, c));
  const double sa =
      (sc * (1 + std::sin(phi * deg)) + 2 * c * std::cos(phi * deg)) / (1 - std::sin(phi * deg));
  Voigt s = Voigt::Zero();
  s[0] = -sa, s[1] = s[2] = -sc; // exactly on the surface: elastic
  EXPECT_NEAR(mc_yield(m, s), 0.0, 1e-9 * sa);
  Voigt inside = s;
  EXPECT_EQ(return_to_mohr_coulomb(m, inside, 0.0), 0.0);
}

TEST(DruckerPrager, UniaxialTensionStopsAtTheCutoff) {
  const double cutoff = 5e3;
  for (auto match : {DruckerPragerMatch::inner, DruckerPragerMatch::plane_strain}) {
    const auto m = dp(match, strength(30, 20e3, 0, cutoff));
    Mat3 D = Mat3::Zero();
    D(0, 0) = 1e-5;
    double e = 0.0;
    const Voigt s = drive(m, Voigt::Zero(), D, 200, &e);
    EXPECT_NEAR(mean_stress(s), cutoff, 1e-9 * cutoff);
    EXPECT_GT(e, 0.0);
    EXPECT_LE(dp_yield(m, s), 1e-10 * 20e3);
  }
}

TEST(MohrCoulomb, UniaxialTensionStopsAtTheCutoff) {
  const double cutoff = 5e3;
  const auto m = mc(strength(30, 20e3, 0, cutoff));
  Mat3 D = Mat3::Zero();
  D(0, 0) = 1e-5;
  const Voigt s = drive(m, Voigt::Zero(), D, 200);
  EXPECT_NEAR(principal(s)[0], cutoff, 1e-9 * cutoff);
  EXPECT_LE(mc_yield(m, s), 1e-10 * 20e3);
}

TEST(DruckerPrager, ReturnsToTheApex) {
  const double phi = 25, c = 10e3;
  const auto m = dp(DruckerPragerMatch::inner, strength(phi, c));
  double a = 0.0, k = 0.0;
  m.match_coefficients(phi * deg, c, a, k);
  Voigt s = isotropic(1e6);
  s[3] = 1e3;
  return_to_drucker_prager(m, s, 0.0);
  const Voigt apex = isotropic(k / (3.0 * a));
  EXPECT_LT((s - apex).norm(), 1e-10 * apex.norm());
}

TEST(MohrCoulomb, ReturnsToTheApex) {
  const double phi = 25, c = 10e3;
  const auto m = mc(strength(phi, c));
  Voigt s = isotropic(1e6);
  s[0] += 1e3;
  return_to_mohr_coulomb(m, s, 0.0);
  const Voigt apex = isotropic(c / std::tan(phi * deg));
  EXPECT_LT((s - apex).norm(), 1e-10 * apex.norm());
}

// Random trial stresses: after every return the stress is admissible, and on the surface (or the
// cut-off) to 1e-10 relative when the return was plastic.
TEST(Plasticity, EveryReturnLandsOnTheSurface) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double c = 30e3, cutoff = 20e3, scale = 1e6;
  const auto d = dp(DruckerPragerMatch::outer, strength(32, c, 10, cutoff));
  const auto m = mc(strength(32, c, 10, cutoff));
  int plastic_dp = 0, plastic_mc = 0;
  for (int i = 0; i < 5000; ++i) {
    Voigt trial;
    for (int k = 0; k < 6; ++k)
      trial[k] = scale * (k < 3 ? u(rng) - 0.3 : 0.3 * u(rng));
    Voigt s = trial;
    if (return_to_drucker_prager(d, s, 0.0) > 0.0) {
      ++plastic_dp;
      const double f = dp_yield(d, s), on_cutoff = mean_stress(s) - cutoff;
      EXPECT_TRUE(std::abs(f) < 1e-10 * scale || std::abs(on_cutoff) < 1e-10 * scale) << f;
    }
    EXPECT_LT(dp_yield(d, s), 1e-10 * scale);
    EXPECT_LT(mean_stress(s), cutoff + 1e-10 * scale);
    s = trial;
    if (return_to_mohr_coulomb(m, s, 0.0) > 0.0) {
      ++plastic_mc;
      const double f = mc_yield(m, s), on_cutoff = principal(s)[0] - cutoff;
      EXPECT_TRUE(std::abs(f) < 1e-10 * scale || std::abs(on_cutoff) < 1e-10 * scale) << f;
    }
    EXPECT_LT(mc_yield(m, s), 1e-10 * scale);
    EXPECT_LT(principal(s)[0], cutoff + 1e-10 * scale);
  }
  EXPECT_GT(plastic_dp, 1000);
  EXPECT_GT(plastic_mc, 1000);
}

// Plane strain (no out-of-plane shear) takes the closed-form, trigonometry-free principal path.
// Random in-plane trials: each return lands on the surface (or cut-off), stays plane, keeps the
// trial's principal directions (the two tensors commute), and a prepared material (constant
// sines and cosines taken once) gives bitwise the same stress.
TEST(Plasticity, PlaneStrainReturnsAreCoaxialAndPreparingChangesNothing) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double c = 30e3, cutoff = 20e3, scale = 1e6;
  const auto m = mc(strength(32, c, 10, cutoff));
  auto m_prepared = m;
  m_prepared.strength.prepare();
  auto d = dp(DruckerPragerMatch::inner, strength(32, c, 10, cutoff));
  auto d_prepared = d;
  d_prepared.prepare();
  ASSERT_TRUE(m_prepared.strength.fixed && d_prepared.fixed);
  int plastic = 0;
  for (int i = 0; i < 5000; ++i) {
    Voigt trial = Voigt::Zero();
    for (int k = 0; k < 4; ++k)
      trial[k] = scale * (k < 3 ? u(rng) - 0.3 : 0.3 * u(rng));
    Voigt s = trial, s_prepared = trial;
    const double dep = return_to_mohr_coulomb(m, s, 0.0);
    EXPECT_EQ(return_to_mohr_coulomb(m_prepared, s_prepared, 0.0), dep);
    EXPECT_TRUE(s == s_prepared) << i;
    Voigt t = trial, t_prepared = trial;
    EXPECT_EQ(return_to_drucker_prager(d, t, 0.0),
              return_to_drucker_prager(d_prepared, t_prepared, 0.0));
    EXPECT_TRUE(t == t_prepared) << i;
    if (dep == 0.0) continue;
    ++plastic;
    EXPECT_EQ(s[4], 0.0);
    EXPECT_EQ(s[5], 0.0);
    const double f = mc_yield(m, s), on_cutoff = principal(s)[0] - cutoff;
    EXPECT_TRUE(std::abs(f) < 1e-10 * scale || std::abs(on_cutoff) < 1e-10 * scale) << f;
    const Mat3 a = to_tensor(trial), b = to_tensor(s);
    EXPECT_LT((a * b - b * a).norm(), 1e-12 * a.norm() * b.norm()) << i;
  }
  EXPECT_GT(plastic, 1000);
}

// The plane-strain pre-check that skips Principal's square root for clearly elastic stresses
// must never pass a stress that the exact check (principal values, tolerance 1e-12) rejects, and
// should pass nearly every stress inside the surface. Random plane stresses around the surface and
// the cut-off, with the angle, the cohesion and the cut-off varied (also no cut-off and phi 0).
TEST(MohrCoulomb, PlaneStrainPreCheckPassesOnlyElasticStresses) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int inside = 0, passed = 0;
  for (const double phi : {0.0, 20.0, 30.0, 45.0})
    for (const double cutoff : {1.0, 20e3, double(INFINITY)}) {
      const double c = 30e3, scale = 2e5;
      const double sp = std::sin(phi * deg), cp = std::cos(phi * deg), K = 2.0 * c * cp;
      const double t = std::min(cutoff, sp > 0.0 ? c * cp / sp : cutoff);
      for (int i = 0; i < 20000; ++i) {
        Voigt s = Voigt::Zero();
        for (int k = 0; k < 4; ++k)
          s[k] = scale * (k < 3 ? u(rng) - 0.3 : 0.3 * u(rng));
        const Eigen::Vector3d p = principal(s);
        const double f = (1 + sp) * p[0] - (1 - sp) * p[2] - K;
        const bool exact = f <= 0.0 && p[0] <= t;
        const bool pre = mc_detail::clearly_elastic_plane(s, sp, K, t);
        if (pre) {
          ++passed;
          EXPECT_TRUE(exact) << "phi " << phi << " cut-off " << cutoff << " sample " << i;
        }
        // Inside by a margin of 1e-6 of the scale: the pre-check must see it.
        if (f < -1e-6 * scale && p[0] < t - 1e-6 * scale) {
          ++inside;
          EXPECT_TRUE(pre) << "phi " << phi << " cut-off " << cutoff << " sample " << i;
        }
      }
    }
  EXPECT_GT(inside, 10000);
  EXPECT_GE(passed, inside);
}

// Plastic strain increment C^-1 (trial - sigma): parallel to the flow direction.
Voigt plastic_strain(double K, double G, const Voigt& trial, const Voigt& s) {
  const Voigt ds = trial - s;
  Voigt e = deviator(ds) / (2 * G);
  for (int i = 0; i < 3; ++i)
    e[i] += mean_stress(ds) / (3 * K);
  return e;
}

TEST(DruckerPrager, FlowIsAssociatedOrIsochoric) {
  Voigt trial = isotropic(-100e3);
  trial[0] -= 300e3;
  trial[3] = 50e3;
  for (double psi : {0.0, 30.0}) {
    const auto m = dp(DruckerPragerMatch::inner, strength(30, 10e3, psi));
    Voigt s = trial;
    return_to_drucker_prager(m, s, 0.0);
    const Voigt e = plastic_strain(m.bulk_modulus(), m.shear_modulus(), trial, s);
    double a_psi, k;
    m.match_coefficients(psi * deg, 0.0, a_psi, k);
    // Flow direction dg/dsigma = s / (2 sqrt(J2)) + alpha_psi I (shear terms as tensor components).
    const Voigt dev = deviator(trial);
    Voigt n = dev / (2 * std::sqrt(second_invariant(dev)));
    for (int i = 0; i < 3; ++i)
      n[i] += a_psi;
    const double cosine = e.dot(n) / (e.norm() * n.norm());
    EXPECT_NEAR(cosine, 1.0, 1e-10) << "psi " << psi;
    if (psi == 0.0)
      EXPECT_NEAR(e[0] + e[1] + e[2], 0.0, 1e-12 * e.norm());
    else
      EXPECT_GT(e[0] + e[1] + e[2], 0.0); // dilation
  }
}

TEST(MohrCoulomb, FlowIsAssociatedOrNonAssociated) {
  Voigt trial = Voigt::Zero();
  trial[0] = -600e3, trial[1] = -250e3, trial[2] = -100e3; // main-plane region
  for (double psi : {0.0, 30.0}) {
    const auto m = mc(strength(30, 10e3, psi));
    Voigt s = trial;
    return_to_mohr_coulomb(m, s, 0.0);
    const Voigt e = plastic_strain(m.bulk_modulus(), m.shear_modulus(), trial, s);
    // Principal order: s1 = sigma_zz (-100e3), s3 = sigma_xx (-600e3). n = (1 + sin psi) e1 - (1 -
    // sin psi) e3.
    const double sd = std::sin(psi * deg);
    EXPECT_NEAR(e[1], 0.0, 1e-12 * e.norm());
    EXPECT_NEAR(e[2] / e[0], -(1 + sd) / (1 - sd), 1e-9);
  }
}

TEST(DruckerPrager, SofteningMovesTheSurfaceToResidual) {
  auto s = strength(30, 20e3);
  s.softening_strain = 0.01;
  s.residual_cohesion = 5e3;
  s.residual_friction_angle = 20 * deg;
  double c, phi;
  s.current(0.005, c, phi);
  EXPECT_DOUBLE_EQ(c, 12.5e3);
  EXPECT_NEAR(phi, 25 * deg, 1e-15);
  s.current(1.0, c, phi);
  EXPECT_DOUBLE_EQ(c, 5e3);
  EXPECT_NEAR(phi, 20 * deg, 1e-15);
}

} // namespace
} // namespace talus
