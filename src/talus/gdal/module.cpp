// libtalus_gdal.so: Talus's calls to GDAL (talus/core/gdal.hpp), loaded on first use. Each call
// silences GDAL's own error printing and returns its last message in the result instead; no
// exception leaves the module.
#include "talus/core/gdal.hpp"

#include <atomic>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <exception>
#include <gdal_alg.h>
#include <gdal_priv.h>
#include <mutex>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <string>

namespace talus::gdal {

namespace {

// GDAL's drivers registered once, and its error handler silenced while a call runs.
struct Quiet {
  Quiet() {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~Quiet() { CPLPopErrorHandler(); }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;
  static std::string last() { return CPLGetLastErrorMsg(); }
};

std::string wkt_of(const OGRSpatialReference* srs) {
  if (!srs) return "";
  char* w = nullptr;
  srs->exportToWkt(&w);
  std::string s = w ? w : "";
  CPLFree(w);
  return s;
}

RasterFile read_raster(const std::string& path, bool values) {
  RasterFile r;
  try {
    Quiet quiet;
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!ds) {
      r.error = Quiet::last();
      return r;
    }
    r.opened = true;
    r.driver = ds->GetDriver()->GetDescription();
    r.nx = ds->GetRasterXSize(), r.ny = ds->GetRasterYSize(), r.bands = ds->GetRasterCount();
    r.georeferenced = ds->GetGeoTransform(r.transform.data()) == CE_None;
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    r.crs = wkt_of(srs);
    r.geographic = srs && srs->IsGeographic();
    if (!values || r.bands < 1 || r.nx < 2 || r.ny < 2) return r;
    GDALRasterBand* band = ds->GetRasterBand(1);
    r.values.resize(static_cast<std::size_t>(r.nx) * r.ny);
    if (band->RasterIO(GF_Read, 0, 0, r.nx, r.ny, r.values.data(), r.nx, r.ny, GDT_Float64, 0, 0) !=
        CE_None) {
      r.error = Quiet::last();
      r.values.clear();
      return r;
    }
    r.read = true;
    int has_nodata = 0;
    r.nodata = band->GetNoDataValue(&has_nodata);
    r.has_nodata = has_nodata != 0;
  } catch (const std::exception& e) {
    r.read = false, r.values.clear(), r.error = e.what();
  } catch (...) {
    r.read = false, r.values.clear(), r.error = "an unknown failure";
  }
  return r;
}

Footprint read_footprint(const std::string& path) {
  Footprint f;
  try {
    Quiet quiet;
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds) {
      f.error = Quiet::last();
      return f;
    }
    f.opened = true;
    for (OGRLayer* layer : ds->GetLayers()) {
      layer->ResetReading();
      while (OGRFeatureUniquePtr feature{layer->GetNextFeature()}) {
        const OGRGeometry* g = feature->GetGeometryRef();
        if (!g) continue;
        // A polygon, or a multipolygon's first.
        const OGRPolygon* poly = nullptr;
        const auto type = wkbFlatten(g->getGeometryType());
        if (type == wkbPolygon)
          poly = g->toPolygon();
        else if (type == wkbMultiPolygon && g->toMultiPolygon()->getNumGeometries() > 0)
          poly = g->toMultiPolygon()->getGeometryRef(0);
        if (!poly || !poly->getExteriorRing()) continue;
        const OGRSpatialReference* srs = layer->GetSpatialRef();
        f.crs = wkt_of(srs);
        f.geographic = srs && srs->IsGeographic();
        const OGRLinearRing* ring = poly->getExteriorRing();
        for (int k = 0; k < ring->getNumPoints(); ++k)
          f.ring.push_back({ring->getX(k), ring->getY(k)});
        f.found = true;
        return f;
      }
    }
  } catch (const std::exception& e) {
    f.found = false, f.ring.clear(), f.error = e.what();
  } catch (...) {
    f.found = false, f.ring.clear(), f.error = "an unknown failure";
  }
  return f;
}

int same_crs(const std::string& a, const std::string& b) {
  try {
    Quiet quiet;
    OGRSpatialReference sa, sb;
    if (sa.importFromWkt(a.c_str()) != OGRERR_NONE || sb.importFromWkt(b.c_str()) != OGRERR_NONE)
      return -1;
    const char* options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", "CRITERION=EQUIVALENT",
                             nullptr};
    return sa.IsSame(&sb, options) ? 1 : 0;
  } catch (...) {
    return -1;
  }
}

std::string crs_name(const std::string& wkt) {
  try {
    Quiet quiet;
    OGRSpatialReference s;
    if (s.importFromWkt(wkt.c_str()) != OGRERR_NONE) return "unreadable";
    const char* name = s.GetName();
    const char* code = s.GetAuthorityCode(nullptr);
    const char* auth = s.GetAuthorityName(nullptr);
    std::string out = name ? name : "unnamed";
    if (code && auth) out += std::string(", ") + auth + ":" + code;
    return out;
  } catch (...) {
    return "unreadable";
  }
}

// A file among GDAL's in-memory ones, removed when it goes out of scope. Maps are made there and
// handed back as bytes, which the caller writes into the run folder atomically (GDAL's own
// writing would bypass the folder's anchor and leave a half-written file if the run were killed).
struct MemoryFile {
  explicit MemoryFile(const char* extension) {
    static std::atomic<int> serial{0};
    name = "/vsimem/talus_map_" + std::to_string(serial++) + "." + extension;
  }
  ~MemoryFile() { VSIUnlink(name.c_str()); } // gone already once its buffer is taken
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  std::string name;
};

