// Shape functions: partition of unity, gradients summing to zero, and exact reproduction of a
// linear field and its gradient, for linear and GIMP kernels in 2D and 3D.
#include "talus/shape.hpp"

#include <gtest/gtest.h>
#include <random>

namespace talus {
namespace {

template <class T>
class ShapeTest : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(ShapeTest, Dims);

template <int D>
Grid<D> test_grid() {
  Vec<D> origin = Vec<D>::Constant(-1.0), extent = Vec<D>::Constant(4.0);
  return Grid<D>(origin, extent, 0.5);
}

TYPED_TEST(ShapeTest, PartitionOfUnityAndLinearReproduction) {
  constexpr int D = TypeParam::value;
  const Grid<D> grid = test_grid<D>();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4, 2.4); // away from the grid's edge
  const Vec<D> a = Vec<D>::LinSpaced(0.3, 1.7);        // linear field f(x) = c + a.x
  const double c = 0.25;
  for (ShapeKind kind : {ShapeKind::linear, ShapeKind::gimp}) {
    for (double lp : {0.125, 0.25 / 3.0, 0.0625}) {
      for (int trial = 0; trial < 200; ++trial) {
        Vec<D> x;
        for (int d = 0; d < D; ++d)
          x[d] = u(rng);
        const ShapeWeights<D> sw = evaluate_shape(grid, kind, lp, x);
        double sum = 0.0, f = 0.0;
        Vec<D> grad_sum = Vec<D>::Zero(), grad_f = Vec<D>::Zero();
        Mat<D> x_grad = Mat<D>::Zero(); // sum x_I (grad N_I)^T = identity
        for_each_node(grid, sw, [&](std::int64_t I, double N, const Vec<D>& g) {
          const Vec<D> xI = grid.node_position(grid.node_coords(I));
          sum += N;
          grad_sum += g;
          f += N * (c + a.dot(xI));
          grad_f += (c + a.dot(xI)) * g;
          x_grad += xI * g.transpose();
        });
        EXPECT_NEAR(sum, 1.0, 1e-13);
        EXPECT_LT(grad_sum.norm(), 1e-12);
        EXPECT_NEAR(f, c + a.dot(x), 1e-12);
        EXPECT_LT((grad_f - a).norm(), 1e-11);
        EXPECT_LT((x_grad - Mat<D>::Identity()).norm(), 1e-12);
      }
    }
  }
}

TEST(Gimp1D, MatchesTheClosedFormPieces) {
  const double h = 1.0, lp = 0.25;
  double w, dw;
  gimp_1d(0.0, h, lp, w, dw); // centred on the node: 1 - lp/(2h)
  EXPECT_DOUBLE_EQ(w, 1.0 - lp / (2.0 * h));
  EXPECT_DOUBLE_EQ(dw, 0.0);
  gimp_1d(0.5, h, lp, w, dw); // linear region
  EXPECT_DOUBLE_EQ(w, 0.5);
  EXPECT_DOUBLE_EQ(dw, -1.0 / h);
  gimp_1d(h + lp, h, lp, w, dw); // edge of the support
  EXPECT_DOUBLE_EQ(w, 0.0);
  gimp_1d(-1.0, h, lp, w, dw); // tail: (h + lp - |r|)^2 / (4 h lp)
  EXPECT_DOUBLE_EQ(w, lp * lp / (4.0 * h * lp));
  EXPECT_DOUBLE_EQ(dw, lp / (2.0 * h * lp));
}

TYPED_TEST(ShapeTest, NodesOutsideTheGridGetNoWeight) {
  constexpr int D = TypeParam::value;
  const Grid<D> grid = test_grid<D>();
  const Vec<D> x = grid.origin + Vec<D>::Constant(0.05);
  const ShapeWeights<D> sw = evaluate_shape(grid, ShapeKind::gimp, 0.125, x);
  double sum = 0.0;
  for_each_node(grid, sw, [&](std::int64_t I, double N, const Vec<D>&) {
    EXPECT_GE(I, 0);
    EXPECT_LT(I, grid.num_nodes());
    sum += N;
  });
  EXPECT_LE(sum, 1.0 + 1e-14);
}

} // namespace
} // namespace talus
