// A body in the corner of two rigid bodies, a wall standing on a floor (docs/formulation.md,
// "Several rigid bodies at a node"): at a node that both reach, the deformable body meets the
// heavier in the node's law and the other in a pair of its own, and a box's normal beside its
// base is its side's. Against statics: a tank whose floor and walls are three rigid bodies holds
// its water at rest with the hydrostatic thrust rho g H^2 / 2 on each wall and rho g H W on the
// floor, at two depths, in 2D and 3D; a block pressed into the corner by gravity tilted towards
// the wall carries m g sin(theta) on the wall and m g cos(theta) on the floor, each along its
// normal, at three angles. With the wall left out of the corner nodes, the water runs under it
// (under FLIP 0.99, out of the grid within 0.2 s; under PIC 2-4 cm into the walls and 10 % of
// the thrust lost in 3D).
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>
#include <string>

namespace talus {
namespace {

constexpr double g = 9.81, rho_w = 1000.0;

// Rigid steel: a floor 0.1 m thick over the whole grid and two walls 0.1 m thick standing on it,
// their inner faces at x = 0.2 and 1.2 m (bodies 0, 1, 2). In 3D the grid is `depth` deep in y,
// between slip faces.
std::string tank_walls(int dim, double h, double depth) {
  const bool three = dim == 3;
  auto point = [&](double x, double y_or_z, double y) {
    return three ? fmt::format("[{}, {}, {}]", x, y, y_or_z) : fmt::format("[{}, {}]", x, y_or_z);
  };
  return fmt::format(R"(
[grid]
extent = {0}
cell_size = {1}
shape_function = "gimp"
{2}
[[material]]
name = "steel"
density = 7800.0
youngs_modulus = 2.0e11
poisson_ratio = 0.3
[[body]]
name = "floor"
material = "steel"
rigid = true
box = {{ min = {3}, max = {4} }}
[[body]]
name = "left"
material = "steel"
rigid = true
box = {{ min = {5}, max = {6} }}
[[body]]
name = "right"
material = "steel"
rigid = true
box = {{ min = {7}, max = {8} }}
)",
                     point(1.4, 0.8, depth), h,
                     three ? "[grid.boundary]\ny_min = \"slip\"\ny_max = \"slip\"" : "",
                     point(0.0, 0.0, 0.0), point(1.4, 0.1, depth), point(0.1, 0.1, 0.0),
                     point(0.2, 0.6, depth), point(1.2, 0.1, 0.0), point(1.3, 0.6, depth));
}

std::string simulation(int dim, double theta_deg, double flip) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  const std::string gravity =
      dim == 3 ? fmt::format("[{:.17g}, 0.0, {:.17g}]", g * std::sin(t), -g * std::cos(t))
               : fmt::format("[{:.17g}, {:.17g}]", g * std::sin(t), -g * std::cos(t));
  return fmt::format("[simulation]\ndimension = {}\nend_time = 1.0\ncfl = 0.4\ngravity = {}\n"
                     "scheme = \"musl\"\nflip = {}\n",
                     dim, gravity, flip);
}

// Water H deep between the walls, started hydrostatic, 1 s under PIC (under FLIP 0.99 water on a
// rigid body creeps, a known limit, docs/formulation.md; in this tank, as on a rigid floor alone
// between slip faces, the 0.35 m water's mean speed grows from 3e-4 m/s at 0.6 s to 1.5e-3 m/s
// at 1 s and 5.4e-3 m/s at 1.5 s): the forces' means over the last
// half second against rho g H^2 / 2 per unit width on each wall and rho g H W on the floor
// (within 1 %), every water particle between the walls' faces and above the floor, no nearer
// a face than an eighth of a cell (a particle's centre starts a quarter cell off it), and the
// water at rest (mass-weighted RMS speed under 1e-3 sqrt(g H)).
template <int D>
void tank_of_rigid_bodies(double H, double h) {
  const double depth = D == 3 ? 0.2 : 1.0; // per unit width in 2D
  const std::string water = fmt::format(
      R"(
[initial_state]
method = "k0"
[[material]]
name = "water"
model = "fluid"
density = 1000.0
sound_speed = 20.0
viscosity = 1.0e-3
[[body]]
name = "water"
material = "water"
box = {{ min = {}, max = {} }}
[[contact]]
friction = 0.0
)",
      D == 3 ? "[0.2, 0.0, 0.1]" : "[0.2, 0.1]",
      D == 3 ? fmt::format("[1.2, {}, {}]", depth, 0.1 + H) : fmt::format("[1.2, {}]", 0.1 + H));
  Simulation<D> sim(test::case_from(simulation(D, 0.0, 0.0) + tank_walls(D, h, depth) + water));
  test::run_to(sim, 0.5);
  sim.reset_force_means();
  test::run_to(sim, 1.0);
  const auto& rec = sim.contact_record();
  const double wall = 0.5 * rho_w * g * H * H * depth, floor = rho_w * g * H * 1.0 * depth;
  const double left = rec.mean_force(3, 1)[0], right = -rec.mean_force(3, 2)[0];
  const double bottom = rec.mean_force(3, 0)[D - 1];
  const auto& P = sim.particles();
  double x_lo = 1e9, x_hi = -1e9, z_lo = 1e9, m = 0.0, mv2 = 0.0;
  for (std::size_t p = P.body_begin[3]; p < P.body_begin[4]; ++p) {
    x_lo = std::min(x_lo, P.x[p][0]), x_hi = std::max(x_hi, P.x[p][0]);
    z_lo = std::min(z_lo, P.x[p][D - 1]);
    m += P.m[p], mv2 += P.m[p] * P.v[p].squaredNorm();
  }
  const double rms = std::sqrt(mv2 / m);
  const std::string figures = fmt::format(
      "{}D, H {} m, h {} m: walls {:.2f} / {:.2f} N against {:.2f} ({:+.2f} / {:+.2f} %), floor "
      "{:.1f} against {:.1f} ({:+.2f} %); water in x [{:.4f}, {:.4f}], z >= {:.4f}; RMS speed "
      "{:.2e} m/s",
      D, H, h, left, right, wall, 100 * (left / wall - 1), 100 * (right / wall - 1), bottom, floor,
      100 * (bottom / floor - 1), x_lo, x_hi, z_lo, rms);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  EXPECT_NEAR(left, wall, 0.01 * wall);
  EXPECT_NEAR(right, wall, 0.01 * wall);
  EXPECT_NEAR(bottom, floor, 0.01 * floor);
  EXPECT_GT(x_lo, 0.2 + 0.25 * h / 2 - 1e-9);
  EXPECT_LT(x_hi, 1.2 - 0.25 * h / 2 + 1e-9);
  EXPECT_GT(z_lo, 0.1 + 0.25 * h / 2 - 1e-9);
  EXPECT_LT(rms, 1e-3 * std::sqrt(g * H));
}

