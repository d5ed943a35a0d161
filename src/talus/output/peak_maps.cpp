#include "talus/output/peak_maps.hpp"

#include "talus/core/gdal.hpp"
#include "talus/output/files.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <limits>

namespace talus {

namespace {

constexpr double no_data = -9999.0;

// The largest shift s with bound * 2^s below 2^62: sums of values up to `bound` in total, each
// rounded to 2^-s, stay within an int64 with room for the rounding.
int fixed_point_shift(double bound) {
  return 62 - static_cast<int>(std::ceil(std::log2(std::max(bound, 1e-300))));
}

std::int64_t fixed(double value, int shift) {
  return std::llround(std::ldexp(value, shift));
}

double unfixed(std::int64_t value, int shift) {
  return std::ldexp(static_cast<double>(value), -shift);
}

// The grid's geotransform, north up (the first row is the northern one), the [terrain] origin
// added back.
std::array<double, 6> geotransform(const MapGrid& grid) {
  return {grid.x0 + grid.origin[0],
          grid.dx,
          0.0,
          grid.y0 + grid.ny * grid.dy + grid.origin[1],
          0.0,
          -grid.dy};
}

// The grid as GDAL writes it: north up, the [terrain] origin added back.
gdal::RasterGrid raster_grid(const MapGrid& grid) {
  return {grid.nx, grid.ny, geotransform(grid), grid.crs};
}

// GDAL's module, or an OutputError naming the map that needed it.
const gdal::Module& gdal_for(const std::string& path) {
  try {
    return gdal::module();
  } catch (const std::runtime_error& e) {
    throw OutputError(fmt::format("{}: {}", path, e.what()));
  }
}

// Writes a map GDAL made in memory to `path` atomically, or throws GDAL's reason.
void write_made(const gdal::Made& made, const std::string& path) {
  if (!made.error.empty()) throw OutputError(fmt::format("{}: {}", path, made.error));
  write_file_atomic(path, made.bytes);
}

} // namespace

void write_geotiff(const std::string& path, const MapGrid& grid,
                   const std::vector<MapLayer>& layers,
                   const std::vector<std::pair<std::string, std::string>>& metadata) {
  // Rows in file order, the northern first; NaN written as the no-data value.
  std::vector<gdal::Band> bands;
  for (const MapLayer& L : layers) {
    gdal::Band& b = bands.emplace_back(gdal::Band{L.name, L.unit, L.description, {}});
    b.rows.resize(grid.cells());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i) {
        const double v = L.values[static_cast<std::size_t>(j) * grid.nx + i];
        b.rows[static_cast<std::size_t>(grid.ny - 1 - j) * grid.nx + i] =
            static_cast<float>(std::isnan(v) ? no_data : v);
      }
  }
  write_made(gdal_for(path).geotiff(raster_grid(grid), bands, metadata, no_data), path);
}

void write_outline(const std::string& path, const MapGrid& grid, const std::vector<char>& inside,
                   const std::string& name) {
  std::vector<unsigned char> rows(grid.cells());
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      rows[static_cast<std::size_t>(grid.ny - 1 - j) * grid.nx + i] =
          inside[static_cast<std::size_t>(j) * grid.nx + i] ? 1 : 0;
  write_made(gdal_for(path).outline(raster_grid(grid), rows, name), path);
}

