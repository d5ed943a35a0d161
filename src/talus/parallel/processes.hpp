// This process's place among a run's processes (MPI, the mpi preset): rank 0 of 1 in a build
// without MPI, or when MPI is not initialized.
#pragma once

#include <functional>
#include <string>

namespace talus {

int process_rank();
int process_count();

// Runs f on rank 0 only; a RunFolderError or OutputError it throws is thrown on every process
// (so that none waits for a process that gave up).
void on_rank_zero(const std::function<void()>& f);

} // namespace talus
