// The machine's memory bandwidth, as a STREAM-style triad a[i] = b[i] + 3 c[i] over three
// 256 MB arrays (2^25 doubles), the best of 10 passes, counted as 24 B per element (the
// write-allocate read of a[] not counted): the roofline docs/performance.md holds the step's
// phases against. Build and run (not part of the CMake build):
//   g++ -O3 -march=native -fopenmp bench/triad.cpp -o /tmp/triad
//   OMP_NUM_THREADS=1 /tmp/triad; OMP_NUM_THREADS=2 /tmp/triad
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <omp.h>
#include <vector>

int main() {
  const std::size_t n = std::size_t{1} << 25;
  std::vector<double> a(n), b(n), c(n);
#pragma omp parallel for // first touch by the threads that will stream them
  for (std::size_t i = 0; i < n; ++i)
    a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  double best = 1e30;
  for (int r = 0; r < 10; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for
    for (std::size_t i = 0; i < n; ++i)
      a[i] = b[i] + 3.0 * c[i];
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("%d threads: triad %.1f GB/s (check %g)\n", omp_get_max_threads(),
              24.0 * n / best / 1e9, a[n / 2]);
}
