// The process's resident memory, for the benchmark and the memory estimate's test (Linux /proc).
#pragma once

#include <fstream>
#include <limits>
#include <string>
#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace talus {

// The resident set now and its peak (bytes; the peak since reset_peak_rss()).
struct Rss {
  double now = 0.0, peak = 0.0;
};

inline Rss read_rss() {
  Rss r;
  std::ifstream in("/proc/self/status");
  std::string key;
  double kb;
  while (in >> key) {
    if (key == "VmRSS:" && in >> kb) r.now = kb * 1024.0;
    if (key == "VmHWM:" && in >> kb) r.peak = kb * 1024.0;
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  if (r.peak == 0.0) { // no /proc: the lifetime peak
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    r.peak = static_cast<double>(u.ru_maxrss) * 1024.0;
  }
  return r;
}

// Restarts the peak at the current resident set (Linux: "5" to clear_refs), after handing the
// freed heap back to the system (glibc's malloc_trim), so that the next peak is the next work's.
inline void reset_peak_rss() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
  std::ofstream("/proc/self/clear_refs") << "5";
}

} // namespace talus
