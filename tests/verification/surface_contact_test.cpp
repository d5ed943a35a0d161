// Contact at surface points ([[contact]] law = "surface", docs/formulation.md): a block slides on
// a rigid plane at the Coulomb rate and carries its weight (2D and 3D, over angles and
// frictions); a disk (2D) and a sphere (3D) roll without slip at the rigid body's closed form
// where friction allows, and slip at the Coulomb rate where it does not. The whole rolling sweep
// (angle x friction x resolution) is `talus verify`'s general_rolling.
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>
#include <string>

namespace talus {
namespace {

constexpr double g = 9.81;

std::string tilted(int dim, double theta_deg) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  return dim == 3 ? fmt::format("[{:.17g}, 0.0, {:.17g}]", g * std::sin(t), -g * std::cos(t))
                  : fmt::format("[{:.17g}, {:.17g}]", g * std::sin(t), -g * std::cos(t));
}

// A deformable body ("body": its shape's lines) of 2000 kg/m^3 and 100 MPa on a rigid plane box
// meeting it at surface points, gravity tilted by theta so that "down the plane" is +x.
std::string on_plane(int dim, double theta, double mu, const std::string& extent,
                     const std::string& body, const std::string& plane_min,
                     const std::string& plane_max, const std::string& tail = "") {
  return fmt::format(R"(
[simulation]
dimension = {}
end_time = 1.0
cfl = 0.4
gravity = {}
scheme = "musl"
flip = 1.0
[grid]
extent = {}
cell_size = 0.1
shape_function = "gimp"
[[material]]
name = "rock"
density = 2000
youngs_modulus = 1.0e8
poisson_ratio = 0.3
[[body]]
name = "body"
material = "rock"
{}
[[body]]
name = "plane"
material = "rock"
rigid = true
box = {{ min = {}, max = {} }}
[[contact]]
bodies = ["body", "plane"]
friction = {}
law = "surface"
{})",
                     dim, tilted(dim, theta), extent, body, plane_min, plane_max, mu, tail);
}

// A block 1 m long and 0.5 m high (1 m wide in 3D), settled with its contact sticking, so that
// the run starts from the equilibrium stress the rigid block's closed form assumes.
std::string block_case(int dim, double theta, double mu) {
  const bool three = dim == 3;
  return on_plane(dim, theta, mu, three ? "[6.0, 1.6, 1.2]" : "[6.0, 1.2]",
                  three ? "box = { min = [0.5, 0.3, 0.4], max = [1.5, 1.3, 0.9] }"
                        : "box = { min = [0.5, 0.4], max = [1.5, 0.9] }",
                  three ? "[0.1, 0.1, 0.2]" : "[0.1, 0.2]",
                  three ? "[5.9, 1.5, 0.4]" : "[5.9, 0.4]",
                  "[initial_state]\nsettle_time = 0.2\nhold_contacts = true\n");
}

// A disk (2D) or sphere (3D) of radius 0.5 m at rest and unstressed, 5 cells per radius.
std::string ball_case(int dim, double theta, double mu) {
  const bool three = dim == 3;
  return on_plane(
      dim, theta, mu, three ? "[4.4, 1.6, 1.6]" : "[4.4, 1.6]",
      three ? "sphere = { center = [0.8, 0.8, 0.9], radius = 0.5 }\nparticles_per_cell = 2"
            : "disk = { center = [0.8, 0.9], radius = 0.5 }\nparticles_per_cell = 4",
      three ? "[0.1, 0.1, 0.1]" : "[0.1, 0.1]", three ? "[4.3, 1.5, 0.4]" : "[4.3, 0.4]");
}

// Body 0's mass-weighted mean of f(p).
template <int D, class F>
double mean(const Simulation<D>& sim, F&& f) {
  const auto& P = sim.particles();
  double m = 0.0, s = 0.0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    m += P.m[p], s += P.m[p] * f(p);
  return s / m;
}

