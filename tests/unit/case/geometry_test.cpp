// Geometry: a shape filled with particles holds its area (2D) or volume (3D) to the sampling's
// error, with n particles per cell per direction of equal mass; surface normals of a box, a
// polygon edge and a disk are the outward unit normals of the nearest face.
#include "talus/case/geometry.hpp"
#include "talus/case/size.hpp"
#include "talus/setup/seeds.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>

namespace talus {
namespace {

std::string one_body(int dim, const std::string& shape, int per_cell) {
  return fmt::format(R"(
[simulation]
dimension = {0}
end_time = 1.0
[grid]
extent = {1}
cell_size = 0.1
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
[[body]]
name = "b"
material = "m"
{2}
particles_per_cell = {3}
)",
                     dim, dim == 2 ? "[2.0, 2.0]" : "[2.0, 2.0, 2.0]", shape, per_cell);
}

TEST(FillParticles, ABoxHoldsItsVolumeAndMass) {
  for (const int n : {1, 2, 3}) {
    const Case c = test::case_from(one_body(2, "box = { min = [0.2, 0.3], max = [1.4, 0.9] }", n));
    const Particles<2> P = fill_particles<2>(c);
    const double area = 1.2 * 0.6, s = 0.1 / n;
    EXPECT_EQ(P.size(), static_cast<std::size_t>(std::lround(area / (s * s)))) << n;
    double vol = 0.0, mass = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p)
      vol += P.vol0[p], mass += P.m[p];
    EXPECT_NEAR(vol, area, 1e-12);
    EXPECT_NEAR(mass, 2000.0 * area, 1e-9);
    EXPECT_EQ(count_particles(c, 0), P.size());
  }
}

TEST(FillParticles, ADiskAndASphereWithinTheSamplingError) {
  const Case disk = test::case_from(one_body(2, "disk = { center = [1.0, 1.0], radius = 0.5 }", 4));
  const double area = std::numbers::pi * 0.25, s2 = 0.1 / 4;
  // The error is at most the particles along the perimeter: 2 pi r / s of them.
  EXPECT_NEAR(fill_particles<2>(disk).size() * s2 * s2, area, 2 * std::numbers::pi * 0.5 * s2);
  const Case ball =
      test::case_from(one_body(3, "sphere = { center = [1.0, 1.0, 1.0], radius = 0.5 }", 2));
  const double volume = 4.0 / 3.0 * std::numbers::pi * 0.125, s3 = 0.05;
  EXPECT_NEAR(fill_particles<3>(ball).size() * s3 * s3 * s3, volume,
              4 * std::numbers::pi * 0.25 * s3);
  EXPECT_NEAR(shape_measure(ball.bodies[0].geometry[0], 3), volume, 1e-12);
}

// GIS exports repeat vertices (the ring closed by its first vertex, doubled points): the same
// polygon, the same particles.
TEST(FillParticles, RepeatedVerticesAreTheSamePolygon) {
  const std::string plain = "polygon = [[0.2, 0.2], [1.4, 0.2], [1.0, 1.1]]";
  const std::string repeated =
      "polygon = [[0.2, 0.2], [1.4, 0.2], [1.4, 0.2], [1.0, 1.1], [0.2, 0.2]]";
  const Case a = test::case_from(one_body(2, plain, 2)),
             b = test::case_from(one_body(2, repeated, 2));
  EXPECT_EQ(b.bodies[0].geometry[0].vertices, a.bodies[0].geometry[0].vertices);
  EXPECT_EQ(fill_particles<2>(b).x, fill_particles<2>(a).x);
}

TEST(SurfaceNormal, TheNearestFacesOutwardNormal) {
  Geometry box;
  box.kind = Geometry::Kind::box, box.min = {0, 0, 0}, box.max = {2, 1, 0};
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(1.0, 0.95)), Vec<2>(0, 1));
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(0.05, 0.5)), Vec<2>(-1, 0));
  // Outside the box, from its nearest point (the distance's gradient): level with the base and
  // beside the box, the side (a wall standing on a floor holds what comes at it there); beyond
  // a corner, the diagonal. On an edge, the x face, whatever the round-off.
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(-0.1, 0.0)), Vec<2>(-1, 0));
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(2.1, 0.02)), Vec<2>(1, 0));
  const Vec<2> corner = surface_normal<2>(box, Vec<2>(2.3, 1.4));
  EXPECT_NEAR(corner[0], 0.6, 1e-12);
  EXPECT_NEAR(corner[1], 0.8, 1e-12);
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(2.0 - 2e-16, 0.0)), Vec<2>(1, 0));
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(0.0, 1.0 - 1e-16)), Vec<2>(-1, 0));
  // A node a round-off below the base of a wall, beside it: on the edge, not below the box.
  bool edge = false;
  EXPECT_EQ(surface_normal<2>(box, Vec<2>(2.0, -1e-17), &edge), Vec<2>(1, 0));
  EXPECT_TRUE(edge);
  surface_normal<2>(box, Vec<2>(2.1, -1e-17), &edge);
  EXPECT_FALSE(edge);
  Geometry cube;
  cube.kind = Geometry::Kind::box, cube.min = {0, 0, 0}, cube.max = {2, 1, 3};
  EXPECT_EQ(surface_normal<3>(cube, Vec<3>(1.0, -0.2, 0.0)), Vec<3>(0, -1, 0));
  EXPECT_EQ(surface_normal<3>(cube, Vec<3>(1.0, 0.5, 3.05)), Vec<3>(0, 0, 1));
  Geometry tri; // counter-clockwise right triangle; its hypotenuse faces (1, 1) / sqrt 2
  tri.kind = Geometry::Kind::polygon, tri.vertices = {{0, 0}, {1, 0}, {0, 1}};
  const Vec<2> n = surface_normal<2>(tri, Vec<2>(0.45, 0.45));
  EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(n[1], std::sqrt(0.5), 1e-12);
  Geometry disk;
  disk.kind = Geometry::Kind::disk, disk.center = {1, 1, 0}, disk.radius = 0.5;
  const Vec<2> r = surface_normal<2>(disk, Vec<2>(1.3, 1.4));
  EXPECT_NEAR(r[0], 0.6, 1e-12);
  EXPECT_NEAR(r[1], 0.8, 1e-12);
}

