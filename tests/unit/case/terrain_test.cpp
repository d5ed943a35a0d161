// Terrain bodies (3D): the region between two elevation rasters (or a constant, or a depth below
// the top) inside a footprint holds the closed form's volume to the sampling's error; an
// extruded polygon holds its area times its length; no-data cells are holes; the origin shift
// moves nothing; the surfaces' normals are the planes'; and every input error is refused with
// the file and what is wrong.
#include "talus/case/geometry.hpp"
#include "talus/case/size.hpp"
#include "talus/setup/seeds.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <iterator>
#include <ogr_spatialref.h>

namespace talus {
namespace {

// An ESRI ASCII grid of nx x ny cells of size `cell`, south-west corner (x0, y0), holding
// z(x, y) at each cell's centre; `nodata(x, y)` marks cells without data (-9999).
void write_asc(const std::string& path, int nx, int ny, double x0, double y0, double cell,
               const std::function<double(double, double)>& z,
               const std::function<bool(double, double)>& nodata = {}) {
  std::ofstream f(path);
  f << fmt::format("ncols {}\nnrows {}\nxllcorner {}\nyllcorner {}\ncellsize {}\n"
                   "NODATA_value -9999\n",
                   nx, ny, x0, y0, cell);
  for (int row = 0; row < ny; ++row) { // the first row is the northern one
    for (int col = 0; col < nx; ++col) {
      const double x = x0 + (col + 0.5) * cell, y = y0 + (ny - 1 - row + 0.5) * cell;
      f << fmt::format("{:.10g} ", nodata && nodata(x, y) ? -9999.0 : z(x, y));
    }
    f << "\n";
  }
}

void write_prj(const std::string& path, int epsg) {
  OGRSpatialReference s;
  ASSERT_EQ(s.importFromEPSG(epsg), OGRERR_NONE);
  char* wkt = nullptr;
  s.exportToWkt(&wkt);
  std::ofstream(path) << wkt;
  CPLFree(wkt);
}

void expect_refused(const std::string& toml, const std::vector<std::string>& words,
                    bool at_fill = false);

// A 3D case of one body `shape` on a grid of 0.5 m cells over [0, 40] x [0, 30] x [0, 40].
std::string terrain_case(const std::string& shape, const std::string& extra = "") {
  return fmt::format(R"(
[simulation]
dimension = 3
end_time = 1.0
gravity = [0, 0, -9.81]
[grid]
extent = [40, 30, 40]
cell_size = 0.5
{1}
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
[[body]]
name = "b"
material = "m"
{0}
)",
                     shape, extra);
}

double volume_of(const Particles<3>& P) {
  double v = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p)
    v += P.vol0[p];
  return v;
}

// The area and centroid of a polygon (shoelace).
std::array<double, 3> area_centroid(const std::vector<std::array<double, 2>>& v) {
  double a = 0.0, cx = 0.0, cy = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto &p = v[i], &q = v[(i + 1) % v.size()];
    const double w = p[0] * q[1] - q[0] * p[1];
    a += w, cx += (p[0] + q[0]) * w, cy += (p[1] + q[1]) * w;
  }
  return {0.5 * a, cx / (3.0 * a), cy / (3.0 * a)};
}

const std::vector<std::array<double, 2>> pentagon = {
    {5.0, 4.0}, {33.0, 6.0}, {36.0, 20.0}, {18.0, 27.0}, {4.0, 18.0}};

std::string inline_polygon(const std::vector<std::array<double, 2>>& v) {
  std::string s = "[";
  for (const auto& p : v)
    s += fmt::format("[{}, {}], ", p[0], p[1]);
  return s + "]";
}

