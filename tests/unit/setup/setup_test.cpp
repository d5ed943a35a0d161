// Setup: the tables derived once from the case (pair friction, interface slots, fixed bodies).
#include "talus/setup/seeding.hpp"
#include "talus/setup/setup.hpp"
#include "two_bodies.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(Setup, PairTablesSlotsAndFixedBodies) {
  const Case c = test::case_from(test::two_blocks(R"(
[[contact]]
friction = 0.3
[[interface]]
bodies = ["upper", "lower"]
friction = { initial = 0.5 }
cohesion = { initial = 0 }
)",
                                                  true));
  Grid<2> grid(Vec<2>(0, 0), Vec<2>(2.0, 1.0), 0.1);
  const Seeded<2> seeded = seed_case<2>(c);
  const talus::Setup<2> s = make_setup<2>(c, grid, seeded.body_mass); // gtest has a Setup()
  ASSERT_EQ(s.num_bodies, 2);
  EXPECT_EQ(s.interface_of(0, 1), 0);
  EXPECT_EQ(s.interface_of(1, 0), 0);
  EXPECT_EQ(s.interface_of(0, 0), -1);
  // The interface pair slides with its initial friction where no interface particle is; the
  // default entry sets the others.
  EXPECT_DOUBLE_EQ(s.friction(0, 1), 0.5);
  EXPECT_DOUBLE_EQ(s.friction(0, 0), 0.3);
  EXPECT_EQ(s.slot(0, 0), 0);
  EXPECT_EQ(s.slot(1, 0), 0);
  EXPECT_TRUE(s.bodies[0].rigid && s.bodies[0].fixed);
  EXPECT_TRUE(s.bodies[0].normal_geometry.has_value()); // geometric_normal: default if rigid
  EXPECT_FALSE(s.bodies[1].rigid || s.bodies[1].fixed);
  // Total mass: density times area.
  EXPECT_NEAR(s.bodies[1].mass, 2000.0 * 0.4 * 0.2, 1e-9);
  EXPECT_NEAR(s.bodies[0].mass, 2000.0 * 1.6 * 0.2, 1e-9);
  EXPECT_DOUBLE_EQ(s.gravity[1], -9.81);
}

} // namespace
} // namespace talus
