// Filling a case's geometry with particles: n particles per cell per direction at the centres of
// the sub-cells whose centre lies inside the shape.
#pragma once

#include "talus/case/case.hpp"
#include "talus/particles.hpp"

#include <array>
#include <functional>
#include <vector>

namespace talus {

bool point_in_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y);

template <int D>
bool inside(const Geometry& g, const Vec<D>& x);

// A prism's in-plane axes: the polygon's two coordinates are these axes of space, in order.
std::array<int, 2> prism_axes(int axis);
// A terrain body's top and bottom elevations at (x, y) (NaN where a raster has no data or does
// not reach).
std::array<double, 2> terrain_column(const Geometry& g, double x, double y);

// Outward unit normal of the geometry's surface nearest to x (nearest polygon edge or box face;
// radial for a disk or sphere). Used as the exact contact normal of rigid bodies.
template <int D>
Vec<D> surface_normal(const Geometry& g, const Vec<D>& x);

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
