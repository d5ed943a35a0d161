#include "talus/setup/seeding.hpp"

#include "talus/case/geometry.hpp"
#include "talus/setup/initial_state.hpp"
#include "talus/setup/interface.hpp"
#include "talus/setup/seeds.hpp"

#include <fmt/format.h>

namespace talus {

template <int D>
Seeded<D> seed_case(const Case& c) {
  Seeded<D> s;
  Particles<D>& P = s.particles = fill_particles<D>(c);
  s.total = P.size();
  check_body_overlaps<D>(c, P);
  if (c.initial_state.method == InitialState::Method::k0) apply_k0_stress<D>(c, P);
  s.warnings = mark_interface_particles<D>(c, P);
  for (int b = 0; b < P.num_bodies(); ++b) {
    double mass = 0.0;
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
      mass += P.m[p];
    s.body_mass.push_back(mass);
    s.body_count.push_back(P.body_begin[b + 1] - P.body_begin[b]);
  }
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.iface[p] >= 0 && has_pore_state(c.interfaces[P.iface[p]]))
      s.pore_particles.emplace_back(P.id[p], P.iface[p]);
  for (const ProbeSpec& pr : c.probes) {
    Vec<D> near;
    for (int d = 0; d < D; ++d)
      near[d] = pr.near[d];
    const double gap = (P.x[nearest_particle(P, pr.body, near)] - near).norm();
    if (std::string w = probe_gap_warning(c, pr, gap); !w.empty()) s.warnings.push_back(w);
  }
  return s;
}

template <int D>
std::size_t nearest_particle(const Particles<D>& P, int body, const Vec<D>& point) {
  std::size_t best = P.body_begin[body];
  double best_d = inf;
  for (std::size_t p = P.body_begin[body]; p < P.body_begin[body + 1]; ++p) {
    const double d = (P.x[p] - point).squaredNorm();
    if (d < best_d) best_d = d, best = p;
  }
  return best;
}

std::string probe_gap_warning(const Case& c, const ProbeSpec& probe, double gap) {
  if (gap <= c.grid.cell_size) return {};
  return fmt::format("probe '{}': the nearest particle of body '{}' is {:.3g} m from its point "
                     "(more than a cell, {:.3g} m): the probe follows that particle",
                     probe.name, c.bodies[probe.body].name, gap, c.grid.cell_size);
}

template Seeded<2> seed_case<2>(const Case&);
template Seeded<3> seed_case<3>(const Case&);
template std::size_t nearest_particle<2>(const Particles<2>&, int, const Vec<2>&);
template std::size_t nearest_particle<3>(const Particles<3>&, int, const Vec<3>&);

} // namespace talus
