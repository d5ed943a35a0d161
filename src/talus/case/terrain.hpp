// Terrain for 3D bodies: elevation rasters (GeoTIFF, ESRI ASCII grid, anything GDAL reads) and
// footprint polygons (CSV, GeoJSON, shapefile), read in projected metres and shifted to the
// case's local coordinates. Elevation is along z; x and y are the raster's easting and northing.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace talus {

// An elevation raster in local coordinates: z(i, j) at the centre of cell (i, j), i along x
// (west to east), j along y (south to north); NaN where the file has no data.
struct Raster {
  std::string file;
  std::string crs;           // the file's coordinate system as WKT, empty if it names none
  bool north_up = true;      // the file's first row is its northern one (GDAL's usual layout)
  double x0 = 0.0, y0 = 0.0; // the south-west corner of the raster (local m)
  double dx = 0.0, dy = 0.0; // cell size (m, both > 0)
  int nx = 0, ny = 0;
  std::vector<double> z;           // nx * ny values, row j at j * nx
  double z_min = 0.0, z_max = 0.0; // over the cells with data

  double at(int i, int j) const { return z[static_cast<std::size_t>(j) * nx + i]; }
  bool covers(double x, double y) const {
    return x >= x0 && x <= x0 + nx * dx && y >= y0 && y <= y0 + ny * dy;
  }
  // Bilinear between the four cell centres around (x, y), constant beyond the outermost
  // centres to the raster's edge; NaN outside the raster or where one of the four has no data.
  double elevation(double x, double y) const;
  // The cell holding (x, y) in the file's own numbering (row 0 is the file's first row).
  std::array<int, 2> file_cell(double x, double y) const;
};

// A surface bounding a terrain body: a raster, a constant elevation, or an offset from the other
// surface (a bottom at a depth below the top, or a top at a height above the bottom).
struct TerrainSurface {
  enum class Kind { constant, raster, offset } kind = Kind::constant;
  double value = 0.0; // elevation (constant) or the depth or height (offset, m)
  std::shared_ptr<const Raster> raster;
};

namespace case_reading {

// Reads band 1 of a raster with GDAL and subtracts `origin` (x, y, z) from its coordinates and
// elevations. Throws CaseError naming the file for what cannot be used: a file GDAL cannot
// open, a rotated or geographic (degrees) grid, fewer than 2 x 2 cells, a value that is NaN or
// absurd for the Earth's surface (naming the cell).
std::shared_ptr<const Raster> read_raster(const std::string& path,
                                          const std::array<double, 3>& origin);

// The outer ring of the first polygon of a vector file (GeoJSON, shapefile, anything OGR reads),
// shifted by `origin`; `crs` receives its coordinate system (WKT, empty if none).
std::vector<std::array<double, 2>> read_footprint_vector(const std::string& path,
                                                         const std::array<double, 3>& origin,
                                                         std::string& crs);

// Whether two coordinate systems (WKT) are the same; an empty one matches anything.
bool same_crs(const std::string& a, const std::string& b);
// A short name for a coordinate system (WKT): its name and EPSG code where it has one.
std::string crs_name(const std::string& wkt);

} // namespace case_reading

} // namespace talus