// The volume between two planes over a polygon is its area times the thickness at its centroid.
// The sampling's error: half a particle layer along the footprint's perimeter (the columns cut
// by its edges) and the layers cut by the two surfaces, half a particle thick over the area.
TEST(Terrain, BetweenTwoPlanarRastersTheClosedFormsVolumeAndMass) {
  const std::string dir = test::temp_dir("terrain_planes");
  auto top = [](double x, double y) { return 20.0 + 0.1 * x + 0.05 * y; };
  auto bottom = [](double x, double) { return 2.0 + 0.02 * x; };
  write_asc(dir + "/top.asc", 42, 32, -1.0, -1.0, 1.0, top);
  write_asc(dir + "/bottom.asc", 21, 16, -1.0, -1.0, 2.0, bottom);
  const Case c = test::case_from(terrain_case(
      fmt::format("terrain = {{ top = '{0}/top.asc', bottom = '{0}/bottom.asc', footprint = {1} }}",
                  dir, inline_polygon(pentagon))));
  const Particles<3> P = fill_particles<3>(c);
  const auto [area, cx, cy] = area_centroid(pentagon);
  const double volume = area * (top(cx, cy) - bottom(cx, cy)), s = 0.25;
  double perimeter = 0.0;
  for (std::size_t i = 0; i < pentagon.size(); ++i)
    perimeter += std::hypot(pentagon[(i + 1) % 5][0] - pentagon[i][0],
                            pentagon[(i + 1) % 5][1] - pentagon[i][1]);
  const double error = 0.5 * s * perimeter * (top(cx, cy) - bottom(cx, cy)) + s * area;
  EXPECT_NEAR(volume_of(P), volume, error);
  EXPECT_LT(std::abs(volume_of(P) / volume - 1.0), 0.01);
  double mass = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p)
    mass += P.m[p];
  EXPECT_NEAR(mass, 2000.0 * volume_of(P), 1e-6 * mass);
  // Every particle between the planes and inside the footprint.
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vec<3>& x = P.x[p];
    ASSERT_TRUE(point_in_polygon(pentagon, x[0], x[1]));
    ASSERT_GE(x[2], bottom(x[0], x[1]) - 1e-9);
    ASSERT_LE(x[2], top(x[0], x[1]) + 1e-9);
  }
  EXPECT_EQ(count_particles(c, 0), P.size());
  // `talus check`'s estimate, from 64 x 64 sampled columns, within 2 %.
  EXPECT_NEAR(shape_measure(c.bodies[0].geometry[0], 3), volume, 0.02 * volume);
}

TEST(Terrain, ADepthBelowTheTopAHeightAboveTheBottomAndConstantSurfaces) {
  const std::string dir = test::temp_dir("terrain_depth");
  write_asc(dir + "/top.asc", 40, 30, 0.0, 0.0, 1.0,
            [](double x, double y) { return 25.0 + 0.2 * x - 0.1 * y; });
  const std::string box = "[[8, 6], [30, 6], [30, 24], [8, 24]]";
  const Case depth = test::case_from(terrain_case(fmt::format(
      "terrain = {{ top = '{}/top.asc', bottom = {{ depth = 6.0 }}, footprint = {} }}", dir, box)));
  const double area = 22.0 * 18.0;
  EXPECT_NEAR(volume_of(fill_particles<3>(depth)), area * 6.0, 0.25 * area);
  const Case height = test::case_from(terrain_case(
      fmt::format("terrain = {{ top = {{ height = 6.0 }}, bottom = '{}/top.asc', footprint = {} }}",
                  dir, box)));
  EXPECT_NEAR(volume_of(fill_particles<3>(height)), area * 6.0, 0.25 * area);
  const Case flat = test::case_from(
      terrain_case(fmt::format("terrain = {{ top = 12.0, bottom = 3.0, footprint = {} }}", box)));
  // Flat surfaces on the particle lattice: exactly 36 layers of 0.25 m.
  EXPECT_NEAR(volume_of(fill_particles<3>(flat)), area * 9.0, 1e-9 * area);
}

// Rasters in projected metres far from the origin, and the [terrain] origin that brings them
// home: the same particles as the local rasters.
TEST(Terrain, TheOriginShiftMovesNothing) {
  const std::string dir = test::temp_dir("terrain_origin");
  auto top = [](double x, double y) { return 20.0 + 0.1 * x + 0.05 * y; };
  const double E = 742000.0, N = 5125000.0, Z = 630.0;
  write_asc(dir + "/local.asc", 40, 30, 0.0, 0.0, 1.0, top);
  write_asc(dir + "/utm.asc", 40, 30, E, N, 1.0,
            [&](double x, double y) { return top(x - E, y - N) + Z; });
  std::ofstream(dir + "/utm.csv") << fmt::format("x,y\n{},{}\n{},{}\n{},{}\n", E + 5, N + 4, E + 33,
                                                 N + 6, E + 18, N + 27);
  const Case local = test::case_from(terrain_case(fmt::format(
      "terrain = {{ top = '{}/local.asc', bottom = 2.0, footprint = [[5, 4], [33, 6], [18, 27]] }}",
      dir)));
  const Case utm = test::case_from(terrain_case(
      fmt::format("terrain = {{ top = '{0}/utm.asc', bottom = 2.0, footprint = '{0}/utm.csv' }}",
                  dir),
      fmt::format("[terrain]\norigin = [{}, {}, {}]", E, N, Z)));
  const Particles<3> a = fill_particles<3>(local), b = fill_particles<3>(utm);
  ASSERT_GT(a.size(), 1000u);
  EXPECT_EQ(a.x, b.x);
}

