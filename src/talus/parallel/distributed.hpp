// Distributed<D>: one process's part of a run on several (MPI) processes, with results bitwise
// those of one process (docs/architecture.md, "Processes").
//
// The grid is cut into slabs of cell columns along x (decomposition.hpp); a process owns the
// particles whose cell lies in its slab. Before each step it receives ghost copies of the other
// processes' particles within ghost_width() columns of its slab, and steps its own and its
// ghost particles together, in one process's particle order (the global index, which the sort
// every sort_interval steps reassigns as one process's sort would). Every node an own particle
// reads is then summed from the same particles in the same order as on one process, so the own
// particles' new state is one process's; ghosts are dropped after the step and the own particles
// that left the slab migrate. Nothing is added across processes except through Exchange, whose
// sums have one contributor per entry.
#pragma once

#include "talus/output/particle_order.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/solver/exchange.hpp"
#include "talus/solver/particle_store.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <mpi.h>
#include <optional>
#include <string>
#include <vector>

namespace talus {

template <int D>
class Distributed final : public Exchange, public ParticleOrder {
public:
  using Start = SlabStart;
  // `sim` holds the whole state (a new case's, or a checkpoint's): this process keeps its slab.
  // Slabs are rebalanced from the particle counts every `rebalance_interval` steps (0: never).
  // Throws DecompositionError if the grid is too narrow for the processes.
  Distributed(Simulation<D>& sim, MPI_Comm comm, std::int64_t rebalance_interval = 200,
              Start start = Start::by_count);
  // `sim` holds this process's own particles in one process's order, `bounds` their slabs and
  // `body_begin` the whole state's body ranges: a new case's particles seeded on their slab
  // alone (seed_share.hpp), whose ids are their global indices; or, given `restored_rows`, a
  // checkpoint's slab (choose_slab), whose rows in the checkpoint are.
  Distributed(Simulation<D>& sim, MPI_Comm comm, std::vector<std::int64_t> bounds,
              std::vector<std::size_t> body_begin, std::int64_t rebalance_interval = 200,
              std::optional<std::vector<std::uint32_t>> restored_rows = std::nullopt);
  Distributed(const Distributed&) = delete;
  Distributed& operator=(const Distributed&) = delete;
  ~Distributed() override { store_.set_exchange(nullptr); }

  // One step on every process (collective). A step that fails on any process throws its
  // SimulationError, named with the process, on every process; any other error stops them all.
  void step(double dt_limit = inf);
  // The end of settling (Simulation::release, collective: the elastic energy at release is
  // summed over every process's own particles).
  void release();
  // Calls f(sim) on rank 0 with the whole state in sim (one process's particle order, the
  // contact nodes of every process); the other processes wait. Collective. Holds the whole
  // state on rank 0: for the tests' state hash; a run's output streams instead (gather).
  template <class F>
  void with_whole_state(F&& f) {
    gather_to_root();
    if (rank_ == 0) f(sim_);
    restore_share();
  }

  // Every process's contact nodes (Simulation::contact_nodes) on rank 0, in node-plane order;
  // none elsewhere. Collective.
  std::vector<ContactNodeForce<D>> gather_contact_nodes();
  // Calls f() on every process while rank 0's sim holds, whole, the state a checkpoint saves
  // besides the particles (every process's contact nodes, the pore pool's entries of every
  // particle); the particles are gathered by the save itself (SaveArchive::set_order). Collective.
  template <class F>
  void with_whole_tables(F&& f) {
    gather_tables();
    f();
    if (rank_ == 0) store_.set_gathered_contact_nodes(std::nullopt);
  }
  // Simulation::check_particles on every process: the first process's failure, everywhere.
  void check_particles();
  // One process's body ranges of the global index (the whole state's).
  const std::vector<std::size_t>& body_begin() const { return body_begin_; }

  // ParticleOrder (output/particle_order.hpp): the own particles' values, to rank 0.
  std::size_t total() const override { return body_begin_.back(); }
  bool receives() const override { return rank_ == 0; }
  using ParticleOrder::gather;
  void gather(std::size_t width, const Fill& fill, const Take& take, const Spans& spans) override;
  void reduce_max(const Spans& spans, const std::function<void(std::size_t p)>& f,
                  std::vector<double>& largest) override;

  int rank() const { return rank_; }
  int size() const { return size_; }
  MPI_Comm comm() const { return comm_; }
  const std::vector<std::int64_t>& bounds() const { return bounds_; }
  int ghost_width() const { return ghost_width_; }
  std::int64_t rebalances() const { return rebalances_; }
  std::size_t own_particles() const { return own_count_; }
  // Whether particle p of the share in sim is this process's own (not a ghost copy).
  bool is_own(std::size_t p) const override { return share_own_[p] != 0; }
  std::size_t global_index(std::size_t p) const override { return share_index_[p]; }
  std::size_t ghost_particles() const { return ghosts_; }
  // Steps after which the share was merged anew (a particle crossed a widened slab's edge),
  // instead of having only its ghosts' values refreshed in place.
  std::int64_t rebuilds() const { return rebuilds_; }
  // Bytes this process sent since construction: ghost copies, and migrating particles.
  double ghost_bytes_sent() const { return ghost_bytes_; }
  double migration_bytes_sent() const { return migration_bytes_; }

