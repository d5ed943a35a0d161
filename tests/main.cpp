// The test programs' main: idle OpenMP threads sleep (talus::share_cores), so that tests run
// side by side (ctest -j) do not spin against each other, then GoogleTest.
#include "talus/core/threads.hpp"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  talus::share_cores(argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