// The same terrain from a GeoTIFF (written here with GDAL) and a GeoJSON footprint, both in a
// projected system far from the origin, gives the particles of the ESRI grid and the inline
// footprint; a footprint in another coordinate system than its raster is refused.
TEST(Terrain, GeoTiffAndGeoJsonReadAsTheGridAndTheInlineFootprint) {
  const std::string dir = test::temp_dir("terrain_formats");
  auto top = [](double x, double y) { return 20.0 + 0.1 * x + 0.05 * y; };
  const double E = 742000.0, N = 5125000.0;
  write_asc(dir + "/local.asc", 40, 30, 0.0, 0.0, 1.0, top);
  GDALAllRegister();
  {
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    ASSERT_NE(gtiff, nullptr);
    GDALDatasetUniquePtr ds(
        gtiff->Create((dir + "/utm.tif").c_str(), 40, 30, 1, GDT_Float32, nullptr));
    double gt[6] = {E, 1.0, 0.0, N + 30.0, 0.0, -1.0}; // north-up: the first row is the north
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(32632);
    ds->SetSpatialRef(&srs);
    std::vector<float> z(40 * 30);
    for (int row = 0; row < 30; ++row)
      for (int col = 0; col < 40; ++col)
        z[row * 40 + col] = static_cast<float>(top(col + 0.5, 29 - row + 0.5));
    ASSERT_EQ(
        ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 40, 30, z.data(), 40, 30, GDT_Float32, 0, 0),
        CE_None);
  }
  auto geojson = [&](int epsg) {
    return fmt::format(
        R"({{"type": "FeatureCollection", "crs": {{"type": "name", "properties": {{"name":
        "urn:ogc:def:crs:EPSG::{}"}}}}, "features": [{{"type": "Feature", "properties": {{}},
        "geometry": {{"type": "Polygon", "coordinates": [[[{}, {}], [{}, {}], [{}, {}], [{}, {}]]]}}}}]}})",
        epsg, E + 5, N + 4, E + 33, N + 6, E + 18, N + 27, E + 5, N + 4);
  };
  std::ofstream(dir + "/utm.geojson") << geojson(32632);
  std::ofstream(dir + "/italy.geojson") << geojson(3003);
  const Case local = test::case_from(terrain_case(fmt::format(
      "terrain = {{ top = '{}/local.asc', bottom = 2.0, footprint = [[5, 4], [33, 6], [18, 27]] }}",
      dir)));
  const std::string origin = fmt::format("[terrain]\norigin = [{}, {}, 0.0]", E, N);
  const Case utm =
      test::case_from(terrain_case(fmt::format("terrain = {{ top = '{0}/utm.tif', bottom = 2.0, "
                                               "footprint = '{0}/utm.geojson' }}",
                                               dir),
                                   origin));
  const Particles<3> a = fill_particles<3>(local), b = fill_particles<3>(utm);
  ASSERT_GT(a.size(), 1000u);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0; // float32 elevations move the top by 1e-6 m, far from any lattice point
  for (std::size_t p = 0; p < a.size(); ++p)
    worst = std::max(worst, (a.x[p] - b.x[p]).norm());
  EXPECT_EQ(worst, 0.0);
  expect_refused(terrain_case(fmt::format("terrain = {{ top = '{0}/utm.tif', bottom = 2.0, "
                                          "footprint = '{0}/italy.geojson' }}",
                                          dir),
                              origin),
                 {"terrain.footprint", "coordinate system", "3003", "32632"});
}

