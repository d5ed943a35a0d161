// Slab decomposition: bounds from per-column counts, exact and the same on every process.
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/processes.hpp"

#include <gtest/gtest.h>
#include <numeric>

namespace talus {
namespace {

// Particles in slab r of `bounds`.
std::int64_t slab_count(const std::vector<std::int64_t>& counts,
                        const std::vector<std::int64_t>& bounds, int r) {
  return std::accumulate(counts.begin() + bounds[r], counts.begin() + bounds[r + 1],
                         std::int64_t{0});
}

TEST(SlabBounds, UniformColumnsSplitEvenly) {
  const std::vector<std::int64_t> counts(12, 5);
  EXPECT_EQ(slab_bounds(counts, 1, 1), (std::vector<std::int64_t>{0, 12}));
  EXPECT_EQ(slab_bounds(counts, 2, 1), (std::vector<std::int64_t>{0, 6, 12}));
  EXPECT_EQ(slab_bounds(counts, 3, 1), (std::vector<std::int64_t>{0, 4, 8, 12}));
  EXPECT_EQ(slab_bounds(counts, 4, 3), (std::vector<std::int64_t>{0, 3, 6, 9, 12}));
}

TEST(SlabBounds, FollowTheParticles) {
  // A slide piled in the middle of an empty valley: each of 4 slabs holds a quarter of it,
  // give or take the last column added.
  std::vector<std::int64_t> counts(100, 0);
  for (int c = 40; c < 60; ++c)
    counts[c] = 1000 + 37 * c;
  const auto b = slab_bounds(counts, 4, 2);
  const std::int64_t total = std::accumulate(counts.begin(), counts.end(), std::int64_t{0});
  for (int r = 0; r < 4; ++r) {
    EXPECT_GE(b[r + 1] - b[r], 2);
    EXPECT_LE(std::abs(4 * slab_count(counts, b, r) - total), 4 * 3300) << "slab " << r;
  }
  // Boundary r is the first column whose running count reaches r/4 of the total.
  for (int r = 1; r < 4; ++r) {
    const std::int64_t before = std::accumulate(counts.begin(), counts.begin() + b[r], 0LL);
    const std::int64_t one_less = std::accumulate(counts.begin(), counts.begin() + b[r] - 1, 0LL);
    EXPECT_GE(4 * before, r * total);
    EXPECT_LT(4 * one_less, r * total);
  }
}

TEST(SlabBounds, MinimumWidthPushesEmptyEnds) {
  // Every particle in the first column: the other slabs are pushed right, min_width each.
  std::vector<std::int64_t> counts(20, 0);
  counts[0] = 500;
  EXPECT_EQ(slab_bounds(counts, 3, 4), (std::vector<std::int64_t>{0, 4, 8, 20}));
  // ... and in the last: pushed left from the right end.
  std::reverse(counts.begin(), counts.end());
  EXPECT_EQ(slab_bounds(counts, 3, 4), (std::vector<std::int64_t>{0, 12, 16, 20}));
  // No particles at all: still valid slabs.
  EXPECT_EQ(slab_bounds(std::vector<std::int64_t>(9, 0), 3, 3),
            (std::vector<std::int64_t>{0, 3, 6, 9}));
}

TEST(SlabBounds, NarrowGridIsRefusedWithTheFigures) {
  try {
    slab_bounds(std::vector<std::int64_t>(10, 1), 4, 3);
    FAIL() << "no error";
  } catch (const DecompositionError& e) {
    EXPECT_NE(std::string(e.what()).find("10 cell columns"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at least 12"), std::string::npos) << e.what();
  }
}

TEST(SlabBounds, HugeCountsDoNotOverflow) {
  const std::vector<std::int64_t> counts(8, std::int64_t{1} << 60);
  EXPECT_EQ(slab_bounds(counts, 4, 1), (std::vector<std::int64_t>{0, 2, 4, 6, 8}));
}

TEST(SlabOwner, ColumnsMapToTheirSlab) {
  const std::vector<std::int64_t> b{0, 3, 7, 10};
  const int expected[] = {0, 0, 0, 1, 1, 1, 1, 2, 2, 2};
  for (int c = 0; c < 10; ++c)
    EXPECT_EQ(slab_owner(b, c), expected[c]) << c;
  EXPECT_EQ(slab_owner(b, -1), 0);
  EXPECT_EQ(slab_owner(b, 10), 2);
  EXPECT_EQ(slab_owner({0, 10}, 5), 0);
}

// The parser's memory check on several processes: the part of the case on one machine.
TEST(MemoryShare, OneMachineHoldsItsProcessesSlabsAndGhosts) {
  EXPECT_EQ(memory_share(1, 1, 4000, 11), 1.0);
  EXPECT_EQ(memory_share(4, 4, 4000, 11), 1.0); // every process on one machine: all of it
  // 30 machines of one process, 4,000 columns: 1/30 + 22/4000.
  EXPECT_DOUBLE_EQ(memory_share(30, 1, 4000, 11), 1.0 / 30 + 22.0 / 4000);
  EXPECT_DOUBLE_EQ(memory_share(30, 2, 4000, 11), 2 * (1.0 / 30 + 22.0 / 4000));
  EXPECT_DOUBLE_EQ(memory_share(8, 1, 40, 11), 1.0 / 8 + 22.0 / 40); // ghosts outweigh the slab
  EXPECT_EQ(memory_share(8, 1, 20, 11), 1.0); // ghosts wider than the grid: the whole
}

} // namespace
} // namespace talus
