#include "talus/case/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

bool point_in_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  // Crossing number: count edges crossed by the ray towards +x (half-open on y, so vertices on
  // the ray count once).
  bool in = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y)) {
      const double xc = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x < xc) in = !in;
    }
  }
  return in;
}

namespace {

// The distance from x to a polygon's nearest edge and that edge's outward unit normal (and, if
// asked, the nearest point on it); edges marked in `open` are skipped (infinite distance if all
// are).
std::pair<double, Vec<2>> nearest_edge(const std::vector<std::array<double, 2>>& v, const Vec<2>& x,
                                       const std::vector<char>& open = {},
                                       Vec<2>* nearest = nullptr) {
  double area = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i)
    area += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  double best = inf;
  Vec<2> n = Vec<2>::Zero();
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!open.empty() && open[i]) continue;
    const Vec<2> a(v[i][0], v[i][1]), b(v[(i + 1) % v.size()][0], v[(i + 1) % v.size()][1]);
    const Vec<2> e = b - a;
    const double t = std::clamp((x - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double dist = (a + t * e - x).norm();
    if (dist < best) {
      best = dist;
      if (nearest) *nearest = a + t * e;
      const Vec<2> right(e[1], -e[0]); // outward for a counter-clockwise polygon
      n = (area > 0.0 ? 1.0 : -1.0) * right / e.norm();
    }
  }
  return {best, n};
}

// The upward unit normal of a terrain surface at (x, y): (-dz/dx, -dz/dy, 1) normalised, the
// slopes by central differences over a raster cell (an offset from the other surface has its).
Vec<3> surface_up(const Geometry& g, const TerrainSurface& s, double x, double y) {
  const TerrainSurface& shaped =
      s.kind != TerrainSurface::Kind::offset ? s : (&s == &g.top ? g.bottom : g.top);
  if (shaped.kind != TerrainSurface::Kind::raster) return Vec<3>(0.0, 0.0, 1.0);
  const Raster& r = *shaped.raster;
  // Central differences over a raster cell, one-sided where a neighbour has no data or is off
  // the raster's edge.
  const double z0 = r.elevation(x, y);
  auto slope = [&](double ex, double ey, double h) {
    const double zp = r.elevation(x + ex, y + ey), zm = r.elevation(x - ex, y - ey);
    const bool p = std::isfinite(zp), m = std::isfinite(zm);
    if (!p && !m) return 0.0;
    return ((p ? zp : z0) - (m ? zm : z0)) / ((p ? h : 0.0) + (m ? h : 0.0));
  };
  const double sx = slope(r.dx, 0.0, r.dx), sy = slope(0.0, r.dy, r.dy);
  const Vec<3> up(-sx, -sy, 1.0);
  return std::isfinite(up.squaredNorm()) ? Vec<3>(up / up.norm()) : Vec<3>(0.0, 0.0, 1.0);
}

// The nearest of `count` candidate faces by their distances: the first within `tie` of the
// smallest (so that a node on an edge is not decided by round-off), and whether two or more are.
inline int nearest_face(const double* dist, int count, double tie, bool* edge) {
  double least = inf;
  for (int i = 0; i < count; ++i)
    least = std::min(least, dist[i]);
  int first = -1, within = 0;
  for (int i = 0; i < count; ++i)
    if (dist[i] <= least + tie) within += 1, first = first < 0 ? i : first;
  if (edge) *edge = within > 1;
  return first;
}

} // namespace

template <int D>
bool inside(const Geometry& g, const Vec<D>& x) {
  switch (g.kind) {
  case Geometry::Kind::box:
    for (int d = 0; d < D; ++d)
      if (x[d] < g.min[d] || x[d] > g.max[d]) return false;
    return true;
  case Geometry::Kind::disk: {
    double r2 = 0.0;
    for (int d = 0; d < D; ++d)
      r2 += (x[d] - g.center[d]) * (x[d] - g.center[d]);
    return r2 <= g.radius * g.radius;
  }
  case Geometry::Kind::polygon:
    if constexpr (D == 2) return point_in_polygon(g.vertices, x[0], x[1]);
    return false;
  case Geometry::Kind::prism:
    if constexpr (D == 3) {
      const auto [u, w] = prism_axes(g.axis);
      return x[g.axis] >= g.min[g.axis] && x[g.axis] <= g.max[g.axis] &&
             point_in_polygon(g.vertices, x[u], x[w]);
    }
    return false;
  case Geometry::Kind::terrain:
    if constexpr (D == 3) {
      if (g.footprint && !point_in_polygon(g.vertices, x[0], x[1])) return false;
      const auto [top, bottom] = terrain_column(g, x[0], x[1]);
      return x[2] >= bottom && x[2] <= top; // false where either is NaN (no data)
    }
    return false;
  }
  return false;
}

std::array<int, 2> prism_axes(int axis) {
  return {axis == 0 ? 1 : 0, axis == 2 ? 1 : 2};
}

