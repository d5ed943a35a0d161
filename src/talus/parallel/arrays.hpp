// Helpers of Distributed<D> (distributed.cpp, distributed_whole.cpp): particle arrays in a new
// order, and bytes gathered on rank 0.
#pragma once

#include <cstdint>
#include <functional>
#include <mpi.h>
#include <vector>

namespace talus {

// Copies a[order[i]] into a new array, for every i.
template <class T>
void reorder(std::vector<T>& a, const std::vector<std::uint32_t>& order) {
  std::vector<T> out(order.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    out[i] = a[order[i]];
  a.swap(out);
}

// Every process's bytes on rank 0, handed to `take` one process at a time in process order
// (rank 0's own first), so that rank 0 never holds them all at once; sent in messages of at most
// 1 GiB (MPI counts are int: one message of a large state would overflow them). Collective.
void gather_in_pieces(MPI_Comm comm, const std::vector<char>& mine,
                      const std::function<void(const std::vector<char>&)>& take);

} // namespace talus