double intensity_class(double h, double v, const MapsSettings& m) {
  if (!(h > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (h > m.high_thickness && v > m.high_speed) return 3.0;
  if (h >= m.medium_thickness && v >= m.medium_speed) return 2.0;
  return 1.0;
}

nlohmann::json map_figures(int dimension, const MapGrid& grid, double area,
                           const std::vector<double>& peak_thickness,
                           const std::vector<double>& peak_speed,
                           const std::vector<double>& deposit, const std::vector<double>& release,
                           const std::function<double(double, double)>& ground, double origin_z) {
  std::size_t impact = 0, deposited = 0;
  double release_volume = 0.0, deposit_volume = 0.0, fastest = 0.0;
  for (std::size_t c = 0; c < grid.cells(); ++c) {
    impact += peak_thickness[c] > 0.0;
    deposited += deposit[c] > 0.0;
    release_volume += release[c] * area, deposit_volume += deposit[c] * area;
    fastest = std::max(fastest, peak_speed[c]);
  }
  nlohmann::json j = nlohmann::json::object();
  const bool plane = dimension == 2; // lengths and areas per unit width
  j[plane ? "impact_length_m" : "impact_area_m2"] = static_cast<double>(impact) * area;
  j[plane ? "deposit_length_m" : "deposit_area_m2"] = static_cast<double>(deposited) * area;
  j[plane ? "release_area_m2" : "release_volume_m3"] = release_volume;
  j[plane ? "deposit_area_m2" : "deposit_volume_m3"] = deposit_volume;
  j["peak_speed_m_s"] = fastest;
  if (!ground || impact == 0) return j;
  // The crown (the highest release cell) and the tip (the impact cell farthest from it in plan).
  auto centre = [&](std::size_t c) {
    return std::array<double, 2>{grid.x0 + (static_cast<double>(c % grid.nx) + 0.5) * grid.dx,
                                 grid.y0 + (static_cast<double>(c / grid.nx) + 0.5) * grid.dy};
  };
  std::size_t crown = grid.cells(), tip = grid.cells();
  double crown_z = -std::numeric_limits<double>::infinity(), farthest = -1.0;
  for (std::size_t c = 0; c < grid.cells(); ++c)
    if (release[c] > 0.0) {
      const auto [x, y] = centre(c);
      if (const double z = ground(x, y); z > crown_z) crown_z = z, crown = c;
    }
  if (crown == grid.cells()) return j;
  const auto [cx, cy] = centre(crown);
  for (std::size_t c = 0; c < grid.cells(); ++c)
    if (peak_thickness[c] > 0.0) {
      const auto [x, y] = centre(c);
      if (const double d = std::hypot(x - cx, y - cy); d > farthest) farthest = d, tip = c;
    }
  const auto [tx, ty] = centre(tip);
  const double tip_z = ground(tx, ty), drop = crown_z - tip_z;
  j["crown"] = {cx + grid.origin[0], cy + grid.origin[1], crown_z + origin_z};
  j["tip"] = {tx + grid.origin[0], ty + grid.origin[1], tip_z + origin_z};
  j["runout_length_m"] = farthest;
  j["drop_height_m"] = drop;
  j["fahrboschung_angle_deg"] = std::atan2(drop, farthest) * 180.0 / 3.14159265358979323846;
  return j;
}

template <int D>
nlohmann::json PeakMaps<D>::figures(const std::vector<double>& deposit) const {
  const MapsSettings& M = settings_;
  std::function<double(double, double)> ground;
  if (M.dem) ground = [&M](double x, double y) { return M.dem->elevation(x, y); };
  return map_figures(D, M.grid, cell_area(), thickness_, speed_, deposit, release_, ground,
                     M.origin_z);
}

template <int D>
PeakMaps<D>::PeakMaps(const Case& c, const Simulation<D>& sim) : settings_(c.maps) {
  const std::size_t n = settings_.grid.cells();
  mapped_.assign(static_cast<std::size_t>(sim.num_bodies()), 0);
  double mass = 0.0;
  for (const int b : settings_.bodies)
    mapped_[b] = 1, mass += sim.setup().bodies[b].mass;
  // Bounds of the sums: the grid's volume (particles stretch to at most a few times their own),
  // the mapped bodies' mass times the largest speed.
  double volume = 1.0;
  for (int d = 0; d < D; ++d)
    volume *= c.grid.extent[d];
  volume_shift_ = fixed_point_shift(8.0 * volume);
  mass_shift_ = fixed_point_shift(2.0 * mass * max_speed);
  sums_.assign(n * (2 + D), 0);
  thickness_.assign(n, 0.0), speed_.assign(n, 0.0), energy_.assign(n, 0.0);
  pressure_.assign(n, 0.0), arrival_.assign(n, std::numeric_limits<double>::quiet_NaN());
  release_ = deposit(sim);
}

template <int D>
double PeakMaps<D>::cell_area() const {
  return D == 2 ? settings_.grid.dx : settings_.grid.dx * settings_.grid.dy;
}

template <int D>
std::int64_t PeakMaps<D>::cell_of(const Vec<D>& x) const {
  const MapGrid& G = settings_.grid;
  // 2D: one row along x, whatever the height (material may flow above the grid's rounded top).
  const double fi = std::floor((x[0] - G.x0) / G.dx),
               fj = D == 2 ? 0.0 : std::floor((x[1] - G.y0) / G.dy);
  if (!(fi >= 0.0 && fi < G.nx && fj >= 0.0 && fj < G.ny)) return -1;
  return static_cast<std::int64_t>(fj) * G.nx + static_cast<std::int64_t>(fi);
}

template <int D>
void PeakMaps<D>::accumulate(const Simulation<D>& sim, double time) {
  const auto& P = sim.particles();
  const MapGrid& G = settings_.grid;
  constexpr int S = 2 + D;
  const std::size_t row = static_cast<std::size_t>(G.nx) * S;
  // Only the rows last step's moving material touched hold sums: clear them.
  if (rows_hi_ >= rows_lo_)
    std::fill(sums_.begin() + rows_lo_ * row, sums_.begin() + (rows_hi_ + 1) * row, 0);
  std::int64_t lo = G.ny, hi = -1; // the rows this process's moving particles touch
  std::string fault;               // this process's first bad particle
  for (int b = 0; b < sim.num_bodies() && fault.empty(); ++b) {
    if (!mapped_[b]) continue;
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      if (!sim.is_own(p)) continue;
      const double speed = P.v[p].norm();
      if (!(speed > settings_.moving_speed)) continue;
      if (!(speed < max_speed)) {
        fault = fmt::format("step {}, time {:.6g} s: particle {} moves at {:.4g} m/s, faster "
                            "than the {} m/s that the maps' sums hold: a speed out of any "
                            "physical range",
                            sim.steps(), time, P.id[p], speed, max_speed);
        break;
      }
      const std::int64_t c = cell_of(P.x[p]);
      if (c < 0) continue;
      lo = std::min(lo, c / G.nx), hi = std::max(hi, c / G.nx);
      std::int64_t* s = sums_.data() + c * S;
      bool overflow = __builtin_add_overflow(s[0], fixed(P.vol[p], volume_shift_), &s[0]);
      overflow |= __builtin_add_overflow(s[1], fixed(P.m[p], mass_shift_), &s[1]);
      for (int d = 0; d < D; ++d)
        overflow |=
            __builtin_add_overflow(s[2 + d], fixed(P.m[p] * P.v[p][d], mass_shift_), &s[2 + d]);
      if (overflow) {
        fault = fmt::format("step {}, time {:.6g} s: particle {}: the maps' cell sums overflow "
                            "(the mapped bodies' volume is many times the grid's): a volume out "
                            "of any physical range",
                            sim.steps(), time, P.id[p]);
        break;
      }
    }
  }
  // Every process learns the rows touched anywhere and whether any process failed (one small
  // collective), so that all of them throw, or all sum, together.
  double row_lo[2] = {static_cast<double>(lo), 0.0};
  double row_hi[2] = {static_cast<double>(hi), fault.empty() ? 0.0 : 1.0};
  Exchange* ex = sim.exchange();
  if (ex) ex->min_max(row_lo, row_hi, 2);
  if (row_hi[1] > 0.0) {
    if (ex) ex->agree_on_failure(fault);
    throw SimulationError(fault);
  }
  rows_lo_ = static_cast<std::int64_t>(row_lo[0]), rows_hi_ = static_cast<std::int64_t>(row_hi[0]);
  if (rows_hi_ < rows_lo_) return; // nothing moves on the raster
  std::int64_t* window = sums_.data() + rows_lo_ * row;
  const std::size_t cells = static_cast<std::size_t>(rows_hi_ - rows_lo_ + 1) * G.nx;
  if (ex) ex->sum_integers(window, cells * S);
  const double area = cell_area();
  for (std::size_t k = 0; k < cells; ++k) {
    const std::int64_t* s = window + k * S;
    if (s[0] <= 0 || s[1] <= 0) continue;
    const std::size_t c = rows_lo_ * G.nx + k;
    const double V = unfixed(s[0], volume_shift_), m = unfixed(s[1], mass_shift_);
    Vec<D> mv;
    for (int d = 0; d < D; ++d)
      mv[d] = unfixed(s[2 + d], mass_shift_);
    const double u = mv.norm() / m;
    thickness_[c] = std::max(thickness_[c], V / area);
    speed_[c] = std::max(speed_[c], u);
    energy_[c] = std::max(energy_[c], 0.5 * m * u * u / area);
    pressure_[c] = std::max(pressure_[c], m / V * u * u);
    if (std::isnan(arrival_[c])) arrival_[c] = time;
  }
}

template <int D>
std::vector<double> PeakMaps<D>::deposit(const Simulation<D>& sim, int body) {
  const auto& P = sim.particles();
  std::vector<std::int64_t> volume(settings_.grid.cells(), 0);
  std::string fault;
  for (int b = 0; b < sim.num_bodies() && fault.empty(); ++b) {
    if (!mapped_[b] || (body >= 0 && b != body)) continue;
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1] && fault.empty(); ++p)
      if (sim.is_own(p))
        if (const std::int64_t c = cell_of(P.x[p]);
            c >= 0 && __builtin_add_overflow(volume[c], fixed(P.vol[p], volume_shift_), &volume[c]))
          fault = fmt::format(
              "step {}, time {:.6g} s: particle {}: the maps' cell sums overflow (the mapped "
              "bodies' volume is many times the grid's): a volume out of any physical range",
              sim.steps(), sim.time(), P.id[p]);
  }
  // An overflow on one process stops every process before the sum.
  Exchange* ex = sim.exchange();
  if (ex) ex->agree_on_failure(fault);
  if (!fault.empty()) throw SimulationError(fault);
  if (ex) ex->sum_integers(volume.data(), volume.size());
  const double area = cell_area();
  std::vector<double> h(volume.size());
  for (std::size_t c = 0; c < volume.size(); ++c)
    h[c] = unfixed(volume[c], volume_shift_) / area;
  return h;
}

