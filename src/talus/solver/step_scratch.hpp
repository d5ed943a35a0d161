// What the step's passes keep for each other and from step to step besides the run's state:
// rebuilt from the state, so a checkpoint does not hold it.
#pragma once

#include "talus/core/math.hpp"
#include "talus/core/shape.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
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

// The shape-weight cache: each particle's weights at its position at the start of the step,
// evaluated by the step's first P2G and read by every later transfer of the step (also by the
// stress pass after the particles moved: it uses the start-of-step weights on purpose). Whatever
// moves or reorders particles outside a step calls invalidate().
template <int D>
struct ShapeCache {
  std::vector<ShapeWeights<D>> weights;
  std::int64_t step = -1; // the step whose positions `weights` holds

  void invalidate() { step = -1; }
  // Throws unless the weights are step `steps`'s for `n` particles.
  void require(std::int64_t steps, std::size_t n) const {
    if (step != steps || weights.size() != n)
      throw std::logic_error("a transfer ran before the P2G that evaluates its shape weights");
  }
  const ShapeWeights<D>& operator[](std::size_t p) const { return weights[p]; }
  std::size_t size() const { return weights.size(); }
};

// The particle check rides on the transfers: the pass that moves a particle checks its position
// and velocity, the stress pass its stress, and the least bad index is kept here; the step's end
// reports it (step, time and particle), before output or a checkpoint can read the state. A state
// the transfers did not make (the case's, a checkpoint's, a test's) is checked whole at the next
// step's start (checked false).
struct StepCheck {
  static constexpr std::size_t no_particle = std::numeric_limits<std::size_t>::max();
  std::size_t bad_particle = no_particle;
  std::string pending_failure; // a failure found mid-step (det F <= 0), thrown at its end
  bool checked = false;
};

} // namespace talus
