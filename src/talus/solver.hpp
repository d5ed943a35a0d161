// Simulation<D>: the state of a run and its explicit time step (ARCHITECTURE.md, "One time step").
// Each body has its own velocity field (multi-velocity-field contact, paper section 2.3).
#pragma once

#include "talus/boundary.hpp"
#include "talus/case/case.hpp"
#include "talus/contact.hpp"
#include "talus/grid.hpp"
#include "talus/nodes.hpp"
#include "talus/output/checkpoint.hpp"
#include "talus/particles.hpp"
#include "talus/shape.hpp"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus {

// A run that went bad: names the step, time, body, particle, position and field.
class SimulationError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Total forces of an interface pair in one step (N, per unit thickness in 2D): the cohesive and
// frictional parts of the tangential resistance and the normal force (paper Figure 5a).
struct InterfaceForce {
  double cohesive = 0, frictional = 0, normal = 0;
};

// The contact force on one body at one node in the last step (output.contact_nodes).
template <int D>
struct ContactNodeForce {
  Vec<D> position = Vec<D>::Zero();    // the node
  int body = 0, other = 0;             // the corrected body, and the heaviest other body there
  Vec<D> force = Vec<D>::Zero();       // m (v_after - v_before) / dt on `body`
  Vec<D> normal = Vec<D>::Zero();      // outward from `body`
  double frictional = 0, cohesive = 0; // tangential resistance used (N)
};

// Wall time spent in each phase of the step, for the benchmark.
struct PhaseTimes {
  double p2g = 0, grid = 0, contact = 0, g2p = 0, stress = 0, other = 0;
};

template <int D>
class Simulation {
public:
  explicit Simulation(const Case& c);

  // Advances one step of at most dt_limit (so output times and the end time are hit exactly).
  // Throws SimulationError naming the step, time and first particle that went bad (a non-finite
  // position, velocity or stress, a particle off the grid, det F <= 0).
  void step(double dt_limit = inf);

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  double last_dt() const { return dt_; }
  const Case& case_() const { return case_data_; }
  const Grid<D>& grid() const { return grid_; }
  const Particles<D>& particles() const { return particles_; }
  const std::vector<BodyField<D>>& fields() const { return fields_; }
  const std::vector<Material>& body_materials() const { return body_material_; }
  const PhaseTimes& phase_times() const { return phase_times_; }
  // Contact force on body a from body b in the last step: contact_force(a, b).
  const Vec<D>& contact_force(int a, int b) const { return contact_force_[a * num_bodies() + b]; }
  int num_bodies() const { return particles_.num_bodies(); }
  const std::vector<InterfaceForce>& interface_forces() const { return interface_force_; }
  // Time means of the contact and interface forces since the last reset_force_means() (the last
  // step's forces if no time has passed): what the run folder's CSVs record per row.
  Vec<D> mean_contact_force(int a, int b) const {
    return impulse_time_ > 0 ? Vec<D>(contact_impulse_[a * num_bodies() + b] / impulse_time_)
                             : contact_force(a, b);
  }
  InterfaceForce mean_interface_force(std::size_t f) const {
    if (impulse_time_ <= 0) return interface_force_[f];
    const InterfaceForce& I = interface_impulse_[f];
    return {I.cohesive / impulse_time_, I.frictional / impulse_time_, I.normal / impulse_time_};
  }
  void reset_force_means();

  // The last step's contact force at every node where contact corrected a body, in node order
  // (recorded only when the case's output.contact_nodes is on).
  std::vector<ContactNodeForce<D>> contact_nodes() const;

  // Energy budget of body b since release (or the start, without settling), J (per unit thickness
  // in 2D): the work of gravity, of the contact and interface forces (the kinetic energy they add
  // at the nodes; negative when they brake), of the stresses (integral of sigma : D dV dt, the
  // elastic energy stored plus the plastic work) and the elastic energy held now. With the kinetic
  // energy, what does not balance is the scheme's own dissipation and the work of the grid
  // conditions.
  double gravity_work(int b) const;
  double contact_work(int b) const { return contact_work_[b]; }
  double internal_work(int b) const { return internal_work_[b]; }
  double strain_energy(int b) const;
  // The elastic energy at release (or at the start, without settling).
  double strain_energy_at_release(int b) const { return strain_energy0_[b]; }

  // What the set-up noticed but did not refuse (e.g. an interface whose bodies do not touch).
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Settling (initial_state.settle_time): damped, interfaces held. release() ends it: time
  // restarts at 0 and displacements are measured from the current positions.
  void set_settling(bool on) { settling_ = on; }
  bool settling() const { return settling_; }
  void release();

