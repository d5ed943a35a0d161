// The test programs' main: idle OpenMP threads sleep (talus::share_cores), so that tests run
// side by side (ctest -j) do not spin against each other; then one thread by default, since a
// test's problem is small: with sleeping threads a parallel region's wake-up costs more than its
// work (the 2D interface sweep: 231 s on 2 threads, 8.8 s on 1). Tests of the threaded paths set
// their thread counts themselves (omp_set_num_threads), and results do not depend on it.
#include "talus/core/threads.hpp"

#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif

int main(int argc, char** argv) {
  talus::share_cores(argv);
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
