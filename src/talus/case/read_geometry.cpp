#include "talus/case/read_geometry.hpp"

#include "talus/case/parse.hpp"
#include "talus/case/terrain.hpp"

#include <algorithm>
#include <cctype>
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

namespace {

// Checks a polygon's vertices (read from `key`): drops repeated vertices (GIS exports close the
// ring with the first one), then refuses fewer than 3, too many, a self-crossing ring or a zero
// area.
void check_polygon(TableReader& r, const std::string& key, std::vector<std::array<double, 2>>& v) {
  v.erase(std::unique(v.begin(), v.end()), v.end());
  while (v.size() > 1 && v.back() == v.front())
    v.pop_back();
  if (v.size() < 3) r.fail(key, "a polygon needs at least 3 distinct vertices");
  if (v.size() > max_polygon_vertices)
    r.fail(key, fmt::format("{} vertices, more than {}: simplify the polygon", v.size(),
                            max_polygon_vertices));
  if (const auto cross = self_intersection(v))
    r.fail(key, fmt::format("the polygon crosses itself: edge {} ({}, {})-({}, {}) meets "
                            "edge {} (vertices are numbered from 0)",
                            cross->first, v[cross->first][0], v[cross->first][1],
                            v[(cross->first + 1) % v.size()][0],
                            v[(cross->first + 1) % v.size()][1], cross->second));
  double area = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i)
    area += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  if (std::abs(area) < 1e-12) r.fail(key, "the polygon has zero area");
}

// Whether a file name is a CSV (read by talus) rather than a vector file (read by GDAL).
bool is_csv(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  return ext == ".csv" || ext == ".txt";
}

// A polygon given inline ([[x, y], ...]) or as a file: a CSV of x,y (shifted by `shift` if
// given), or, with `vector_files`, anything GDAL's vector reader takes (always shifted).
std::vector<std::array<double, 2>> read_polygon(TableReader& r, const std::string& key,
                                                InputFiles& files, std::string& file,
                                                const Vec3a* shift, std::string* crs) {
  std::vector<std::array<double, 2>> v;
  const toml::node* n = r.find(key);
  if (n->is_string()) {
    const std::string written = r.string(key); // printable: it reaches the messages
    if (written.empty()) r.fail(key, "the file name is empty");
    file = files.resolve(written);
    try {
      const bool csv = is_csv(written) || !crs;
      check_input_file(file, csv ? max_polygon_csv_bytes : max_input_bytes);
      if (csv) {
        v = read_polygon_csv(file);
        if (shift)
          for (auto& p : v)
            p[0] -= (*shift)[0], p[1] -= (*shift)[1];
      } else {
        files.add_sidecars(file);
        v = read_footprint_vector(file, *shift, *crs);
      }
    } catch (const CaseError& e) {
      r.fail(key, e.what());
    }
  } else if (const toml::array* a = n->as_array()) {
    for (std::size_t i = 0; i < a->size(); ++i) {
      const Vec3a p = r.as_vector(*a->get(i), fmt::format("{}[{}]", key, i), 2);
      v.push_back({p[0], p[1]});
    }
  } else {
    r.fail(key, crs ? "expected a file name (CSV, GeoJSON, shapefile) or an array of [x, y] "
                      "vertices"
                    : "expected a CSV file name or an array of [x, y] vertices");
  }
  check_polygon(r, key, v);
  return v;
}

// One surface of a terrain body: a raster file, a constant elevation, or an offset from the
// other surface: { depth = d } below the top (a bottom), { height = h } above the bottom (a top).
TerrainSurface read_surface(TableReader& t, const std::string& key, bool bottom, InputFiles& files,
                            const Vec3a& origin) {
  TerrainSurface s;
  const toml::node* n = t.find(key);
  if (!n) t.fail_missing(key);
  if (n->is_string()) {
    const std::string written = t.string(key); // printable: it reaches the messages
    if (written.empty()) t.fail(key, "the file name is empty");
    const std::string path = files.resolve(written);
    files.add_sidecars(path);
    s.kind = TerrainSurface::Kind::raster;
    try {
      check_input_file(path, max_input_bytes);
      s.raster = read_raster(path, origin);
    } catch (const CaseError& e) {
      t.fail(key, e.what());
    }
  } else if (n->is_number()) {
    s.value = t.number(key);
  } else if (n->is_table()) {
    TableReader d(*n->as_table(), t.key_path(key), t.where());
    const std::string offset = bottom ? "depth" : "height";
    s.kind = TerrainSurface::Kind::offset;
    s.value = d.number(offset);
    require(d, offset, s.value > 0.0, "must be > 0 m");
    d.finish();
  } else {
    t.fail(key, bottom ? "expected a raster file, an elevation (m) or { depth = d }"
                       : "expected a raster file, an elevation (m) or { height = h }");
  }
  return s;
}

