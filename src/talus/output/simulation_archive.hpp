// A Simulation's evolving state in a checkpoint (output/checkpoint.hpp's archives): what a
// restored simulation needs to continue bitwise as the saved one would have. The rest is rebuilt
// from the case.
#pragma once

#include "talus/output/checkpoint.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace talus {

// Saves (SaveArchive) or restores (LoadArchive) everything that evolves: the particles, the
// clocks, the last step's forces, work and contact nodes, the pore pool. `source` names the
// checkpoint in errors.
template <class Ar, int D>
void serialize_state(Ar& ar, Simulation<D>& sim, const std::string& source) {
  if constexpr (Ar::loading) {
    // The whole case's body ranges; the particles are all of them, or on several processes
    // this process's slab (LoadArchive::set_choose).
    const std::vector<std::size_t> whole = sim.case_body_begin();
    io_expect(ar, whole, "bodies and particle counts", source);
    if (ar.particles(sim.particles_, whole) != sim.setup().apic)
      throw CheckpointError(source + (sim.setup().apic
                                          ? ": corrupt checkpoint (its case sets simulation.apic, "
                                            "but it holds no affine velocities)"
                                          : ": corrupt checkpoint (affine velocities, but its "
                                            "case does not set simulation.apic)"));
    sim.invalidate_shape();
    sim.check_.checked = false;
    // The map from id to index, from the ids (each once, within the case's).
    std::fill(sim.index_of_id_.begin(), sim.index_of_id_.end(), std::uint32_t(-1));
    for (std::size_t p = 0; p < sim.particles_.size(); ++p) {
      const std::uint32_t id = sim.particles_.id[p];
      if (id >= sim.index_of_id_.size() || sim.index_of_id_[id] != std::uint32_t(-1))
        throw CheckpointError(source + ": corrupt checkpoint (particle ids)");
      sim.index_of_id_[id] = static_cast<std::uint32_t>(p);
    }
  } else {
    // On several processes the whole state's, gathered.
    ar.particles(sim.particles_, sim.setup().apic);
  }
  ar.io(sim.time_), ar.io(sim.dt_), ar.io(sim.dt_reference_), ar.io(sim.steps_),
      ar.io(sim.settling_);
  ar.io(sim.record_.force_), ar.io(sim.record_.interface_force);
  ar.io(sim.record_.impulse_), ar.io(sim.record_.interface_impulse),
      ar.io(sim.record_.impulse_time);
  ar.io(sim.record_.work), ar.io(sim.internal_work_), ar.io(sim.strain_energy0_),
      ar.io(sim.pore_.data);
  // The last step's contact nodes, for a frame written before the next step (the release
  // after a restart from the checkpoint at the end of settling).
  std::vector<double> nodes;
  if constexpr (!Ar::loading) nodes = flatten(sim.contact_nodes());
  ar.io(nodes);
  if (nodes.size() % (3 * D + 4) != 0)
    throw CheckpointError(source + ": corrupt checkpoint (contact nodes)");
  if constexpr (Ar::loading) sim.record_.restore_nodes(unflatten<D>(nodes));
  sim.drop_held_fields(); // rescattered from the restored particles: the same sums
}

} // namespace talus
