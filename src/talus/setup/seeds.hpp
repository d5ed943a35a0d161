// Filling a case's bodies with particles: n particles per cell per direction at the centres of
// the sub-cells whose centre lies inside the body's shape (case/geometry.hpp).
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/particles.hpp"

#include <functional>

namespace talus {

// Particles of every body, grouped by body in case order. Throws CaseError for an empty body.
template <int D>
Particles<D> fill_particles(const Case& c);

// What each seed of a body becomes: its particle's mass, volume and initial velocity.
template <int D>
struct SeedParticle {
  double m = 0.0, vol = 0.0;
  Vec<D> v = Vec<D>::Zero();
};
template <int D>
SeedParticle<D> seed_particle(const Case& c, std::size_t body);

// Calls f at each seed of body `body`, in fill order (the order of its particles' ids).
template <int D>
void for_each_seed_of(const Case& c, std::size_t body, const std::function<void(const Vec<D>&)>& f);

// Particle count without allocating (for `talus check` and memory estimates).
std::size_t count_particles(const Case& c, std::size_t body);

// Throws CaseError naming the body if `count` (its particle count) is zero.
void require_particles(const Case& c, std::size_t body, std::size_t count);

} // namespace talus
