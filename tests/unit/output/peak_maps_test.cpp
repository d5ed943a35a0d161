// Hazard maps ([maps], output/peak_maps.hpp): a block gliding at a known speed over a level floor
// gives its closed-form thickness, speed, kinetic energy, dynamic pressure and arrival times; the
// maps are the same bits on 1 and 2 threads and across a restart; the GeoTIFFs carry the grid,
// the coordinate system, the units and no data where nothing came; bad [maps] tables are named.
#include "talus/case/parse.hpp"
#include "talus/output/peak_maps.hpp"
#include "talus/run/run.hpp"
#include "test_support.hpp"

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <iterator>
#include <numbers>
#include <ogr_spatialref.h>
#include <sstream>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {
namespace {

constexpr double density = 2000.0, speed = 2.0, height = 0.5;

// A block 1 m x 1 m x 0.5 m (2000 kg/m^3) gliding along x at 2 m/s with no gravity, in a grid of
// 0.25 m cells (2 particles per cell and direction: 0.125 m apart); maps on 0.5 m cells.
std::string gliding_block(const std::string& extra = "") {
  return R"(
[simulation]
dimension = 3
end_time = 1.0
gravity = [0.0, 0.0, 0.0]
[grid]
extent = [5.0, 2.0, 1.0]
cell_size = 0.25
[[material]]
name = "m"
density = 2000.0
youngs_modulus = 1e7
poisson_ratio = 0.3
[[body]]
name = "block"
material = "m"
box = { min = [0.5, 0.5, 0.25], max = [1.5, 1.5, 0.75] }
velocity = [2.0, 0.0, 0.0]
[maps]
bodies = ["block"]
cell_size = 0.5
moving_speed = 0.5
)" + extra;
}

template <class T>
std::vector<T> run_maps(const Case& c, int threads, double until) {
#ifdef _OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
#else
  (void)threads; // one thread: the sanitizer builds have no OpenMP
#endif
  Simulation<3> sim(c);
  PeakMaps<3> maps(c, sim);
  while (sim.time() < until - 1e-12) {
    sim.step(until - sim.time());
    maps.accumulate(sim, sim.time());
  }
#ifdef _OPENMP
  omp_set_num_threads(before);
#endif
  std::vector<T> all;
  for (const auto* v : {&maps.peak_thickness(), &maps.peak_speed(), &maps.peak_energy(),
                        &maps.peak_pressure(), &maps.arrival(), &maps.release_thickness()})
    all.insert(all.end(), v->begin(), v->end());
  const std::vector<double> h = maps.deposit(sim);
  all.insert(all.end(), h.begin(), h.end());
  return all;
}

// Cell (i, j) of the 10 x 4 map (0.5 m cells); the block covers x 0.5-1.5 m at first and moves
// 1 m in 0.5 s, so after 0.5 s cells i 1-4 (x 0.5-2.5 m), j 1-2 (y 0.5-1.5 m) have seen it.
TEST(PeakMaps, AGlidingBlockGivesItsClosedForms) {
  const Case c = test::case_from(gliding_block());
  const double until = 0.5;
  const std::vector<double> all = run_maps<double>(c, 1, until);
  const std::size_t n = 40;
  auto at = [&](int field, int i, int j) { return all[field * n + j * 10 + i]; };
  for (int j = 1; j <= 2; ++j)
    for (int i = 1; i <= 4; ++i) {
      // The block's whole height passes over each cell, at its speed: h = 0.5 m, u = 2 m/s,
      // e = rho h u^2 / 2 = 2000 J/m^2, rho u^2 = 8000 Pa (the elastic block barely deforms).
      EXPECT_NEAR(at(0, i, j), height, 1e-3 * height) << i << ", " << j;
      EXPECT_NEAR(at(1, i, j), speed, 1e-6 * speed) << i << ", " << j;
      EXPECT_NEAR(at(2, i, j), 0.5 * density * height * speed * speed, 2.0) << i << ", " << j;
      EXPECT_NEAR(at(3, i, j), density * speed * speed, 8.0) << i << ", " << j;
      // Arrival: the first step for the cells under the block; ahead of it, when its leading
      // particles (0.0625 m behind the front at x = 1.5 m) cross the cell's west edge.
      const double edge = 0.5 * i, lead = 1.5 - 0.0625;
      const double expected = edge < lead ? 0.0 : (edge - lead) / speed;
      EXPECT_NEAR(at(4, i, j), expected, 0.01) << i << ", " << j;
    }
  // Nothing reached the cells beside the block's path or ahead of where it is now.
  EXPECT_EQ(at(0, 1, 0), 0.0);
  EXPECT_EQ(at(0, 6, 1), 0.0);
  EXPECT_TRUE(std::isnan(at(4, 6, 1)));
  // The release area: the block over x 0.5-1.5 m at the start; the deposit now over 1.5-2.5 m.
  EXPECT_NEAR(at(5, 1, 1), height, 1e-9);
  EXPECT_EQ(at(5, 3, 1), 0.0);
  EXPECT_NEAR(at(6, 3, 1), height, 1e-3 * height);
  EXPECT_EQ(at(6, 1, 1), 0.0);
}

