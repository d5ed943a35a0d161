// Simulation<D>: the state of a run and its explicit time step (docs/architecture.md).
// Each body has its own velocity field (multi-velocity-field contact, paper section 2.3). What
// is fixed for the run is in setup_ (setup/setup.hpp); the phases of step() live in solver/, a file
// per equation group (particle_order, field_boxes, p2g, grid_update, contact_pass, g2p,
// stress_update, interface_history, orphans, time_step, particle_check).
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/grid.hpp"
#include "talus/core/nodes.hpp"
#include "talus/core/particles.hpp"
#include "talus/core/pore_pool.hpp"
#include "talus/core/shape.hpp"
#include "talus/setup/seeding.hpp"
#include "talus/setup/setup.hpp"
#include "talus/solver/contact_record.hpp"
#include "talus/solver/exchange.hpp"
#include "talus/solver/step_scratch.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus {

// A run that went bad: names the step, time, body, particle, position and field.
class SimulationError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Wall time spent in each phase of the step, for the benchmark.
struct PhaseTimes {
  double p2g = 0, grid = 0, contact = 0, g2p = 0, stress = 0, other = 0;
};

template <int D>
class ParticleStore;

// What a contact pass corrects (Simulation::apply_contact): the step's momentum, v^{n+1}
// (recorded: forces, work, slip rates); a velocity a strain alone is taken from (USF's v^n and
// MUSL's re-map), where the pairs' friction and impenetrability act but not their bonds, whose
// capacity the momentum pass spends (docs/formulation.md, "Contact and the strain's velocity");
// or XPIC's start-of-step field, which the particles carry.
enum class ContactPass { momentum, strain, carried };

template <int D>
class Simulation {
public:
  explicit Simulation(const Case& c);
  // From seeded particles: the whole case's, or on several processes one process's own slab
  // (which parallel/distributed.hpp then steps).
  Simulation(const Case& c, Seeded<D> seeded);

  // Advances one step of at most dt_limit (so output times and the end time are hit exactly).
  // Throws SimulationError naming the step, time and first particle that went bad (a non-finite
  // position, velocity or stress, a particle off the grid, det F <= 0).
  void step(double dt_limit = inf);

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  double last_dt() const { return dt_; }
  // The last step's stable step (CFL or fixed), before an output time shortened it.
  double last_stable_dt() const { return stable_dt_; }
  // The case as given: for the output writers (names, probes, output options), not the phases.
  const Case& case_() const { return case_data_; }
  const Setup<D>& setup() const { return setup_; }
  const Grid<D>& grid() const { return grid_; }
  const Particles<D>& particles() const { return particles_; }
  const std::vector<BodyField<D>>& fields() const { return fields_; }
  const PhaseTimes& phase_times() const { return phase_times_; }
  int num_bodies() const { return particles_.num_bodies(); }

  // The contact pass's record (solver/contact_record.hpp): per pair and interface the totals of
  // the last step and their time means since reset_force_means(), and per body the work of the
  // contact and interface forces since release (negative when they brake).
  const ContactRecord<D>& contact_record() const { return record_; }
  void reset_force_means() { record_.reset_means(); }
  // The contact force at every node where contact corrected a body (every process's on rank 0).
  std::vector<ContactNodeForce<D>> contact_nodes() const {
    return gathered_nodes_ ? *gathered_nodes_ : record_.nodes();
  }
  // The stresses' work on body b since release, integral of sigma : D dV dt (J; per unit
  // thickness in 2D). The rest of the budget is read from the particles: solver/diagnostics.hpp.
  double internal_work(int b) const { return internal_work_[b]; }
  // Whether particle p counts in this process's sums: on one process every particle does.
  bool is_own(std::size_t p) const { return !exchange_ || exchange_->is_own(p); }
  // Particle p's index on one process (as errors name it, on any number of processes).
  std::size_t one_process_index(std::size_t p) const {
    return exchange_ ? exchange_->global_index(p) : p;
  }
  Exchange* exchange() const { return exchange_; }
  // The elastic energy at release (or at the start, without settling).
  double strain_energy_at_release(int b) const { return strain_energy0_[b]; }

  // An interface particle's excess pore pressure (Pa): its interface's, plus its band's
  // thermal-pressurization rise; 0 off an interface.
  double interface_pore_pressure(std::size_t p) const;
  // An interface particle's effective share, 1 - r^p = max(1 - p / sigma_n, 0) (1 where it has
  // no normal stress yet), sigma_n its total normal stress over its recent steps (the pore
  // pool's, a mean with weight normal_stress_weight on each step's, 0 where its nodes do not
  // touch; set by update_interface_history). A node's frictional heat goes to its particles'
  // bands in proportion to N_I A^p (1 - r^p): by sigma'^p itself, which is noisy from particle to
  // particle, a node's whole heat would go to the one band with a small weight where the
  // others carry none.
  double effective_share(std::size_t p) const {
    const double sigma_n = pore_.at(particles_.pore[p]).normal_stress();
    return sigma_n > 0.0 ? std::max(1.0 - interface_pore_pressure(p) / sigma_n, 0.0) : 1.0;
  }
  // The weight of each step's normal stress in an interface particle's recent mean: the contact's
  // normal impulse at a node flickers from step to step, and its mean over about ten steps does
  // not.
  static constexpr double normal_stress_weight = 0.1;

