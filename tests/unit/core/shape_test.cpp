// Shape functions: partition of unity, gradients summing to zero, and exact reproduction of a
// linear field and its gradient, for linear, GIMP and quadratic B-spline kernels in 2D and 3D;
// the B-spline's pieces, its continuity, and its open knots at the grid's faces.
#include "talus/core/shape.hpp"

#include <gtest/gtest.h>
#include <random>
#include <vector>

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
  // Away from the grid's edge (the faces at -1 and 3, cells of 0.5); the B-spline's open knots
  // reach 2.5 cells in from a face (BSplineIsAnOpenSplineAtTheGridsFaces).
  std::uniform_real_distribution<double> u(-0.4, 2.4), u_bspline(0.25, 1.75);
  const Vec<D> a = Vec<D>::LinSpaced(0.3, 1.7); // linear field f(x) = c + a.x
  const double c = 0.25;
  for (ShapeKind kind : {ShapeKind::linear, ShapeKind::gimp, ShapeKind::bspline}) {
    for (double lp : {0.125, 0.25 / 3.0, 0.0625}) {
      for (int trial = 0; trial < 200; ++trial) {
        Vec<D> x;
        for (int d = 0; d < D; ++d)
          x[d] = kind == ShapeKind::bspline ? u_bspline(rng) : u(rng);
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

// The B-spline's three pieces at s = xi - floor(xi - 1/2): at a node (s = 1) 1/8, 3/4, 1/8 with
// slopes -1/2, 0, 1/2 per h; midway between nodes (s = 1/2) 1/2, 1/2, 0.
TEST(BSpline1D, MatchesTheClosedFormPieces) {
  ShapeWeights<1> sw;
  const double h = 0.5, inv_h = 1.0 / h;
  bspline_1d(sw, 0, 4.0, 0, 99, inv_h); // on node 4: base 3
  EXPECT_EQ(sw.base[0], 3);
  EXPECT_DOUBLE_EQ(sw.w[0][0], 0.125);
  EXPECT_DOUBLE_EQ(sw.w[0][1], 0.75);
  EXPECT_DOUBLE_EQ(sw.w[0][2], 0.125);
  EXPECT_DOUBLE_EQ(sw.dw[0][0], -0.5 * inv_h);
  EXPECT_DOUBLE_EQ(sw.dw[0][1], 0.0);
  EXPECT_DOUBLE_EQ(sw.dw[0][2], 0.5 * inv_h);
  bspline_1d(sw, 0, 4.5, 0, 99, inv_h); // midway: base 4
  EXPECT_EQ(sw.base[0], 4);
  EXPECT_DOUBLE_EQ(sw.w[0][0], 0.5);
  EXPECT_DOUBLE_EQ(sw.w[0][1], 0.5);
  EXPECT_DOUBLE_EQ(sw.w[0][2], 0.0);
}

// C1: each node's weight and its slope are continuous where the support shifts by a node
// (xi = k + 1/2), from either side.
TEST(BSpline1D, WeightsAndSlopesAreContinuous) {
  const double eps = 1e-9;
  for (const double at : {3.5, 4.5, 7.5}) {
    ShapeWeights<1> lo, hi;
    bspline_1d(lo, 0, at - eps, 0, 99, 1.0);
    bspline_1d(hi, 0, at + eps, 0, 99, 1.0);
    ASSERT_EQ(hi.base[0], lo.base[0] + 1);
    for (int a = 0; a < 3; ++a) {
      const std::int64_t node = lo.base[0] + a;
      const int b = static_cast<int>(node - hi.base[0]); // the same node in hi's record
      const double w_hi = b >= 0 ? hi.w[0][b] : 0.0, dw_hi = b >= 0 ? hi.dw[0][b] : 0.0;
      EXPECT_NEAR(lo.w[0][a], w_hi, 1e-8) << "node " << node;
      EXPECT_NEAR(lo.dw[0][a], dw_hi, 1e-8) << "node " << node;
    }
  }
}

// The open knot vector of a grid of n cells (n >= 2), in cells from the lower face: triple knots
// on the faces, the cell centres between, less the two nearest each face.
std::vector<double> open_knots(int n) {
  std::vector<double> t{0.0, 0.0, 0.0};
  for (int j = 3; j <= n; ++j)
    t.push_back(j - 1.5);
  t.insert(t.end(), 3, static_cast<double>(n));
  return t;
}

// Node i's B-spline on knots t_i .. t_{i+3} by the Cox-de Boor recursion (0 / 0 = 0): an
// evaluation independent of bspline_1d's.
double cox_de_boor(const std::vector<double>& t, int i, int p, double x, bool last_span) {
  if (p == 0) {
    if (t[i] <= x && x < t[i + 1]) return 1.0;
    // x on the upper face belongs to the last non-empty span
    return last_span && x == t[i + 1] && t[i] < t[i + 1] && x == t.back() ? 1.0 : 0.0;
  }
  double v = 0.0;
  if (t[i + p] > t[i]) v += (x - t[i]) / (t[i + p] - t[i]) * cox_de_boor(t, i, p - 1, x, last_span);
  if (t[i + p + 1] > t[i + 1])
    v +=
        (t[i + p + 1] - x) / (t[i + p + 1] - t[i + 1]) * cox_de_boor(t, i + 1, p - 1, x, last_span);
  return v;
}

// Within 5/2 cells of a face the B-spline is that of the open knot vector: each node's weight is
// the Cox-de Boor recursion's, the weights sum to 1 and their slopes to 0, only the face node has
// weight on the face, linear fields are reproduced through the Greville points (t_{i+1} +
// t_{i+2}) / 2, and the weights and slopes are continuous across every knot, inside the faces'
// spans and where they meet the uniform ones. Grids of 2 to 8 cells, the faces at several
// positions of the numbering (a body's frame starts inside the grid).
TEST(BSpline1D, IsAnOpenSplineAtTheGridsFaces) {
  for (const int n : {2, 3, 4, 5, 8}) {
    const std::vector<double> t = open_knots(n);
    for (const std::int64_t lo : {0, -3}) {
      const std::int64_t hi = lo + n;
      auto weights = [&](double xi) {
        ShapeWeights<1> sw;
        bspline_1d(sw, 0, xi, lo, hi, 1.0);
        return sw;
      };
      for (int step = 0; step <= 40 * n; ++step) {
        const double cells = n * step / (40.0 * n); // from the lower face
        const ShapeWeights<1> sw = weights(static_cast<double>(lo) + cells);
        double sum = 0.0, slope = 0.0, greville = 0.0, greville_slope = 0.0;
        for (int a = 0; a < sw.k[0]; ++a) {
          const int i = static_cast<int>(sw.base[0] - lo) + a; // node from the lower face
          ASSERT_GE(i, 0);
          ASSERT_LE(i, n);
          EXPECT_GE(sw.w[0][a], 0.0);
          EXPECT_NEAR(sw.w[0][a], cox_de_boor(t, i, 2, cells, true), 1e-14)
              << "n " << n << ", node " << i << " at " << cells;
          const double g = 0.5 * (t[i + 1] + t[i + 2]);
          sum += sw.w[0][a], slope += sw.dw[0][a];
          greville += g * sw.w[0][a], greville_slope += g * sw.dw[0][a];
        }
        EXPECT_NEAR(sum, 1.0, 1e-14);
        EXPECT_NEAR(slope, 0.0, 1e-13);
        EXPECT_NEAR(greville, cells, 1e-13);
        EXPECT_NEAR(greville_slope, 1.0, 1e-13);
        if (cells == 0.0 || cells == n) { // on a face: the face node alone
          for (int a = 0; a < sw.k[0]; ++a) {
            const std::int64_t node = sw.base[0] + a;
            EXPECT_EQ(sw.w[0][a], node == (cells == 0.0 ? lo : hi) ? 1.0 : 0.0);
          }
        }
      }
      // Continuity across the knots (and where the uniform spans begin, 5/2 cells in).
      const double eps = 1e-9;
      for (const double knot : {1.5, 2.5, n - 2.5, n - 1.5}) {
        if (knot <= 0.0 || knot >= n) continue;
        const double xi = static_cast<double>(lo) + knot;
        const ShapeWeights<1> below = weights(xi - eps), above = weights(xi + eps);
        auto at = [](const ShapeWeights<1>& sw, std::int64_t node, const double(&v)[3]) {
          const std::int64_t a = node - sw.base[0];
          return a >= 0 && a < sw.k[0] ? v[a] : 0.0;
        };
        for (std::int64_t node = lo; node <= hi; ++node) {
          EXPECT_NEAR(at(below, node, below.w[0]), at(above, node, above.w[0]), 1e-8)
              << "n " << n << ", node " << node << " across " << knot;
          EXPECT_NEAR(at(below, node, below.dw[0]), at(above, node, above.dw[0]), 1e-8)
              << "n " << n << ", node " << node << " across " << knot;
        }
      }
    }
  }
}

// The faces in 2D and 3D: every node inside the grid, a partition of unity with gradients summing
// to zero, and on a face only the nodes on it have weight.
TYPED_TEST(ShapeTest, BSplineKeepsAPartitionOfUnityAtTheGridsFaces) {
  constexpr int D = TypeParam::value;
  const Grid<D> grid = test_grid<D>();
  for (const double offset : {0.0, 0.05, 0.2, 0.2499, 0.7, 1.2}) {
    for (const bool upper : {false, true}) {
      const Vec<D> x = upper ? Vec<D>(grid.origin + Vec<D>::Constant(4.0 - offset))
                             : Vec<D>(grid.origin + Vec<D>::Constant(offset));
      const ShapeWeights<D> sw = evaluate_shape(grid, ShapeKind::bspline, 0.0, x);
      double sum = 0.0;
      Vec<D> grad = Vec<D>::Zero();
      for_each_node(grid, sw, [&](std::int64_t I, double N, const Vec<D>& g) {
        EXPECT_GE(I, 0);
        EXPECT_LT(I, grid.num_nodes());
        sum += N, grad += g;
        if (offset == 0.0 && N != 0.0) { // on the face's corner node only
          EXPECT_EQ(grid.node_position(grid.node_coords(I)), x);
        }
      });
      EXPECT_NEAR(sum, 1.0, 1e-14) << "offset " << offset << (upper ? " upper" : " lower");
      EXPECT_LT(grad.norm(), 1e-12);
    }
  }
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

// GIMP's record keeps a third node in a direction only while the particle's domain straddles a
// node line (its weight is exactly zero otherwise): the walk visits exactly the nodes with
// weight, and its sums are bitwise those of the untrimmed 3 x 3 (x 3) walk, zeros included.
TYPED_TEST(ShapeTest, GimpWalksExactlyTheNodesWithWeight) {
  constexpr int D = TypeParam::value;
  const Grid<D> grid = test_grid<D>();
  const double lp = 0.125; // a quarter of the cell: 2 particles per cell
  const GimpFactors f(grid.h, lp);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.4, 2.4);
  int three = 0, total = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Vec<D> x;
    for (int d = 0; d < D; ++d)
      x[d] = u(rng);
    if (trial == 0) x.setConstant(0.125); // on the edge of the support: exactly 2 per direction
    const ShapeWeights<D> sw = evaluate_shape(grid, ShapeKind::gimp, f, x);
    // The untrimmed record: 3 nodes per direction from floor(xi - 1/2), as evaluate_shape
    // rounds; the trimmed one must hold the same values at the nodes it keeps.
    ShapeWeights<D> full;
    int with_weight = 1;
    for (int d = 0; d < D; ++d) {
      const double xi = (x[d] - grid.origin[d]) * f.inv_h;
      full.base[d] = static_cast<std::int64_t>(std::floor(xi - 0.5));
      full.k[d] = 3;
      int nonzero = 0;
      for (int a = 0; a < 3; ++a) {
        gimp_1d((xi - static_cast<double>(full.base[d] + a)) * grid.h, f, full.w[d][a],
                full.dw[d][a]);
        nonzero += full.w[d][a] != 0.0;
        const std::int64_t kept = full.base[d] + a - sw.base[d];
        if (kept >= 0 && kept < sw.k[d]) {
          EXPECT_EQ(sw.w[d][kept], full.w[d][a]);
          EXPECT_EQ(sw.dw[d][kept], full.dw[d][a]);
        } else {
          EXPECT_EQ(full.w[d][a], 0.0); // only a node with no weight is dropped
          EXPECT_EQ(full.dw[d][a], 0.0);
        }
      }
      with_weight *= nonzero;
      EXPECT_EQ(sw.k[d], nonzero);
      three += sw.k[d] == 3, ++total;
    }
    auto sums = [&](const ShapeWeights<D>& r, int* visited, auto walk) {
      double sum = 0.0;
      Vec<D> grad = Vec<D>::Zero();
      walk(r, [&](std::int64_t I, double N, const Vec<D>& g) {
        if (visited) ++*visited;
        sum += N * static_cast<double>(I);
        grad += g * static_cast<double>(I);
      });
      return std::pair{sum, grad};
    };
    int visited = 0;
    const auto trimmed = sums(
        sw, &visited, [&](const ShapeWeights<D>& r, auto&& fn) { for_each_node(grid, r, fn); });
    const auto untrimmed = sums(full, nullptr, [&](const ShapeWeights<D>& r, auto&& fn) {
      shape_detail::for_each_node_k<3, 3, 3>(grid, r, fn);
    });
    EXPECT_EQ(visited, with_weight) << "trial " << trial;
    EXPECT_EQ(trimmed.first, untrimmed.first) << "trial " << trial;
    EXPECT_TRUE(trimmed.second == untrimmed.second) << "trial " << trial;
    if (trial == 0) {
      for (int d = 0; d < D; ++d)
        EXPECT_EQ(sw.k[d], 2);
    }
  }
  // A domain of half-width h/4 straddles a node line for half of the positions.
  EXPECT_NEAR(static_cast<double>(three) / total, 0.5, 0.06);
}

} // namespace
} // namespace talus
