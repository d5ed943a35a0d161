// This process's place among a run's processes (MPI, the mpi preset): rank 0 of 1 in a build
// without MPI, or when MPI is not initialized.
#pragma once

#include "talus/case/parse.hpp"

#include <algorithm>
#include <functional>
#include <string>

namespace talus {

int process_rank();
int process_count();
// How many of the run's processes share this machine (and its memory). Collective on its first
// call, which the program makes right after starting MPI.
int processes_on_this_node();
// The part of a whole case's memory that `here` of a run's `processes` hold together on one
// machine: each holds 1/N of the `columns` cell columns along x plus its ghosts (at most
// ghost_columns_each_side on either side); at most 1.
inline double memory_share(int processes, int here, double columns, int ghost_columns_each_side) {
  if (processes <= 1 || columns <= 0.0) return 1.0;
  const double each = 1.0 / processes + 2.0 * ghost_columns_each_side / columns;
  return std::min(1.0, each * here);
}
// The memory budget (case/parse.hpp) of this run's processes on this machine: the machine's
// memory, and memory_share with the widest ghost slab (contact.normal_smoothing at its maximum).
MemoryBudget this_machine_budget();

// The failure (a message; empty: none) of the lowest process that has one, on every process.
// Collective.
std::string first_failure(const std::string& failure);
// Runs f on every process; if it throws E on any (a read or a check that may fail on one
// process alone), every process throws E with the lowest failing process's message, so that
// none goes on into a collective the others never reach. Collective.
template <class E, class F>
void agreed(F&& f) {
  std::string failure;
  try {
    f();
  } catch (const E& e) {
    failure = e.what();
  }
  if (failure = first_failure(failure); !failure.empty()) throw E(failure);
}

// The largest of every process's values, in place, on every process (one process: as they are).
// Collective.
void max_over_processes(double* values, int n);
int max_over_processes(int value);
// The sums of every process's values, in place, on every process. Collective.
void sum_over_processes(double* values, int n);
// Returns when every process has called it. Collective.
void wait_for_processes();

// The program's processes for its lifetime: MPI started (with funnelled threads: OpenMP runs
// inside each process and only the main thread calls MPI) and stopped; nothing without MPI.
class ProcessSession {
public:
  ProcessSession(int* argc, char*** argv);
  ~ProcessSession();
  ProcessSession(const ProcessSession&) = delete;
  ProcessSession& operator=(const ProcessSession&) = delete;
};

// Runs f on rank 0 only; a RunFolderError or OutputError it throws is thrown on every process
// (so that none waits for a process that gave up).
void on_rank_zero(const std::function<void()>& f);

} // namespace talus
