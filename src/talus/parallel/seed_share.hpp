// A new case seeded on several processes, each process its own slab alone (docs/architecture.md,
// "Processes"): no process holds the whole case's particles. Every process walks the whole
// case's seeds twice (a count per column, then the seeds of its slab and a margin), which costs
// time of the order of one process's set-up but memory of the slab only. The ids, the bodies'
// masses, the pore pool's order, the interface marks and every error and warning are those of
// one process (setup/seeding.hpp).
#pragma once

#include "talus/output/checkpoint.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/setup/seeding.hpp"

#include <mpi.h>
#include <string>
#include <vector>

namespace talus {

template <int D>
struct SharedSeeding {
  Seeded<D> seeded;                    // this process's own particles
  std::vector<std::int64_t> bounds;    // the slabs (slab_bounds), cut as `start` says
  std::vector<std::size_t> body_begin; // the whole case's body ranges of the ids
};

// Collective. Throws CaseError (an empty body, overlapping bodies) and DecompositionError (a grid
// too narrow for the processes) on every process alike.
template <int D>
SharedSeeding<D> seed_share(const Case& c, MPI_Comm comm, SlabStart start = SlabStart::by_count);

// A checkpoint restored on several processes, each process reading its slab alone: the slabs
// are cut from the checkpoint's particles per column (`start`) as Distributed's constructor cuts
// them from the whole state, so that the run continues as it would from the whole state.
struct RestoredShare {
  std::vector<std::int64_t> bounds;
  std::vector<std::uint32_t> rows; // this process's own particles' rows: their global indices
};
// Sets `ar` to keep this process's slab (LoadArchive::set_choose); `out` is filled as the
// particles are read, with `ghost` columns of ghosts each side (ghost_columns). Reading then
// throws DecompositionError (a grid too narrow for the processes) on every process alike.
template <int D>
void choose_slab(LoadArchive& ar, const Grid<D>& G, int ghost, MPI_Comm comm, RestoredShare& out,
                 SlabStart start = SlabStart::by_count);

// The message of the process with the least key, on every process (keys differ between
// processes; a process with nothing to say gives no_key); empty if none has one. Collective.
inline constexpr std::uint64_t no_key = ~std::uint64_t{0};
std::string first_message(MPI_Comm comm, std::uint64_t key, std::string message);

} // namespace talus
