// The memory estimate against this machine's resident set (label machine: it reads
// /proc/self/status and depends on the allocator, so it is not a unit test).
#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"
#include "talus/case/size.hpp"
#include "talus/core/memory_usage.hpp"
#include "talus/setup/seeds.hpp"
#include "talus/solver/simulation.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <string>

namespace talus {
namespace {

// The estimate `talus check` prints and the parser refuses by is within 25 % of the rise of the
// peak resident set over building the simulation and 20 steps.
template <int D>
void expect_estimate_near_peak(const Case& c, const std::string& file) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory is in the resident set";
#endif
  std::vector<std::size_t> counts;
  for (std::size_t b = 0; b < c.bodies.size(); ++b)
    counts.push_back(count_particles(c, b));
  const double estimate = estimate_memory(c, counts);
  reset_peak_rss();
  const Rss before = read_rss();
  if (before.peak == 0.0) GTEST_SKIP() << "no /proc/self/status";
  double rise = 0.0;
  {
    Simulation<D> sim(c);
    for (int s = 0; s < 20; ++s)
      sim.step();
    rise = read_rss().peak - before.now;
  }
  EXPECT_NEAR(estimate / rise, 1.0, 0.25)
      << file << ": estimate " << estimate / 1e6 << " MB, peak rise " << rise / 1e6 << " MB";
}

template <int D>
void expect_estimate_near_peak(const std::string& file, const std::vector<std::string>& set) {
  expect_estimate_near_peak<D>(parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + file, set),
                               file);
}

TEST(MemoryEstimate, OneBodyColumnWithin25PercentOfThePeak) {
  expect_estimate_near_peak<2>("bench/column.toml", {});
}

TEST(MemoryEstimate, ThreeBodyVaiontWithin25PercentOfThePeak) {
  expect_estimate_near_peak<2>("cases/vaiont/three_bodies.toml",
                               {"grid.cell_size=4", "initial_state.settle_time=0"});
}

TEST(MemoryEstimate, SphereIn3DWithin25PercentOfThePeak) {
  expect_estimate_near_peak<3>("cases/benchmarks/rolling_sphere.toml", {"grid.cell_size=0.05"});
}

// 2,000 blocks of 16 particles in rows on a 400 m floor: what grows with the number of bodies
// (the pair tables, the contact record's rows, the scatter's offsets) is counted. Each block is
// 1 m square; the rows are 4 m apart, so no two blocks touch.
TEST(MemoryEstimate, TwoThousandSmallBodiesWithin25PercentOfThePeak) {
  std::string text = R"(
[simulation]
dimension = 2
end_time = 1.0
gravity = [0, -9.81]
[grid]
extent = [400, 60]
cell_size = 0.5
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
)";
  for (int i = 0; i < 2000; ++i) {
    const double x = 2.0 + 2.0 * (i % 190), y = 2.0 + 4.0 * (i / 190);
    text += fmt::format("[[body]]\nname = \"b{}\"\nmaterial = \"m\"\n"
                        "box = {{ min = [{}, {}], max = [{}, {}] }}\n",
                        i, x, y, x + 1.0, y + 1.0);
  }
  expect_estimate_near_peak<2>(
      parse_case_text(text, std::string(TALUS_SOURCE_DIR) + "/tests/inline.toml"), "2,000 blocks");
}

} // namespace
} // namespace talus
