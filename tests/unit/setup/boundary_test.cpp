// Grid velocity conditions: a Coulomb wall takes a node's velocity into it and up to mu times
// that much of its tangential velocity; a prescribed component applies only to its body.
#include "talus/setup/boundary.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

BodyField<2> small_field() {
  Grid<2> grid(Vec<2>(0, 0), Vec<2>(1.0, 1.0), 0.25);
  BodyField<2> N;
  N.needs = {false, false, false};
  N.fit(grid, Index<2>{0, 0}, Index<2>{5, 5});
  return N;
}

TEST(GridConditions, CoulombWallOnTheFloor) {
  BodyField<2> N = small_field();
  GridConditions<2> gc;
  FrictionWall<2> w;
  w.nodes.lo = {0, 0}, w.nodes.hi = {5, 1}; // the row y = 0
  w.axis = 1, w.outward = -1.0, w.mu = 0.4;
  gc.walls.push_back(w);
  std::vector<Vec<2>> v(N.size(), Vec<2>(1.0, -0.5));
  v[N.box.node_index(Index<2>{2, 0})] = Vec<2>(0.1, -0.5); // slow: friction stops it
  v[N.box.node_index(Index<2>{3, 0})] = Vec<2>(1.0, 0.5);  // leaving the wall: untouched
  apply_grid_conditions<2>(gc, 0, N, v);
  // v_t' = v_t max(0, 1 - mu v_n / |v_t|): 1 - 0.4 * 0.5 / 1 = 0.8.
  EXPECT_EQ(v[N.box.node_index(Index<2>{0, 0})], Vec<2>(0.8, 0.0));
  EXPECT_EQ(v[N.box.node_index(Index<2>{2, 0})], Vec<2>(0.0, 0.0));
  EXPECT_EQ(v[N.box.node_index(Index<2>{3, 0})], Vec<2>(1.0, 0.5));
  EXPECT_EQ(v[N.box.node_index(Index<2>{0, 1})], Vec<2>(1.0, -0.5)); // off the wall
}

TEST(GridConditions, PrescribedComponentForOneBody) {
  BodyField<2> N = small_field();
  GridConditions<2> gc;
  NodeCondition<2> nc;
  nc.nodes.lo = {4, 0}, nc.nodes.hi = {5, 5}; // the column x = 1
  nc.body = 1, nc.component = 0, nc.velocity = -0.2;
  gc.prescribed.push_back(nc);
  std::vector<Vec<2>> v0(N.size(), Vec<2>(1.0, 1.0)), v1 = v0;
  apply_grid_conditions<2>(gc, 0, N, v0);
  apply_grid_conditions<2>(gc, 1, N, v1);
  const std::int64_t edge = N.box.node_index(Index<2>{4, 2}), inside = N.box.node_index({1, 2});
  EXPECT_EQ(v0[edge], Vec<2>(1.0, 1.0)); // another body: untouched
  EXPECT_EQ(v1[edge], Vec<2>(-0.2, 1.0));
  EXPECT_EQ(v1[inside], Vec<2>(1.0, 1.0));
}

} // namespace
} // namespace talus
