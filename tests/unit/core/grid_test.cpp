// Grid<D> (core/grid.hpp): node and cell indexing, positions, the cell of a point, containment.
#include "talus/core/grid.hpp"

#include <gtest/gtest.h>

using namespace talus;

// Every node's index and coordinates round-trip, and the index is row-major with x slowest (so
// that nodes sorted by index form slabs along x).
TEST(Grid, NodeIndexRoundTripsAndXIsSlowest) {
  const Grid<3> g(Vec<3>(-1.0, 2.0, 0.5), Vec<3>(3.0, 2.0, 4.0), 0.5);
  ASSERT_EQ(g.num_nodes(), 7 * 5 * 9);
  ASSERT_EQ(g.num_cells(), 6 * 4 * 8);
  std::int64_t last_x = 0;
  for (std::int64_t n = 0; n < g.num_nodes(); ++n) {
    const Index<3> i = g.node_coords(n);
    EXPECT_EQ(g.node_index(i), n);
    EXPECT_GE(i[0], last_x); // x never decreases along the index
    last_x = i[0];
  }
  EXPECT_EQ(g.node_index(Index<3>{1, 0, 0}), 5 * 9); // one x plane holds ny * nz nodes
  EXPECT_EQ(g.cell_index(Index<3>{1, 0, 0}), 4 * 8);
}

// An extent that is not a whole number of cells is rounded up; one that is, within round-off, is
// not given an extra cell.
TEST(Grid, CellCountsRoundUpButNotForRoundOff) {
  for (const double extent : {1.0, 0.3 + 0.7, 10.0 * 0.1 * 3.0}) {
    const Grid<2> g(Vec<2>::Zero(), Vec<2>(extent, extent), extent / 10.0);
    EXPECT_EQ(g.cells[0], 10) << "extent " << extent;
  }
  const Grid<2> g(Vec<2>::Zero(), Vec<2>(1.05, 0.95), 0.1);
  EXPECT_EQ(g.cells[0], 11);
  EXPECT_EQ(g.cells[1], 10);
  EXPECT_NEAR(g.upper()[0], 1.1, 1e-12);
}

// Node positions, the cell of a point (floor, also outside the grid) and containment with its
// faces included.
TEST(Grid, PositionsCellsAndContainment) {
  const Grid<2> g(Vec<2>(10.0, -5.0), Vec<2>(4.0, 2.0), 0.25);
  EXPECT_EQ(g.node_position(Index<2>{4, 2}), Vec<2>(11.0, -4.5));
  EXPECT_EQ(g.cell_of(Vec<2>(11.1, -4.4)), (Index<2>{4, 2}));
  EXPECT_EQ(g.cell_of(Vec<2>(9.9, -5.1)), (Index<2>{-1, -1})); // below the origin: negative
  EXPECT_TRUE(g.contains(Vec<2>(10.0, -5.0)));
  EXPECT_TRUE(g.contains(g.upper()));
  EXPECT_FALSE(g.contains(Vec<2>(14.0 + 1e-9, -4.0)));
  EXPECT_FALSE(g.contains(Vec<2>(std::nan(""), -4.0))); // NaN is never inside
}
