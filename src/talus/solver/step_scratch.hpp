// What the step's passes keep for each other and from step to step besides the run's state:
// rebuilt from the state, so a checkpoint does not hold it.
#pragma once

#include "talus/core/math.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace talus {

// The coloured scatter's plan: particles of slab s and body b are
// bin_index[bin_offset[s * B + b] .. bin_offset[s * B + b + 1]) (none for a held field); and
// fit_body_fields' per-body particle bounds (of every process's particles, and of this one's).
struct ScatterPlan {
  int slab_width = 4;
  std::int64_t num_slabs = 1;
  std::vector<std::uint32_t> bin_index;
  std::vector<std::size_t> bin_offset;
  std::vector<std::uint32_t> particle_bin;
  std::vector<double> box_bounds, box_bounds_local;
};

// Per body with geometric_normal, per node row along x, per line of nodes along the last axis:
// its surface normal at the line's nodes [first, first + size) (NaN: not yet met), the range the
// contact pass has met (Simulation::geometric_normal). Unused for rigid bodies that move.
template <int D>
struct NormalLine {
  std::int64_t first = 0;
  std::vector<Vec<D>> normals;
};
template <int D>
using NormalCache = std::vector<std::vector<std::vector<NormalLine<D>>>>;

// The stress work's sums (update_stress): per chunk of `chunk` particles in one process's order,
// each summed in index order, so that every thread and process count gives the same bits.
struct StressWorkSums {
  static constexpr std::int64_t chunk = 1024;
  std::vector<double> chunk_work;
  std::vector<double> particle_work, chunk_work_global; // with an exchange
};

} // namespace talus
