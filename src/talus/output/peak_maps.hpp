// Hazard maps ([maps], docs/case-file.md): the peak fields of the mapped bodies' moving material
// on a horizontal raster, accumulated every step from release, and their deposit; written as
// GeoTIFFs into the run folder's maps/ (3D), or as a profile along the section, one row of
// cells along x, into maps/profile.csv (2D).
//
// Each step, the moving particles (|v| > moving_speed) of each raster cell give its column's
// volume V, mass m and momentum m v, and from them
//   thickness h = V / A,  depth-averaged speed u = |sum m v| / sum m,
//   kinetic energy per unit area e = m u^2 / (2 A),  dynamic pressure rho u^2, rho = m / V
// (A: the cell's area), whose largest values over the run are kept, with the arrival time (the
// first time h > 0), and the intensity class of each cell from its peak h and u (the Swiss
// debris-flow classes by default; intensity_class). The thickness change is the deposit less
// the release (the ground surface's change where the mapped bodies are the ground that moves). The
// deposit thickness is the mapped bodies' whole volume per cell at the time written, the release
// thickness the same at release; the ground (the DEM, if the maps have one) is written beside them
// for the pictures (tools/plot_maps.py). The cell sums are fixed-point integers (2^-s units), so
// they are the same bits in any order: on any number of threads and processes.
#pragma once

#include "talus/case/case.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace talus {

// One raster per band of a map file: its name, unit and values (nx * ny, row j at j * nx, south
// to north; NaN: no data).
struct MapLayer {
  std::string name, unit, description;
  std::vector<double> values;
};

// Writes `layers` as a GeoTIFF at `path` (atomically, through the run folder's anchor): one
// Float32 band each, DEFLATE-compressed, no-data -9999, the grid's georeferencing (its origin
// added back) and coordinate system, `metadata` as key=value items. Throws OutputError.
void write_geotiff(const std::string& path, const MapGrid& grid,
                   const std::vector<MapLayer>& layers,
                   const std::vector<std::pair<std::string, std::string>>& metadata);

// Writes the outline of the cells where `inside` is nonzero as GeoJSON polygons (GDAL's
// polygonize: one polygon per connected patch, holes kept) in the grid's coordinate system, a
// layer named `name`, at `path` (atomically). Throws OutputError.
void write_outline(const std::string& path, const MapGrid& grid, const std::vector<char>& inside,
                   const std::string& name);

// The intensity class of a cell from its peak thickness h and peak speed v (MapsSettings):
// 3 high, 2 medium, 1 low, NaN never reached (h = 0).
double intensity_class(double h, double v, const MapsSettings& m);

// The maps' figures (summary.json "maps"), from the peak thickness, the peak speed, the
// deposit and the release thickness on `grid` (cells of `area` m^2; in 2D the grid is one row
// along x, `area` its cells' length, and volumes are per unit width):
// - the impact area (peak thickness > 0) and the deposit area, the release and deposit volumes,
//   the largest peak speed;
// - with `ground` (the ground's elevation at a local point, the DEM's): the crown, the release
//   cell whose ground is highest, and the tip, the impact cell farthest from it in plan (cell
//   centres, [E, N, z] with the grid's origin and `origin_z` added back); the run-out length L
//   between them in plan, the drop H, and the Fahrboschung angle atan(H / L).
nlohmann::json map_figures(int dimension, const MapGrid& grid, double area,
                           const std::vector<double>& peak_thickness,
                           const std::vector<double>& peak_speed,
                           const std::vector<double>& deposit, const std::vector<double>& release,
                           const std::function<double(double, double)>& ground = {},
                           double origin_z = 0.0);

template <int D>
class PeakMaps {
public:
  // The largest speed the fixed-point momentum sums hold; a faster mapped particle stops the run.
  static constexpr double max_speed = 4096.0;

  // At release: the release thickness is the state's deposit (collective).
  PeakMaps(const Case& c, const Simulation<D>& sim);

  // One step's cell sums of the moving material (collective on several processes), and the peak
  // fields and arrival times updated with them at `time`.
  void accumulate(const Simulation<D>& sim, double time);
  // The maps written into `folder`/maps, with `deposit` (deposit(sim)) as the deposit thickness
  // and `each` (body_deposits(sim)) as each mapped body's.
  void write(const Simulation<D>& sim, const std::string& folder,
             const std::vector<double>& deposit,
             const std::vector<std::vector<double>>& each = {}) const;

  const std::vector<double>& peak_thickness() const { return thickness_; }
  const std::vector<double>& peak_speed() const { return speed_; }
  const std::vector<double>& peak_energy() const { return energy_; }
  const std::vector<double>& peak_pressure() const { return pressure_; }
  const std::vector<double>& arrival() const { return arrival_; }
  // The mapped bodies' thickness at release (the release area: where it is > 0).
  const std::vector<double>& release_thickness() const { return release_; }
  // The mapped bodies' volume per unit area in each cell now (collective); body >= 0: that
  // mapped body's alone.
  std::vector<double> deposit(const Simulation<D>& sim, int body = -1);
  // The maps' figures with `deposit` (deposit(sim)) as the deposit (map_figures).
  nlohmann::json figures(const std::vector<double>& deposit) const;
  // With two or more mapped bodies, each one's deposit (in [maps] bodies' order); else none
  // (collective).
  std::vector<std::vector<double>> body_deposits(const Simulation<D>& sim);

  template <class Ar>
  void serialize(Ar& ar) {
    ar.io(thickness_), ar.io(speed_), ar.io(energy_), ar.io(pressure_), ar.io(arrival_);
    ar.io(release_);
  }

private:
  // The raster cell of a point, or -1 outside the raster.
  std::int64_t cell_of(const Vec<D>& x) const;
  // A cell's area (2D: its length along x; the volumes are per unit width).
  double cell_area() const;
  // 2D: the profile along x as CSV at `path` (atomically), with `deposit` beside the peaks, the
  // mapped bodies and the time in its first line.
  void write_profile(const std::string& path, const std::vector<double>& deposit,
                     const std::vector<std::vector<double>>& each, const Simulation<D>& sim,
                     const std::string& bodies) const;

  MapsSettings settings_;
  std::vector<char> mapped_;                // per body
  int volume_shift_ = 0, mass_shift_ = 0;   // fixed point: value * 2^shift, rounded
  std::vector<std::int64_t> sums_;          // per cell: V, m, then m v (D components)
  std::int64_t rows_lo_ = 0, rows_hi_ = -1; // the raster rows whose sums are not all zero
  std::vector<double> thickness_, speed_, energy_, pressure_, arrival_, release_;
};

} // namespace talus