  // The stable time step of the current state (CFL) or the fixed one.
  double compute_time_step() const;
  // Current index of the particle with stable id `id`.
  std::size_t index_of(std::uint32_t id) const { return index_of_id_[id]; }
  // Stable ids of the case's probes: the particle of the probe's body nearest its point now.
  std::vector<std::uint32_t> probe_ids() const;
  // Index of the particle nearest `point` in body b (for probes).
  std::size_t nearest_particle(int body, const Vec<D>& point) const;

  // Saves or restores everything that evolves (particles, clocks, last step's forces): a restored
  // simulation continues bitwise as the saved one would have. The rest is rebuilt from the case.
  template <class Ar>
  void serialize(Ar& ar, const std::string& source) {
    io_expect(ar, particles_.body_begin, "bodies and particle counts", source);
    particles_.for_each_array([&](auto& a) {
      ar.io(a);
      if (a.size() != particles_.size())
        throw CheckpointError(source + ": corrupt checkpoint (particle array length)");
    });
    ar.io(time_), ar.io(dt_), ar.io(dt_reference_), ar.io(steps_), ar.io(settling_);
    ar.io(index_of_id_), ar.io(contact_force_), ar.io(interface_force_);
    ar.io(contact_impulse_), ar.io(interface_impulse_), ar.io(impulse_time_);
    ar.io(contact_work_), ar.io(internal_work_), ar.io(strain_energy0_);
    std::fill(fixed_field_ready_.begin(), fixed_field_ready_.end(), 0); // rescatter: same sums
  }

  // Initial conditions that a case file cannot express (tests set a velocity field here).
  Particles<D>& particles_mut() {
    shape_step_ = -1;           // the caller may move particles
    particles_checked_ = false; // and the next step checks them all
    std::fill(fixed_field_ready_.begin(), fixed_field_ready_.end(), 0); // and fixed bodies
    return particles_;
  }

  // Whether body b's field is held from an earlier step instead of scattered (a fixed body).
  bool fixed_field_cached(int b) const { return fixed_field_ready_[b] != 0; }

  // The phases of step(), public so the tests can check each transfer on its own.
  void sort_particles_by_cell();
  void bin_particles_by_slab();
  void fit_body_fields();
  void map_particles_to_nodes(bool with_forces);
  void map_forces_to_nodes();
  // MUSL's particle velocity update, move and momentum re-map in one coloured pass.
  void update_velocities_and_remap(double dt);
  void compute_node_velocities(double dt);
  // Contact on one velocity array of every body field (v, v_new or v_remap).
  void apply_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt, bool record);
  // What one G2P pass does: blend the particle velocity, move the particle, and/or update F,
  // volume and stress from the velocity gradient of the field `strain_rate`.
  struct Gather {
    bool velocity = false;
    bool move = false;
    std::vector<Vec<D>> BodyField<D>::*strain_rate = nullptr;
  };
  void map_nodes_to_particles(double dt, const Gather& what);
  void check_particles() const;
  // Re-decides which particles are orphans mapped to another body's field
  // (contact.orphan_fraction).
  void update_orphans();
  // Particles mapped to another body's field (counted from Particles::field).
  std::int64_t orphans() const;

