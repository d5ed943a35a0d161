// A case's shapes as point queries: inside or not, a terrain's column, the nearest surface's
// normal (setup/seeds.hpp fills them with particles; the contact pass reads their normals).
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/math.hpp"

#include <array>
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
// radial for a disk or sphere; outside a box or a terrain body's footprint, from its nearest
// point). Used as the exact contact normal of rigid bodies. `edge` (if given) is set where x
// lies on an edge or corner of a box or a terrain body, two or more of its faces equally near:
// the normal there is the first's, and a caller that knows from where a body comes at it can
// ask again from there.
template <int D>
Vec<D> surface_normal(const Geometry& g, const Vec<D>& x, bool* edge = nullptr);

// The shapes law = "surface" reads exactly: boxes, polygons and disks (2D); boxes and spheres (3D).
bool has_exact_surface(const Geometry& g, int dimension);

// The signed distance to the surface (negative inside), and the outward normal at its nearest
// point.
template <int D>
double signed_distance(const Geometry& g, const Vec<D>& x, Vec<D>& normal);

// Appends, for x inside, the nearest point of each box face or polygon edge (or the disk's) within
// reach.
template <int D>
void surface_points_near(const Geometry& g, const Vec<D>& x, double within,
                         std::vector<Vec<D>>& out);

} // namespace talus
