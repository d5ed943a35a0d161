// The door through which several processes (parallel/distributed.hpp) reach into a Simulation:
// the exchange its collective points call, and this process's share of the particles (its own
// and its ghosts, in one process's order) swapped in and out around each step. Distributed alone
// uses it; a Simulation on one process never needs it.
#pragma once

#include "talus/solver/simulation.hpp"

#include <optional>
#include <utility>
#include <vector>

namespace talus {

template <int D>
class ParticleStore {
public:
  explicit ParticleStore(Simulation<D>& sim) : sim_(sim) {}

  void set_exchange(Exchange* exchange) { sim_.exchange_ = exchange; }
  // Swaps in a new share. `fields_stand`: it holds the same particles of every held (fixed) body
  // as before, so their held fields stand.
  void replace_particles(Particles<D>&& share, bool fields_stand) {
    sim_.particles_ = std::move(share);
    sim_.invalidate_shape();
    if (!fields_stand) sim_.drop_held_fields();
    for (std::size_t p = 0; p < sim_.particles_.size(); ++p)
      sim_.index_of_id_[sim_.particles_.id[p]] = static_cast<std::uint32_t>(p);
  }
  // The share to refresh in place: the same particles in the same slots, with new values.
  Particles<D>& share_in_place() {
    sim_.invalidate_shape();
    return sim_.particles_;
  }
  Particles<D> take_particles() {
    sim_.invalidate_shape();
    return std::move(sim_.particles_);
  }
  // Every process's contact nodes, gathered on rank 0 for output (nullopt: this process's own).
  void set_gathered_contact_nodes(std::optional<std::vector<ContactNodeForce<D>>> nodes) {
    sim_.gathered_nodes_ = std::move(nodes);
  }
  // Drops a restored state's contact nodes (on the processes other than rank 0, which alone
  // keeps them for the first frame).
  void drop_contact_nodes() { sim_.record_.restore_nodes({}); }
  // Each process holds the whole pore pool; migration and ghosts bring its particles' entries.
  std::vector<double>& pore_state() { return sim_.pore_.data; }
  int sort_interval() const { return sim_.sort_interval_; }

private:
  Simulation<D>& sim_;
};

} // namespace talus
