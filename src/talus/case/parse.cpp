#include "talus/case/parse.hpp"

#include "talus/case/geometry.hpp"
#include "talus/case/read_geometry.hpp"
#include "talus/case/read_materials.hpp"
#include "talus/case/read_outputs.hpp"
#include "talus/case/read_sweep.hpp"
#include "talus/case/run_entries.hpp"
#include "talus/case/size.hpp"
#include "talus/case/toml_reader.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

namespace talus {
namespace {

using namespace case_reading;

SimulationSettings read_simulation(TableReader& r) {
  SimulationSettings s;
  s.dimension = r.integer("dimension", 2, 2, 3);
  require(r, "dimension", s.dimension == 2 || s.dimension == 3, "must be 2 (plane strain) or 3");
  s.end_time = r.number("end_time");
  require(r, "end_time", s.end_time > 0.0, "must be > 0 s");
  s.cfl = r.number("cfl", 0.4);
  require(r, "cfl", s.cfl > 0.0 && s.cfl <= 1.0, "must be in (0, 1]");
  s.dt = r.optional_number("dt");
  if (s.dt) require(r, "dt", *s.dt > 0.0, "must be > 0 s");
  s.dt_max = r.number("dt_max", inf);
  require(r, "dt_max", s.dt_max > 0.0, "must be > 0 s");
  if (s.dt && r.has("dt_max"))
    r.fail("dt_max", "caps the CFL step, so it cannot go with a fixed dt: remove one");
  s.dt_min = r.optional_number("dt_min");
  if (s.dt_min) require(r, "dt_min", *s.dt_min > 0.0, "must be > 0 s");
  s.gravity = r.vector("gravity", s.dimension, Vec3a{0.0, 0.0, 0.0});
  const std::string scheme = r.choice("scheme", {"usf", "usl", "musl"}, "musl");
  s.scheme = scheme == "usf" ? Scheme::usf : scheme == "usl" ? Scheme::usl : Scheme::musl;
  s.flip = r.number("flip", 1.0);
  require(r, "flip", s.flip >= 0.0 && s.flip <= 1.0, "must be in [0, 1] (1 = FLIP, 0 = PIC)");
  const double xpic = r.number("xpic", 0.0); // checked before the cast: a huge value is no int
  require(r, "xpic", xpic >= 0.0 && xpic <= 8.0 && xpic == std::floor(xpic),
          "must be an integer from 0 (off) to 8");
  s.xpic = static_cast<int>(xpic);
  s.apic = r.boolean("apic", false);
  if (s.apic && s.xpic > 0) r.fail("apic", "cannot go with xpic: choose one transfer");
  if (s.apic && r.has("flip"))
    r.fail("flip", "has no meaning under apic (the particles take the grid's velocity and its "
                   "gradient): remove it");
  s.damping = r.number("damping", 0.0);
  require(r, "damping", s.damping >= 0.0 && s.damping < 1.0, "must be in [0, 1)");
  return s;
}

GridSettings read_grid(TableReader& r, int dim) {
  GridSettings g;
  g.origin = r.vector("origin", dim, Vec3a{0.0, 0.0, 0.0});
  g.extent = r.vector("extent", dim);
  for (int d = 0; d < dim; ++d)
    require(r, "extent", g.extent[d] > 0.0, "every extent must be > 0 m");
  g.cell_size = r.number("cell_size");
  require(r, "cell_size", g.cell_size > 0.0, "must be > 0 m");
  for (int d = 0; d < dim; ++d) {
    const double n = g.extent[d] / g.cell_size;
    require(r, "cell_size", n >= 2.0, "the grid needs at least 2 cells per direction");
    require(r, "cell_size", n <= 1e7, "more than 1e7 cells per direction");
  }
  const double nodes = grid_nodes(g, dim), need = nodes * bytes_per_grid_node;
  if (need > machine_memory())
    r.fail("cell_size", fmt::format("{:.3g} grid nodes need about {:.3g} GB, more than this "
                                    "machine's {:.3g} GB: use larger cells",
                                    nodes, need / 1e9, machine_memory() / 1e9));
  const std::string shape = r.choice("shape_function", {"linear", "gimp", "bspline"}, "gimp");
  g.shape = shape == "linear" ? ShapeKind::linear
            : shape == "gimp" ? ShapeKind::gimp
                              : ShapeKind::bspline;
  g.faces.fill(FaceCondition::free);
  if (const toml::table* t = r.table("boundary")) {
    TableReader b(*t, r.key_path("boundary"), r.where());
    const char* names[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    for (int f = 0; f < 2 * dim; ++f) {
      if (const toml::node* n = b.find(names[f]); n && n->is_table()) {
        TableReader w(*n->as_table(), b.key_path(names[f]), r.where());
        g.faces[f] = FaceCondition::friction;
        g.face_friction[f] = w.number("friction");
        require(w, "friction", g.face_friction[f] >= 0.0, "must be >= 0");
        w.finish();
        continue;
      }
      const std::string c = b.choice(names[f], {"free", "fixed", "slip", "outflow"}, "free");
      g.faces[f] = c == "fixed"     ? FaceCondition::fixed
                   : c == "slip"    ? FaceCondition::slip
                   : c == "outflow" ? FaceCondition::outflow
                                    : FaceCondition::free;
    }
    b.finish();
  }
  return g;
}

constexpr double degrees = 3.14159265358979323846 / 180.0;

// [terrain]: the origin of the case's local coordinates in the terrain files' (easting,
// northing, elevation), subtracted from every raster and footprint file a body reads.
void read_terrain_settings(TableReader& root, Case& c) {
  const toml::table* t = root.table("terrain");
  if (!t) return;
  TableReader rt(*t, "terrain", root.where());
  if (c.simulation.dimension != 3) rt.fail("origin", "[terrain] is for 3D cases");
  c.terrain_origin = rt.vector("origin", 3, Vec3a{0.0, 0.0, 0.0});
  rt.finish();
}

// [[body]]: the bodies (at least one), each inside the grid and within the machine's memory.
void read_bodies(TableReader& root, Case& c, InputFiles& files, const MemoryBudget& budget) {
  const int dim = c.simulation.dimension;
  std::vector<std::string> body_names;
  const std::vector<std::string> material_names = names_of(c.materials);
  // On several processes the processes on this machine hold `share` of the particles and
  // fields (MemoryBudget); the grid is counted whole on each.
  const int here = budget.processes_here, processes = budget.processes;
  const double available = budget.bytes > 0.0 ? budget.bytes : machine_memory();
  const double grid = grid_nodes(c.grid, dim) * bytes_per_grid_node * here;
  const double share = budget.share ? budget.share(c.grid.extent[0] / c.grid.cell_size) : 1.0;
  double memory = 0.0;
  for_each_entry(root, "body", [&](TableReader& r, std::size_t) {
    BodySpec b;
    b.name = r.name("name", "");
    if (std::count(body_names.begin(), body_names.end(), b.name))
      r.fail("name", "two bodies have this name");
    b.material = lookup(r, "material", material_names, "material");
    if (c.simulation.apic && std::holds_alternative<Fluid>(c.materials[b.material].model))
      r.fail("material", "a fluid body cannot run under simulation.apic: its particles' affine "
                         "velocities carry the contact's correction into rigid walls (water in a "
                         "tank reaches 0.03 m/s; docs/formulation.md, \"APIC\"): use FLIP or PIC");
    b.geometry.push_back(read_geometry(r, dim, files, c.terrain_origin));
    b.particles_per_cell = r.integer("particles_per_cell", 2, 1, 8);
    b.velocity = r.vector("velocity", dim, Vec3a{0.0, 0.0, 0.0});
    b.rigid = r.boolean("rigid", false);
    b.geometric_normal = r.boolean("geometric_normal", b.rigid);
    if (r.has("lattice_angle")) {
      if (dim != 2) r.fail("lattice_angle", "a rotated particle lattice is 2D only");
      const double a = r.number("lattice_angle");
      require(r, "lattice_angle", std::abs(a) <= 90.0, "must be in [-90, 90] degrees");
      b.lattice_angle = a * degrees;
    }
    b.fill_around = r.boolean("fill_around", false);
    if (b.fill_around && b.lattice_angle != 0.0)
      r.fail("fill_around", "a body filling around the others is seeded on the grid's lattice: "
                            "remove lattice_angle");
    Vec3a lo{}, hi{};
    Geometry& g = b.geometry[0];
    // A terrain body without a footprint is the part of its rasters inside the grid.
    if (g.kind == Geometry::Kind::terrain && !g.footprint)
      for (int d = 0; d < 2; ++d) {
        g.min[d] = std::max(g.min[d], c.grid.origin[d]);
        g.max[d] = std::min(g.max[d], c.grid.origin[d] + c.grid.extent[d]);
        if (g.min[d] >= g.max[d])
          r.fail("terrain",
                 fmt::format("its rasters do not reach into the grid along {}", "xy"[d]));
      }
    geometry_bounds(g, dim, lo, hi);
    for (int d = 0; d < dim; ++d) {
      const double g0 = c.grid.origin[d], g1 = g0 + c.grid.extent[d];
      if (lo[d] < g0 || hi[d] > g1)
        r.fail(g.kind == Geometry::Kind::polygon || g.kind == Geometry::Kind::prism ? "polygon"
               : g.kind == Geometry::Kind::box                                      ? "box"
               : g.kind == Geometry::Kind::terrain                                  ? "terrain"
                                                   : (dim == 2 ? "disk" : "sphere"),
               fmt::format("the body reaches outside the grid along {} ([{}, {}] is not inside "
                           "[{}, {}])",
                           "xyz"[d], lo[d], hi[d], g0, g1));
    }
    // A prism's or a terrain's faces on the grid's faces bound nothing (no body can be beyond):
    // the geometric normal ignores them, so a wall of the grid is not a wall of the body.
    if (g.kind == Geometry::Kind::prism || (g.kind == Geometry::Kind::terrain && g.footprint)) {
      const int u = g.kind == Geometry::Kind::prism ? prism_axes(g.axis)[0] : 0;
      const int w = g.kind == Geometry::Kind::prism ? prism_axes(g.axis)[1] : 1;
      auto on_face = [&](int d, double v) {
        return v == c.grid.origin[d] || v == c.grid.origin[d] + c.grid.extent[d];
      };
      const auto& v = g.vertices;
      g.open_edge.assign(v.size(), 0);
      for (std::size_t i = 0; i < v.size(); ++i) {
        const auto &a = v[i], &e = v[(i + 1) % v.size()];
        g.open_edge[i] = (a[0] == e[0] && on_face(u, a[0])) || (a[1] == e[1] && on_face(w, a[1]));
      }
      if (g.kind == Geometry::Kind::prism)
        g.open_cap = {on_face(g.axis, g.min[g.axis]), on_face(g.axis, g.max[g.axis])};
    }
    // Memory, before anything is allocated: this body's particles and velocity field on top of
    // the bodies before it and the grid (its field counted with contact, MUSL's re-map and one
    // interface slot: the interfaces are read later).
    memory += estimate_particles(b.geometry[0], dim, c.grid.cell_size, b.particles_per_cell) *
                  bytes_per_particle(dim, c.simulation.apic) +
              field_nodes(lo, hi, dim, c.grid.cell_size) *
                  bytes_per_field_node(dim, true, c.simulation.scheme == Scheme::musl, 1);
    if (const double need = grid + share * memory; need > available)
      r.fail("particles_per_cell",
             fmt::format("the case needs about {:.3g} GB up to this body{}, more than this "
                         "machine's {:.3g} GB: use larger grid cells or fewer particles per "
                         "cell{}",
                         need / 1e9,
                         processes > 1
                             ? fmt::format(" on this machine's {} of {} processes", here, processes)
                             : std::string(),
                         available / 1e9, processes > 1 ? ", or run on more machines" : ""));
    c.bodies.push_back(std::move(b));
    body_names.push_back(c.bodies.back().name);
  });
  if (c.bodies.empty()) root.fail_missing("body");
}

// [[boundary]]: velocity conditions on the nodes in a box.
void read_boundaries(TableReader& root, Case& c) {
  const int dim = c.simulation.dimension;
  const std::vector<std::string> body_names = names_of(c.bodies);
  for_each_entry(root, "boundary", [&](TableReader& r, std::size_t i) {
    BoundarySpec b;
    b.name = r.string("name", fmt::format("boundary{}", i));
    if (r.has("body")) b.body = lookup(r, "body", body_names, "body");
    b.min = r.vector("min", dim, Vec3a{-inf, -inf, -inf});
    b.max = r.vector("max", dim, Vec3a{inf, inf, inf});
    const char* comps[3] = {"velocity_x", "velocity_y", "velocity_z"};
    for (int d = 0; d < dim; ++d)
      if (r.has(comps[d])) b.fixed[d] = true, b.velocity[d] = r.number(comps[d]);
    if (r.has("velocity")) {
      b.velocity = r.vector("velocity", dim);
      for (int d = 0; d < dim; ++d)
        b.fixed[d] = true;
    }
    if (!b.fixed[0] && !b.fixed[1] && !b.fixed[2])
      r.fail("velocity", "a boundary must set velocity or at least one of velocity_x/_y/_z");
    for (int d = 0; d < dim; ++d) {
      const double g0 = c.grid.origin[d], g1 = g0 + c.grid.extent[d];
      if (b.min[d] > b.max[d])
        r.fail("max", fmt::format("max is below min along {}: the box holds no node", "xyz"[d]));
      if (b.max[d] < g0 || b.min[d] > g1)
        r.fail(r.has("min") ? "min" : "max",
               fmt::format("the box [{}, {}] along {} misses the grid [{}, {}]: it holds no node",
                           b.min[d], b.max[d], "xyz"[d], g0, g1));
    }
    c.boundaries.push_back(b);
  });
}

// [[contact]]: an entry with `bodies` sets that pair's friction; one entry without sets the
// default friction, the gap check, the normal smoothing, the law at a node of three or more
// bodies and the orphan fraction.
void read_contact(TableReader& root, Case& c) {
  const std::vector<std::string> body_names = names_of(c.bodies);
  bool has_default = false;
  for_each_entry(root, "contact", [&](TableReader& r, std::size_t) {
    const double mu = r.number("friction");
    require(r, "friction", mu >= 0.0, "must be >= 0");
    if (!r.has("bodies")) {
      if (has_default)
        r.fail("friction", "only one [[contact]] entry may omit bodies (the default)");
      has_default = true;
      c.contact.friction = mu;
      c.contact.gap_cutoff = r.number("gap_cutoff", 0.8);
      c.contact.normal_smoothing =
          r.integer("normal_smoothing", c.contact.normal_smoothing, 0, max_normal_smoothing);
      c.contact.pairwise_nodes =
          r.choice("node_law", {"pairs", "centre_of_mass"}, "pairs") == "pairs";
      c.contact.orphan_fraction = r.number("orphan_fraction", c.contact.orphan_fraction);
      require(r, "orphan_fraction",
              c.contact.orphan_fraction >= 0.0 && c.contact.orphan_fraction < 0.5,
              "must be in [0, 0.5) (a fraction of a filled cell's nodal mass)");
      return;
    }
    const auto [first, second] = read_body_pair(r, body_names);
    for (const ContactPair& q : c.contact.pairs)
      if (std::minmax(q.a, q.b) == std::minmax(first, second))
        r.fail("bodies", fmt::format("the pair '{}'-'{}' already has a [[contact]] entry",
                                     body_names[first], body_names[second]));
    const bool surface = r.choice("law", {"nodes", "surface"}, "nodes") == "surface";
    if (surface) { // a deformable body of one exact shape against a rigid body of one
      const int dim = c.simulation.dimension;
      const BodySpec& A = c.bodies[first];
      const BodySpec& B = c.bodies[second];
      if (A.rigid == B.rigid)
        r.fail("law", fmt::format("\"surface\" needs one rigid and one deformable body; '{}' and "
                                  "'{}' are both {}",
                                  A.name, B.name, A.rigid ? "rigid" : "deformable"));
      const BodySpec& soft = A.rigid ? B : A;
      if (std::holds_alternative<Fluid>(c.materials[soft.material].model))
        r.fail("law", fmt::format("\"surface\" needs a solid body: '{}' is a fluid, whose "
                                  "particles keep no surface",
                                  soft.name));
      for (const BodySpec* body : {&A, &B})
        if (body->geometry.size() != 1 || !has_exact_surface(body->geometry[0], dim))
          r.fail("law", fmt::format("\"surface\" needs each body to be one box, disk or polygon "
                                    "(2D) or one box or sphere (3D); '{}' is {}",
                                    body->name,
                                    body->geometry.size() != 1 ? "a union of shapes"
                                                               : "another kind of shape"));
      if (A.fill_around || B.fill_around)
        r.fail("law", fmt::format("\"surface\" does not take '{}', a body filled around the others",
                                  A.fill_around ? A.name : B.name));
    }
    c.contact.pairs.push_back(ContactPair{first, second, mu, surface});
  });
}

// [[interface]]: cohesive-frictional pairs, their degradation with slip.
void read_interfaces(TableReader& root, Case& c) {
  const std::vector<std::string> body_names = names_of(c.bodies);
  for_each_entry(root, "interface", [&](TableReader& r, std::size_t) {
    InterfaceSpec f;
    std::tie(f.a, f.b) = read_body_pair(r, body_names);
    for (const ContactPair& q : c.contact.pairs)
      if (q.surface && std::minmax(q.a, q.b) == std::minmax(f.a, f.b))
        r.fail("bodies", fmt::format("the pair '{}'-'{}' meets at surface points ([[contact]] law "
                                     "= \"surface\"), which carry no interface",
                                     body_names[f.a], body_names[f.b]));
    for (const InterfaceSpec& q : c.interfaces)
      if (std::minmax(q.a, q.b) == std::minmax(f.a, f.b))
        r.fail("bodies", fmt::format("the pair '{}'-'{}' already has an [[interface]] entry",
                                     body_names[f.a], body_names[f.b]));
    auto degradation = [&](const std::string& key, const std::string& unit) {
      const toml::table* t = r.table(key);
      if (!t) r.fail_missing(key);
      TableReader d(*t, r.key_path(key), r.where());
      Degradation g;
      g.initial = d.number("initial");
      require(d, "initial", g.initial >= 0.0, "must be >= 0 " + unit);
      g.residual = d.number("residual", g.initial);
      require(d, "residual", g.residual >= 0.0 && g.residual <= g.initial,
              "must be in [0, initial]");
      g.slip = d.number("slip", 1.0);
      require(d, "slip", g.slip > 0.0, "must be > 0 m");
      d.finish();
      return g;
    };
    f.friction = degradation("friction", "");
    f.cohesion = degradation("cohesion", "Pa");
    const std::string curve = r.choice("curve", {"linear", "bilinear", "exponential"}, "linear");
    f.curve = curve == "bilinear"      ? DegradationCurve::bilinear
              : curve == "exponential" ? DegradationCurve::exponential
                                       : DegradationCurve::linear;
    f.tensile_strength = r.number("tensile_strength", -1.0);
    if (r.has("tensile_strength"))
      require(r, "tensile_strength", f.tensile_strength >= 0.0, "must be >= 0 Pa");
    f.pore_pressure = r.number("pore_pressure", 0.0);
    require(r, "pore_pressure", f.pore_pressure >= 0.0, "must be >= 0 Pa (an excess pressure)");
    if (const toml::table* t = r.table("thermal_pressurization")) {
      TableReader tp(*t, r.key_path("thermal_pressurization"), r.where());
      ThermalPressurization th;
      auto positive = [&](const std::string& key, const std::string& unit) {
        const double v = tp.number(key);
        require(tp, key, v > 0.0, "must be > 0 " + unit);
        return v;
      };
      auto non_negative = [&](const std::string& key, const std::string& unit) {
        const double v = tp.number(key);
        require(tp, key, v >= 0.0, "must be >= 0 " + unit);
        return v;
      };
      th.band.thickness = positive("thickness", "m");
      th.band.heat_capacity = positive("heat_capacity", "J/(m^3 K)");
      th.band.thermal_diffusivity = non_negative("thermal_diffusivity", "m^2/s");
      th.band.hydraulic_diffusivity = non_negative("hydraulic_diffusivity", "m^2/s");
      th.band.lambda = non_negative("lambda", "Pa/K");
      th.temperature = tp.number("temperature", 20.0);
      require(tp, "temperature", th.temperature > -273.15, "must be above absolute zero (deg C)");
      tp.finish();
      f.thermal_pressurization = th;
    }
    c.interfaces.push_back(f);
  });
}

// [initial_state]: K0 stresses and the settling phase.
void read_initial_state(TableReader& root, Case& c) {
  if (const toml::table* init = root.table("initial_state")) {
    TableReader ri(*init, "initial_state", root.where());
    const std::string method = ri.choice("method", {"none", "k0"}, "none");
    c.initial_state.method = method == "k0" ? InitialState::Method::k0 : InitialState::Method::none;
    if (ri.has("k0")) {
      c.initial_state.k0 = ri.number("k0");
      require(ri, "k0", c.initial_state.k0 > 0.0 && c.initial_state.k0 <= 3.0, "must be in (0, 3]");
      if (c.initial_state.method != InitialState::Method::k0)
        ri.fail("k0", "is used only with method = \"k0\"");
    }
    c.initial_state.settle_time = ri.number("settle_time", 0.0);
    require(ri, "settle_time", c.initial_state.settle_time >= 0.0, "must be >= 0 s");
    c.initial_state.settle_damping = ri.number("settle_damping", 0.2);
    require(ri, "settle_damping",
            c.initial_state.settle_damping >= 0.0 && c.initial_state.settle_damping < 1.0,
            "must be in [0, 1)");
    c.initial_state.hold_interfaces = ri.boolean("hold_interfaces", true);
    c.initial_state.hold_contacts = ri.boolean("hold_contacts", false);
    c.initial_state.settle_cfl = ri.optional_number("settle_cfl");
    if (c.initial_state.settle_cfl) {
      require(ri, "settle_cfl",
              *c.initial_state.settle_cfl > 0.0 && *c.initial_state.settle_cfl <= 1.0,
              "must be in (0, 1]");
      if (c.simulation.dt)
        ri.fail("settle_cfl", "has no effect with a fixed simulation.dt: remove one");
    }
    ri.finish();
  }
}

// [water]: a hydrostatic level, and the water's density, below the saturated density of every
// deformable body's material (a saturated soil is heavier than water; a water body is the water).
void read_water(TableReader& root, Case& c) {
  const toml::table* w = root.table("water");
  if (!w) return;
  TableReader rw(*w, "water", root.where());
  c.water.level = rw.number("level");
  c.water.density = rw.number("density", 1000.0);
  require(rw, "density", c.water.density > 0.0, "must be > 0 kg/m^3");
  double g = 0.0;
  for (const double x : c.simulation.gravity)
    g += x * x;
  require(rw, "level", g > 0.0, "a water level needs gravity (simulation.gravity is zero)");
  for (const BodySpec& b : c.bodies) {
    const Material& m = c.materials[b.material];
    if (!b.rigid && !std::holds_alternative<Fluid>(m.model) && m.density() <= c.water.density)
      rw.fail("density",
              fmt::format("{} kg/m^3 is not below the density of material '{}' ({} kg/m^3) of "
                          "body '{}': below the level a material's density is the saturated one",
                          c.water.density, m.name, m.density(), b.name));
  }
  rw.finish();
}

} // namespace

namespace {

// A dotted key or table header nested deeper than any case needs (a.a.a... 100,000 deep made the
// TOML reader recurse off the stack): refused, naming the line, before the text is parsed. Dots
// inside quotes do not count.
void refuse_deep_keys(const std::string& text, const std::string& path) {
  constexpr int max_depth = 32;
  std::size_t at = 0;
  for (int line = 1; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    int dots = 0;
    char quote = 0;
    std::size_t i = std::min(text.find_first_not_of(" \t", at), end);
    for (int k = 0; k < 2 && i < end && text[i] == '['; ++k)
      ++i; // a [table] or [[array]] header
    for (; i < end; ++i) {
      const char ch = text[i];
      if (quote) {
        if (ch == quote) quote = 0;
      } else if (ch == '"' || ch == '\'') {
        quote = ch;
      } else if (ch == '.') {
        ++dots;
      } else if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' &&
                 ch != ' ' && ch != '\t') {
        break; // past the key: '=', ']', ',', a comment
      }
    }
    if (dots >= max_depth)
      throw CaseError(fmt::format("{}:{}: a key nested {} tables deep; a case's keys are at "
                                  "most {} deep",
                                  path, line, dots + 1, max_depth));
    at = end + 1;
  }
}

} // namespace

Case parse_case_text(const std::string& text, const std::string& path,
                     const std::vector<std::string>& overrides, const MemoryBudget& budget) {
  refuse_deep_keys(text, path);
  toml::table doc;
  try {
    doc = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw CaseError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  }
  Where where{path};
  InputFiles files(std::filesystem::path(path).parent_path());
  for (const auto& o : take_run_entries(doc, where, files))
    apply_override(doc, o, path);
  for (const auto& o : overrides)
    apply_override(doc, Override{o}, path);

  TableReader root(doc, "", where);
  Case c;
  c.file = path;
  std::ostringstream resolved;
  resolved << doc << "\n";
  c.resolved = resolved.str();
  c.title = root.string("title", "");

  const toml::table* sim = root.table("simulation");
  if (!sim) root.fail_missing("simulation");
  TableReader rs(*sim, "simulation", where);
  c.simulation = read_simulation(rs);
  rs.finish();
  const int dim = c.simulation.dimension;

  const toml::table* grid = root.table("grid");
  if (!grid) root.fail_missing("grid");
  TableReader rg(*grid, "grid", where);
  c.grid = read_grid(rg, dim);
  rg.finish();

  read_materials(root, c);
  read_terrain_settings(root, c);
  read_bodies(root, c, files, budget);
  read_boundaries(root, c);
  read_contact(root, c);
  read_interfaces(root, c);
  read_initial_state(root, c);
  read_water(root, c);
  read_results(root, c);
  read_probes(root, c);
  read_gauges(root, c);
  read_run_ups(root, c);
  read_output(root, c);
  read_checkpoint(root, c);
  read_maps(root, c);
  read_checks(root, c);
  read_verify(root, c);
  read_sweep(root, c);
  read_observed(root, c, files);
  root.finish();
  c.inputs = files.files();
  c.text = text_as_run(text, overrides, files);
  return c;
}

Case parse_case_file(const std::string& path, const std::vector<std::string>& overrides,
                     const MemoryBudget& budget) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw CaseError(fmt::format("{}: {}", path,
                                std::filesystem::exists(path, ec)
                                    ? "not a regular file (a case file is a TOML text file)"
                                    : "no such file"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CaseError(fmt::format("{}: cannot open the case file", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_case_text(ss.str(), path, overrides, budget);
}

} // namespace talus