void read_terrain(TableReader& r, Geometry& g, InputFiles& files, const Vec3a& origin) {
  g.kind = Geometry::Kind::terrain;
  const toml::table* tt = r.table("terrain");
  if (!tt) r.fail("terrain", "expected a table { top = ..., bottom = ..., footprint = ... }");
  TableReader t(*tt, r.key_path("terrain"), r.where());
  g.top = read_surface(t, "top", false, files, origin);
  g.bottom = read_surface(t, "bottom", true, files, origin);
  if (g.top.kind == TerrainSurface::Kind::offset && g.bottom.kind == TerrainSurface::Kind::offset)
    t.fail("top", "a height above a bottom given as a depth below the top: give one surface");
  std::string footprint_crs;
  if (t.has("footprint")) {
    g.footprint = true;
    g.vertices = read_polygon(t, "footprint", files, g.polygon_file, &origin, &footprint_crs);
  }
  t.finish();
  // One coordinate system for every file that names one.
  std::vector<std::pair<std::string, std::string>> named; // key, crs
  for (const auto& [key, s] : {std::pair{"top", &g.top}, std::pair{"bottom", &g.bottom}})
    if (s->raster) named.emplace_back(key, s->raster->crs);
  if (g.footprint) named.emplace_back("footprint", footprint_crs);
  for (std::size_t i = 1; i < named.size(); ++i)
    if (!same_crs(named[0].second, named[i].second))
      t.fail(named[i].first,
             fmt::format("its coordinate system ({}) is not {}'s ({})", crs_name(named[i].second),
                         named[0].first, crs_name(named[0].second)));
  // The plan bounds: the footprint's, which each raster must cover, or the rasters' overlap.
  double lo[2] = {-inf, -inf}, hi[2] = {inf, inf};
  for (const auto& [key, s] : {std::pair{"top", &g.top}, std::pair{"bottom", &g.bottom}}) {
    if (!s->raster) continue;
    const Raster& ras = *s->raster;
    if (g.footprint)
      for (std::size_t k = 0; k < g.vertices.size(); ++k)
        if (!ras.covers(g.vertices[k][0], g.vertices[k][1]))
          t.fail(key, fmt::format("{} does not cover the footprint: its vertex {} ({}, {}) is "
                                  "outside the raster's x [{}, {}], y [{}, {}] (local m, after "
                                  "[terrain] origin)",
                                  ras.file, k, g.vertices[k][0], g.vertices[k][1], ras.x0,
                                  ras.x0 + ras.nx * ras.dx, ras.y0, ras.y0 + ras.ny * ras.dy));
    lo[0] = std::max(lo[0], ras.x0), hi[0] = std::min(hi[0], ras.x0 + ras.nx * ras.dx);
    lo[1] = std::max(lo[1], ras.y0), hi[1] = std::min(hi[1], ras.y0 + ras.ny * ras.dy);
  }
  if (g.footprint) {
    lo[0] = lo[1] = inf, hi[0] = hi[1] = -inf;
    for (const auto& v : g.vertices)
      for (int d = 0; d < 2; ++d)
        lo[d] = std::min(lo[d], v[d]), hi[d] = std::max(hi[d], v[d]);
  } else if (!g.top.raster && !g.bottom.raster) {
    r.fail("terrain", "two constant surfaces need a footprint to bound the body");
  } else if (lo[0] >= hi[0] || lo[1] >= hi[1]) {
    r.fail("terrain", fmt::format("the rasters {} and {} do not overlap", g.top.raster->file,
                                  g.bottom.raster->file));
  }
  // The elevation bounds.
  using K = TerrainSurface::Kind;
  auto lowest = [](const TerrainSurface& s) { return s.raster ? s.raster->z_min : s.value; };
  auto highest = [](const TerrainSurface& s) { return s.raster ? s.raster->z_max : s.value; };
  const double top_hi = g.top.kind == K::offset ? highest(g.bottom) + g.top.value : highest(g.top);
  const double bottom_lo =
      g.bottom.kind == K::offset ? lowest(g.top) - g.bottom.value : lowest(g.bottom);
  if (g.top.kind == K::constant && g.bottom.kind == K::constant && g.bottom.value >= g.top.value)
    t.fail("bottom", fmt::format("the bottom ({} m) is not below the top ({} m)", g.bottom.value,
                                 g.top.value));
  g.min = {lo[0], lo[1], bottom_lo};
  g.max = {hi[0], hi[1], top_hi};
}

} // namespace

