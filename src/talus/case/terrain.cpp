#include "talus/case/terrain.hpp"

#include "talus/case/parse.hpp"
#include "talus/case/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cpl_error.h>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <gdal_priv.h>
#include <mutex>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
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

void register_gdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL reports errors through a handler; it is silenced while a file is read and its last
// message goes into ours.
struct QuietGdal {
  QuietGdal() {
    register_gdal();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  static std::string last() {
    const std::string m = CPLGetLastErrorMsg();
    return m.empty() ? "" : ": " + m;
  }
};

std::string wkt_of(const OGRSpatialReference* srs) {
  if (!srs) return "";
  char* w = nullptr;
  srs->exportToWkt(&w);
  std::string s = w ? w : "";
  CPLFree(w);
  return s;
}

void require_projected(const std::string& path, const OGRSpatialReference* srs) {
  if (srs && srs->IsGeographic())
    throw CaseError(fmt::format("{}: its coordinates are in degrees ({}); Talus needs projected "
                                "metres: reproject it first (e.g. gdalwarp -t_srs EPSG:32632)",
                                path, crs_name(wkt_of(srs))));
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
  QuietGdal quiet;
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool ascii = ext == ".asc" || ext == ".ASC" ||
                     (ds && std::string(ds->GetDriver()->GetDescription()) == "AAIGrid");
  if (!ds) {
    const std::string why = QuietGdal::last();
    if (ascii) check_ascii_grid(path, false); // a header typo, named by its line
    throw CaseError(
        fmt::format("{}: GDAL does not read it as a raster of a format it knows{}", path, why));
  }
  if (ascii) check_ascii_grid(path, true);
  auto r = std::make_shared<Raster>();
  r->file = path;
  r->nx = ds->GetRasterXSize();
  r->ny = ds->GetRasterYSize();
  if (ds->GetRasterCount() < 1 || r->nx < 2 || r->ny < 2)
    throw CaseError(fmt::format("{}: {} x {} cells in {} bands; a raster needs one band of at "
                                "least 2 x 2 cells",
                                path, r->nx, r->ny, ds->GetRasterCount()));
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    throw CaseError(fmt::format("{}: has no georeferencing (origin and cell size)", path));
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw CaseError(fmt::format("{}: a rotated grid; warp it north-up first (gdalwarp)", path));
  if (!(gt[1] > 0.0) || gt[5] == 0.0)
    throw CaseError(fmt::format("{}: cell size {} x {} m is not usable", path, gt[1], gt[5]));
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  require_projected(path, srs);
  r->crs = wkt_of(srs);
  r->dx = gt[1];
  r->dy = std::abs(gt[5]);
  r->north_up = gt[5] < 0.0;
  r->x0 = gt[0] - origin[0];
  r->y0 = (r->north_up ? gt[3] + r->ny * gt[5] : gt[3]) - origin[1];
  GDALRasterBand* band = ds->GetRasterBand(1);
  std::vector<double> rows(static_cast<std::size_t>(r->nx) * r->ny);
  if (band->RasterIO(GF_Read, 0, 0, r->nx, r->ny, rows.data(), r->nx, r->ny, GDT_Float64, 0, 0) !=
      CE_None)
    throw CaseError(fmt::format("{}: cannot read its values{}", path, QuietGdal::last()));
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
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
  QuietGdal quiet;
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!ds)
    throw CaseError(fmt::format("{}: cannot read it as a vector file (GeoJSON, shapefile){}", path,
                                QuietGdal::last()));
  for (OGRLayer* layer : ds->GetLayers()) {
    layer->ResetReading();
    while (OGRFeatureUniquePtr f{layer->GetNextFeature()}) {
      const OGRGeometry* g = f->GetGeometryRef();
      if (!g) continue;
      const OGRPolygon* poly = nullptr;
      const auto type = wkbFlatten(g->getGeometryType());
      if (type == wkbPolygon)
        poly = g->toPolygon();
      else if (type == wkbMultiPolygon && g->toMultiPolygon()->getNumGeometries() > 0)
        poly = g->toMultiPolygon()->getGeometryRef(0);
      if (!poly || !poly->getExteriorRing()) continue;
      const OGRSpatialReference* srs = layer->GetSpatialRef();
      require_projected(path, srs);
      crs = wkt_of(srs);
      std::vector<std::array<double, 2>> v;
      const OGRLinearRing* ring = poly->getExteriorRing();
      for (int k = 0; k < ring->getNumPoints(); ++k)
        v.push_back({ring->getX(k) - origin[0], ring->getY(k) - origin[1]});
      return v;
    }
  }
  throw CaseError(fmt::format("{}: holds no polygon", path));
}

bool same_crs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return true;
  OGRSpatialReference sa, sb;
  if (sa.importFromWkt(a.c_str()) != OGRERR_NONE || sb.importFromWkt(b.c_str()) != OGRERR_NONE)
    return a == b;
  const char* options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", "CRITERION=EQUIVALENT",
                           nullptr};
  return sa.IsSame(&sb, options);
}

std::string crs_name(const std::string& wkt) {
  if (wkt.empty()) return "none";
  OGRSpatialReference s;
  if (s.importFromWkt(wkt.c_str()) != OGRERR_NONE) return "unreadable";
  const char* name = s.GetName();
  const char* code = s.GetAuthorityCode(nullptr);
  const char* auth = s.GetAuthorityName(nullptr);
  std::string out = name ? name : "unnamed";
  if (code && auth) out += fmt::format(", {}:{}", auth, code);
  return out;
}

} // namespace case_reading

} // namespace talus