private:
  double wave_speed(std::int64_t p, double modulus) const;
  // Finite position, velocity and stress, inside [lo, hi]; and the error naming what is not.
  bool particle_ok(std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) const;
  // Position and velocity finite, the particle inside [lo, hi] (checked in the passes that move).
  bool motion_ok(std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) const {
    const auto& P = particles_;
    return P.x[p].allFinite() && P.v[p].allFinite() && (P.x[p].array() >= lo.array()).all() &&
           (P.x[p].array() <= hi.array()).all();
  }
  [[noreturn]] void report_bad_particle(std::size_t p) const;
  // P2G with its options fixed at compile time (see map_particles_to_nodes).
  template <bool with_forces, bool with_contact>
  void scatter_particles();
  bool reaches_other_body(int body, const ShapeWeights<D>& sw, int margin) const;
  // One body's G2P with the gather's options fixed at compile time (model == nullptr: no stress).
  template <class Model, bool velocity, bool move>
  void map_nodes_to_body(int body, double dt, const Gather& what, const Model* model);
  void gather_slip(std::size_t p, const BodyField<D>& N, const ShapeWeights<D>& sw, double dt);
  [[noreturn]] void report_time_step_collapse(double stable, double floor) const;
  // The transfers after the step's first P2G read its shape weights: they must be current.
  void assert_shape_current() const {
    if (shape_step_ != steps_ || shape_.size() != particles_.size())
      throw std::logic_error("a transfer ran before the P2G that evaluates its shape weights");
  }
  void impose_rigid_velocity(std::vector<Vec<D>> BodyField<D>::*velocity);
  // Calls f(p, body) for every particle, slab colour by slab colour, so that no two threads
  // write one node and every node sums its particles in one fixed order (thread-count independent).
  template <class F>
  void scatter(F&& f);

  Case case_data_;
  Grid<D> grid_;
  Particles<D> particles_;
  std::vector<BodyField<D>> fields_;    // one per body
  std::vector<Material> body_material_; // per body
  std::vector<GimpFactors> body_gimp_;  // GIMP shape factors per body (its half-width lp in them)
  std::vector<Vec<D>> rigid_velocity_;  // per body (used if rigid)
  // A fixed body (rigid, velocity zero) never moves, so its field (mass, mass gradient, position,
  // bond capacities; momentum zero) is the same every step: it is scattered once, in full, and
  // then neither refitted, cleared nor scattered again (docs/performance.md). Per body.
  std::vector<char> fixed_field_ready_;
  bool fixed(int b) const { return case_data_.bodies[b].rigid && rigid_velocity_[b].isZero(); }
  std::vector<double> pair_friction_; // B x B
  std::vector<double> body_mass_;     // total mass per body: the master of a contact pair
  std::vector<double> body_density_;  // material density per body: nodal volume shares
  // Per body with geometric_normal: its surface normal at every grid node, filled as contact
  // first meets the node (NaN: not yet); unused for rigid bodies that move.
  std::vector<std::vector<Vec<D>>> normal_cache_;
  GridConditions<D> conditions_;
  ContactLaw contact_law_;
  Vec<D> gravity_ = Vec<D>::Zero();

  // Slab binning for the coloured scatter: particles of slab s and body b are
  // bin_index_[bin_offset_[s * B + b] .. bin_offset_[s * B + b + 1]) (none for a held fixed body).
  int slab_width_ = 4;
  std::int64_t num_slabs_ = 1;
  std::vector<std::uint32_t> bin_index_;
  std::vector<std::size_t> bin_offset_;
  std::vector<std::uint32_t> particle_bin_;
  std::vector<double> box_bounds_;           // fit_body_fields' per-body particle bounds
  static constexpr int orphan_interval = 10; // steps between update_orphans()

  // Body `body`'s slot for interface f in its field's interface arrays.
  int interface_slot(int body, int f) const {
    return interface_slot_[body * static_cast<int>(case_data_.interfaces.size()) + f];
  }

  std::vector<Vec<D>> contact_force_;   // B x B, last step
  std::vector<Vec<D>> contact_impulse_; // B x B, since reset_force_means()
  std::vector<InterfaceForce> interface_impulse_;
  double impulse_time_ = 0.0;
  std::vector<int> pair_interface_;             // B x B: interface index or -1
  std::vector<int> interface_slot_;             // B x F: the interface's slot in the body's field
  std::vector<InterfaceForce> interface_force_; // per interface, last step
  std::vector<InterfaceForce> interface_rows_;  // per grid row x interface
  std::vector<Vec<D>> contact_rows_;            // per grid row x B x B, summed in row order
  std::vector<double> contact_work_rows_;       // per grid row x B
  std::vector<std::vector<ContactNodeForce<D>>> contact_node_rows_;   // per grid row
  std::vector<double> contact_work_, internal_work_, strain_energy0_; // per body, since release
  static constexpr std::int64_t work_chunk = 1024; // particles per chunk of the stress work sum
  std::vector<double> chunk_work_;
  // Each particle's shape weights at its position at the start of the step, evaluated by the
  // step's first P2G and read by every later transfer of the step. The particles move in the
  // last transfer (USF, USL) or in MUSL's velocity/re-map pass, whose stress pass then reads
  // the start-of-step weights on purpose; step() invalidates them at its end.
  std::vector<ShapeWeights<D>> shape_;
  std::int64_t shape_step_ = -1; // the step whose positions shape_ holds

  double time_ = 0.0;
  double dt_ = 0.0;
  double dt_reference_ = 0.0; // the first stable step: the floor is a fraction of it
  std::int64_t steps_ = 0;
  int sort_interval_ = 20;
  // The particle check rides on the transfers: the pass that moves a particle checks its position
  // and velocity, the stress pass its stress, and the least bad index is kept here; the step's
  // end reports it (step, time and particle), before output or a checkpoint can read the state.
  // A state the transfers did not make (the case's, a checkpoint's, a test's) is checked whole
  // at the next step's start.
  static constexpr std::size_t no_particle = std::numeric_limits<std::size_t>::max();
  std::size_t bad_particle_ = no_particle;
  bool particles_checked_ = false;
  bool settling_ = false;
  std::vector<std::uint32_t> index_of_id_;
  PhaseTimes phase_times_;
  std::vector<std::string> warnings_;
};

} // namespace talus