// The block after release: its acceleration down the plane (the slope of a least-squares line
// through its mean velocity every 0.01 s from 0.2 to 0.8 s) and the plane's mean normal force on
// it over that window, against the rigid block's a = g (sin - mu cos) and N = m g cos.
template <int D>
void block_slides(double theta, double mu) {
  const Case c = test::case_from(block_case(D, theta, mu));
  Simulation<D> sim(c);
  test::settle(sim, c);
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
  for (int k = 20; k <= 80; ++k) {
    const double at = 0.01 * k;
    test::run_to(sim, at);
    if (k == 20) sim.reset_force_means();
    const double v = mean(sim, [&](std::size_t p) { return sim.particles().v[p][0]; });
    n += 1, st += at, sv += v, stt += at * at, stv += at * v;
  }
  const double a = (n * stv - st * sv) / (n * stt - st * st);
  const double t = theta * std::numbers::pi / 180.0;
  const double closed = g * (std::sin(t) - mu * std::cos(t));
  const double mass = sim.setup().bodies[0].mass;
  const double normal = sim.contact_record().mean_force(0, 1)[D - 1] / (mass * g * std::cos(t));
  std::printf("%dD block, theta %2.0f, mu %.1f: a %.4f against %.4f m/s^2 (%+.3f %%), normal force "
              "/ m g cos %.4f\n",
              D, theta, mu, a, closed, 100 * (a / closed - 1), normal);
  EXPECT_NEAR(a / closed, 1.0, 0.005) << D << "D theta " << theta << " mu " << mu;
  EXPECT_NEAR(normal, 1.0, 0.01) << D << "D theta " << theta << " mu " << mu;
}

TEST(SurfaceContact, ABlockSlidesAtTheCoulombRateAndCarriesItsWeight) {
  // Measured: within 0.17 % (2D) and 0.19 % (3D) of the closed form, the normal force 0.31 %.
  for (const auto& [theta, mu] :
       {std::pair{10.0, 0.1}, {25.0, 0.1}, {25.0, 0.3}, {40.0, 0.1}, {40.0, 0.3}})
    block_slides<2>(theta, mu);
  block_slides<3>(25.0, 0.3);
}

// The ball's displacement down the plane at time T against the rigid body's closed form: rolling
// without slip, x = g t^2 sin / (2 (1 + k)) with k = I / (m R^2) (1/2 a cylinder, 2/5 a sphere),
// where tan(theta) <= (1 + 1/k) mu; otherwise slipping, x = g t^2 (sin - mu cos) / 2.
template <int D>
double ball_error(double theta, double mu, double T) {
  const Case c = test::case_from(ball_case(D, theta, mu));
  Simulation<D> sim(c);
  const double x0 = mean(sim, [&](std::size_t p) { return sim.particles().x[p][0]; });
  test::run_to(sim, T);
  const double x = mean(sim, [&](std::size_t p) { return sim.particles().x[p][0]; }) - x0;
  const double t = theta * std::numbers::pi / 180.0, k = D == 2 ? 0.5 : 0.4;
  const bool rolls = std::tan(t) <= (1.0 + 1.0 / k) * mu;
  const double closed = rolls ? g * T * T * std::sin(t) / (2.0 * (1.0 + k))
                              : 0.5 * g * T * T * (std::sin(t) - mu * std::cos(t));
  std::printf("%dD %s, theta %2.0f, mu %g (%s): x %.4f against %.4f m at %g s (%+.2f %%)\n", D,
              D == 2 ? "disk" : "sphere", theta, mu, rolls ? "rolls" : "slips", x, closed, T,
              100 * (x / closed - 1));
  return x / closed - 1.0;
}

// Node by node these rolling cells miss by -11.9 % (disk, 30 deg, mu 10) and -11.5 % (sphere);
// at surface points -0.3 % and -1.3 % (5 cells per radius: the sphere held to 3 %, not 2 %).
TEST(SurfaceContact, ADiskAndASphereRollOrSlipAsTheRigidBodyDoes) {
  EXPECT_NEAR(ball_error<2>(30.0, 10.0, 1.0), 0.0, 0.02);
  EXPECT_NEAR(ball_error<2>(60.0, 0.2887, 0.8), 0.0, 0.005);
  EXPECT_NEAR(ball_error<3>(30.0, 10.0, 1.0), 0.0, 0.03);
  EXPECT_NEAR(ball_error<3>(30.0, 0.08, 0.8), 0.0, 0.005);
}

} // namespace
} // namespace talus
