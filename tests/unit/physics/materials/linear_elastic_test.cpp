// The hypoelastic material with the Jaumann rate: elastic moduli and objectivity under rotation.
#include "talus/physics/materials/linear_elastic.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>
#include <random>

namespace talus {
namespace {

const LinearElastic rock{2500.0, 50e6, 0.25};

TEST(LinearElastic, UniaxialStrainGivesTheConstrainedModulus) {
  Voigt sigma = Voigt::Zero();
  double eps_p = 0.0;
  Mat3 D = Mat3::Zero();
  D(0, 0) = -1e-3; // strain rate
  const double dt = 0.01;
  for (int i = 0; i < 100; ++i)
    update_stress(rock, sigma, eps_p, D, Mat3::Zero(), dt);
  const double eps = -1e-3; // total strain
  const double K = rock.bulk_modulus(), G = rock.shear_modulus();
  EXPECT_NEAR(sigma[0], (K + 4.0 / 3.0 * G) * eps, 1e-9 * std::abs(K * eps));
  EXPECT_NEAR(sigma[1], (K - 2.0 / 3.0 * G) * eps, 1e-9 * std::abs(K * eps));
  EXPECT_NEAR(sigma[2], (K - 2.0 / 3.0 * G) * eps, 1e-9 * std::abs(K * eps));
  // nu / (1 - nu) is the lateral ratio under uniaxial strain.
  EXPECT_NEAR(sigma[1] / sigma[0], rock.poisson_ratio / (1.0 - rock.poisson_ratio), 1e-12);
}

TEST(LinearElastic, PureShearGivesTwiceTheShearModulus) {
  Voigt sigma = Voigt::Zero();
  double eps_p = 0.0;
  Mat3 D = Mat3::Zero();
  D(0, 1) = D(1, 0) = 2e-3;
  update_stress(rock, sigma, eps_p, D, Mat3::Zero(), 0.5);
  EXPECT_NEAR(sigma[3], 2.0 * rock.shear_modulus() * 1e-3, 1e-6);
  EXPECT_NEAR(sigma[0], 0.0, 1e-9);
}

// The paper's example (section 2.2): a bar stressed along x and rotated rigidly by 90 degrees
// carries the same stress along y. Without the Jaumann terms the stress would not turn at all.
TEST(LinearElastic, RigidRotationByNinetyDegreesSwapsTheStress) {
  const double s0 = 1e6;
  Voigt sigma = Voigt::Zero();
  double eps_p = 0.0;
  sigma[0] = s0;
  const double omega = 1.0; // rad/s, counter-clockwise
  Mat3 W = Mat3::Zero();
  W(0, 1) = -omega; // W = (L - L^T)/2 for v = omega x (-y, x)
  W(1, 0) = omega;
  const int steps = 2000;
  const double dt = std::numbers::pi / 2.0 / omega / steps;
  for (int i = 0; i < steps; ++i)
    update_stress(rock, sigma, eps_p, Mat3::Zero(), W, dt);
  EXPECT_NEAR(sigma[0], 0.0, 0.01 * s0);
  EXPECT_NEAR(sigma[1], s0, 0.01 * s0);
  EXPECT_NEAR(sigma[3], 0.0, 0.01 * s0);
}

TEST(LinearElastic, HalfwayThroughTheRotationTheStressIsTheRotatedTensor) {
  const double s0 = 1e6, theta = std::numbers::pi / 4.0;
  Voigt sigma = Voigt::Zero();
  double eps_p = 0.0;
  sigma[0] = s0;
  Mat3 W = Mat3::Zero();
  W(0, 1) = -1.0;
  W(1, 0) = 1.0;
  const int steps = 4000;
  for (int i = 0; i < steps; ++i)
    update_stress(rock, sigma, eps_p, Mat3::Zero(), W, theta / steps);
  // R diag(s0, 0) R^T at 45 degrees: xx = yy = xy = s0 / 2.
  EXPECT_NEAR(sigma[0], s0 * std::cos(theta) * std::cos(theta), 1e-3 * s0);
  EXPECT_NEAR(sigma[1], s0 * std::sin(theta) * std::sin(theta), 1e-3 * s0);
  EXPECT_NEAR(sigma[3], s0 * std::sin(theta) * std::cos(theta), 1e-3 * s0);
}

// The plane-strain shortcut of the trial increment agrees with the general 3x3 form for random
// in-plane stresses, strain rates and spins (and the general form is taken with out-of-plane
// shear present).
TEST(LinearElastic, PlaneStrainShortcutEqualsTheGeneralIncrement) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double K = rock.bulk_modulus(), G = rock.shear_modulus();
  for (int i = 0; i < 1000; ++i) {
    Voigt sigma = Voigt::Zero();
    for (int k = 0; k < 4; ++k)
      sigma[k] = 1e6 * u(rng);
    Mat3 L = Mat3::Zero();
    L(0, 0) = u(rng), L(0, 1) = u(rng), L(1, 0) = u(rng), L(1, 1) = u(rng);
    const Mat3 D = 0.5 * (L + L.transpose()), W = 0.5 * (L - L.transpose());
    const Voigt fast = trial_increment(K, G, sigma, D, W, 1e-3);
    const Voigt general = trial_increment_general(K, G, sigma, D, W, 1e-3);
    EXPECT_LT((fast - general).norm(), 1e-12 * (general.norm() + 1e6)) << i;
    EXPECT_EQ(fast[4], 0.0);
    EXPECT_EQ(fast[5], 0.0);
    Voigt s3 = sigma;
    s3[4] = 1e5; // out-of-plane shear: the general form is taken
    EXPECT_TRUE(trial_increment(K, G, s3, D, W, 1e-3) ==
                trial_increment_general(K, G, s3, D, W, 1e-3));
  }
}

} // namespace
} // namespace talus