std::array<double, 2> terrain_column(const Geometry& g, double x, double y) {
  // A raster's or a constant's elevation; an offset surface is the other one's plus or minus.
  auto z = [&](const TerrainSurface& s) { return s.raster ? s.raster->elevation(x, y) : s.value; };
  if (g.top.kind == TerrainSurface::Kind::offset) { // a height above the bottom
    const double bottom = z(g.bottom);
    return {bottom + g.top.value, bottom};
  }
  const double top = z(g.top);
  return {top, g.bottom.kind == TerrainSurface::Kind::offset ? top - g.bottom.value : z(g.bottom)};
}

template <int D>
Vec<D> surface_normal(const Geometry& g, const Vec<D>& x, bool* edge) {
  Vec<D> n = Vec<D>::Zero();
  if (edge) *edge = false;
  if (g.kind == Geometry::Kind::disk) {
    Vec<D> c;
    for (int d = 0; d < D; ++d)
      c[d] = g.center[d];
    const Vec<D> r = x - c;
    return r.norm() > 0.0 ? Vec<D>(r / r.norm()) : n;
  }
  if (g.kind == Geometry::Kind::box) {
    // Distances below a billionth of the box's size are round-off: a node on a face or an edge
    // is on it.
    double size = 0.0;
    for (int d = 0; d < D; ++d)
      size = std::max(size, g.max[d] - g.min[d]);
    const double tie = 1e-9 * size;
    // Outside the box: from its nearest point towards x, the gradient of the distance to it
    // (beside a box standing on a floor, level with its base, the side's normal: a wall on a
    // floor, a dam on a valley floor, holds what comes at it there; beyond a corner, the
    // diagonal from the corner).
    Vec<D> out = Vec<D>::Zero();
    for (int d = 0; d < D; ++d)
      out[d] =
          x[d] < g.min[d] - tie ? x[d] - g.min[d] : (x[d] > g.max[d] + tie ? x[d] - g.max[d] : 0.0);
    if (const double r = out.norm(); r > 0.0) return out / r;
    // On or in it: the nearest face's plane; two or more equally near are an edge (the first,
    // x before y (before z), is returned).
    double dist[2 * D];
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side)
        dist[2 * d + side] = std::abs(x[d] - (side ? g.max[d] : g.min[d]));
    const int face = nearest_face(dist, 2 * D, tie, edge);
    n[face / 2] = face % 2 ? 1.0 : -1.0;
    return n;
  }
  if constexpr (D == 3) {
    if (g.kind == Geometry::Kind::prism) {
      // Nearest of the two end caps and the polygon's side walls.
      const auto [u, w] = prism_axes(g.axis);
      double best = inf;
      for (int side = 0; side < 2; ++side) {
        if (g.open_cap[side]) continue;
        const double dist = std::abs(x[g.axis] - (side ? g.max[g.axis] : g.min[g.axis]));
        if (dist < best) best = dist, n.setZero(), n[g.axis] = side ? 1.0 : -1.0;
      }
      const auto [dist, edge] = nearest_edge(g.vertices, Vec<2>(x[u], x[w]), g.open_edge);
      if (dist < best) n.setZero(), n[u] = edge[0], n[w] = edge[1];
      return n;
    }
    if (g.kind == Geometry::Kind::terrain) {
      const double tie = 1e-9 * std::max({1.0, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
      // Outside the footprint in plan (not on it, and nearest a wall, not an edge on the grid's
      // face): the gradient of the distance to the body, from its nearest point q on that wall:
      // level with the wall there, (x - q) in plan; above its top or below its bottom at q, from
      // the wall's rim. Beside a dam standing on a valley floor, level with its foot, the wall's
      // normal.
      if (g.footprint && !point_in_polygon(g.vertices, x[0], x[1])) {
        const Vec<2> p(x[0], x[1]);
        Vec<2> q;
        const double dist = nearest_edge(g.vertices, p, g.open_edge, &q).first;
        if (dist > tie && dist == nearest_edge(g.vertices, p).first) {
          const auto [top, bottom] = terrain_column(g, q[0], q[1]);
          const double above = std::isfinite(top) ? std::max(x[2] - top, 0.0) : 0.0;
          const double below = std::isfinite(bottom) ? std::max(bottom - x[2], 0.0) : 0.0;
          const Vec<3> out(p[0] - q[0], p[1] - q[1], above - below);
          if (const double r = out.norm(); r > 0.0) return out / r;
        }
      }
      // In it (or on its walls): the nearest of the top (up, normal (-dz/dx, -dz/dy, 1)), the
      // bottom (down) and the footprint's walls; a surface's distance is its vertical gap times
      // the normal's z. Two or more equally near are an edge (the first is returned).
      const auto [top, bottom] = terrain_column(g, x[0], x[1]);
      double dist[3] = {inf, inf, inf};
      Vec<3> normal[3] = {Vec<3>::Zero(), Vec<3>::Zero(), Vec<3>::Zero()};
      for (int side = 0; side < 2; ++side) {
        const TerrainSurface& s = side ? g.bottom : g.top;
        const double z = side ? bottom : top;
        if (!std::isfinite(z)) continue;
        const Vec<3> up = surface_up(g, s, x[0], x[1]);
        dist[side] = std::abs(x[2] - z) * up[2];
        normal[side] = side ? Vec<3>(-up) : up;
      }
      if (g.footprint) {
        const auto [d, wall] = nearest_edge(g.vertices, Vec<2>(x[0], x[1]), g.open_edge);
        dist[2] = d, normal[2] = Vec<3>(wall[0], wall[1], 0.0);
      }
      if (!std::isfinite(std::min({dist[0], dist[1], dist[2]}))) return n;
      return normal[nearest_face(dist, 3, tie, edge)];
    }
  }
  if constexpr (D == 2) n = nearest_edge(g.vertices, x).second; // the polygon's nearest edge
  return n;
}

bool has_exact_surface(const Geometry& g, int dimension) {
  return g.kind == Geometry::Kind::box || g.kind == Geometry::Kind::disk ||
         (g.kind == Geometry::Kind::polygon && dimension == 2);
}

template <int D>
double signed_distance(const Geometry& g, const Vec<D>& x, Vec<D>& normal) {
  normal.setZero();
  if (g.kind == Geometry::Kind::disk) { // |x - c| - R, radial
    Vec<D> r;
    for (int d = 0; d < D; ++d)
      r[d] = x[d] - g.center[d];
    const double len = r.norm();
    if (len > 0.0)
      normal = r / len;
    else
      normal[D - 1] = 1.0;
    return len - g.radius;
  }
  if (g.kind == Geometry::Kind::box) {
    // Outside: the distance to the box's nearest point, from it; inside: the nearest face's.
    Vec<D> out;
    for (int d = 0; d < D; ++d)
      out[d] = x[d] < g.min[d] ? x[d] - g.min[d] : (x[d] > g.max[d] ? x[d] - g.max[d] : 0.0);
    if (const double len = out.norm(); len > 0.0) {
      normal = out / len;
      return len;
    }
    double least = inf;
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side)
        if (const double dist = side ? g.max[d] - x[d] : x[d] - g.min[d]; dist < least)
          least = dist, normal.setZero(), normal[d] = side ? 1.0 : -1.0;
    return -least;
  }
  if constexpr (D == 2)
    if (g.kind == Geometry::Kind::polygon) {
      // The nearest edge's point q: outside, the normal is (x - q) / |x - q| (beyond a vertex,
      // from the vertex); inside or on it, the edge's outward normal.
      Vec<2> q;
      const auto [dist, edge_normal] = nearest_edge(g.vertices, x, {}, &q);
      const bool in = point_in_polygon(g.vertices, x[0], x[1]);
      normal = in || !(dist > 0.0) ? edge_normal : Vec<2>((x - q) / dist);
      return in ? -dist : dist;
    }
  return inf;
}

