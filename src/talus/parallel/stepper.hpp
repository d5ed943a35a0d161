// Stepper<D>: a run's state and step on one process or on several (MPI), behind one interface.
// The run loop (run/run.cpp) and the benchmark speak to it alone; make_stepper is the one place
// that knows whether the program was built with MPI and how many processes run it.
#pragma once

#include "talus/output/checkpoint.hpp"
#include "talus/output/particle_order.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace talus {

// What the share between processes cost so far (this process's counts), for the benchmark.
struct ShareCounters {
  int processes = 1;
  double ghost_particles = 0.0;
  double ghost_bytes = 0.0;     // sent since the start
  double migration_bytes = 0.0; // sent since the start
  std::int64_t rebuilds = 0;    // steps after which the share was merged anew
  std::int64_t rebalances = 0;
};

template <int D>
class Stepper {
public:
  virtual ~Stepper() = default;

  // The state: the whole case's on one process, this process's share (own and ghost particles)
  // on several. Output reads it through the collectives below.
  virtual Simulation<D>& sim() = 0;
  const Simulation<D>& sim() const { return const_cast<Stepper*>(this)->sim(); }

  // A restart: `ar` will read only this process's slab of the checkpoint's particles (one
  // process: all of them). Call before reading the state.
  virtual void read_own_slab(LoadArchive& ar) { (void)ar; }
  // From here on each process steps its own slab (once; nothing on one process). A restart calls
  // it as soon as the particles and clocks are read.
  virtual void distribute() {}

  // One step of at most dt_limit; a SimulationError on any process is thrown on every one.
  virtual void step(double dt_limit) = 0;
  // The end of settling (Simulation::release).
  virtual void release() = 0;
  // Simulation::check_particles on every process: the first process's failure everywhere.
  virtual void check_particles() = 0;

  // The particles in one process's order, gathered to rank 0 for frames.
  virtual ParticleOrder& particle_order() = 0;
  // Every process's contact nodes on rank 0 (none elsewhere). Collective.
  virtual std::vector<ContactNodeForce<D>> contact_nodes() = 0;
  // A checkpoint: `ar` gathers the particles in one process's order; f() runs on every process
  // while rank 0's sim holds the tables a checkpoint saves besides the particles. Collective.
  virtual void order_checkpoint(SaveArchive& ar) { (void)ar; }
  virtual void with_whole_tables(const std::function<void()>& f) { f(); }

  // The share's costs (nullopt on one process).
  virtual std::optional<ShareCounters> share_counters() const { return std::nullopt; }
};

// The stepping of case c on this program's processes: one process seeds the whole case; under
// mpirun each process seeds its own slab (parallel/seed_share.hpp) and is stepped by
// Distributed<D>. `restoring`: the particles will be read from a checkpoint (read_own_slab).
template <int D>
std::unique_ptr<Stepper<D>> make_stepper(const Case& c, bool restoring = false);

} // namespace talus