// Cells without data are holes through the body: no particle above them, and the rest whole.
TEST(Terrain, NoDataCellsAreHoles) {
  const std::string dir = test::temp_dir("terrain_holes");
  auto hole = [](double x, double y) { return x > 10 && x < 16 && y > 10 && y < 14; };
  write_asc(
      dir + "/top.asc", 40, 30, 0.0, 0.0, 1.0, [](double, double) { return 10.0; }, hole);
  const Case c = test::case_from(
      terrain_case(fmt::format("terrain = {{ top = '{}/top.asc', bottom = 4.0 }}", dir)));
  const Particles<3> P = fill_particles<3>(c);
  for (std::size_t p = 0; p < P.size(); ++p)
    ASSERT_FALSE(P.x[p][0] > 9.5 && P.x[p][0] < 16.5 && P.x[p][1] > 9.5 && P.x[p][1] < 14.5)
        << P.x[p].transpose();
  // The hole is 6 x 4 cells, and bilinear interpolation reaches half a cell beyond it; the
  // raster (no footprint) covers the grid's plan.
  const double missing = 7.0 * 5.0 * 6.0;
  EXPECT_NEAR(volume_of(P), 40.0 * 30.0 * 6.0 - missing, 1e-9);
}

TEST(Terrain, AnExtrudedPolygonHoldsItsAreaTimesItsLength) {
  const std::string tri = "polygon = [[2, 1], [30, 3], [12, 25]]";
  for (const std::string axis : {"x", "y", "z"}) {
    const Case c = test::case_from(terrain_case(
        fmt::format("{}\nextrude = {{ axis = '{}', from = 3.0, to = 27.0 }}", tri, axis)));
    const Geometry& g = c.bodies[0].geometry[0];
    const Particles<3> P = fill_particles<3>(c);
    const double area = area_centroid(g.vertices)[0] * (area_centroid(g.vertices)[0] > 0 ? 1 : -1);
    const double volume = area * 24.0;
    EXPECT_NEAR(volume_of(P), volume, 0.01 * volume) << axis;
    EXPECT_NEAR(shape_measure(g, 3), volume, 1e-9 * volume) << axis;
    const int a = axis[0] - 'x';
    const auto [u, w] = prism_axes(a);
    for (std::size_t p = 0; p < P.size(); ++p) {
      ASSERT_TRUE(P.x[p][a] >= 3.0 && P.x[p][a] <= 27.0);
      ASSERT_TRUE(point_in_polygon(g.vertices, P.x[p][u], P.x[p][w]));
    }
  }
}

