#include "talus/case/size.hpp"
#include "talus/core/particles.hpp"

#include <gtest/gtest.h>
#include <string>

namespace talus {
namespace {

// Counted from the types: a 2D particle holds at least its own arrays (positions, velocity,
// stress, F, ...) and more in 3D.
TEST(MemoryEstimate, BytesPerParticleFromTheTypes) {
  Particles<2> P2;
  double own = 0.0;
  P2.for_each_array(
      [&](auto& a) { own += sizeof(typename std::decay_t<decltype(a)>::value_type); });
  EXPECT_GT(bytes_per_particle(2), own);
  EXPECT_GT(bytes_per_particle(3), bytes_per_particle(2));
  EXPECT_EQ(bytes_per_field_node(2, false, false, 0), 8.0 + 4 * 16.0);
  EXPECT_EQ(bytes_per_field_node(3, true, true, 2), 8.0 + 7 * 24.0 + 12 * 8.0);
}

} // namespace
} // namespace talus