TEST(RigidCorner, ATankOfThreeRigidBodiesHoldsItsWater) {
  for (const double H : {0.2, 0.35})
    tank_of_rigid_bodies<2>(H, 0.025);
  tank_of_rigid_bodies<3>(0.3, 0.05);
}

// An elastic block 0.4 x 0.025 m (2000 kg/m^3, 5 MPa; two particles tall, so that every node
// row it reaches is a corner row) on the floor against the right wall, every contact
// frictionless, gravity tilted towards the wall by theta, 1 s under PIC (under FLIP 0.99 the thin
// block rattles against the wall and the half-second means are 1.3 % high): the means over the
// last half second carry m g sin(theta) on the wall and m g cos(theta) on the floor within 1 %,
// each face's force along its normal alone (under 1e-3 m g along it: with the wall's normal at
// its foot taken from its base, the wall pushed the block down by 4e-3 m g at 60 deg), and the
// block stays out of the wall (no particle nearer its face than an eighth of a cell).
TEST(RigidCorner, ABlockPressedIntoTheCornerCarriesItsWeightOnBothFaces) {
  constexpr double h = 0.025, rho_s = 2000.0;
  for (const double theta : {10.0, 30.0, 60.0}) {
    const std::string block = R"(
[[material]]
name = "rock"
density = 2000.0
youngs_modulus = 5.0e6
poisson_ratio = 0.3
[[body]]
name = "block"
material = "rock"
box = { min = [0.8, 0.1], max = [1.2, 0.125] }
[[contact]]
friction = 0.0
)";
    Simulation<2> sim(test::case_from(simulation(2, theta, 0.0) + tank_walls(2, h, 1.0) + block));
    test::run_to(sim, 0.5);
    sim.reset_force_means();
    test::run_to(sim, 1.0);
    const double t = theta * std::numbers::pi / 180.0;
    const double mg = rho_s * 0.4 * 0.025 * g;
    const auto& rec = sim.contact_record();
    const double wall = rec.mean_force(3, 2)[0], floor = rec.mean_force(3, 0)[1];
    const double along_wall = rec.mean_force(3, 2)[1], along_floor = rec.mean_force(3, 0)[0];
    const auto& P = sim.particles();
    double x_hi = -1e9;
    for (std::size_t p = P.body_begin[3]; p < P.body_begin[4]; ++p)
      x_hi = std::max(x_hi, P.x[p][0]);
    const std::string figures = fmt::format(
        "theta {}: wall {:.2f} N against m g sin = {:.2f} ({:+.2f} %), floor {:.2f} against m g "
        "cos = {:.2f} ({:+.2f} %); along the faces: wall {:.3f} N, floor {:.3f} N; the block's "
        "last particle at x = {:.5f} (face 1.2)",
        theta, -wall, mg * std::sin(t), 100 * (-wall / (mg * std::sin(t)) - 1), floor,
        mg * std::cos(t), 100 * (floor / (mg * std::cos(t)) - 1), along_wall, along_floor, x_hi);
    std::printf("%s\n", figures.c_str());
    SCOPED_TRACE(figures);
    EXPECT_NEAR(-wall, mg * std::sin(t), 0.01 * mg * std::sin(t));
    EXPECT_NEAR(floor, mg * std::cos(t), 0.01 * mg * std::cos(t));
    EXPECT_LT(std::abs(along_wall), 1e-3 * mg);
    EXPECT_LT(std::abs(along_floor), 1e-3 * mg);
    EXPECT_LT(x_hi, 1.2 - 0.25 * h / 2 + 1e-9);
  }
}

} // namespace
} // namespace talus