// Geometric normals: the top plane's upward normal, the bottom's downward, the footprint's walls
// outward, a prism's caps and walls (the raster holds 10 significant digits: 1e-6).
TEST(Terrain, SurfaceNormalsOfThePlanesAndWalls) {
  const std::string dir = test::temp_dir("terrain_normals");
  write_asc(dir + "/top.asc", 40, 30, 0.0, 0.0, 1.0,
            [](double x, double y) { return 20.0 + 0.3 * x - 0.2 * y; });
  const Case c = test::case_from(
      terrain_case(fmt::format("terrain = {{ top = '{}/top.asc', bottom = {{ depth = 8.0 }}, "
                               "footprint = [[5, 5], [35, 5], [35, 25], [5, 25]] }}",
                               dir)));
  const Geometry& g = c.bodies[0].geometry[0];
  const Vec<3> up = Vec<3>(-0.3, 0.2, 1.0).normalized();
  auto z_top = [](double x, double y) { return 20.0 + 0.3 * x - 0.2 * y; };
  EXPECT_LT((surface_normal<3>(g, Vec<3>(20, 15, z_top(20, 15) + 0.3)) - up).norm(), 1e-6);
  EXPECT_LT((surface_normal<3>(g, Vec<3>(20, 15, z_top(20, 15) - 0.5)) - up).norm(), 1e-6);
  EXPECT_LT((surface_normal<3>(g, Vec<3>(20, 15, z_top(20, 15) - 7.8)) + up).norm(), 1e-6);
  EXPECT_LT((surface_normal<3>(g, Vec<3>(5.2, 15, z_top(5.2, 15) - 4)) - Vec<3>(-1, 0, 0)).norm(),
            1e-12);
  EXPECT_LT((surface_normal<3>(g, Vec<3>(20, 24.9, z_top(20, 24.9) - 4)) - Vec<3>(0, 1, 0)).norm(),
            1e-12);
  // Outside the footprint, from the body's nearest point: beside the wall level with its foot
  // (0.1 m above the bottom's surface there, which the old rule took), the wall's normal;
  // beside it above the top, from the wall's rim (0.5 m out, 0.4 m above the top at the wall,
  // 21 m); on the wall at the bottom's
  // level, two faces equally near, an edge.
  EXPECT_LT(
      (surface_normal<3>(g, Vec<3>(20, 25.5, z_top(20, 25.5) - 7.9)) - Vec<3>(0, 1, 0)).norm(),
      1e-12);
  EXPECT_LT((surface_normal<3>(g, Vec<3>(20, 25.5, z_top(20, 25.5) + 0.5)) -
             Vec<3>(0, 0.5, 0.4).normalized())
                .norm(),
            1e-6);
  bool edge = false;
  surface_normal<3>(g, Vec<3>(20, 25, z_top(20, 25) - 8), &edge);
  EXPECT_TRUE(edge);
  surface_normal<3>(g, Vec<3>(20, 15, z_top(20, 15) - 0.5), &edge);
  EXPECT_FALSE(edge);
  // A footprint's wall on the grid's face bounds nothing: there the normal is the top's (0.6 m
  // from the wall, 0.67 m below the top).
  const Case flush = test::case_from(
      terrain_case(fmt::format("terrain = {{ top = '{}/top.asc', bottom = {{ depth = 8.0 }}, "
                               "footprint = [[0, 0], [40, 0], [40, 30], [0, 30]] }}",
                               dir)));
  const Geometry& f = flush.bodies[0].geometry[0];
  EXPECT_EQ(f.open_edge, std::vector<char>(4, 1));
  EXPECT_LT((surface_normal<3>(f, Vec<3>(20, 0.6, z_top(20, 0.6) - 0.7)) - up).norm(), 1e-6);
  const Case p = test::case_from(terrain_case("polygon = [[2, 1], [30, 1], [30, 25], [2, "
                                              "25]]\nextrude = { axis = 'y', from = 3, to = 27 }"));
  const Geometry& q = p.bodies[0].geometry[0]; // the polygon's (x, z), extruded along y
  EXPECT_EQ(surface_normal<3>(q, Vec<3>(10, 3.2, 12)), Vec<3>(0, -1, 0));
  EXPECT_EQ(surface_normal<3>(q, Vec<3>(10, 15, 24.5)), Vec<3>(0, 0, 1));
  EXPECT_EQ(surface_normal<3>(q, Vec<3>(29.9, 15, 12)), Vec<3>(1, 0, 0));
  // Extruded across the whole grid: its caps are the grid's faces, not surfaces.
  const Case across =
      test::case_from(terrain_case("polygon = [[2, 1], [30, 1], [30, 25], [2, 25]]\nextrude = { "
                                   "axis = 'y', from = 0, to = 30 }"));
  EXPECT_EQ(surface_normal<3>(across.bodies[0].geometry[0], Vec<3>(10, 0.2, 24.5)),
            Vec<3>(0, 0, 1));
}

// Every input error names the file and what is wrong.
void expect_refused(const std::string& toml, const std::vector<std::string>& words, bool at_fill) {
  try {
    const Case c = test::case_from(toml);
    if (at_fill) fill_particles<3>(c);
    ADD_FAILURE() << "accepted: " << toml;
  } catch (const CaseError& e) {
    for (const std::string& w : words)
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos)
          << "'" << e.what() << "' lacks '" << w << "'";
  }
}

