#include "talus/core/threads.hpp"

#include <algorithm>
#include <cstdlib>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {

#ifdef _OPENMP
namespace {
const int threads_at_start = omp_get_max_threads(); // before anyone sets the number
} // namespace
#endif

int team_size() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

int available_threads() {
#ifdef _OPENMP
  return threads_at_start;
#else
  return 1;
#endif
}

void share_cores(char** argv) {
#ifdef _OPENMP
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  // The program's own path, not /proc/self/exe, so that ps and pgrep still name it talus.
  char self[4096] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  execv(n > 0 ? self : "/proc/self/exe", argv); // returns only on failure: carry on as we are
#else
  (void)argv; // without OpenMP no thread waits: the program need not start again
#endif
}

int set_threads(int requested, std::size_t particles) {
#ifdef _OPENMP
  const int cores = available_threads();
  const int by_size = static_cast<int>(std::min<std::size_t>(
      static_cast<std::size_t>(cores), std::max<std::size_t>(1, particles / particles_per_thread)));
  const int threads = requested > 0 ? requested : by_size;
  omp_set_num_threads(threads);
  return threads;
#else
  (void)requested, (void)particles;
  return 1;
#endif
}

} // namespace talus