// A failure to make a file, with GDAL's last message where it gave one.
Made failed(const std::string& what) {
  const std::string gdal = CPLGetLastErrorMsg();
  return {"", gdal.empty() ? what : what + ": " + gdal};
}

// Closes a dataset and takes the in-memory file's bytes, or GDAL's reason for failing.
Made finish(GDALDatasetUniquePtr& ds, const MemoryFile& mem, const char* what) {
  Made m;
  CPLErrorReset();
  GDALClose(GDALDataset::ToHandle(ds.release()));
  if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal) {
    m.error = std::string("GDAL cannot finish the ") + what + ": " + CPLGetLastErrorMsg();
    return m;
  }
  vsi_l_offset size = 0;
  GByte* bytes = VSIGetMemFileBuffer(mem.name.c_str(), &size, TRUE);
  if (!bytes) {
    m.error = std::string("GDAL made no ") + what;
    return m;
  }
  try {
    m.bytes.assign(reinterpret_cast<const char*>(bytes), size);
  } catch (...) {
    CPLFree(bytes);
    throw;
  }
  CPLFree(bytes);
  return m;
}

Made geotiff(const RasterGrid& grid, const std::vector<Band>& bands,
             const std::vector<std::pair<std::string, std::string>>& metadata, double no_data) {
  try {
    Quiet quiet;
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (!driver) return {"", "GDAL has no GeoTIFF driver"};
    const MemoryFile mem("tif");
    CPLStringList options;
    options.SetNameValue("COMPRESS", "DEFLATE");
    options.SetNameValue("PREDICTOR", "3");
    GDALDatasetUniquePtr ds(driver->Create(mem.name.c_str(), grid.nx, grid.ny,
                                           static_cast<int>(bands.size()), GDT_Float32,
                                           options.List()));
    if (!ds) return failed("GDAL cannot make the GeoTIFF");
    std::array<double, 6> gt = grid.transform;
    ds->SetGeoTransform(gt.data());
    if (!grid.crs.empty()) ds->SetProjection(grid.crs.c_str());
    for (const auto& [key, value] : metadata)
      ds->SetMetadataItem(key.c_str(), value.c_str());
    for (std::size_t k = 0; k < bands.size(); ++k) {
      const Band& b = bands[k];
      GDALRasterBand* band = ds->GetRasterBand(static_cast<int>(k) + 1);
      band->SetNoDataValue(no_data);
      band->SetDescription(b.name.c_str());
      band->SetUnitType(b.unit.c_str());
      band->SetMetadataItem("DESCRIPTION", b.description.c_str());
      if (band->RasterIO(GF_Write, 0, 0, grid.nx, grid.ny, const_cast<float*>(b.rows.data()),
                         grid.nx, grid.ny, GDT_Float32, 0, 0) != CE_None)
        return failed("GDAL cannot write band " + std::to_string(k + 1));
    }
    return finish(ds, mem, "GeoTIFF");
  } catch (const std::exception& e) {
    return {"", e.what()};
  } catch (...) {
    return {"", "an unknown failure"};
  }
}

Made outline(const RasterGrid& grid, const std::vector<unsigned char>& inside,
             const std::string& layer_name) {
  try {
    Quiet quiet;
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* json = GetGDALDriverManager()->GetDriverByName("GeoJSON");
    if (!mem || !json) return {"", "GDAL has no GeoJSON driver"};
    const MemoryFile vmem("geojson");
    GDALDatasetUniquePtr mask(mem->Create("", grid.nx, grid.ny, 1, GDT_Byte, nullptr));
    if (!mask) return failed("GDAL cannot make the outline's mask");
    std::array<double, 6> gt = grid.transform;
    mask->SetGeoTransform(gt.data());
    GDALRasterBand* band = mask->GetRasterBand(1);
    if (band->RasterIO(GF_Write, 0, 0, grid.nx, grid.ny, const_cast<unsigned char*>(inside.data()),
                       grid.nx, grid.ny, GDT_Byte, 0, 0) != CE_None)
      return failed("GDAL cannot hold the outline's cells");
    GDALDatasetUniquePtr out(json->Create(vmem.name.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!out) return failed("GDAL cannot make the GeoJSON");
    OGRSpatialReference srs;
    const bool has_crs = !grid.crs.empty() && srs.importFromWkt(grid.crs.c_str()) == OGRERR_NONE;
    OGRLayer* layer =
        out->CreateLayer(layer_name.c_str(), has_crs ? &srs : nullptr, wkbPolygon, nullptr);
    OGRFieldDefn field("inside", OFTInteger);
    if (!layer || layer->CreateField(&field) != OGRERR_NONE ||
        GDALPolygonize(band, band, layer, 0, nullptr, nullptr, nullptr) != CE_None)
      return failed("GDAL cannot trace the outline");
    return finish(out, vmem, "GeoJSON");
  } catch (const std::exception& e) {
    return {"", e.what()};
  } catch (...) {
    return {"", "an unknown failure"};
  }
}

const Module calls{module_version, read_raster, read_footprint, same_crs,
                   crs_name,       geotiff,     outline};

} // namespace

} // namespace talus::gdal

extern "C" __attribute__((visibility("default"))) const talus::gdal::Module* talus_gdal_module() {
  return &talus::gdal::calls;
}