  // Exchange (exchange.hpp).
  double max(double local) override;
  void min_max(double* lo, double* hi, int n) override;
  bool owns_plane(std::int64_t i) const override;
  void plane_reach(std::int64_t& lo, std::int64_t& hi) const override;
  void sum_disjoint(double* data, std::size_t n) override;
  void sum_exact(ExactSum* sums, std::size_t n) override;
  void sum_integers(std::int64_t* data, std::size_t n) override;
  void agree_on_failure(std::string failure) override;
  void chunk_sums(int b, std::size_t begin, std::size_t end, const double* value,
                  std::int64_t chunk, std::vector<double>& sums) override;

private:
  void init(); // what both constructors set first
  // The column that decides ownership (decomposition.hpp).
  std::int64_t owner_column(const Vec<D>& x) const;
  // The column of the particle's cell, for the ghosts' reach.
  std::int64_t column(const Vec<D>& x) const;
  void rebalance();
  void sort_own();
  void build_share();   // the share from own_ and the ghosts the others send
  void collect_own();   // own_ from the share
  void migrate();       // own_ particles whose owner column left the slab (after a rebalance)
  void refresh_share(); // after a step: the ghosts' new values, and ownership
  void send_ghosts(Particles<D>& P, const std::vector<std::uint32_t>& rows,
                   const std::vector<std::uint32_t>& index);
  void merge_share(Particles<D>& own, const std::vector<std::uint32_t>& rows,
                   const std::vector<std::uint32_t>& index);
  void set_ownership(const Particles<D>& share);
  void gather_to_root();
  void restore_share();
  void gather_tables(); // with_whole_tables' gather
  // Appends particle p of P (global index g) to buf; unpack appends the record at buf[pos] to P.
  void pack(Particles<D>& P, std::size_t p, std::uint32_t g, std::vector<char>& buf);
  std::size_t unpack(const std::vector<char>& buf, std::size_t pos, Particles<D>& P,
                     std::vector<std::uint32_t>& index);
  // Writes the record at buf[pos] to P's slot g, its global index (P sized to hold it).
  std::size_t unpack_in_place(const std::vector<char>& buf, std::size_t pos, Particles<D>& P);
  // Sends buffers[q] to process q, returns what every process sent here (concatenated).
  const std::vector<char>& all_to_all(const std::vector<std::vector<char>>& buffers, double& sent);
  // body_begin of particles sorted by global index.
  std::vector<std::size_t> body_begin_of(const std::vector<std::uint32_t>& index) const;
  [[noreturn]] void abort_run(const std::exception& e) const;
  // f(array) for every array a particle's record carries: Particles::arrays(), and APIC's C
  // where the case runs APIC (an optional array, empty otherwise).
  template <class Fn>
  void each_array(Particles<D>& P, Fn&& f) const {
    P.for_each_array(f);
    if (affine_) f(P.C);
  }
  // f(a's array, b's array) for each of those arrays.
  template <class Fn>
  void each_array_pair(Particles<D>& a, Particles<D>& b, Fn&& f) const {
    Particles<D>::for_each_array_pair(a, b, f);
    if (affine_) f(a.C, b.C);
  }

  Simulation<D>& sim_;
  ParticleStore<D> store_{sim_}; // the share's door into sim_ (solver/particle_store.hpp)
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  std::int64_t rebalance_interval_;
  std::vector<std::int64_t> bounds_; // slab bounds in cell columns (size_ + 1)
  int ghost_width_ = 0;              // columns of ghosts beyond the slab, each side
  std::int64_t cells_per_column_ = 1;
  std::vector<std::size_t> body_begin_; // one process's body ranges of the global index

  Particles<D> own_;                       // this process's particles, by global index
  std::vector<std::uint32_t> own_index_;   // their global indices
  std::vector<std::uint32_t> share_index_; // the share's (own and ghosts) global indices
  std::vector<char> share_own_;            // 1: own, 0: ghost
  // Reused from step to step, so that their arrays keep their capacity (no page faults): the
  // last share, the ghosts received, the byte buffers.
  Particles<D> spare_, ghost_;
  std::vector<std::uint32_t> ghost_index_;
  std::vector<std::vector<char>> outgoing_;
  std::vector<std::uint32_t> rows_, index_, ghost_slots_, g_order_;
  std::vector<Vec<D>> before_;
  std::vector<char> send_buf_, recv_buf_;
  Particles<D> parked_share_; // the share, parked while the whole state is in sim
  bool fields_stand_ = true;  // the next share holds the same fixed-body particles as the last
  std::vector<std::uint32_t> pool_size_; // per pore-pool offset: its entry's length (0: none)
  std::size_t record_bytes_ = 0;
  bool affine_ = false; // the particles carry APIC's C (simulation.apic)
  std::size_t ghosts_ = 0, own_count_ = 0;
  std::int64_t rebuilds_ = 0;
  std::int64_t rebalances_ = 0;
  double ghost_bytes_ = 0, migration_bytes_ = 0;
};

} // namespace talus
