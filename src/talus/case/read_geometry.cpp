#include "talus/case/read_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

namespace talus {

namespace case_reading {

namespace {

constexpr std::size_t max_polygon_vertices = 20000;

// The first pair of non-adjacent edges (i, i+1) and (j, j+1) that touch or cross, if any: such a
// polygon has no well-defined inside. O(n^2), n <= max_polygon_vertices.
std::optional<std::pair<std::size_t, std::size_t>>
self_intersection(const std::vector<std::array<double, 2>>& v) {
  const std::size_t n = v.size();
  auto orient = [](const std::array<double, 2>& a, const std::array<double, 2>& b,
                   const std::array<double, 2>& c) {
    const double o = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    return (o > 0) - (o < 0);
  };
  auto on_segment = [](const std::array<double, 2>& a, const std::array<double, 2>& b,
                       const std::array<double, 2>& c) { // c collinear with a-b
    return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) &&
           std::min(a[1], b[1]) <= c[1] && c[1] <= std::max(a[1], b[1]);
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue; // adjacent through the closing edge
      const auto &a = v[i], &b = v[(i + 1) % n], &c = v[j], &d = v[(j + 1) % n];
      const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
                o4 = orient(c, d, b);
      if ((o1 != o2 && o3 != o4) || (o1 == 0 && on_segment(a, b, c)) ||
          (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
          (o4 == 0 && on_segment(c, d, b)))
        return std::make_pair(i, j);
    }
  return std::nullopt;
}

} // namespace

Geometry read_geometry(TableReader& r, int dim, InputFiles& files) {
  const std::vector<std::string> kinds = {"box", "polygon", "disk", "sphere"};
  std::vector<std::string> present;
  for (const auto& k : kinds)
    if (r.has(k)) present.push_back(k);
  if (present.size() != 1)
    r.fail(present.empty() ? "box" : present[1],
           "a body needs exactly one geometry: box, polygon (2D), disk (2D) or sphere (3D)");
  Geometry g;
  const std::string kind = present[0];
  if (kind == "box") {
    g.kind = Geometry::Kind::box;
    const toml::table* t = r.table("box");
    if (!t) r.fail("box", "expected a table { min = [...], max = [...] }");
    TableReader b(*t, r.key_path("box"), r.where());
    g.min = b.vector("min", dim);
    g.max = b.vector("max", dim);
    for (int d = 0; d < dim; ++d)
      require(b, "max", g.max[d] > g.min[d], "max must exceed min in every direction");
    b.finish();
  } else if (kind == "polygon") {
    if (dim != 2) r.fail("polygon", "polygons are 2D; use box or sphere in 3D");
    g.kind = Geometry::Kind::polygon;
    const toml::node* n = r.find("polygon");
    if (n->is_string()) {
      if (n->value<std::string>()->empty()) r.fail("polygon", "the file name is empty");
      g.polygon_file = files.resolve(n->value<std::string>().value());
      try {
        g.vertices = read_polygon_csv(g.polygon_file);
      } catch (const CaseError& e) {
        r.fail("polygon", e.what());
      }
    } else if (const toml::array* a = n->as_array()) {
      for (std::size_t i = 0; i < a->size(); ++i) {
        const Vec3a v = r.as_vector(*a->get(i), fmt::format("polygon[{}]", i), 2);
        g.vertices.push_back({v[0], v[1]});
      }
    } else {
      r.fail("polygon", "expected a CSV file name or an array of [x, y] vertices");
    }
    // A vertex equal to the one before it (GIS exports repeat the first vertex at the end to
    // close the ring) adds no edge: it is dropped.
    auto& v = g.vertices;
    v.erase(std::unique(v.begin(), v.end()), v.end());
    while (v.size() > 1 && v.back() == v.front())
      v.pop_back();
    if (g.vertices.size() < 3) r.fail("polygon", "a polygon needs at least 3 distinct vertices");
    if (g.vertices.size() > max_polygon_vertices)
      r.fail("polygon", fmt::format("{} vertices, more than {}: simplify the polygon",
                                    g.vertices.size(), max_polygon_vertices));
    if (const auto cross = self_intersection(g.vertices))
      r.fail("polygon",
             fmt::format("the polygon crosses itself: edge {} ({}, {})-({}, {}) meets "
                         "edge {} (vertices are numbered from 0)",
                         cross->first, g.vertices[cross->first][0], g.vertices[cross->first][1],
                         g.vertices[(cross->first + 1) % g.vertices.size()][0],
                         g.vertices[(cross->first + 1) % g.vertices.size()][1], cross->second));
    double area = 0.0;
    for (std::size_t i = 0; i < g.vertices.size(); ++i) {
      const auto& a = g.vertices[i];
      const auto& b = g.vertices[(i + 1) % g.vertices.size()];
      area += a[0] * b[1] - b[0] * a[1];
    }
    if (std::abs(area) < 1e-12) r.fail("polygon", "the polygon has zero area");
  } else {
    if ((kind == "disk") != (dim == 2)) r.fail(kind, "use disk in 2D and sphere in 3D");
    g.kind = Geometry::Kind::disk;
    const toml::table* t = r.table(kind);
    if (!t) r.fail(kind, "expected a table { center = [...], radius = r }");
    TableReader b(*t, r.key_path(kind), r.where());
    g.center = b.vector("center", dim);
    g.radius = b.number("radius");
    require(b, "radius", g.radius > 0.0, "must be > 0 m");
    b.finish();
  }
  return g;
}

} // namespace case_reading

std::vector<std::array<double, 2>> read_polygon_csv(const std::string& path) {
  std::ifstream in(path);
  if (std::filesystem::is_directory(path))
    throw CaseError(fmt::format("{}: is a folder, not a polygon file", path));
  if (!in) throw CaseError(fmt::format("{}: cannot open the polygon file", path));
  std::vector<std::array<double, 2>> v;
  std::string line;
  bool seen_header = false;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    std::array<double, 2> p{};
    char* end = nullptr;
    const char* s = line.c_str();
    p[0] = std::strtod(s, &end);
    const bool first_ok = end != s;
    bool ok = first_ok && *end == ',';
    if (ok) {
      const char* s2 = end + 1;
      p[1] = std::strtod(s2, &end);
      ok = end != s2 && line.find_first_not_of(" \t", end - s) == std::string::npos;
    }
    if (!ok) {
      // One header line such as "x,z" or "x (m),y (m)" before the first vertex: words, no digits.
      const bool header_like =
          line.find_first_of("0123456789.") == std::string::npos && !seen_header;
      if (v.empty() && !first_ok && header_like) {
        seen_header = true;
        continue;
      }
      throw CaseError(
          fmt::format("{}:{}: expected two numbers 'x,y', got '{}'", path, lineno, line));
    }
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
      throw CaseError(fmt::format("{}:{}: coordinates must be finite", path, lineno));
    v.push_back(p);
  }
  if (v.size() > 1 && v.front() == v.back()) v.pop_back(); // closed ring
  return v;
}

} // namespace talus
