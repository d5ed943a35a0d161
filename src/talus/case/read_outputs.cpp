#include "talus/case/read_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace talus::case_reading {

// [results]: the body whose motion the summary reports.
void read_results(TableReader& root, Case& c) {
  const std::vector<std::string> body_names = names_of(c.bodies);
  if (const toml::table* res = root.table("results")) {
    TableReader rr(*res, "results", root.where());
    c.results.body = lookup(rr, "body", body_names, "body");
    c.results.stop_speed = rr.number("stop_speed", 0.5);
    require(rr, "stop_speed", c.results.stop_speed > 0.0, "must be > 0 m/s");
    rr.finish();
  }
}

// [[probe]]: particles followed by name.
void read_probes(TableReader& root, Case& c) {
  const int dim = c.simulation.dimension;
  const std::vector<std::string> body_names = names_of(c.bodies);
  for_each_entry(root, "probe", [&](TableReader& r, std::size_t i) {
    ProbeSpec p;
    p.name = r.name("name", fmt::format("probe{}", i));
    for (const ProbeSpec& q : c.probes)
      if (q.name == p.name) r.fail("name", "two probes have this name");
    p.body = lookup(r, "body", body_names, "body");
    p.near = r.vector("near", dim);
    for (int d = 0; d < dim; ++d)
      if (p.near[d] < c.grid.origin[d] || p.near[d] > c.grid.origin[d] + c.grid.extent[d])
        r.fail("near", fmt::format("the point is outside the grid along {}", "xyz"[d]));
    c.probes.push_back(p);
  });
}

// [[gauge]]: surface gauges (waves.csv).
void read_gauges(TableReader& root, Case& c) {
  const int dim = c.simulation.dimension;
  const std::vector<std::string> body_names = names_of(c.bodies);
  for_each_entry(root, "gauge", [&](TableReader& r, std::size_t i) {
    GaugeSpec g;
    g.name = r.name("name", fmt::format("gauge{}", i));
    for (const GaugeSpec& q : c.gauges)
      if (q.name == g.name) r.fail("name", "two gauges have this name");
    g.body = lookup(r, "body", body_names, "body");
    if (dim == 2) {
      g.at[0] = r.number("at");
    } else {
      const Vec3a a = r.vector("at", 2);
      g.at = {a[0], a[1]};
    }
    for (int d = 0; d < dim - 1; ++d)
      if (g.at[d] < c.grid.origin[d] || g.at[d] > c.grid.origin[d] + c.grid.extent[d])
        r.fail("at", fmt::format("the point is outside the grid along {}", "xy"[d]));
    c.gauges.push_back(g);
  });
}

// [[run_up]]: the highest point a body reaches over a region of the plan (summary.json).
void read_run_ups(TableReader& root, Case& c) {
  const int dim = c.simulation.dimension;
  const std::vector<std::string> body_names = names_of(c.bodies);
  for_each_entry(root, "run_up", [&](TableReader& r, std::size_t i) {
    RunUpSpec u;
    u.name = r.name("name", fmt::format("run_up{}", i));
    for (const RunUpSpec& q : c.run_ups)
      if (q.name == u.name) r.fail("name", "two run-up probes have this name");
    u.body = lookup(r, "body", body_names, "body");
    // The region's corners in the plan (x in 2D, x and y in 3D): the grid's by default.
    for (int d = 0; d < dim - 1; ++d)
      u.min[d] = c.grid.origin[d], u.max[d] = c.grid.origin[d] + c.grid.extent[d];
    for (const char* key : {"min", "max"}) {
      if (!r.has(key)) continue;
      std::array<double, 2>& corner = key[1] == 'i' ? u.min : u.max;
      if (dim == 2) {
        corner[0] = r.number(key);
      } else {
        const Vec3a a = r.vector(key, 2);
        corner = {a[0], a[1]};
      }
    }
    for (int d = 0; d < dim - 1; ++d)
      if (!(u.min[d] < u.max[d]))
        r.fail("max", fmt::format("the region is empty along {}: max must exceed min", "xy"[d]));
    u.level = r.number("level", c.water.level.value_or(0.0));
    c.run_ups.push_back(u);
  });
}

