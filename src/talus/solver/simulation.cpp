#include "talus/solver/simulation.hpp"

#include "talus/solver/detail.hpp"
#include "talus/solver/diagnostics.hpp"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <utility>

namespace talus {

using detail::timed;

template <int D>
Simulation<D>::Simulation(const Case& c) : Simulation(c, seed_case<D>(c)) {}

template <int D>
Simulation<D>::Simulation(const Case& c, Seeded<D> seeded) : case_data_(c) {
  Vec<D> origin, extent;
  for (int d = 0; d < D; ++d)
    origin[d] = c.grid.origin[d], extent[d] = c.grid.extent[d];
  grid_ = Grid<D>(origin, extent, c.grid.cell_size);
  particles_ = std::move(seeded.particles);
  index_of_id_.resize(seeded.total);
  for (std::size_t p = 0; p < particles_.size(); ++p)
    index_of_id_[particles_.id[p]] = static_cast<std::uint32_t>(p);
  warnings_ = std::move(seeded.warnings);
  body_count_ = std::move(seeded.body_count);
  setup_ = make_setup<D>(c, grid_, seeded.body_mass);
  if (setup_.apic) particles_.C.assign(particles_.size(), Mat<D>::Zero()); // at rest or translating
  const int B = particles_.num_bodies();
  fields_.resize(B);
  for (int b = 0; b < B; ++b) {
    BodyField<D>& N = fields_[b];
    for (int f = 0; f < setup_.num_interfaces; ++f)
      N.slots += setup_.slot(b, f) >= 0;
    N.needs.contact = B > 1;
    N.needs.interfaces = N.slots > 0;
    N.needs.remap = setup_.scheme == Scheme::musl;
    N.needs.xpic = setup_.xpic > 0;
    N.needs.pressure = setup_.pore_pressure;
    N.needs.heating = setup_.heating;
  }
  // A water body below a [water] level beside bodies that level buoys (docs/formulation.md,
  // "A water body below a level").
  bool buoyed = false;
  for (const BodySetup<D>& body : setup_.bodies)
    buoyed = buoyed || body.buoyancy > 0.0;
  for (int b = 0; b < B; ++b)
    fields_[b].needs.hydro = buoyed && setup_.bodies[b].fluid && setup_.water.on;
  // Each interface particle of an interface with pore pressure gets its state, zero rises, in
  // id order over the whole case (a process's particles take their offsets in that pool).
  for (const auto& [id, f] : seeded.pore_particles) {
    const std::size_t at = pore_.add(f, setup_.bands[f] ? setup_.bands[f]->state_size() : 0);
    if (const std::size_t p = index_of_id_[id]; p < particles_.size() && particles_.id[p] == id)
      particles_.pore[p] = static_cast<std::int64_t>(at);
  }
  field_held_.assign(B, 0);
  normal_cache_.resize(B);
  for (int b = 0; b < B; ++b)
    if (setup_.bodies[b].normal_geometry)
      normal_cache_[b].resize(static_cast<std::size_t>(grid_.nodes[0]));
  record_.resize(B, setup_.interfaces.size());
  build_surface_points();
  internal_work_.assign(B, 0.0);
  // Slab width: GIMP writes nodes [cell-1, cell+2], so slabs of 4 cells keep two slabs of one
  // colour at least one slab apart.
  plan_.slab_width = 4;
  plan_.num_slabs = (grid_.cells[0] + plan_.slab_width - 1) / plan_.slab_width;
  plan_.bin_offset.assign(static_cast<std::size_t>(plan_.num_slabs * B + 1), 0);
  // The energy budget counts from the start (the initial stresses' elastic energy is its
  // baseline) until release() restarts it.
  set_energy_baseline();
}

template <int D>
void Simulation<D>::set_energy_baseline() {
  const int B = num_bodies();
  std::vector<ExactSum> gravity(B), strain(B);
  for (int b = 0; b < B; ++b)
    add_energy_terms(*this, b, true, gravity[b], strain[b]);
  if (exchange_) exchange_->sum_exact(strain.data(), strain.size());
  strain_energy0_.resize(B);
  for (int b = 0; b < B; ++b)
    strain_energy0_[b] = strain[b].value();
}

// One explicit step (docs/architecture.md, "One time step"): one phase per line, with the
// scheme's hooks for the stress update (USF first, USL last from v^{n+1}, MUSL last from the
// velocity re-mapped from the updated particles). Each line starts with its phase's timer, a
// temporary that adds the line's wall time to that phase when the line ends.
template <int D>
void Simulation<D>::step(double dt_limit) {
  using F = BodyField<D>;
  auto& T = phase_times_;
  const Scheme scheme = setup_.scheme;
  timed(T.other), begin_step(dt_limit);                        // dt, sort, bins, boxes
  timed(T.p2g), map_particles_to_nodes(scheme != Scheme::usf); // eq. 14-18, 30
  if (scheme != Scheme::usf) timed(T.grid), hold_hydrostatic_load();
  timed(T.contact), share_interface_loads(); // eq. 37, pore pressure
  timed(T.grid), compute_node_velocities(), apply_velocity_conditions(&F::v); // eq. 19
  if (scheme == Scheme::usf) { // stress first, from the velocity of the mapped momentum
    timed(T.contact), apply_contact(&F::v, dt_, ContactPass::strain),
        apply_velocity_conditions(&F::v);
    timed(T.stress), update_stress(&F::v, dt_); // eq. 24-28
    timed(T.p2g), map_forces_to_nodes();        // eq. 17-18
    timed(T.grid), hold_hydrostatic_load();
    timed(T.grid), compute_node_velocities(), apply_velocity_conditions(&F::v);
  }
  timed(T.grid), integrate_node_forces(dt_), apply_velocity_conditions(&F::v_new); // eq. 20
  // Eq. 31-37: contact on v^{n+1}, recorded (forces, work, contact nodes, slip rates), after the
  // interfaces' pore pressure has pushed each pair apart.
  timed(T.contact), apply_contact(&F::v_new, dt_, ContactPass::momentum),
      apply_velocity_conditions(&F::v_new);
  if (setup_.xpic > 0) timed(T.g2p), extrapolate_xpic_velocity(dt_); // XPIC(m)'s v*
  if (scheme == Scheme::musl) { // eq. 22-23, then the re-map and the stress from it
    timed(T.g2p), update_particles_and_remap(dt_), apply_velocity_conditions(&F::v_remap);
    timed(T.contact), apply_contact(&F::v_remap, dt_, ContactPass::strain);
    timed(T.contact), apply_velocity_conditions(&F::v_remap);
    timed(T.stress), update_stress(&F::v_remap, dt_);
  } else {
    timed(T.g2p), update_particles(dt_);                                       // eq. 22-23
    if (scheme == Scheme::usl) timed(T.stress), update_stress(&F::v_new, dt_); // eq. 24-28
  }
  timed(T.other), update_interface_history(dt_); // eq. 38-39
  // Orphans change over thousands of steps: every tenth step's masses and weights decide them.
  if (steps_ % orphan_interval == 0) timed(T.other), update_orphans();
  end_step();
}

// Reads the particles; writes dt_, the particle order (every sort_interval_ steps), the slab
// bins and the fields' boxes (cleared).
template <int D>
void Simulation<D>::begin_step(double dt_limit) {
  check_.bad_particle =
      StepCheck::no_particle; // a phase run on its own before (tests) leaves nothing behind
  check_.pending_failure.clear();
  if (!check_.checked) check_particles(), check_.checked = true;
  const double stable = compute_time_step();
  const TimeStepSetup& ts = setup_.time_step;
  if (dt_reference_ == 0.0 && std::isfinite(stable)) {
    // The reference is a step of the motion: a settling step at settle_cfl is scaled to cfl.
    dt_reference_ =
        settling_ && ts.settle_cfl && !ts.fixed_dt ? stable * ts.cfl / *ts.settle_cfl : stable;
  }
  const double floor = ts.dt_min.value_or(1e-4 * dt_reference_);
  if (!ts.fixed_dt && stable < floor) report_time_step_collapse(stable, floor);
  stable_dt_ = stable;
  dt_ = std::min(stable, dt_limit);
  if (steps_ % sort_interval_ == 0) sort_particles_by_cell();
  bin_particles_by_slab();
  fit_body_fields();
}

// Writes the clocks, the time means of the contact record and the held fields; reports the
// step's first bad particle before anything (output, a checkpoint, the next step) reads it.
template <int D>
void Simulation<D>::end_step() {
  if (!check_.pending_failure.empty())
    throw SimulationError(std::exchange(check_.pending_failure, {}));
  invalidate_shape(); // the particles have moved
  record_.accumulate(dt_);
  time_ += dt_;
  ++steps_;
  for (int b = 0; b < num_bodies(); ++b)
    field_held_[b] = setup_.bodies[b].fixed;
  if (check_.bad_particle != StepCheck::no_particle) report_bad_particle(check_.bad_particle);
}

template <int D>
void Simulation<D>::release() {
  settling_ = false;
  time_ = 0.0;
  record_.reset_means();
  particles_.x0 = particles_.x;
  std::fill(record_.work.begin(), record_.work.end(), 0.0);
  std::fill(internal_work_.begin(), internal_work_.end(), 0.0);
  set_energy_baseline();
}

template <int D>
double Simulation<D>::interface_pore_pressure(std::size_t p) const {
  const auto& P = particles_;
  if (P.iface[p] < 0) return 0.0;
  const double p0 = setup_.interfaces[P.iface[p]].pore_pressure;
  return P.pore[p] >= 0 ? p0 + pore_.at(P.pore[p]).pressure_rise() : p0;
}

template <int D>
std::vector<std::size_t> Simulation<D>::case_body_begin() const {
  std::vector<std::size_t> begin{0};
  for (const std::size_t n : body_count_)
    begin.push_back(begin.back() + n);
  return begin;
}

template class Simulation<2>;
template class Simulation<3>;

} // namespace talus
