#include "talus/case/terrain.hpp"

#include "talus/case/parse.hpp"
#include "talus/case/toml_reader.hpp"
#include "talus/core/gdal.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace talus {

double Raster::elevation(double x, double y) const {
  if (!covers(x, y)) return std::nan("");
  // Cell-centre coordinates: u = 0 at the first centre; clamped so the half cell at the edge
  // takes the edge's values.
  const double u = std::clamp((x - x0) / dx - 0.5, 0.0, nx - 1.0);
  const double v = std::clamp((y - y0) / dy - 0.5, 0.0, ny - 1.0);
  const int i = std::min(static_cast<int>(u), nx - 2), j = std::min(static_cast<int>(v), ny - 2);
  const double fu = u - i, fv = v - j;
  // z = (1-fu)(1-fv) z00 + fu (1-fv) z10 + (1-fu) fv z01 + fu fv z11; NaN if any of them is.
  return (1.0 - fv) * ((1.0 - fu) * at(i, j) + fu * at(i + 1, j)) +
         fv * ((1.0 - fu) * at(i, j + 1) + fu * at(i + 1, j + 1));
}

std::array<int, 2> Raster::file_cell(double x, double y) const {
  const int i = std::clamp(static_cast<int>(std::floor((x - x0) / dx)), 0, nx - 1);
  const int j = std::clamp(static_cast<int>(std::floor((y - y0) / dy)), 0, ny - 1);
  return {north_up ? ny - 1 - j : j, i};
}

