// The time step: CFL on the fastest P-wave plus particle speed, or the case's fixed step.
#include "talus/solver/simulation.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

// The P-wave speed of particle p at its current density, sqrt(M V / m). It grows as sqrt(J): a
// particle's internal force scales with its current volume, so its stiffness over its mass does
// too (docs/performance.md: why it is not capped).
template <int D>
double Simulation<D>::wave_speed(std::int64_t p, double modulus) const {
  const auto& P = particles_;
  return P.m[p] > 0.0 ? std::sqrt(modulus * P.vol[p] / P.m[p]) : 0.0; // 0: left by an outflow
}

// Reads the particles' volume, mass and velocity: dt = cfl h / max(c_p + |v_p|), capped at
// dt_max; one pass over the particles.
template <int D>
double Simulation<D>::compute_time_step() const {
  const auto& P = particles_;
  const TimeStepSetup& ts = setup_.time_step;
  if (ts.fixed_dt) return std::min(*ts.fixed_dt, ts.dt_max);
  double max_speed = 0.0;
  // One parallel region for every body (waking the threads costs more than a small body's loop).
#pragma omp parallel reduction(max : max_speed)
  for (int b = 0; b < P.num_bodies(); ++b) {
    if (field_held_[b]) continue; // a fixed rigid body: speed 0, which cannot raise the maximum
    // A rigid body carries no stress wave: only its speed counts.
    const BodySetup<D>& body = setup_.bodies[b];
    const double modulus = body.rigid ? 0.0 : body.material.p_wave_modulus();
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp for schedule(static) nowait
    for (std::int64_t p = begin; p < end; ++p)
      max_speed = std::max(max_speed, wave_speed(p, modulus) + P.v[p].norm());
  }
  if (exchange_) max_speed = exchange_->max(max_speed); // every process's particles
  const double cfl = settling_ && ts.settle_cfl ? *ts.settle_cfl : ts.cfl;
  // A viscous fluid's explicit diffusion limit, dt <= rho h^2 / (2 D mu), times the CFL number.
  double limit = ts.dt_max;
  for (const BodySetup<D>& body : setup_.bodies)
    if (const Fluid* f = std::get_if<Fluid>(&body.material.model); f && f->viscosity > 0.0)
      limit = std::min(limit, cfl * f->density * grid_.h * grid_.h / (2.0 * D * f->viscosity));
  return std::min(cfl * grid_.h / max_speed, limit);
}

// The CFL step fell below its floor: name the particle that sets it (fastest wave plus speed).
template <int D>
void Simulation<D>::report_time_step_collapse(double stable, double floor) const {
  const auto& P = particles_;
  std::size_t worst = 0;
  double worst_speed = -1.0;
  for (int b = 0; b < P.num_bodies(); ++b) {
    const BodySetup<D>& body = setup_.bodies[b];
    const double modulus = body.rigid ? 0.0 : body.material.p_wave_modulus();
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      const double speed = wave_speed(p, modulus) + P.v[p].norm();
      if (speed > worst_speed) worst_speed = speed, worst = p;
    }
  }
  throw SimulationError(fmt::format(
      "step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): time step collapsed to "
      "{:.3g} s, below the floor {:.3g} s (simulation.dt_min): speed {:.4g} m/s, volume ratio "
      "{:.3g}",
      steps_, time_, setup_.bodies[P.body_of(worst)].name, one_process_index(worst), P.id[worst],
      fmt::join(P.x[worst].data(), P.x[worst].data() + D, ", "), stable, floor, P.v[worst].norm(),
      P.vol[worst] / P.vol0[worst]));
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template double Simulation<D>::wave_speed(std::int64_t, double) const;                           \
  template double Simulation<D>::compute_time_step() const;                                        \
  template void Simulation<D>::report_time_step_collapse(double, double) const;
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