  // The pore pool (core/pore_pool.hpp): per interface particle with pore pressure
  // (Particles::pore), the band-mean temperature and pore pressure rises (zero without a band),
  // its total compressive normal stress (the running mean above), then the profiles across its
  // band if it has one.
  const PorePool& pore_pool() const { return pore_; }

  // What the set-up noticed but did not refuse (e.g. an interface whose bodies do not touch).
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Settling (initial_state.settle_time): damped, interfaces held. release() ends it: time
  // restarts at 0 and displacements are measured from the current positions.
  void set_settling(bool on) { settling_ = on; }
  bool settling() const { return settling_; }
  void release();
  // The elastic energy the budget counts from (strain_energy_at_release): the particles' now,
  // summed over every process's own particles (collective on several processes).
  void set_energy_baseline();

  // The stable time step of the current state (CFL) or the fixed one.
  double compute_time_step() const;
  // The whole case's particle count (on several processes too).
  std::size_t case_particles() const { return index_of_id_.size(); }
  // The whole case's particles of body b.
  std::size_t body_particles(int b) const { return body_count_[b]; }
  // The whole case's body ranges of one process's particle order (from the counts).
  std::vector<std::size_t> case_body_begin() const;
  // Current index of the particle with stable id `id`.
  std::size_t index_of(std::uint32_t id) const { return index_of_id_[id]; }

  // A checkpoint's reading and writing of the state (output/simulation_archive.hpp), and the
  // share's door on several processes (solver/particle_store.hpp).
  template <class Ar, int E>
  friend void serialize_state(Ar& ar, Simulation<E>& sim, const std::string& source);
  friend class ParticleStore<D>;

  // Initial conditions that a case file cannot express (tests set a velocity field here).
  Particles<D>& particles_mut() {
    invalidate_shape();     // the caller may move particles
    check_.checked = false; // and the next step checks them all
    drop_held_fields();     // and fixed bodies
    return particles_;
  }

  // Whether body b's field is held from an earlier step instead of scattered (a fixed body).
  bool fixed_field_cached(int b) const { return field_held_[b] != 0; }

  // The phases of step() (docs/architecture.md), public so the tests can run each on its own.
  // Each one's definition starts with what it reads and what it writes.
  void sort_particles_by_cell();
  void bin_particles_by_slab();
  void fit_body_fields();
  void map_particles_to_nodes(bool with_forces);
  void map_forces_to_nodes();
  void scatter_hydrostatic_load(BodyField<D>& N, const ShapeWeights<D>& sw, std::uint32_t p);
  void compute_node_velocities();
  // The interfaces' cohesive and tensile capacities and excess pore pressure's force, shared over
  // the nodes where each pair meets: the bond and the push (effective stress) of the contact pass.
  void share_interface_loads();
  // Interface f's slave body, as the contact pass decides it (detail::is_slave): the deformable
  // one against a rigid body, else the lighter (ties: the earlier).
  int interface_slave(int f) const;
  void integrate_node_forces(double dt);
  void hold_hydrostatic_load();
  void apply_velocity_conditions(std::vector<Vec<D>> BodyField<D>::*velocity);
  // Contact on one velocity array of every body field (v, v_new, v_remap or xpic_w); the
  // momentum pass keeps its forces, work, contact nodes and the interfaces' slip rates.
  void apply_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt, ContactPass pass);
  // Its two parts: node by node (contact_pass.cpp), and at surface points for the pairs of
  // law = "surface" (surface_contact.cpp), after it.
  void apply_node_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt, ContactPass pass);
  void apply_surface_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                             ContactPass pass);
  // The deformable bodies' surface points of law = "surface", from the particles' first
  // positions (constructor).
  void build_surface_points();
  // A node three or more deformable bodies share, resolved pair by pair with resolve_node
  // (contact.node_law = "pairs"); in the momentum pass each body's work is its whole change's.
  void resolve_pairwise(ContactNode<D>& node, const std::int64_t* local, const Index<D>& g,
                        std::int64_t r, double dt, std::vector<Vec<D>> BodyField<D>::*velocity,
                        ContactPass pass);
  // The law at one node of contact row r (its bodies' fields at `local`): their friction and
  // bonds, the pore pressure's push, the correction written to `velocity`, and in the momentum
  // pass the forces, work, contact nodes and slip rates.
  void resolve_node(ContactNode<D>& node, const std::int64_t* local, const Index<D>& g,
                    std::int64_t r, double dt, std::vector<Vec<D>> BodyField<D>::*velocity,
                    ContactPass pass);
  // Body b's geometric normal at node g, cached for a body whose geometry stays put; on an edge
  // of its geometry, the normal seen from `from`.
  Vec<D> geometric_normal(int b, const Index<D>& g, const Vec<D>& from);
  // XPIC(m): each deformable field's v* - v_c from v, by m - 1 gathers and scatters.
  void extrapolate_xpic_velocity(double dt);
  // G2P of the velocity and position (eq. 22-23), from v and v_new.
  void update_particles(double dt);
  // MUSL's particle update and momentum re-map in one coloured pass, then the re-mapped velocity.
  void update_particles_and_remap(double dt);
  // F, volume and stress from the velocity gradient of `velocity` (eq. 24-28).
  void update_stress(std::vector<Vec<D>> BodyField<D>::*velocity, double dt);
  // The interface particles' slip, cohesion and friction (eq. 38-39).
  void update_interface_history(double dt);
  void check_particles() const;
  // Re-decides which particles are orphans mapped to another body's field
  // (contact.orphan_fraction).
  void update_orphans();
  // Particles mapped to another body's field (counted from Particles::field).
  std::int64_t orphans() const;

