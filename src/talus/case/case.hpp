// The case file, one-to-one: every TOML section maps onto one struct here. Units are SI, angles
// in degrees. docs/case-file.md documents each key; parse_case() fills and validates it.
#pragma once

#include "talus/case/input_files.hpp"
#include "talus/case/terrain.hpp"
#include "talus/core/shape.hpp"
#include "talus/physics/band.hpp"
#include "talus/physics/materials/material.hpp"

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace talus {

using Vec3a = std::array<double, 3>;
constexpr double inf = std::numeric_limits<double>::infinity();

enum class Scheme { usf, usl, musl };

struct SimulationSettings {
  int dimension = 2;
  double end_time = 0.0;
  double cfl = 0.4;         // used when dt is not given
  std::optional<double> dt; // fixed time step
  double dt_max = inf;      // cap on the CFL step
  // Floor of the CFL step: below it the run stops as blown up (default 1e-4 of the first step).
  std::optional<double> dt_min;
  Vec3a gravity{0.0, 0.0, 0.0};
  Scheme scheme = Scheme::musl;
  double flip = 1.0;    // 1 = pure FLIP, 0 = pure PIC
  int xpic = 0;         // XPIC(m)'s order m; 0: the particles carry their own velocity
  bool apic = false;    // APIC: the particles carry an affine velocity field
  double damping = 0.0; // local (Cundall) damping fraction of the nodal force
};

// What a face of the domain does to the grid velocity: nothing, stop it, stop its normal
// component (a roller), or a Coulomb wall (no penetration, tangential friction).
enum class FaceCondition { free, fixed, slip, friction, outflow };

struct GridSettings {
  Vec3a origin{0.0, 0.0, 0.0};
  Vec3a extent{0.0, 0.0, 0.0};
  double cell_size = 0.0;
  ShapeKind shape = ShapeKind::gimp;
  // x_min, x_max, y_min, y_max, z_min, z_max
  std::array<FaceCondition, 6> faces{};
  std::array<double, 6> face_friction{}; // friction coefficient of `friction` faces
};

struct Geometry {
  // prism: a polygon extruded along an axis (3D); terrain: between two surfaces z = top(x, y)
  // and z = bottom(x, y), inside a footprint polygon if there is one (3D).
  enum class Kind { box, polygon, disk, prism, terrain } kind = Kind::box;
  Vec3a min{}, max{};                          // box (rectangle in 2D); prism and terrain: bounds
  std::vector<std::array<double, 2>> vertices; // polygon (2D), prism section, terrain footprint
  std::string polygon_file;                    // where the vertices came from, if a file
  Vec3a center{};                              // disk (2D) or sphere (3D)
  double radius = 0.0;
  int axis = 2;               // prism: the extrusion's axis; the polygon's two coordinates are
                              // the other two axes in order (axis y: the polygon's (x, z))
  TerrainSurface top, bottom; // terrain
  bool footprint = false;     // terrain: clipped by the polygon in `vertices`
  // Prism and terrain: the faces on the grid's own faces (polygon edge i to i + 1, a prism's
  // caps at from and to), with nothing beyond them: not surfaces for the geometric normal.
  std::vector<char> open_edge;
  std::array<bool, 2> open_cap{};
};

struct BodySpec {
  std::string name;
  int material = 0;               // index into Case::materials
  std::vector<Geometry> geometry; // union of shapes
  int particles_per_cell = 2;     // per direction
  Vec3a velocity{0.0, 0.0, 0.0};  // initial velocity (a rigid body keeps it)
  bool rigid = false;             // prescribed velocity, infinite mass in contact
  bool geometric_normal = false;  // contact normal from the geometry (default: if rigid)
  double lattice_angle = 0.0;     // 2D: rotation (radians) of the particle lattice about the
                                  // first polygon vertex, so an inclined edge is seeded straight
  bool fill_around = false;       // the geometry less every other body's (a reservoir's water)
  // Rigid at rest: its particles and field never change (held by the solver, written once).
  bool fixed(int dimension) const {
    for (int d = 0; d < dimension; ++d)
      if (velocity[d] != 0.0) return false;
    return rigid;
  }
};

// Friction between a pair of bodies; pairs not listed use ContactSettings::friction.
struct ContactPair {
  int a = 0, b = 0;
  double friction = 0.0;
  bool surface = false; // law = "surface": at the deformable body's surface points (formulation.md)
};

// How an interface property degrades with slip s from its initial value v0 to its residual vr
// over the slip s_c (paper Figure 11): linear, bilinear (held at v0 until s_c / 2, then linear
// to vr at s_c) or exponential (vr + (v0 - vr) exp(-3 s / s_c), 95 % degraded at s_c).
enum class DegradationCurve { linear, bilinear, exponential };

struct Degradation {
  double initial = 0.0, residual = 0.0, slip = 1.0;
  double at(double s, DegradationCurve curve) const;
};

// A cohesive-frictional interface between two bodies (paper section 2.4).
// Thermal pressurization of an interface's shear band (physics/band.hpp): its properties and the
// band's temperature before the slide (for output; the model works with the rise).
struct ThermalPressurization {
  BandProperties band;
  double temperature = 20.0; // deg C
};

struct InterfaceSpec {
  int a = 0, b = 0;
  Degradation friction; // coefficient
  Degradation cohesion; // Pa
  DegradationCurve curve = DegradationCurve::linear;
  double tensile_strength = -1; // Pa, degrades with the cohesion; < 0: equal to the cohesion
  // Excess pore pressure on the interface (Pa, over the hydrostatic state of [water]): friction
  // acts on the effective normal traction, c + mu max(sigma_n - p, 0).
  double pore_pressure = 0.0;
  std::optional<ThermalPressurization> thermal_pressurization; // adds its rise to pore_pressure
};

constexpr int max_normal_smoothing = 3; // cells

struct ContactSettings {
  double friction = 0.0;   // default Coulomb coefficient
  double gap_cutoff = 0.8; // cells; < 0 switches the gap check off
  // Contact normals from each body's mass gradient smoothed over the nodes within this many
  // cells (0: the node's own gradient; 2 rounds small blocks' corners). docs/formulation.md.
  int normal_smoothing = 1;
  // A node three or more deformable bodies share (no rigid one): true, the two-body law on each
  // pair in turn (node_law "pairs"); false, each body against the centre of mass of all (the
  // paper's law, "centre_of_mass").
  bool pairwise_nodes = true;
  // A deformable body's particle whose own-body neighbours put less than this fraction of a
  // filled cell's mass on its nodes, with another deformable body's mass around it, maps to that
  // body's field (an orphan; 0 switches it off). See docs/formulation.md.
  double orphan_fraction = 0.1;
  std::vector<ContactPair> pairs;
};

// A velocity condition on the grid nodes inside a box, optionally only for one body's field.
struct BoundarySpec {
  std::string name;
  int body = -1; // -1: every body
  Vec3a min{-inf, -inf, -inf}, max{inf, inf, inf};
  std::array<bool, 3> fixed{false, false, false};
  Vec3a velocity{0.0, 0.0, 0.0};
};

struct ProbeSpec {
  std::string name;
  int body = 0;
  Vec3a near{};
};

// A surface gauge ([[gauge]]): the top of a body's material over a point of the plan (x in 2D,
// x and y in 3D), as a wave gauge reads a free surface (waves.csv).
struct GaugeSpec {
  std::string name;
  int body = 0;
  std::array<double, 2> at{};
};

// A run-up probe ([[run_up]]): the highest point a body's particles reach over a region of the plan
// (an x range in 2D, an x-y box in 3D) from release on, as a slope's wetted line or trimline is
// read (summary.json, `run_up`). `level`: the elevation it is counted from.
struct RunUpSpec {
  std::string name;
  int body = 0;
  std::array<double, 2> min{}, max{};
  double level = 0.0;
};

// Checkpoints for restart (output/checkpoint.hpp): every `every` simulated seconds and every
// `wall_minutes` of wall time (the first after at most first_wall_minutes; 0 turns either off),
// keeping the newest `keep`.
constexpr double first_wall_minutes = 0.5; // a run killed in its first minute can restart
struct CheckpointSettings {
  double every = 0.0;
  double wall_minutes = 3.0;
  int keep = 2;
};

// A verification check (`talus verify`, tools/verify.py): a quantity of the run compared with a
// reference (closed form, experiment, paper) within a tolerance, or with bounds. The solver does
// not use these; they are validated here so a typo fails at once.
struct CheckSpec {
  std::string name, quantity, source, known_miss;
  std::vector<std::string> set; // overrides of the run this check belongs to
  std::optional<double> time, reference, tolerance, abs_tolerance, min, max;
};

// Overrides for `talus verify --quick` (CI resolution) and `--full` (the paper's).
struct VerifySettings {
  std::vector<std::string> quick, full;
};

struct OutputSettings {
  double every = 0.0;              // simulated seconds between frames and CSV rows (0: end only)
  bool particles = true;           // write particles_NNNNNN.vtu
  std::vector<std::string> fields; // extra VTU fields; empty: all
  bool contact_nodes = false;      // write contact_nodes_NNNNNN.vtu: the last step's contact
                                   // force at every node where a body was corrected
  bool float64_fields = false;     // precision = "float64" (default "float32")
  // position_precision: "float32", "float64" or (unset) "auto", float32 where it rounds a
  // position by less than a 2,000th of a cell (float32_positions_suffice).
  std::optional<bool> float32_positions;
  // field_bits: each real field rounded per body to 2^-field_bits of the body's largest value in
  // the frame, and float32 positions to a power of two <= a 1,000th of a cell (0: exact).
  int field_bits = 12;
  // compression = "zlib": frames compressed with zlib (faster to write, about 1.7 times the
  // bytes) instead of "lzma", the default.
  bool zlib_frames = false;
};

// How the stress starts. "none": stress-free. "k0": the overburden of each grid column,
// sigma_v = -|g| (mass above) / (column area), sigma_h = K0 sigma_v with K0 = nu / (1 - nu) of
// each particle's material unless `k0` is given.
// Then, optionally, a settling phase of settle_time seconds with local damping settle_damping
// and the interfaces held (no slip accumulates, so nothing degrades); time restarts at 0 when
// it ends ("release") and displacements are measured from there.
struct InitialState {
  enum class Method { none, k0 } method = Method::none;
  double k0 = -1.0; // < 0: nu / (1 - nu)
  double settle_time = 0.0;
  double settle_damping = 0.2;
  // true: bonded interface nodes have unlimited capacity while settling (the paper's way); false:
  // they have their own, so the settled state already carries any local slip that the weight
  // causes where the bond is weaker than the traction (still nothing degrades).
  bool hold_interfaces = true;
  // true: while settling, every contact sticks (unlimited friction; bodies may still separate),
  // so a body resting on a slope settles to the stress of its equilibrium there: a benchmark
  // whose closed form is a rigid block's then starts from that stress and measures the law.
  bool hold_contacts = false;
  // CFL number while settling (default: simulation.cfl). The settling is damped and quasi-static:
  // a larger number reaches a similar rest in fewer steps.
  std::optional<double> settle_cfl;
};

// A hydrostatic water level ([water]): below it particles weigh their buoyant weight, so the
// stress is the effective stress; the materials' densities are the saturated ones. No seepage.
struct WaterSettings {
  std::optional<double> level; // height of the free surface along -gravity from the origin, m
  double density = 1000.0;     // kg/m^3
};

// Headline figures of a run (summary.json "results"): the motion of one body and its probes.
// Run-out duration: from release until the body's mass-averaged speed falls below stop_speed
// for the last time.
struct ResultsSpec {
  int body = -1;           // -1: no results
  double stop_speed = 0.5; // m/s
};

// A horizontal raster (3D): cell (i, j) covers [x0 + i dx, x0 + (i + 1) dx) x
// [y0 + j dy, y0 + (j + 1) dy) in local metres, i west to east, j south to north; `crs` (WKT,
// empty if none) and `origin` (the [terrain] origin, added back when written) place it on the map.
struct MapGrid {
  double x0 = 0.0, y0 = 0.0, dx = 0.0, dy = 0.0;
  int nx = 0, ny = 0;
  std::string crs;
  std::array<double, 2> origin{};
  std::size_t cells() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
};

// Hazard maps ([maps], 3D): the peak fields of the mapped bodies' moving material on a raster,
// accumulated every step from release, and their deposit (output/peak_maps.hpp).
struct MapsSettings {
  bool enabled = false;
  std::vector<int> bodies;   // the bodies mapped
  double moving_speed = 0.1; // m/s: a particle faster than this is moving material
  // Intensity classes (maps/intensity.tif): high where the peak thickness and the peak speed both
  // exceed the high thresholds, medium where both reach the medium ones, low elsewhere reached.
  // The defaults are the Swiss debris-flow classes (BWW/BRP/BUWAL 1997): high where h > 1 m and
  // v > 1 m/s, medium elsewhere (no low class).
  double high_thickness = 1.0, high_speed = 1.0;     // m, m/s
  double medium_thickness = 0.0, medium_speed = 0.0; // m, m/s
  MapGrid grid;
  std::shared_ptr<const Raster> dem; // the ground drawn under the maps (elevation.tif), if any
  double origin_z = 0.0;             // the [terrain] origin's z, added back to the ground
};

// One parameter of an ensemble ([[sweep.parameter]], `talus sweep`, tools/sweep.py): a `--set`
// key and how its values are drawn. The solver does not use these; they are validated here.
struct SweepParameter {
  std::string key;
  std::string distribution = "uniform"; // uniform, normal, lognormal, triangular (Latin hypercube)
  std::optional<double> lo, hi;         // range (uniform, triangular; bounds of normal/lognormal)
  std::optional<double> mean, sd, mode; // normal and lognormal: of the value; triangular: mode
  int levels = 0;                       // grid design: evenly spaced values over the range
  std::vector<std::string> values;      // a list of values (TOML text) instead of a range
  long line = 0;                        // where `key` is written, for the sweep's messages
};

// [sweep]: the ensemble `talus sweep` runs, and the thresholds of its probability maps.
struct SweepSettings {
  bool present = false;
  std::string design = "lhs"; // "lhs" (Latin hypercube, `runs` runs) or "grid" (all levels)
  int runs = 0;
  long long seed = 1;
  std::vector<SweepParameter> parameters;
  // Probability maps: field (peak_thickness, peak_speed, peak_kinetic_energy, peak_pressure) ->
  // thresholds; the share of runs whose peak exceeds each is mapped.
  std::vector<std::pair<std::string, std::vector<double>>> exceed;
};

// [observed]: what was seen, for a sweep's back-analysis (each run scored against it).
struct ObservedSettings {
  bool present = false;
  std::string impact_area;        // polygons (GeoJSON or anything GDAL reads) in the maps' system
  std::string deposit_thickness;  // a raster on the maps' grid (m)
  double deposit_threshold = 0.1; // m: thicker counts as deposit
  // summary.json `results` figures: key path ("maps.runout_length_m") -> [lo, hi] (lo = hi for a
  // single value).
  std::vector<std::pair<std::string, std::array<double, 2>>> figures;
};

struct Case {
  std::string title;
  std::string file; // path of the case file as given
  std::string text; // the case as written, and a [[run]] entry of its overrides and input copies
  std::string resolved;          // the document as read: overrides applied, [[run]] gone, TOML
  std::vector<InputFile> inputs; // the files it reads, each copied into a run folder's inputs/
  SimulationSettings simulation;
  GridSettings grid;
  std::vector<Material> materials;
  std::vector<BodySpec> bodies;
  std::vector<BoundarySpec> boundaries;
  ContactSettings contact;
  std::vector<InterfaceSpec> interfaces;
  InitialState initial_state;
  WaterSettings water;
  Vec3a terrain_origin{}; // [terrain] origin: subtracted from what the terrain files hold
  ResultsSpec results;
  std::vector<ProbeSpec> probes;
  std::vector<GaugeSpec> gauges;
  std::vector<RunUpSpec> run_ups;
  OutputSettings output;
  CheckpointSettings checkpoint;
  MapsSettings maps;
  std::vector<CheckSpec> checks;
  VerifySettings verify;
  SweepSettings sweep;
  ObservedSettings observed;
};

} // namespace talus
