#include "talus/core/threads.hpp"

#include <algorithm>
#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <string>

namespace talus {
namespace {

// One thread per particles_per_thread particles, at least one, at most the cores; a request wins.
TEST(SetThreads, ByTheProblemsSizeUnlessRequested) {
#ifndef _OPENMP
  GTEST_SKIP() << "built without OpenMP";
#else
  const int cores = available_threads();
  EXPECT_EQ(set_threads(0, 10), 1);
  EXPECT_EQ(omp_get_max_threads(), 1);
  EXPECT_EQ(set_threads(0, particles_per_thread - 1), 1);
  EXPECT_EQ(set_threads(0, 2 * particles_per_thread), std::min(2, cores));
  EXPECT_EQ(set_threads(0, 1000 * particles_per_thread), cores);
  EXPECT_EQ(set_threads(3, 10), 3);
  EXPECT_EQ(omp_get_max_threads(), 3);
  set_threads(cores, 0);
#endif
}

} // namespace
} // namespace talus
