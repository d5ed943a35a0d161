// Helpers of Distributed<D> (distributed.cpp, distributed_whole.cpp): bytes gathered on rank 0.
#pragma once

#include <cstdint>
#include <functional>
#include <mpi.h>
#include <vector>

namespace talus {

// Every process's bytes on rank 0, handed to `take` one process at a time in process order
// (rank 0's own first), so that rank 0 never holds them all at once; sent in messages of at most
// 1 GiB (MPI counts are int: one message of a large state would overflow them). Collective.
void gather_in_pieces(MPI_Comm comm, const std::vector<char>& mine,
                      const std::function<void(const std::vector<char>&)>& take);

} // namespace talus
