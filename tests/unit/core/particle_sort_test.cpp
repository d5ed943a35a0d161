// The sort by cell (core/particle_sort.hpp): a stable order by cell index within each body, and
// the in-place permutation that applies it to every per-particle array.
#include "talus/core/particle_sort.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace talus;

// Within each body the cells never decrease along the new order, equal cells keep their old
// order, and no particle crosses into another body's range.
TEST(ParticleSort, OrdersByCellStablyWithinEachBody) {
  const Grid<2> grid(Vec<2>::Zero(), Vec<2>(4.0, 4.0), 1.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  std::vector<Vec<2>> x(200);
  for (auto& xi : x)
    xi = Vec<2>(std::floor(u(rng)) + 0.5, std::floor(u(rng)) + 0.5); // many share a cell
  const std::vector<std::size_t> body_begin{0, 70, 70, 200};         // an empty body too
  const std::vector<std::uint32_t> order = order_by_cell(grid, x, body_begin);
  auto key = [&](std::uint32_t i) { return grid.cell_index(grid.cell_of(x[i])); };
  for (std::size_t b = 0; b + 1 < body_begin.size(); ++b)
    for (std::size_t i = body_begin[b]; i < body_begin[b + 1]; ++i) {
      EXPECT_GE(order[i], body_begin[b]);
      EXPECT_LT(order[i], body_begin[b + 1]);
      if (i > body_begin[b]) {
        EXPECT_LE(key(order[i - 1]), key(order[i]));
        if (key(order[i - 1]) == key(order[i])) {
          EXPECT_LT(order[i - 1], order[i]); // stable
        }
      }
    }
}

// permute(a, order) is a[i] <- a[order[i]] for random permutations (cycles of every length,
// fixed points included).
TEST(ParticleSort, PermuteAppliesTheOrderInPlace) {
  std::mt19937 rng(3);
  for (const std::size_t n : {0u, 1u, 2u, 17u, 1000u}) {
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<double> a(n);
    for (std::size_t i = 0; i < n; ++i)
      a[i] = 10.0 * static_cast<double>(i) + 0.5;
    const std::vector<double> before = a;
    std::vector<char> done;
    permute(a, order, done);
    for (std::size_t i = 0; i < n; ++i)
      EXPECT_EQ(a[i], before[order[i]]) << "n " << n << ", i " << i;
  }
}

// apply_order moves every per-particle array together: each particle keeps its own id, position
// and mass after the sort.
TEST(ParticleSort, ApplyOrderMovesEveryArrayTogether) {
  Particles<2> P;
  const std::size_t n = 50;
  P.body_begin = {0, n};
  P.for_each_array([&](auto& a) { a.resize(n); });
  for (std::size_t p = 0; p < n; ++p) {
    P.id[p] = static_cast<std::uint32_t>(p);
    P.x[p] = Vec<2>(static_cast<double>((p * 37) % n) * 0.07, 0.5);
    P.m[p] = 1.0 + static_cast<double>(p);
  }
  const Grid<2> grid(Vec<2>::Zero(), Vec<2>(4.0, 1.0), 0.25);
  const std::vector<std::uint32_t> order = order_by_cell(grid, P.x, P.body_begin);
  const Particles<2> before = P;
  apply_order(P, order);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = P.id[i];
    EXPECT_EQ(id, order[i]);
    EXPECT_EQ(P.x[i], before.x[id]);
    EXPECT_EQ(P.m[i], before.m[id]);
  }
}