template <int D>
std::vector<std::vector<double>> PeakMaps<D>::body_deposits(const Simulation<D>& sim) {
  std::vector<std::vector<double>> each;
  if (settings_.bodies.size() > 1)
    for (const int b : settings_.bodies)
      each.push_back(deposit(sim, b));
  return each;
}

template <int D>
void PeakMaps<D>::write(const Simulation<D>& sim, const std::string& folder,
                        const std::vector<double>& h,
                        const std::vector<std::vector<double>>& each) const {
  const MapsSettings& M = settings_;
  std::string bodies;
  for (const int b : M.bodies)
    bodies += (bodies.empty() ? "" : ", ") + sim.case_().bodies[b].name;
  const std::vector<std::pair<std::string, std::string>> meta = {
      {"TALUS_BODIES", bodies},
      {"TALUS_MOVING_SPEED_M_S", fmt::format("{}", M.moving_speed)},
      {"TALUS_TIME_S", fmt::format("{:.9g}", sim.time())}};
  const std::string dir = folder + "/maps";
  make_folder(dir);
  if constexpr (D == 2) return write_profile(dir + "/profile.csv", h, each, sim, bodies);
  const std::string moving = fmt::format("of material moving faster than {} m/s", M.moving_speed);
  auto one = [&](const std::string& file, MapLayer layer) {
    write_geotiff(dir + "/" + file, M.grid, {std::move(layer)}, meta);
  };
  one("peak_thickness.tif", {"peak_thickness", "m", "largest thickness " + moving, thickness_});
  one("peak_speed.tif", {"peak_speed", "m/s", "largest depth-averaged speed " + moving, speed_});
  one("peak_kinetic_energy.tif",
      {"peak_kinetic_energy", "J/m^2", "largest kinetic energy per unit area " + moving, energy_});
  one("peak_pressure.tif",
      {"peak_pressure", "Pa", "largest dynamic pressure rho u^2 " + moving, pressure_});
  one("arrival_time.tif",
      {"arrival_time", "s",
       fmt::format("first time after release that material moving faster than {} m/s covers "
                   "the cell (no data: never)",
                   M.moving_speed),
       arrival_});
  one("deposit_thickness.tif",
      {"deposit_thickness", "m", "the mapped bodies' thickness at the time written", h});
  one("release_thickness.tif",
      {"release_thickness", "m", "the mapped bodies' thickness at release", release_});
  std::vector<double> change(h.size());
  for (std::size_t c = 0; c < h.size(); ++c)
    change[c] = h[c] - release_[c];
  one("thickness_change.tif",
      {"thickness_change", "m",
       "the change of the ground surface: the mapped bodies' thickness now less at release "
       "(negative where they left, positive where they deposited)",
       change});
  for (std::size_t k = 0; k < each.size(); ++k) { // with several mapped bodies, each one's
    const std::string& name = sim.case_().bodies[M.bodies[k]].name;
    one("deposit_thickness_" + name + ".tif",
        {"deposit_thickness_" + name, "m", "body '" + name + "''s thickness at the time written",
         each[k]});
  }
  std::vector<double> intensity(thickness_.size());
  for (std::size_t c = 0; c < intensity.size(); ++c)
    intensity[c] = intensity_class(thickness_[c], speed_[c], M);
  one("intensity.tif",
      {"intensity", "class",
       fmt::format("intensity class: 3 high (peak thickness > {} m and peak speed > {} m/s), "
                   "2 medium (>= {} m and >= {} m/s), 1 low (reached otherwise); no data: never "
                   "reached",
                   M.high_thickness, M.high_speed, M.medium_thickness, M.medium_speed),
       intensity});
  // The outlines: where moving material passed, where the bodies lie now, where they started.
  auto outline = [&](const std::string& file, const std::vector<double>& v, const char* name) {
    std::vector<char> inside(v.size());
    for (std::size_t c = 0; c < v.size(); ++c)
      inside[c] = v[c] > 0.0;
    write_outline(dir + "/" + file, M.grid, inside, name);
  };
  outline("impact_area.geojson", thickness_, "impact_area");
  outline("deposit_area.geojson", h, "deposit_area");
  outline("release_area.geojson", release_, "release_area");
  if (M.dem) { // the ground at each cell's centre (bilinear), for the pictures' hillshade
    const MapGrid& G = M.grid;
    std::vector<double> z(G.cells());
    for (int j = 0; j < G.ny; ++j)
      for (int i = 0; i < G.nx; ++i)
        z[static_cast<std::size_t>(j) * G.nx + i] =
            M.dem->elevation(G.x0 + (i + 0.5) * G.dx, G.y0 + (j + 0.5) * G.dy) + M.origin_z;
    one("elevation.tif", {"elevation", "m", "the ground (the DEM the maps are on)", z});
  }
}

