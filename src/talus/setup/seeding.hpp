// The particles a run starts from, and what the whole case decides about them: the seeds
// (case/geometry.hpp) checked for overlaps, with their K0 stresses and interface marks. On one
// process these are the whole case's particles; on several, each process's own slab alone
// (parallel/seed_share.hpp), with the same ids, masses and pore-pool order.
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/particles.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace talus {

template <int D>
struct Seeded {
  Particles<D> particles;              // by id; ids number the whole case's particles in fill order
  std::size_t total = 0;               // the whole case's particle count
  std::vector<double> body_mass;       // per body: its particles' masses summed in id order
  std::vector<std::size_t> body_count; // per body: the whole case's particles
  // The whole case's particles on an interface with pore pressure: (id, interface), by id.
  std::vector<std::pair<std::uint32_t, int>> pore_particles;
  std::vector<std::string> warnings; // the set-up's (interfaces that bond nothing, far probes)
};

// The whole case's particles on one process. Throws CaseError for an empty body or overlapping
// bodies.
template <int D>
Seeded<D> seed_case(const Case& c);

// The particle of `body` in P nearest `point` (the first of equals in particle order).
template <int D>
std::size_t nearest_particle(const Particles<D>& P, int body, const Vec<D>& point);

// The warning for a probe whose nearest particle is `gap` from its point; empty within a cell.
std::string probe_gap_warning(const Case& c, const ProbeSpec& probe, double gap);

} // namespace talus
