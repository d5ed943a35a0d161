// What Talus asks of GDAL (rasters and footprints read, GeoTIFFs and outlines made), in plain
// types. GDAL and its ~115 libraries take 0.15 s to load, which every start of the program would
// pay (twice: share_cores starts it again); so the calls live in a module, libtalus_gdal.so
// (src/talus/gdal/module.cpp), loaded the first time a case reads a raster or writes a map.
// No exception crosses the module's edge: each call reports GDAL's failure in its result.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace talus::gdal {

// Band 1 of a raster file as GDAL reads it.
struct RasterFile {
  bool opened = false; // GDAL opened it as a raster
  std::string error;   // GDAL's last message where it failed, "" if none
  std::string driver;  // the driver's short name ("GTiff", "AAIGrid", ...)
  int nx = 0, ny = 0, bands = 0;
  bool georeferenced = false;        // it has a geotransform
  std::array<double, 6> transform{}; // x = t0 + col t1 + row t2, y = t3 + col t4 + row t5
  std::string crs;                   // WKT, "" if it names none
  bool geographic = false;           // its coordinates are degrees
  bool read = false;                 // band 1's values were read (it has one, of >= 2 x 2 cells)
  std::vector<double> values;        // nx * ny, the file's rows in order (row 0 first)
  bool has_nodata = false;
  double nodata = 0.0;
};

// The outer ring of the first polygon of a vector file.
struct Footprint {
  bool opened = false;
  std::string error;
  bool found = false; // a polygon was found
  std::string crs;
  bool geographic = false;
  std::vector<std::array<double, 2>> ring;
};

// A north-up raster to write: its size, geotransform and coordinate system (WKT, may be "").
struct RasterGrid {
  int nx = 0, ny = 0;
  std::array<double, 6> transform{};
  std::string crs;
};

// One Float32 band of a GeoTIFF: rows in file order (northern row first).
struct Band {
  std::string name, unit, description;
  std::vector<float> rows;
};

// A file made in memory: its bytes, or the reason GDAL failed, with its own message (bytes empty).
struct Made {
  std::string bytes, error;
};

// The layout of Module and its structs: the loader refuses a module built with another.
constexpr int module_version = 1;

// The module's calls; every string argument is a path or WKT.
struct Module {
  int version = module_version;
  // With `values` false, all but band 1's values (a header's checks before a large read).
  RasterFile (*read_raster)(const std::string& path, bool values);
  Footprint (*read_footprint)(const std::string& path);
  // Whether two coordinate systems (WKT, both readable) are the same; -1 if one is unreadable.
  int (*same_crs)(const std::string& a, const std::string& b);
  // A short name: the system's name and its authority code where it has one.
  std::string (*crs_name)(const std::string& wkt);
  // A DEFLATE-compressed GeoTIFF, one Float32 band each, `no_data` marking missing values.
  Made (*geotiff)(const RasterGrid& grid, const std::vector<Band>& bands,
                  const std::vector<std::pair<std::string, std::string>>& metadata, double no_data);
  // GeoJSON polygons around the cells that are nonzero in `inside` (rows in file order), a layer
  // `layer` with one integer field "inside".
  Made (*outline)(const RasterGrid& grid, const std::vector<unsigned char>& inside,
                  const std::string& layer);
};

// The module, loaded on the first call: from beside the running program, else from where the
// build put it. Throws std::runtime_error naming both places if it cannot be loaded.
const Module& module();

} // namespace talus::gdal

// The module's one exported symbol.
extern "C" const talus::gdal::Module* talus_gdal_module();