TEST(PeakMaps, TheSameBitsOnOneAndTwoThreads) {
  const Case c = test::case_from(gliding_block());
  const std::vector<double> one = run_maps<double>(c, 1, 0.3), two = run_maps<double>(c, 2, 0.3);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t k = 0; k < one.size(); ++k)
    ASSERT_TRUE(one[k] == two[k] || (std::isnan(one[k]) && std::isnan(two[k]))) << k;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const char* const map_files[] = {
    "peak_thickness.tif",    "peak_speed.tif",       "peak_kinetic_energy.tif",
    "peak_pressure.tif",     "arrival_time.tif",     "deposit_thickness.tif",
    "release_thickness.tif", "thickness_change.tif", "intensity.tif",
    "impact_area.geojson",   "deposit_area.geojson", "release_area.geojson"};

// A run stopped by SIGTERM after a checkpoint and restarted writes the same maps, byte for byte,
// as one that ran through: the peak fields and arrival times are in the checkpoint.
TEST(PeakMaps, ARestartContinuesThem) {
  const Case c = test::case_from(gliding_block(R"(
[output]
every = 0.1
[checkpoint]
every = 0.2
wall_minutes = 0
)"));
  RunOptions whole;
  whole.out_dir = test::temp_dir("maps_whole");
  whole.threads = 1;
  ASSERT_EQ(run_case(c, whole).status, "completed");
  RunOptions part = whole;
  part.out_dir = test::temp_dir("maps_restarted");
  part.inject_signal = SIGTERM;
  part.inject_signal_step = 30;
  ASSERT_EQ(run_case(c, part).status, "interrupted");
  part.inject_signal_step = -1;
  part.threads = 2;
  ASSERT_EQ(restart_run(part).status, "completed");
  for (const char* f : map_files) {
    const std::string a = file_bytes(whole.out_dir + "/maps/" + f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, file_bytes(part.out_dir + "/maps/" + f)) << f;
  }
}

// 2D: the maps are a profile along the section (maps/profile.csv, one row per cell along x). A
// block 1 m long and 0.5 m high gliding at 2 m/s for 0.5 s: each cell it passed over has
// h = 0.5 m (area per unit width over the cell's length), u = 2 m/s, e = rho h u^2 / 2,
// rho u^2, and the arrival of its leading particles.
TEST(PeakMaps, A2DSectionGivesItsProfile) {
  std::string text = gliding_block("[output]\nevery = 0.5\n");
  for (const auto& [from, to] :
       std::vector<std::pair<std::string, std::string>>{{"dimension = 3", "dimension = 2"},
                                                        {"[0.0, 0.0, 0.0]", "[0.0, 0.0]"},
                                                        {"[5.0, 2.0, 1.0]", "[5.0, 2.0]"},
                                                        {"[0.5, 0.5, 0.25]", "[0.5, 0.25]"},
                                                        {"[1.5, 1.5, 0.75]", "[1.5, 0.75]"},
                                                        {"[2.0, 0.0, 0.0]", "[2.0, 0.0]"}})
    text.replace(text.find(from), from.size(), to);
  const Case c = test::case_from(text, {"simulation.end_time=0.5"});
  RunOptions opt;
  opt.out_dir = test::temp_dir("maps_2d");
  opt.threads = 1;
  ASSERT_EQ(run_case(c, opt).status, "completed");
  std::ifstream in(opt.out_dir + "/maps/profile.csv");
  std::string line;
  std::getline(in, line); // the units
  std::getline(in, line);
  EXPECT_EQ(line, "x,peak_thickness,peak_speed,peak_kinetic_energy,peak_pressure,arrival_time,"
                  "intensity,deposit_thickness,release_thickness,thickness_change");
  int rows = 0;
  while (std::getline(in, line)) {
    double v[10];
    std::string cells = line;
    for (char& ch : cells)
      if (ch == ',') ch = ' ';
    std::istringstream row(cells);
    for (double& x : v)
      row >> x;
    const int i = rows++;
    SCOPED_TRACE(line);
    if (i < 1 || i > 4) { // beside the path: nothing
      EXPECT_EQ(v[1], 0.0);
      continue;
    }
    EXPECT_NEAR(v[0], 0.5 * i + 0.25, 1e-12);
    EXPECT_NEAR(v[1], height, 1e-3 * height);
    EXPECT_NEAR(v[2], speed, 1e-6 * speed);
    EXPECT_NEAR(v[3], 0.5 * density * height * speed * speed, 2.0);
    EXPECT_NEAR(v[4], density * speed * speed, 8.0);
    const double edge = 0.5 * i, lead = 1.5 - 0.0625;
    EXPECT_NEAR(v[5], edge < lead ? 0.0 : (edge - lead) / speed, 0.01);
    EXPECT_EQ(v[6], 2.0); // medium: h 0.5 m is below the high class's 1 m
    EXPECT_NEAR(v[7], i >= 3 ? height : 0.0, 1e-3 * height);
    EXPECT_NEAR(v[8], i <= 2 ? height : 0.0, 1e-9);
    EXPECT_NEAR(v[9], v[7] - v[8], 1e-9);
  }
  EXPECT_EQ(rows, 10);
}

// The maps' figures (summary.json "maps"): the gliding block after 0.5 s has reached 8 cells
// (2 m^2), lies on 4 (1 m^2), keeps its 0.5 m^3 and went at 2 m/s; with no DEM, no crown.
// Over a ground falling 1 in 2 along x, a release in the first two cells and an impact area
// over the first eight: the crown is the first cell, the tip the eighth, 7 m away in plan and
// 3.5 m lower: a Fahrboschung angle of atan(1/2), with the grid's origin added back.
TEST(PeakMaps, TheirFigures) {
  const Case c = test::case_from(gliding_block());
  Simulation<3> sim(c);
  PeakMaps<3> maps(c, sim);
  while (sim.time() < 0.5 - 1e-12) {
    sim.step(0.5 - sim.time());
    maps.accumulate(sim, sim.time());
  }
  const nlohmann::json f = maps.figures(maps.deposit(sim));
  EXPECT_DOUBLE_EQ(f["impact_area_m2"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(f["deposit_area_m2"].get<double>(), 1.0);
  EXPECT_NEAR(f["release_volume_m3"].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(f["deposit_volume_m3"].get<double>(), 0.5, 1e-3);
  EXPECT_NEAR(f["peak_speed_m_s"].get<double>(), speed, 1e-6 * speed);
  EXPECT_FALSE(f.contains("crown"));

  MapGrid g;
  g.nx = 10, g.ny = 1, g.dx = g.dy = 1.0, g.origin = {1000.0, 2000.0};
  std::vector<double> release(10, 0.0), peak(10, 0.0), deposit(10, 0.0), fast(10, 1.0);
  release[0] = release[1] = 2.0;
  for (int i = 0; i < 8; ++i)
    peak[i] = 1.0;
  deposit[6] = deposit[7] = 2.0;
  const nlohmann::json r = map_figures(
      3, g, 1.0, peak, fast, deposit, release, [](double x, double) { return 100.0 - 0.5 * x; },
      500.0);
  EXPECT_DOUBLE_EQ(r["impact_area_m2"].get<double>(), 8.0);
  EXPECT_DOUBLE_EQ(r["release_volume_m3"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(r["deposit_volume_m3"].get<double>(), 4.0);
  EXPECT_EQ(r["crown"], nlohmann::json({1000.5, 2000.5, 599.75}));
  EXPECT_EQ(r["tip"], nlohmann::json({1007.5, 2000.5, 596.25}));
  EXPECT_DOUBLE_EQ(r["runout_length_m"].get<double>(), 7.0);
  EXPECT_DOUBLE_EQ(r["drop_height_m"].get<double>(), 3.5);
  EXPECT_NEAR(r["fahrboschung_angle_deg"].get<double>(), std::atan(0.5) * 180.0 / std::numbers::pi,
              1e-12);
  // In 2D the same row is a section: lengths, and areas per unit width.
  const nlohmann::json s = map_figures(2, g, 1.0, peak, fast, deposit, release);
  EXPECT_DOUBLE_EQ(s["impact_length_m"].get<double>(), 8.0);
  EXPECT_DOUBLE_EQ(s["deposit_area_m2"].get<double>(), 4.0);
  EXPECT_FALSE(s.contains("runout_length_m"));
}

// The GeoTIFF: the grid with its origin added back, north up, the coordinate system, units,
// band names and no data (-9999) where a value is NaN.
TEST(PeakMaps, TheGeoTiffCarriesTheGridAndUnits) {
  MapGrid g;
  g.x0 = 10.0, g.y0 = 20.0, g.dx = 5.0, g.dy = 5.0, g.nx = 3, g.ny = 2;
  g.origin = {500000.0, 5000000.0};
  OGRSpatialReference srs;
  srs.importFromEPSG(32632); // UTM 32N
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  g.crs = wkt;
  CPLFree(wkt);
  const std::string dir = test::temp_dir("maps_tiff");
  MapLayer L{"peak_speed", "m/s", "largest speed", {0.0, 1.0, 2.0, 3.0, 4.0, std::nan("")}};
  write_geotiff(dir + "/m.tif", g, {L}, {{"TALUS_BODIES", "slide"}});
  GDALDatasetUniquePtr ds(GDALDataset::Open((dir + "/m.tif").c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(ds);
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  EXPECT_EQ(gt[0], 500010.0);
  EXPECT_EQ(gt[3], 5000030.0); // the northern edge: y0 + ny dy + origin
  EXPECT_EQ(gt[1], 5.0);
  EXPECT_EQ(gt[5], -5.0);
  ASSERT_TRUE(ds->GetSpatialRef());
  EXPECT_TRUE(ds->GetSpatialRef()->IsSame(&srs));
  EXPECT_STREQ(ds->GetMetadataItem("TALUS_BODIES"), "slide");
  GDALRasterBand* band = ds->GetRasterBand(1);
  EXPECT_STREQ(band->GetUnitType(), "m/s");
  EXPECT_STREQ(band->GetDescription(), "peak_speed");
  int has = 0;
  EXPECT_EQ(band->GetNoDataValue(&has), -9999.0);
  EXPECT_TRUE(has);
  float rows[6];
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 3, 2, rows, 3, 2, GDT_Float32, 0, 0), CE_None);
  // Row 0 is the north row (j = 1): 3, 4, no data; then j = 0: 0, 1, 2.
  EXPECT_EQ(rows[0], 3.0f);
  EXPECT_EQ(rows[1], 4.0f);
  EXPECT_EQ(rows[2], -9999.0f);
  EXPECT_EQ(rows[3], 0.0f);
  EXPECT_EQ(rows[5], 2.0f);
}

// The intensity classes over a sweep of thicknesses and speeds, for the Swiss debris-flow
// defaults (high: h > 1 m and v > 1 m/s; medium otherwise) and a three-class scheme.
TEST(PeakMaps, IntensityClassesFollowTheirThresholds) {
  MapsSettings swiss;
  MapsSettings three;
  three.high_thickness = 2.0, three.high_speed = 3.0;
  three.medium_thickness = 0.5, three.medium_speed = 1.0;
  for (const double h : {0.0, 0.1, 0.5, 0.99, 1.0, 1.01, 2.0, 2.5, 10.0})
    for (const double v : {0.2, 0.9, 1.0, 1.5, 3.0, 3.5, 30.0}) {
      const double a = intensity_class(h, v, swiss), b = intensity_class(h, v, three);
      if (h == 0.0) {
        EXPECT_TRUE(std::isnan(a) && std::isnan(b)) << h << ", " << v;
        continue;
      }
      EXPECT_EQ(a, h > 1.0 && v > 1.0 ? 3.0 : 2.0) << h << ", " << v;
      EXPECT_EQ(b, h > 2.0 && v > 3.0 ? 3.0 : h >= 0.5 && v >= 1.0 ? 2.0 : 1.0) << h << ", " << v;
    }
}

// Bad [maps] tables: the file, the line and the key named.
TEST(PeakMaps, BadTablesAreNamed) {
  auto error = [](const std::string& maps, int dimension = 3) {
    std::string text = gliding_block();
    text = text.substr(0, text.find("[maps]")) + maps;
    if (dimension == 2) {
      text.replace(text.find("dimension = 3"), 13, "dimension = 2");
      text.replace(text.find("[0.0, 0.0, 0.0]"), 15, "[0.0, 0.0]");
      text.replace(text.find("[5.0, 2.0, 1.0]"), 15, "[5.0, 2.0]");
      text.replace(text.find("[0.5, 0.5, 0.25]"), 16, "[0.5, 0.5]");
      text.replace(text.find("[1.5, 1.5, 0.75]"), 16, "[1.5, 1.5]");
      text.replace(text.find("[2.0, 0.0, 0.0]"), 15, "[2.0, 0.0]");
    }
    try {
      test::case_from(text);
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("[maps]\ncell_size = 1.0\n").find("maps.bodies: required key is missing"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"blok\"]\ncell_size = 1.0\n")
                .find("maps.bodies: no body is named 'blok' (did you mean 'block'?)"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"block\"]\n")
                .find("maps.cell_size: required: no mapped body has a terrain top raster"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"block\"]\ncell_size = -1.0\n").find("inline.toml:"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"block\"]\ncell_size = 1.0\nmoving_speed = 0.0\n")
                .find("maps.moving_speed: must be > 0"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"block\"]\ncell_size = 1.0\nmedium_speed = 2.0\n")
                .find("maps.high_speed: must be >= medium_speed"),
            std::string::npos);
  EXPECT_NE(error("[maps]\nbodies = [\"block\"]\n", 2).find("maps.cell_size: required"),
            std::string::npos);
  // A mapped body's name names files: letters, digits, _ and - only.
  std::string odd = gliding_block();
  odd.replace(odd.find("name = \"block\""), 14, "name = \"a/b\"");
  odd.replace(odd.find("bodies = [\"block\"]"), 18, "bodies = [\"a/b\"]");
  try {
    test::case_from(odd);
    ADD_FAILURE() << "a mapped body named a/b was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("letters, digits, _ and - only"), std::string::npos)
        << e.what();
  }
}

} // namespace
} // namespace talus
