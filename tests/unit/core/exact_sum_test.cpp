// ExactSum (core/exact_sum.hpp): the exact sum rounded once, whatever the order and the split.
#include "talus/core/exact_sum.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <gtest/gtest.h>
#include <random>
#include <vector>

namespace talus {
namespace {

double exact_sum(const std::vector<double>& xs) {
  ExactSum s;
  for (const double x : xs)
    s += x;
  return s.value();
}

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

TEST(ExactSum, CancellationLeavesTheSmallTerm) {
  std::vector<double> xs = {1e16, 1.0, -1e16};
  std::sort(xs.begin(), xs.end());
  do
    EXPECT_EQ(exact_sum(xs), 1.0);
  while (std::next_permutation(xs.begin(), xs.end()));
  EXPECT_EQ(exact_sum({1e300, 1e-300, -1e300}), 1e-300);
}

// Ten times the double 0.1 is 1 + 5.55e-17 exactly, which rounds to 1 (a running sum gives
// 0.9999999999999999).
TEST(ExactSum, RoundsOnceToNearest) {
  EXPECT_EQ(exact_sum(std::vector<double>(10, 0.1)), 1.0);
  const double big = std::ldexp(1.0, 53);
  EXPECT_EQ(exact_sum({big, 1.0}), big);                             // a tie: to even
  EXPECT_EQ(exact_sum({big, 3.0}), big + 4.0);                       // a tie: to even
  EXPECT_EQ(exact_sum({big, 1.0, std::ldexp(1.0, -40)}), big + 2.0); // past the tie: up
  EXPECT_EQ(exact_sum({-big, -1.0, -std::ldexp(1.0, -40)}), -big - 2.0);
  EXPECT_EQ(exact_sum({big, 1.0, -std::ldexp(1.0, -40)}), big); // short of the tie: down
}

// Integers times powers of two whose exact sum fits an __int128, compared with its conversion
// (correctly rounded), in shuffled orders and split into parts combined as processes combine them.
TEST(ExactSum, MatchesExactIntegerSumsInAnyOrderAndSplit) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 300);
    std::vector<double> xs;
    __int128 exact = 0;
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::int64_t>(rng() >> 11) * (rng() % 2 ? 1 : -1); // < 2^53
      const int e = static_cast<int>(rng() % 61) - 30;                              // 2^-30..2^30
      xs.push_back(std::ldexp(static_cast<double>(k), e));
      exact += static_cast<__int128>(k) << (e + 30);
    }
    const double want = std::ldexp(static_cast<double>(exact), -30);
    ASSERT_EQ(bits(exact_sum(xs)), bits(want)) << "trial " << trial;
    std::shuffle(xs.begin(), xs.end(), rng);
    ASSERT_EQ(bits(exact_sum(xs)), bits(want));
    // Three parts: one added with +=, one through the words as an integer MPI sum adds them.
    ExactSum a, b, c;
    for (int i = 0; i < n; ++i)
      (i % 3 == 0 ? a : i % 3 == 1 ? b : c) += xs[static_cast<std::size_t>(i)];
    a += b;
    a.normalize(), c.normalize();
    for (int w = 0; w < ExactSum::words; ++w)
      a.data()[w] += c.data()[w];
    a.normalize();
    ASSERT_EQ(bits(a.value()), bits(want));
  }
}

TEST(ExactSum, SubnormalsAndTheLargestDoubles) {
  const double tiny = std::ldexp(1.0, -1074);
  EXPECT_EQ(exact_sum({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(exact_sum({DBL_MIN, -tiny}), DBL_MIN - tiny);
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX, -DBL_MAX}), DBL_MAX); // past DBL_MAX on the way
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX}), INFINITY);
  EXPECT_EQ(exact_sum({-DBL_MAX, -DBL_MAX}), -INFINITY);
  EXPECT_EQ(bits(exact_sum({})), bits(0.0));
  EXPECT_EQ(bits(exact_sum({2.5, -2.5})), bits(0.0));
}

TEST(ExactSum, InfinitiesAndNaN) {
  EXPECT_EQ(exact_sum({1.0, INFINITY}), INFINITY);
  EXPECT_EQ(exact_sum({-INFINITY, 1.0}), -INFINITY);
  EXPECT_TRUE(std::isnan(exact_sum({INFINITY, -INFINITY})));
  EXPECT_TRUE(std::isnan(exact_sum({1.0, NAN})));
}

// Carrying (normalize) anywhere between terms leaves the sum as it is.
TEST(ExactSum, CarryingAnywhereKeepsTheSum) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  ExactSum plain, carried;
  for (int i = 0; i < 10000; ++i) {
    const double x = u(rng) * std::ldexp(1.0, static_cast<int>(rng() % 200) - 100);
    plain += x, carried += x;
    if (rng() % 7 == 0) carried.normalize();
  }
  EXPECT_EQ(bits(plain.value()), bits(carried.value()));
}

} // namespace
} // namespace talus
