#include "talus/case/size.hpp"
#include "talus/core/particles.hpp"
#include "two_bodies.hpp"

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
  // APIC's affine velocity C_p, a D x D matrix, only when a case asks for it.
  EXPECT_EQ(bytes_per_particle(2, true) - bytes_per_particle(2), sizeof(Mat<2>));
  EXPECT_EQ(bytes_per_particle(3, true) - bytes_per_particle(3), sizeof(Mat<3>));
  EXPECT_EQ(bytes_per_field_node(2, false, false, 0), 8.0 + 4 * 16.0);
  EXPECT_EQ(bytes_per_field_node(3, true, true, 2), 8.0 + 7 * 24.0 + 12 * 8.0);
}

// The output estimate counts a fixed body (rigid, at rest) beside others once, as the frames write
// it (RunWriter::frame_parts), and every body at every frame otherwise.
TEST(OutputEstimate, FixedBodiesOnce) {
  const std::vector<std::size_t> counts{300, 100};
  for (const bool fixed : {false, true}) {
    const Case c = test::case_from(test::two_blocks("[output]\nevery = 0.1\n", fixed));
    const RunPlan plan = plan_run(c, counts, ".");
    EXPECT_EQ(plan.frames, 11.0);
    const double particle_frames = fixed ? 11.0 * 100 + 300 : 11.0 * 400;
    EXPECT_DOUBLE_EQ(plan.output_bytes, particle_frames * plan.frame_bytes) << fixed;
  }
}

} // namespace
} // namespace talus
