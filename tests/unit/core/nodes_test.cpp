// BodyField<D> (core/nodes.hpp): the box a body's field covers, its local node index, the shape
// weights taken on the frame and indexed in the box, and which arrays a run's needs allocate.
#include "talus/core/nodes.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace talus;

// The box of global node range [lo, hi): its size, origin and cell size; local() maps the box's
// nodes row-major (x slowest) and every node outside it to -1.
TEST(BodyField, FitsTheBoxAndIndexesItsNodes) {
  const Grid<3> grid(Vec<3>(-2.0, 0.0, 1.0), Vec<3>(8.0, 6.0, 4.0), 0.5);
  BodyField<3> f;
  const Index<3> lo{3, 2, 1}, hi{7, 5, 6};
  f.fit(grid, lo, hi);
  EXPECT_EQ(f.box.nodes, (Index<3>{4, 3, 5}));
  EXPECT_EQ(f.size(), 4u * 3u * 5u);
  EXPECT_EQ(f.box.h, grid.h);
  EXPECT_EQ(f.box.origin, grid.node_position(lo));
  EXPECT_EQ(f.frame.origin, f.box.origin); // on one process the frame is the box

  std::int64_t expected = 0;
  for (std::int64_t i = lo[0]; i < hi[0]; ++i)
    for (std::int64_t j = lo[1]; j < hi[1]; ++j)
      for (std::int64_t k = lo[2]; k < hi[2]; ++k)
        EXPECT_EQ(f.local(Index<3>{i, j, k}), expected++);
  for (const Index<3>& out : {Index<3>{2, 2, 1}, Index<3>{7, 2, 1}, Index<3>{3, 5, 1},
                              Index<3>{3, 2, 6}, Index<3>{-1, 3, 3}})
    EXPECT_EQ(f.local(out), -1);
}

// An empty range still holds a node per direction (a body whose particles sit on one node line).
TEST(BodyField, AnEmptyRangeKeepsOneNode) {
  const Grid<2> grid(Vec<2>::Zero(), Vec<2>(4.0, 4.0), 1.0);
  BodyField<2> f;
  f.fit(grid, Index<2>{2, 3}, Index<2>{2, 1});
  EXPECT_EQ(f.box.nodes, (Index<2>{1, 1}));
  EXPECT_EQ(f.local(Index<2>{2, 3}), 0);
}

// A refit clears what the last step mapped, and the optional arrays follow the run's needs:
// empty when a need is off, one value per node and interface slot when on.
TEST(BodyField, RefitClearsAndAllocatesOnlyWhatTheRunNeeds) {
  const Grid<2> grid(Vec<2>::Zero(), Vec<2>(10.0, 10.0), 1.0);
  BodyField<2> lean;
  lean.needs = {false, false, false, false, false};
  lean.fit(grid, Index<2>{0, 0}, Index<2>{4, 4});
  EXPECT_EQ(lean.m.size(), 16u);
  for (const std::size_t n :
       {lean.grad_m.size(), lean.mx.size(), lean.v_remap.size(), lean.cohesion.size(),
        lean.area.size(), lean.heat_weight.size(), lean.heat.size()})
    EXPECT_EQ(n, 0u);

  BodyField<2> full;
  full.slots = 2;
  full.needs = {true, true, true, true, true};
  full.fit(grid, Index<2>{0, 0}, Index<2>{4, 4});
  EXPECT_EQ(full.grad_m.size(), 16u);
  EXPECT_EQ(full.v_remap.size(), 16u);
  for (const std::size_t n : {full.cohesion.size(), full.tension.size(), full.slip_weight.size(),
                              full.heat_weight.size(), full.normal_stress.size(), full.heat.size()})
    EXPECT_EQ(n, 32u);

  full.m[5] = 3.0;
  full.p[5] = Vec<2>(1.0, 2.0);
  full.area[7] = 0.5;
  full.heat[9] = 4.0;
  full.fit(grid, Index<2>{1, 1}, Index<2>{5, 5});
  for (std::size_t i = 0; i < full.size(); ++i) {
    EXPECT_EQ(full.m[i], 0.0);
    EXPECT_EQ(full.p[i], Vec<2>::Zero());
  }
  for (std::size_t i = 0; i < full.area.size(); ++i)
    EXPECT_EQ(full.area[i] + full.heat[i], 0.0);
}

// The weights of a point taken on a frame wider than the stored box land on the same global nodes,
// with the same values, as the weights taken on the whole grid: the frame is what keeps one
// process's bits on several processes (a process stores only its part of the frame).
TEST(BodyField, WeightsOnTheFrameLandOnTheSameGlobalNodes) {
  const Grid<2> grid(Vec<2>(-1.0, -1.0), Vec<2>(12.0, 12.0), 0.5);
  for (const ShapeKind kind : {ShapeKind::linear, ShapeKind::gimp}) {
    BodyField<2> f;
    f.fit(grid, Index<2>{2, 3}, Index<2>{20, 22}, Index<2>{6, 7}, Index<2>{14, 15});
    const GimpFactors gf(grid.h, 0.125);
    for (const Vec<2>& x : {Vec<2>(3.13, 4.02), Vec<2>(4.0, 3.5), Vec<2>(2.71, 4.9)}) {
      // global node -> weight, from the whole grid
      std::map<std::int64_t, double> whole;
      for_each_node(grid, evaluate_shape(grid, kind, gf, x),
                    [&](std::int64_t I, double N, const Vec<2>&) { whole[I] += N; });
      ShapeWeights<2> sw;
      f.weights(sw, kind, gf, x);
      std::map<std::int64_t, double> framed;
      double sum = 0.0;
      for_each_node(f.box, sw, [&](std::int64_t I, double N, const Vec<2>&) {
        const Index<2> local = f.box.node_coords(I);
        const Index<2> global{local[0] + f.offset[0], local[1] + f.offset[1]};
        framed[grid.node_index(global)] += N;
        sum += N;
      });
      EXPECT_NEAR(sum, 1.0, 1e-14);
      ASSERT_EQ(framed.size(), whole.size());
      for (const auto& [I, N] : whole)
        EXPECT_NEAR(framed.at(I), N, 1e-14) << "node " << I;
    }
  }
}
