// The particle check: a state the transfers did not make is checked whole; the transfers check
// what they write, and the step's end reports the first bad particle (step, time, particle).
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"

#include <atomic>
#include <fmt/format.h>

namespace talus {

template <int D>
bool Simulation<D>::particle_ok(std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) const {
  return detail::motion_ok(particles_, p, lo, hi) && particles_.stress[p].allFinite();
}

// Reads every particle's position, velocity and stress; throws naming the first bad one.
template <int D>
void Simulation<D>::check_particles() const {
  const auto& P = particles_;
  std::atomic<std::size_t> bad{P.size()};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
#pragma omp parallel for schedule(static)
  for (std::int64_t p = 0; p < static_cast<std::int64_t>(P.size()); ++p)
    if (!particle_ok(p, lo, hi)) detail::record_bad(bad, static_cast<std::size_t>(p), exchange_);
  if (bad.load() != P.size()) report_bad_particle(bad.load());
}

template <int D>
void Simulation<D>::report_bad_particle(std::size_t p) const {
  const auto& P = particles_;
  const char* what = !P.x[p].allFinite()        ? "position is not finite"
                     : !P.v[p].allFinite()      ? "velocity is not finite"
                     : !P.stress[p].allFinite() ? "stress is not finite"
                                                : "particle left the grid";
  throw SimulationError(
      fmt::format("step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): {}", steps_,
                  time_, setup_.bodies[P.body_of(p)].name, one_process_index(p), P.id[p],
                  fmt::join(P.x[p].data(), P.x[p].data() + D, ", "), what));
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template bool Simulation<D>::particle_ok(std::int64_t, const Vec<D>&, const Vec<D>&) const;      \
  template void Simulation<D>::check_particles() const;                                            \
  template void Simulation<D>::report_bad_particle(std::size_t) const;
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