template <int D>
void surface_points_near(const Geometry& g, const Vec<D>& x, double within,
                         std::vector<Vec<D>>& out) {
  if (g.kind == Geometry::Kind::disk) {
    Vec<D> c, r;
    for (int d = 0; d < D; ++d)
      c[d] = g.center[d], r[d] = x[d] - g.center[d];
    const double len = r.norm();
    if (len > 0.0 && g.radius - len <= within) out.push_back(c + (g.radius / len) * r);
    return;
  }
  if (g.kind == Geometry::Kind::box) {
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) {
        const double face = side ? g.max[d] : g.min[d];
        if (std::abs(x[d] - face) > within) continue;
        Vec<D> q = x;
        q[d] = face;
        out.push_back(q);
      }
    return;
  }
  if constexpr (D == 2)
    if (g.kind == Geometry::Kind::polygon) {
      const auto& v = g.vertices;
      const std::size_t first = out.size();
      for (std::size_t i = 0; i < v.size(); ++i) {
        const Vec<2> a(v[i][0], v[i][1]), b(v[(i + 1) % v.size()][0], v[(i + 1) % v.size()][1]);
        const Vec<2> e = b - a;
        const double t = std::clamp((x - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
        const Vec<2> q = a + t * e;
        if ((q - x).norm() > within) continue;
        // A vertex nearest to both its edges is one point.
        bool again = false;
        for (std::size_t k = first; k < out.size(); ++k)
          again = again || (out[k] - q).norm() <= 1e-12 * (1.0 + q.norm());
        if (!again) out.push_back(q);
      }
    }
}

template double signed_distance<2>(const Geometry&, const Vec<2>&, Vec<2>&);
template double signed_distance<3>(const Geometry&, const Vec<3>&, Vec<3>&);
template void surface_points_near<2>(const Geometry&, const Vec<2>&, double, std::vector<Vec<2>>&);
template void surface_points_near<3>(const Geometry&, const Vec<3>&, double, std::vector<Vec<3>>&);

template Vec<2> surface_normal<2>(const Geometry&, const Vec<2>&, bool*);
template Vec<3> surface_normal<3>(const Geometry&, const Vec<3>&, bool*);

template bool inside<2>(const Geometry&, const Vec<2>&);
template bool inside<3>(const Geometry&, const Vec<3>&);

} // namespace talus