Geometry read_geometry(TableReader& r, int dim, InputFiles& files, const Vec3a& origin) {
  const std::vector<std::string> kinds = {"box", "polygon", "disk", "sphere", "terrain"};
  std::vector<std::string> present;
  for (const auto& k : kinds)
    if (r.has(k)) present.push_back(k);
  if (present.size() != 1)
    r.fail(present.empty() ? "box" : present[1],
           "a body needs exactly one geometry: box, polygon (2D, or 3D with extrude), disk (2D), "
           "sphere (3D) or terrain (3D)");
  Geometry g;
  const std::string kind = present[0];
  if (r.has("extrude") && !(kind == "polygon" && dim == 3))
    r.fail("extrude", "extrude is for a polygon in 3D");
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
    if (dim != 2 && !r.has("extrude"))
      r.fail("polygon", "a polygon in 3D needs extrude = { axis = \"y\", from = ..., to = ... }; "
                        "or use box, sphere or terrain");
    g.kind = dim == 2 ? Geometry::Kind::polygon : Geometry::Kind::prism;
    g.vertices = read_polygon(r, "polygon", files, g.polygon_file, nullptr, nullptr);
    if (dim == 3) {
      const toml::table* t = r.table("extrude");
      if (!t) r.fail("extrude", "expected a table { axis = \"y\", from = ..., to = ... }");
      TableReader e(*t, r.key_path("extrude"), r.where());
      const std::string axis = e.choice("axis", {"x", "y", "z"}, "z");
      g.axis = axis[0] - 'x';
      const double from = e.number("from"), to = e.number("to");
      require(e, "to", to > from, "must exceed from");
      e.finish();
      // The bounds: the polygon's coordinates on the two other axes, the extrusion on its own.
      const int u = g.axis == 0 ? 1 : 0, w = g.axis == 2 ? 1 : 2;
      g.min[g.axis] = from, g.max[g.axis] = to;
      g.min[u] = g.min[w] = inf, g.max[u] = g.max[w] = -inf;
      for (const auto& v : g.vertices) {
        g.min[u] = std::min(g.min[u], v[0]), g.max[u] = std::max(g.max[u], v[0]);
        g.min[w] = std::min(g.min[w], v[1]), g.max[w] = std::max(g.max[w], v[1]);
      }
    }
  } else if (kind == "terrain") {
    if (dim != 3) r.fail("terrain", "terrain bodies are 3D (elevation along z)");
    read_terrain(r, g, files, origin);
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

namespace {
// What a bad CSV line's error says of it: a short line of printable characters (a typo, a
// header) is quoted; any other is not, so that no more of another file than a short line (no
// secret, binary byte or terminal escape sequence) reaches the terminal.
std::string what_the_line_holds(const std::string& line) {
  constexpr std::size_t longest = 24;
  const bool printable = std::all_of(line.begin(), line.end(), [](char c) {
    return static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) < 0x7f;
  });
  return printable && line.size() <= longest
             ? ", got '" + line + "'"
             : fmt::format(" (the line, {} characters, is not quoted)", line.size());
}
} // namespace

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
      throw CaseError(fmt::format("{}:{}: expected two numbers 'x,y'{}", path, lineno,
                                  what_the_line_holds(line)));
    }
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
      throw CaseError(fmt::format("{}:{}: coordinates must be finite", path, lineno));
    v.push_back(p);
  }
  if (v.size() > 1 && v.front() == v.back()) v.pop_back(); // closed ring
  return v;
}

} // namespace talus
