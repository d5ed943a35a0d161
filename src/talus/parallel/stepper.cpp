#include "talus/parallel/stepper.hpp"

#include "talus/parallel/processes.hpp"

#include <stdexcept>
#ifdef TALUS_MPI
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/distributed.hpp"
#include "talus/parallel/seed_share.hpp"
#endif

namespace talus {

namespace {

// One process: the whole case in one Simulation, stepped as it is.
template <int D>
class LocalStepper final : public Stepper<D> {
public:
  explicit LocalStepper(const Case& c) : sim_(c), order_(0) {}
  Simulation<D>& sim() override { return sim_; }
  void step(double dt_limit) override { sim_.step(dt_limit); }
  void release() override { sim_.release(); }
  void check_particles() override { sim_.check_particles(); }
  ParticleOrder& particle_order() override {
    order_ = LocalOrder(sim_.particles().size());
    return order_;
  }
  std::vector<ContactNodeForce<D>> contact_nodes() override { return sim_.contact_nodes(); }

private:
  Simulation<D> sim_;
  LocalOrder order_;
};

#ifdef TALUS_MPI
// Several processes: each seeds its own slab (or reads its slab of a checkpoint) and, once
// distributed, steps it with Distributed<D> (docs/architecture.md, "Processes").
template <int D>
class SharedStepper final : public Stepper<D> {
public:
  SharedStepper(const Case& c, bool restoring) : sim_(seed(c, restoring)) {}
  Simulation<D>& sim() override { return sim_; }

  void read_own_slab(LoadArchive& ar) override {
    restored_.emplace();
    const Setup<D>& s = sim_.setup();
    choose_slab<D>(ar, sim_.grid(), ghost_columns(s.normal_smoothing, s.xpic), MPI_COMM_WORLD,
                   *restored_);
  }
  void distribute() override {
    if (dist_) return;
    if (restored_) {
      dist_ =
          std::make_unique<Distributed<D>>(sim_, MPI_COMM_WORLD, std::move(restored_->bounds),
                                           sim_.case_body_begin(), 200, std::move(restored_->rows));
      restored_.reset();
    } else {
      dist_ = std::make_unique<Distributed<D>>(sim_, MPI_COMM_WORLD, std::move(seeded_bounds_),
                                               std::move(seeded_body_begin_));
    }
  }

  void step(double dt_limit) override { dist().step(dt_limit); }
  void release() override { dist().release(); }
  void check_particles() override { dist().check_particles(); }
  ParticleOrder& particle_order() override { return dist(); }
  std::vector<ContactNodeForce<D>> contact_nodes() override {
    return dist().gather_contact_nodes();
  }
  void order_checkpoint(SaveArchive& ar) override { ar.set_order(&dist(), dist().body_begin()); }
  void with_whole_tables(const std::function<void()>& f) override { dist().with_whole_tables(f); }

  std::optional<ShareCounters> share_counters() const override {
    if (!dist_) return std::nullopt;
    return ShareCounters{dist_->size(),
                         static_cast<double>(dist_->ghost_particles()),
                         dist_->ghost_bytes_sent(),
                         dist_->migration_bytes_sent(),
                         dist_->rebuilds(),
                         dist_->rebalances()};
  }

private:
  // This process's slab of a new case; a restart replaces its particles with the checkpoint's.
  Simulation<D> seed(const Case& c, bool restoring) {
    SharedSeeding<D> s = seed_share<D>(c, MPI_COMM_WORLD);
    if (!restoring)
      seeded_bounds_ = std::move(s.bounds), seeded_body_begin_ = std::move(s.body_begin);
    return Simulation<D>(c, std::move(s.seeded));
  }
  Distributed<D>& dist() {
    if (!dist_) throw std::logic_error("SharedStepper: stepped before distribute()");
    return *dist_;
  }

  std::vector<std::int64_t> seeded_bounds_;    // a new case's first slabs (seed_share)
  std::vector<std::size_t> seeded_body_begin_; // and its body ranges of the ids
  std::optional<RestoredShare> restored_;      // a restart's slab of the checkpoint
  Simulation<D> sim_;
  std::unique_ptr<Distributed<D>> dist_;
};
#endif

} // namespace

template <int D>
std::unique_ptr<Stepper<D>> make_stepper(const Case& c, bool restoring) {
#ifdef TALUS_MPI
  if (process_count() > 1) return std::make_unique<SharedStepper<D>>(c, restoring);
#endif
  (void)restoring;
  return std::make_unique<LocalStepper<D>>(c);
}

template std::unique_ptr<Stepper<2>> make_stepper<2>(const Case&, bool);
template std::unique_ptr<Stepper<3>> make_stepper<3>(const Case&, bool);

} // namespace talus