// The 2D maps: one row per cell along x, at the cell's centre; empty where not reached.
template <int D>
void PeakMaps<D>::write_profile(const std::string& path, const std::vector<double>& h,
                                const std::vector<std::vector<double>>& each,
                                const Simulation<D>& sim, const std::string& bodies) const {
  const MapGrid& G = settings_.grid;
  std::string per_body;
  for (std::size_t k = 0; k < each.size(); ++k)
    per_body += ",deposit_thickness_" + sim.case_().bodies[settings_.bodies[k]].name;
  std::string text = fmt::format(
      "# {} moving faster than {} m/s, to t = {:.6g} s; thickness m (area per unit width / cell "
      "length), "
      "speed m/s, kinetic energy J/m^2, pressure Pa, arrival s; intensity 3 high, 2 medium, 1 "
      "low\nx,peak_thickness,peak_speed,peak_kinetic_energy,peak_pressure,arrival_time,"
      "intensity,deposit_thickness,release_thickness,thickness_change{}\n",
      bodies, settings_.moving_speed, sim.time(), per_body);
  auto value = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.9g}", v); };
  for (int i = 0; i < G.nx; ++i) {
    text +=
        fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},{},{:.9g},{:.9g},{:.9g}",
                    G.x0 + (i + 0.5) * G.dx, thickness_[i], speed_[i], energy_[i], pressure_[i],
                    value(arrival_[i]), value(intensity_class(thickness_[i], speed_[i], settings_)),
                    h[i], release_[i], h[i] - release_[i]);
    for (const std::vector<double>& e : each)
      text += fmt::format(",{:.9g}", e[i]);
    text += '\n';
  }
  write_file_atomic(path, text);
}

template class PeakMaps<2>;
template class PeakMaps<3>;

} // namespace talus
