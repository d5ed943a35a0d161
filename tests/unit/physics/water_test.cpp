// The water level's submerged share and its integral (physics/water.hpp).
#include "talus/physics/water.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace talus;

// The share is 0 above the level's band, 1 below, and linear across it (1/2 at the level); the
// integral's derivative is minus the share, so the buoyancy's work rho_w / rho m g (H(z0) - H(z))
// is the integral of the buoyant force along the path. Swept over levels and particle heights.
TEST(Water, SubmergedShareAndItsIntegral) {
  for (const double level : {-3.0, 0.0, 12.5})
    for (const double l : {0.05, 0.5, 2.0}) {
      EXPECT_EQ(submerged_fraction(level, level + 0.51 * l, l), 0.0);
      EXPECT_EQ(submerged_fraction(level, level - 0.51 * l, l), 1.0);
      const double round_off = 1e-14 * (std::abs(level) + l); // of level +- a multiple of l
      EXPECT_DOUBLE_EQ(submerged_fraction(level, level, l), 0.5);
      EXPECT_NEAR(submerged_fraction(level, level + 0.25 * l, l), 0.25, round_off / l);
      EXPECT_EQ(submerged_integral(level, level + l, l), 0.0);
      EXPECT_NEAR(submerged_integral(level, level - 3.0 * l, l), 3.0 * l, round_off);
      for (double z = level - 2.0 * l; z <= level + 2.0 * l; z += 0.01 * l) {
        const double e = 1e-6 * l;
        const double slope =
            (submerged_integral(level, z + e, l) - submerged_integral(level, z - e, l)) / (2 * e);
        EXPECT_NEAR(slope, -submerged_fraction(level, z, l), 1e-6) << level << " " << l << " " << z;
      }
      // Continuous at the band's edges.
      for (const double edge : {level - 0.5 * l, level + 0.5 * l})
        EXPECT_NEAR(submerged_integral(level, edge - 1e-12, l),
                    submerged_integral(level, edge + 1e-12, l), 1e-9);
    }
}