// The exact shapes of a surface contact: the signed distance (negative inside) with the outward
// normal at the nearest surface point, and the surface points near a point inside.
TEST(SignedDistance, BoxPolygonDiskAndSphere) {
  Geometry box;
  box.kind = Geometry::Kind::box, box.min = {0, 0, 0}, box.max = {2, 1, 0};
  Vec<2> n;
  EXPECT_NEAR(signed_distance<2>(box, Vec<2>(1.0, 1.3), n), 0.3, 1e-12);
  EXPECT_EQ(n, Vec<2>(0, 1));
  EXPECT_NEAR(signed_distance<2>(box, Vec<2>(1.9, 0.5), n), -0.1, 1e-12); // nearest the right face
  EXPECT_EQ(n, Vec<2>(1, 0));
  EXPECT_NEAR(signed_distance<2>(box, Vec<2>(2.3, 1.4), n), 0.5, 1e-12); // beyond a corner
  EXPECT_NEAR(n[0], 0.6, 1e-12);
  EXPECT_NEAR(n[1], 0.8, 1e-12);
  Geometry tri; // clockwise this time: the normal is outward whatever the order
  tri.kind = Geometry::Kind::polygon, tri.vertices = {{0, 0}, {0, 1}, {1, 0}};
  EXPECT_NEAR(signed_distance<2>(tri, Vec<2>(0.4, 0.45), n), -0.15 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(n[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(n[1], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(signed_distance<2>(tri, Vec<2>(0.5, -0.2), n), 0.2, 1e-12);
  EXPECT_NEAR(n[1], -1.0, 1e-12);
  Geometry ball;
  ball.kind = Geometry::Kind::disk, ball.center = {1, 1, 1}, ball.radius = 0.5;
  Vec<3> m;
  EXPECT_NEAR(signed_distance<3>(ball, Vec<3>(1.0, 1.3, 1.4), m), 0.0, 1e-12);
  EXPECT_NEAR(m[1], 0.6, 1e-12);
  EXPECT_NEAR(signed_distance<3>(ball, Vec<3>(1.0, 1.0, 1.2), m), -0.3, 1e-12);
  Geometry prism;
  prism.kind = Geometry::Kind::prism;
  EXPECT_FALSE(has_exact_surface(prism, 3));
  EXPECT_TRUE(has_exact_surface(tri, 2));
}

TEST(SurfacePointsNear, OnePerFaceOrEdgeWithinReach) {
  Geometry box;
  box.kind = Geometry::Kind::box, box.min = {0, 0, 0}, box.max = {2, 1, 0};
  std::vector<Vec<2>> q;
  surface_points_near<2>(box, Vec<2>(0.05, 0.05), 0.075, q); // a corner's particle: two points
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0], Vec<2>(0.0, 0.05));
  EXPECT_EQ(q[1], Vec<2>(0.05, 0.0));
  q.clear();
  surface_points_near<2>(box, Vec<2>(1.0, 0.5), 0.075, q); // inside: none
  EXPECT_TRUE(q.empty());
  Geometry tri;
  tri.kind = Geometry::Kind::polygon, tri.vertices = {{0, 0}, {1, 0}, {0, 1}};
  surface_points_near<2>(tri, Vec<2>(0.02, 0.5), 0.05, q); // the left edge only
  ASSERT_EQ(q.size(), 1u);
  EXPECT_NEAR(q[0][0], 0.0, 1e-15);
  EXPECT_NEAR(q[0][1], 0.5, 1e-15);
  q.clear();
  surface_points_near<2>(tri, Vec<2>(0.9, 0.02), 0.2, q); // near a vertex: its two edges
  EXPECT_EQ(q.size(), 2u);
  Geometry disk;
  disk.kind = Geometry::Kind::disk, disk.center = {1, 1, 0}, disk.radius = 0.5;
  q.clear();
  surface_points_near<2>(disk, Vec<2>(1.0, 0.55), 0.1, q); // its point straight below
  ASSERT_EQ(q.size(), 1u);
  EXPECT_NEAR(q[0][1], 0.5, 1e-15);
}

} // namespace
} // namespace talus