TEST(Terrain, InputErrorsAreRefusedNamingTheFileAndTheProblem) {
  const std::string dir = test::temp_dir("terrain_errors");
  auto flat = [](double v) { return [v](double, double) { return v; }; };
  write_asc(dir + "/top.asc", 40, 30, 0.0, 0.0, 1.0, flat(20.0));
  write_asc(dir + "/small.asc", 10, 10, 0.0, 0.0, 1.0, flat(5.0));
  write_asc(dir + "/far.asc", 10, 10, 100.0, 100.0, 1.0, flat(5.0));
  write_asc(dir + "/absurd.asc", 10, 10, 0.0, 0.0, 1.0,
            [](double x, double y) { return x > 3 && x < 4 && y > 7 && y < 8 ? 2.0e5 : 5.0; });
  write_asc(dir + "/crossing.asc", 40, 30, 0.0, 0.0, 1.0,
            [](double x, double) { return x < 20 ? 10.0 : 30.0; });
  write_asc(dir + "/utm.asc", 40, 30, 0.0, 0.0, 1.0, flat(3.0));
  write_prj(dir + "/utm.prj", 32632);
  write_asc(dir + "/italy.asc", 40, 30, 0.0, 0.0, 1.0, flat(20.0));
  write_prj(dir + "/italy.prj", 3003);
  write_asc(dir + "/degrees.asc", 40, 30, 0.0, 0.0, 1.0, flat(20.0));
  write_prj(dir + "/degrees.prj", 4326);
  std::ofstream(dir + "/not_a_raster.asc") << "hello\n";
  std::ofstream(dir + "/not_a_raster.tif") << "hello\n";
  // A header typo on the first or a later line; a header of 5 x 5 cells over 10 x 10 values.
  auto edit = [&](const std::string& from, const std::string& to, const std::string& was,
                  const std::string& now) {
    std::ifstream in(dir + "/" + from);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find(was), was.size(), now);
    std::ofstream(dir + "/" + to) << text;
  };
  write_asc(dir + "/ten.asc", 10, 10, 0.0, 0.0, 4.0, flat(20.0));
  edit("ten.asc", "typo.asc", "nrows", "nrowz");
  edit("ten.asc", "typo_first.asc", "ncols", "ncolls");
  edit("ten.asc", "short_header.asc", "ncols 10\nnrows 10\n", "ncols 5\nnrows 5\n");
  edit("ten.asc", "twice.asc", "nrows 10\n", "nrows 10\nncols 10\n");
  // A header of 30,000 x 30,000 cells over 100 values: refused from its header, before the
  // 7.2 GB its values would take are asked for.
  edit("ten.asc", "huge_header.asc", "ncols 10\nnrows 10\n", "ncols 30000\nnrows 30000\n");
  edit("ten.asc", "fraction.asc", "ncols 10\n", "ncols 10.5\n");
  write_asc(dir + "/high.asc", 40, 30, 0.0, 0.0, 1.0, flat(30.0));
  {
    // A float GeoTIFF with a NaN where the file declares no no-data value.
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
        (dir + "/nan.tif").c_str(), 2, 2, 1, GDT_Float32, nullptr));
    double gt[6] = {0.0, 20.0, 0.0, 40.0, 0.0, -20.0};
    ds->SetGeoTransform(gt);
    float z[4] = {5.0f, 5.0f, std::nanf(""), 5.0f};
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 2, 2, z, 2, 2, GDT_Float32, 0, 0),
              CE_None);
  }
  write_asc(dir + "/one_cell.asc", 1, 1, 0.0, 0.0, 40.0, flat(5.0));
  const std::string fp = "footprint = [[5, 5], [35, 5], [35, 25], [5, 25]]";
  auto terrain = [&](const std::string& keys) {
    return terrain_case("terrain = { " + keys + " }");
  };
  expect_refused(
      terrain(fmt::format("top = '{0}/top.asc', bottom = '{0}/small.asc', {1}", dir, fp)),
      {"small.asc does not cover the footprint", "vertex 1 (35, 5)", "terrain.bottom"});
  expect_refused(terrain(fmt::format("top = '{0}/top.asc', bottom = '{0}/far.asc'", dir)),
                 {"do not overlap"});
  expect_refused(terrain(fmt::format("top = 30.0, bottom = '{0}/absurd.asc'", dir)),
                 {"absurd.asc", "row 2, column 3", "200000", "not an elevation"});
  expect_refused(terrain(fmt::format("top = '{0}/italy.asc', bottom = '{0}/utm.asc'", dir)),
                 {"terrain.bottom", "coordinate system", "32632", "3003"});
  expect_refused(terrain(fmt::format("top = '{0}/degrees.asc', bottom = 2.0", dir)),
                 {"degrees.asc", "in degrees", "reproject"});
  expect_refused(
      terrain(fmt::format("top = '{0}/not_a_raster.asc', bottom = 2.0", dir)),
      {"not_a_raster.asc:1: 'hello' is not a key of an ESRI ASCII grid's header", "terrain.top"});
  expect_refused(terrain(fmt::format("top = '{0}/not_a_raster.tif', bottom = 2.0", dir)),
                 {"not_a_raster.tif: GDAL does not read it as a raster", "terrain.top"});
  expect_refused(terrain(fmt::format("top = '{0}/typo.asc', bottom = 2.0", dir)),
                 {"typo.asc:2: 'nrowz' is not a key", "terrain.top"});
  expect_refused(terrain(fmt::format("top = '{0}/typo_first.asc', bottom = 2.0", dir)),
                 {"typo_first.asc:1: 'ncolls' is not a key", "terrain.top"});
  expect_refused(terrain(fmt::format("top = '{0}/short_header.asc', bottom = 2.0", dir)),
                 {"short_header.asc", "header says 5 x 5 cells (25 values)",
                  "holds 100 values after the header"});
  expect_refused(terrain(fmt::format("top = '{0}/huge_header.asc', bottom = 2.0", dir)),
                 {"huge_header.asc", "header says 30000 x 30000 cells (900000000 values)",
                  "holds 100 values after the header"});
  expect_refused(terrain(fmt::format("top = '{0}/twice.asc', bottom = 2.0", dir)),
                 {"twice.asc:3: 'ncols' is given twice"});
  expect_refused(terrain(fmt::format("top = '{0}/fraction.asc', bottom = 2.0", dir)),
                 {"fraction.asc:1: ncols '10.5' is not a whole number"});
  expect_refused(terrain("top = \"\\u001b[31mtop.asc\", bottom = 2.0"),
                 {"terrain.top", "holds a control character"});
  expect_refused(terrain(fmt::format("top = 30.0, bottom = '{0}/nan.tif'", dir)),
                 {"nan.tif", "row 1, column 0", "nan", "not an elevation"});
  expect_refused(terrain(fmt::format("top = 30.0, bottom = '{0}/one_cell.asc'", dir)),
                 {"one_cell.asc", "1 x 1 cells", "at least 2 x 2"});
  expect_refused(terrain(fmt::format("top = '{0}/missing.tif', bottom = 2.0", dir)),
                 {"missing.tif", "missing.tif: no such file"});
  expect_refused(terrain(fmt::format("top = '{0}/crossing.asc', bottom = 20.0", dir)),
                 {"bottom (20 m) is above its top (10 m)", "crossing.asc", "row", "column"}, true);
  // A bottom above its top everywhere: the surfaces' ranges do not overlap at all.
  expect_refused(terrain(fmt::format("top = '{0}/top.asc', bottom = '{0}/high.asc'", dir)),
                 {"bottom (30 m) is above its top (20 m) at x =", "row", "column"}, true);
  expect_refused(terrain("top = 10.0, bottom = 2.0"), {"need a footprint"});
  expect_refused(terrain("top = 10.0, bottom = 12.0, " + fp), {"is not below the top"});
  expect_refused(terrain("top = 10.0, bottom = { depth = -1 }, " + fp), {"depth", "> 0"});
  expect_refused(terrain("top = { height = 2 }, bottom = { depth = 1 }, " + fp),
                 {"terrain.top", "give one surface"});
  expect_refused(terrain("top = 10.0, bottom = 2.0, footprint = [[50, 5], [60, 5], [60, 9]]"),
                 {"outside the grid"});
  expect_refused(
      terrain("top = 30.0, bottom = 25.0, footprint = [[5.01, 5.01], [5.1, 5.01], [5.05, 5.1]]"),
      {"holds no particle"}, true);
  expect_refused(terrain_case("polygon = [[1, 1], [5, 1], [3, 4]]"), {"extrude"});
  // 2D: neither terrain nor extrude.
  std::string two_d = terrain_case("terrain = { top = 10.0, bottom = 2.0, " + fp + " }");
  two_d.replace(two_d.find("dimension = 3"), 13, "dimension = 2");
  two_d.replace(two_d.find("[0, 0, -9.81]"), 13, "[0, -9.81]");
  two_d.replace(two_d.find("[40, 30, 40]"), 12, "[40, 30]");
  expect_refused(two_d, {"terrain bodies are 3D"});
}

} // namespace
} // namespace talus