namespace case_reading {

namespace {

// The Earth's surface lies between the Challenger Deep (-10,935 m) and Everest (8,849 m): an
// elevation far outside is a unit or no-data mistake.
constexpr double lowest_elevation = -12000.0, highest_elevation = 9000.0;

// Throws for a file whose coordinates are degrees.
void require_projected(const std::string& path, bool geographic, const std::string& crs) {
  if (geographic)
    throw CaseError(fmt::format("{}: its coordinates are in degrees ({}); Talus needs projected "
                                "metres: reproject it first (e.g. gdalwarp -t_srs EPSG:32632)",
                                path, crs_name(crs)));
}

// GDAL's module, or a CaseError naming what needed it.
const gdal::Module& gdal_for(const std::string& what) {
  try {
    return gdal::module();
  } catch (const std::runtime_error& e) {
    throw CaseError(fmt::format("{}: {}", what, e.what()));
  }
}

// GDAL's message after a colon, or nothing.
std::string because(const std::string& message) {
  return message.empty() ? "" : ": " + message;
}

// An ESRI ASCII grid checked where GDAL is silent or vague: each header line's key is one the
// format has (naming the line of one that is not), given once; ncols and nrows are whole
// numbers; and the file holds ncols x nrows values (GDAL reads the first ncols x nrows values and
// ignores the rest). `opened`: whether GDAL read it.
void check_ascii_grid(const std::string& path, bool opened) {
  std::ifstream in(path);
  static const std::vector<std::string> keys = {
      "ncols",     "nrows",    "xllcorner", "yllcorner", "xllcenter",
      "yllcenter", "cellsize", "dx",        "dy",        "nodata_value"};
  std::string line;
  int number = 0;
  long long ncols = -1, nrows = -1;
  std::vector<std::string> seen;
  std::streampos values = 0;
  while (values = in.tellg(), std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) continue;
    if (!std::isalpha(static_cast<unsigned char>(key[0]))) break; // the values start
    std::string lower = key;
    for (char& ch : lower)
      ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (std::find(keys.begin(), keys.end(), lower) == keys.end())
      throw CaseError(fmt::format("{}:{}: '{}' is not a key of an ESRI ASCII grid's header (ncols, "
                                  "nrows, xllcorner or xllcenter, yllcorner or yllcenter, "
                                  "cellsize, NODATA_value)",
                                  path, number, printable(key)));
    if (std::find(seen.begin(), seen.end(), lower) != seen.end())
      throw CaseError(fmt::format("{}:{}: '{}' is given twice in the header", path, number, key));
    seen.push_back(lower);
    if (lower == "ncols" || lower == "nrows") {
      std::string count;
      words >> count;
      if (count.empty() || count.size() > 9 ||
          !std::all_of(count.begin(), count.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
        throw CaseError(fmt::format("{}:{}: {} '{}' is not a whole number of cells", path, number,
                                    key, printable(count)));
      (lower == "ncols" ? ncols : nrows) = std::stoll(count);
    }
  }
  if (!opened || ncols <= 0 || nrows <= 0) return;
  in.clear();
  in.seekg(values);
  long long count = 0;
  for (std::string word; in >> word;)
    ++count;
  if (count != ncols * nrows)
    throw CaseError(fmt::format("{}: its header says {} x {} cells ({} values) but the file holds "
                                "{} values after the header",
                                path, ncols, nrows, ncols * nrows, count));
}

} // namespace

std::shared_ptr<const Raster> read_raster(const std::string& path,
                                          const std::array<double, 3>& origin) {
  if (std::filesystem::is_directory(path))
    throw CaseError(fmt::format("{}: is a folder, not a raster", path));
  // The header first, checked before band 1's values are read (a typo's gigabytes never asked).
  gdal::RasterFile f = gdal_for(path).read_raster(path, false);
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool ascii = ext == ".asc" || ext == ".ASC" || f.driver == "AAIGrid";
  if (!f.opened) {
    if (ascii) check_ascii_grid(path, false); // a header typo, named by its line
    throw CaseError(fmt::format("{}: GDAL does not read it as a raster of a format it knows{}",
                                path, because(f.error)));
  }
  if (ascii) check_ascii_grid(path, true);
  auto r = std::make_shared<Raster>();
  r->file = path;
  r->nx = f.nx;
  r->ny = f.ny;
  if (f.bands < 1 || r->nx < 2 || r->ny < 2)
    throw CaseError(fmt::format("{}: {} x {} cells in {} bands; a raster needs one band of at "
                                "least 2 x 2 cells",
                                path, r->nx, r->ny, f.bands));
  const std::array<double, 6>& gt = f.transform;
  if (!f.georeferenced)
    throw CaseError(fmt::format("{}: has no georeferencing (origin and cell size)", path));
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw CaseError(fmt::format("{}: a rotated grid; warp it north-up first (gdalwarp)", path));
  if (!(gt[1] > 0.0) || gt[5] == 0.0)
    throw CaseError(fmt::format("{}: cell size {} x {} m is not usable", path, gt[1], gt[5]));
  require_projected(path, f.geographic, f.crs);
  r->crs = f.crs;
  r->dx = gt[1];
  r->dy = std::abs(gt[5]);
  r->north_up = gt[5] < 0.0;
  r->x0 = gt[0] - origin[0];
  r->y0 = (r->north_up ? gt[3] + r->ny * gt[5] : gt[3]) - origin[1];
  f = gdal_for(path).read_raster(path, true);
  if (f.read && (f.nx != r->nx || f.ny != r->ny))
    throw CaseError(fmt::format("{}: changed while it was read", path));
  if (!f.read) throw CaseError(fmt::format("{}: cannot read its values{}", path, because(f.error)));
  const std::vector<double>& rows = f.values;
  const bool has_nodata = f.has_nodata;
  const double nodata = f.nodata;
  r->z.resize(rows.size());
  r->z_min = inf, r->z_max = -inf;
  for (int row = 0; row < r->ny; ++row)
    for (int col = 0; col < r->nx; ++col) {
      double v = rows[static_cast<std::size_t>(row) * r->nx + col];
      const bool missing = has_nodata && (v == nodata || (std::isnan(nodata) && std::isnan(v)));
      if (!missing && !(std::isfinite(v) && v >= lowest_elevation && v <= highest_elevation))
        throw CaseError(fmt::format(
            "{}: cell (row {}, column {}) holds {}, not an elevation in metres ([{}, {}] m; "
            "mark missing cells with the raster's no-data value)",
            path, row, col, v, lowest_elevation, highest_elevation));
      v = missing ? std::nan("") : v - origin[2];
      const int j = r->north_up ? r->ny - 1 - row : row;
      r->z[static_cast<std::size_t>(j) * r->nx + col] = v;
      if (!missing) r->z_min = std::min(r->z_min, v), r->z_max = std::max(r->z_max, v);
    }
  if (r->z_min > r->z_max) throw CaseError(fmt::format("{}: every cell is no-data", path));
  return r;
}

std::vector<std::array<double, 2>> read_footprint_vector(const std::string& path,
                                                         const std::array<double, 3>& origin,
                                                         std::string& crs) {
  if (std::filesystem::is_directory(path))
    throw CaseError(fmt::format("{}: is a folder, not a footprint file", path));
  const gdal::Footprint f = gdal_for(path).read_footprint(path);
  if (!f.opened)
    throw CaseError(fmt::format("{}: cannot read it as a vector file (GeoJSON, shapefile){}", path,
                                because(f.error)));
  if (!f.found && !f.error.empty())
    throw CaseError(fmt::format("{}: cannot read its polygons: {}", path, f.error));
  if (!f.found) throw CaseError(fmt::format("{}: holds no polygon", path));
  require_projected(path, f.geographic, f.crs);
  crs = f.crs;
  std::vector<std::array<double, 2>> v;
  for (const auto& [x, y] : f.ring)
    v.push_back({x - origin[0], y - origin[1]});
  return v;
}

bool same_crs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return true;
  const int same = gdal_for("comparing coordinate systems").same_crs(a, b);
  return same < 0 ? a == b : same == 1;
}

std::string crs_name(const std::string& wkt) {
  return wkt.empty() ? "none" : gdal_for("naming a coordinate system").crs_name(wkt);
}

} // namespace case_reading

} // namespace talus