// [output]: the frames and their fields.
void read_output(TableReader& root, Case& c) {
  if (const toml::table* out = root.table("output")) {
    TableReader ro(*out, "output", root.where());
    c.output.every = ro.number("every", 0.0);
    require(ro, "every", c.output.every >= 0.0, "must be >= 0 s");
    c.output.particles = ro.boolean("particles", true);
    c.output.contact_nodes = ro.boolean("contact_nodes", false);
    c.output.float64_fields =
        ro.choice("precision", {"float32", "float64"}, "float32") == "float64";
    // Frames compact by default: each float32 field to 12 bits of its body's range (docs/
    // case-file.md, [output]); float64 fields are exact unless field_bits is given.
    c.output.field_bits = ro.integer("field_bits", c.output.float64_fields ? 0 : 12, 0, 22);
    require(ro, "field_bits", c.output.field_bits == 0 || c.output.field_bits >= 8,
            "must be 0 (exact) or in [8, 22]");
    c.output.zlib_frames = ro.choice("compression", {"lzma", "zlib"}, "lzma") == "zlib";
    if (const std::string p =
            ro.choice("position_precision", {"auto", "float64", "float32"}, "auto");
        p != "auto")
      c.output.float32_positions = p == "float32";
    if (const toml::array* f = ro.array("fields")) {
      const std::vector<std::string> known = {
          "velocity", "stress",   "displacement", "mass",  "volume",        "plastic_strain",
          "body",     "material", "interface",    "field", "pore_pressure", "band_temperature"};
      for (std::size_t i = 0; i < f->size(); ++i) {
        const auto s = f->get(i)->value<std::string>();
        if (!s)
          ro.where().fail(f->get(i)->source(), fmt::format("output.fields[{}]", i),
                          fmt::format("expected a field name (a string), got {}",
                                      TableReader::type_name(*f->get(i))));
        if (std::find(known.begin(), known.end(), *s) == known.end())
          ro.where().fail(f->get(i)->source(), fmt::format("output.fields[{}]", i),
                          fmt::format("unknown field '{}'{}", *s, suggest(*s, known)));
        c.output.fields.push_back(*s);
      }
    }
    ro.finish();
  }
}

// [checkpoint]: how often checkpoints are written and how many are kept.
void read_checkpoint(TableReader& root, Case& c) {
  if (const toml::table* ck = root.table("checkpoint")) {
    TableReader rc(*ck, "checkpoint", root.where());
    c.checkpoint.every = rc.number("every", 0.0);
    require(rc, "every", c.checkpoint.every >= 0.0, "must be >= 0 s (0: off)");
    c.checkpoint.wall_minutes = rc.number("wall_minutes", c.checkpoint.wall_minutes);
    require(rc, "wall_minutes", c.checkpoint.wall_minutes >= 0.0, "must be >= 0 min (0: off)");
    c.checkpoint.keep = rc.integer("keep", 2, 1, 100);
    rc.finish();
  }
}

