// How a run shares the machine's cores: OpenMP's idle threads sleep instead of spinning, and a
// problem gets as many threads as its size pays for (docs/performance.md, "Sharing the cores").
#pragma once

#include <cstddef>

namespace talus {

// Particles per thread below which another thread costs more in synchronisation than it saves.
constexpr std::size_t particles_per_thread = 25000;

// Makes OpenMP's waiting threads sleep at once (OMP_WAIT_POLICY=passive) unless the user chose a
// policy (OMP_WAIT_POLICY or GOMP_SPINCOUNT set). libgomp reads the policy once, when it loads,
// so the program executes itself again with it set; call it first in main(). If that fails the
// program goes on with the default policy. Without OpenMP it does nothing.
void share_cores(char** argv);

// The threads OpenMP would use when the program started: OMP_NUM_THREADS, or the cores it may
// run on.
int available_threads();

// Sets the number of OpenMP threads and returns it: `requested` if positive, otherwise one
// thread per particles_per_thread particles, at least 1 and at most the cores OpenMP may use.
int set_threads(int requested, std::size_t particles);

// OpenMP's thread count for the next parallel region (1 without OpenMP).
int team_size();

} // namespace talus