private:
  void begin_step(double dt_limit);
  void end_step();
  double wave_speed(std::int64_t p, double modulus) const;
  // Finite position, velocity and stress, inside [lo, hi]; and the error naming what is not.
  bool particle_ok(std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) const;
  [[noreturn]] void report_bad_particle(std::size_t p) const;
  [[noreturn]] void report_time_step_collapse(double stable, double floor) const;
  // P2G with its options fixed at compile time (see map_particles_to_nodes).
  template <bool with_forces, bool with_contact, bool apic>
  void scatter_particles();
  bool reaches_other_body(int body, const ShapeWeights<D>& sw, int margin) const;
  template <class Model>
  void update_body_stress(int body, std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                          const Model& model);
  // Calls f(p, body) for every particle, slab colour by slab colour, so that no two threads
  // write one node and every node sums its particles in one fixed order (thread-count independent).
  template <class F>
  void scatter(F&& f);

  void invalidate_shape() { shape_.invalidate(); }
  // A fixed body's field (mass, gradient, position, friction and area; velocity zero) is the same
  // every step: held after its first full scatter, until this drops it (its bond capacities are
  // shared out anew every step, share_interface_loads).
  void drop_held_fields() { std::fill(field_held_.begin(), field_held_.end(), 0); }

  Case case_data_; // for the writers (case_()); the phases read setup_
  Grid<D> grid_;
  Particles<D> particles_;
  Setup<D> setup_;
  std::vector<BodyField<D>> fields_; // one per body
  std::vector<char> field_held_;     // per body: its field stands from an earlier step
  NormalCache<D> normal_cache_;
  ScatterPlan plan_;
  static constexpr int orphan_interval = 10; // steps between update_orphans()

  ContactRecord<D> record_;
  std::vector<double> internal_work_, strain_energy0_; // per body, since release
  StressWorkSums work_sums_;
  Exchange* exchange_ = nullptr; // the other processes (solver/exchange.hpp); null on one
  std::optional<std::vector<ContactNodeForce<D>>> gathered_nodes_;
  ShapeCache<D> shape_; // each particle's weights of this step (solver/step_scratch.hpp)

  double time_ = 0.0;
  double dt_ = 0.0;
  double dt_reference_ = 0.0; // the first stable step: the floor is a fraction of it
  double stable_dt_ = 0.0;    // the last step's, before dt_limit (last_stable_dt)
  std::int64_t steps_ = 0;
  int sort_interval_ = 20;
  StepCheck check_; // the particle check riding on the transfers (solver/step_scratch.hpp)
  bool settling_ = false;
  std::vector<std::uint32_t> index_of_id_;
  // law = "surface" (surface_contact.cpp): the points (id, body, r_0) and the step's constraints.
  struct SurfacePoint {
    std::uint32_t id;
    int body;
    Vec<D> offset;
  };
  struct SurfaceRow {
    int pair = 0;
    double gap = 0.0, inverse_mass = 0.0;
    Vec<D> normal = Vec<D>::Zero();
    std::size_t first = 0, count = 0;
  };
  struct SurfaceNode {
    std::int64_t node;
    double a;
  };
  struct SurfaceAnchor { // a rigid body's particle and its seeded position: the shape's shift
    std::uint32_t id;
    Vec<D> x;
  };
  std::vector<SurfacePoint> surface_points_;
  std::vector<SurfaceAnchor> surface_anchors_; // per surface pair
  std::vector<SurfaceRow> surface_rows_;
  std::vector<SurfaceNode> surface_nodes_;
  std::int64_t surface_step_ = -1;      // the step surface_rows_ were found in
  std::vector<std::size_t> body_count_; // per body: the whole case's particles
  PhaseTimes phase_times_;
  std::vector<std::string> warnings_;
  PorePool pore_; // interface pore pressure and thermal pressurization (pore_pool())
};

} // namespace talus