// [maps] (3D): the mapped bodies, the speed that counts as moving, and the raster: the DEM of the
// first mapped body with a terrain top (its grid, extent and coordinate system), or a cell size
// over the case's grid.
void read_maps(TableReader& root, Case& c) {
  const toml::table* t = root.table("maps");
  if (!t) return;
  TableReader r(*t, "maps", root.where());
  MapsSettings& m = c.maps;
  m.enabled = true;
  const std::vector<std::string> body_names = names_of(c.bodies);
  if (!r.has("bodies")) r.fail_missing("bodies");
  for (const std::string& name : string_list(r, "bodies")) {
    const auto it = std::find(body_names.begin(), body_names.end(), name);
    if (it == body_names.end())
      r.fail("bodies", fmt::format("no body is named '{}'{}", name, suggest(name, body_names)));
    const int b = static_cast<int>(it - body_names.begin());
    if (std::find(m.bodies.begin(), m.bodies.end(), b) != m.bodies.end())
      r.fail("bodies", fmt::format("'{}' is named twice", name));
    // A mapped body's name goes into file names (deposit_thickness_NAME.tif) and CSV columns.
    if (name.find_first_not_of(
            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
        std::string::npos)
      r.fail("bodies", fmt::format("'{}': a mapped body's name is letters, digits, _ and - only "
                                   "(it names its map files)",
                                   name));
    m.bodies.push_back(b);
  }
  if (m.bodies.empty()) r.fail("bodies", "name at least one body, e.g. bodies = [\"slide\"]");
  m.moving_speed = r.number("moving_speed", m.moving_speed);
  require(r, "moving_speed", m.moving_speed > 0.0, "must be > 0 m/s");
  m.high_thickness = r.number("high_thickness", m.high_thickness);
  m.high_speed = r.number("high_speed", m.high_speed);
  m.medium_thickness = r.number("medium_thickness", m.medium_thickness);
  m.medium_speed = r.number("medium_speed", m.medium_speed);
  require(r, "medium_thickness", m.medium_thickness >= 0.0, "must be >= 0 m");
  require(r, "medium_speed", m.medium_speed >= 0.0, "must be >= 0 m/s");
  require(r, "high_thickness", m.high_thickness >= m.medium_thickness,
          "must be >= medium_thickness (the classes are nested)");
  require(r, "high_speed", m.high_speed >= m.medium_speed,
          "must be >= medium_speed (the classes are nested)");
  // The DEM: the top raster of the first mapped body that has one.
  std::shared_ptr<const Raster> dem;
  for (const int b : m.bodies)
    for (const Geometry& g : c.bodies[b].geometry)
      if (!dem && g.kind == Geometry::Kind::terrain && g.top.raster) dem = g.top.raster;
  MapGrid& G = m.grid;
  if (c.simulation.dimension == 2) { // a profile along the section: one row of cells along x
    if (!r.has("cell_size")) r.fail_missing("cell_size");
    const double h = r.number("cell_size");
    require(r, "cell_size", h > 0.0, "must be > 0 m");
    const double nx = std::ceil(c.grid.extent[0] / h - 1e-9);
    require(r, "cell_size", nx <= 1e8, "gives more than 1e8 profile cells");
    G.x0 = c.grid.origin[0], G.dx = h, G.nx = static_cast<int>(nx);
    G.y0 = c.grid.origin[1], G.dy = c.grid.extent[1], G.ny = 1;
    r.finish();
    return;
  }
  G.origin = {c.terrain_origin[0], c.terrain_origin[1]};
  m.dem = dem, m.origin_z = c.terrain_origin[2];
  if (const std::optional<double> h = r.optional_number("cell_size")) {
    require(r, "cell_size", *h > 0.0, "must be > 0 m");
    G.x0 = c.grid.origin[0], G.y0 = c.grid.origin[1], G.dx = G.dy = *h;
    const double nx = std::ceil(c.grid.extent[0] / *h - 1e-9),
                 ny = std::ceil(c.grid.extent[1] / *h - 1e-9);
    require(r, "cell_size", nx * ny <= 1e8, "gives more than 1e8 raster cells");
    G.nx = static_cast<int>(nx), G.ny = static_cast<int>(ny);
    if (dem) G.crs = dem->crs;
  } else {
    if (!dem)
      r.fail("cell_size", "required: no mapped body has a terrain top raster to take the grid "
                          "from");
    G.x0 = dem->x0, G.y0 = dem->y0, G.dx = dem->dx, G.dy = dem->dy;
    G.nx = dem->nx, G.ny = dem->ny, G.crs = dem->crs;
    require(r, "cell_size", static_cast<double>(G.nx) * G.ny <= 1e8,
            fmt::format("required: the DEM has {} x {} cells, more than the 1e8 a map may have",
                        G.nx, G.ny));
  }
  r.finish();
}

// [[check]]: verification checks (talus verify).
void read_checks(TableReader& root, Case& c) {
  const int dim = c.simulation.dimension;
  for_each_entry(root, "check", [&](TableReader& r, std::size_t) {
    CheckSpec k;
    k.name = r.name("name", "");
    for (const CheckSpec& q : c.checks)
      if (q.name == k.name) r.fail("name", "two checks have this name");
    k.quantity = r.name("quantity", "");
    k.source = r.name("source", "");
    if (r.has("known_miss")) k.known_miss = r.name("known_miss", "");
    k.set = string_list(r, "set");
    k.time = r.optional_number("time");
    if (k.time) require(r, "time", *k.time >= 0.0, "must be >= 0 s");
    k.reference = r.optional_number("reference");
    k.tolerance = r.optional_number("tolerance");
    k.abs_tolerance = r.optional_number("abs_tolerance");
    k.min = r.optional_number("min");
    k.max = r.optional_number("max");
    if (k.tolerance) require(r, "tolerance", *k.tolerance > 0.0, "must be > 0 (relative)");
    if (k.abs_tolerance) require(r, "abs_tolerance", *k.abs_tolerance > 0.0, "must be > 0");
    if (k.reference.has_value() == (k.min || k.max))
      r.fail("reference", "give a reference (with tolerance or abs_tolerance) or min/max bounds");
    if (k.reference && !k.tolerance && !k.abs_tolerance)
      r.fail("tolerance", "a reference needs tolerance (relative) or abs_tolerance");
    if (r.has("direction")) r.vector("direction", dim);
    if (r.has("near")) r.vector("near", dim);
    c.checks.push_back(k);
  });
}

// [verify]: the overrides of talus verify --quick and --full.
void read_verify(TableReader& root, Case& c) {
  if (const toml::table* v = root.table("verify")) {
    TableReader rv(*v, "verify", root.where());
    c.verify.quick = string_list(rv, "quick");
    c.verify.full = string_list(rv, "full");
    rv.finish();
  }
}

} // namespace talus::case_reading
