// The fluid material (model = "fluid", physics/materials/fluid.hpp) against closed forms: a tank
// started hydrostatic keeps its pressure p = rho g (H - y) and stays still for 10 s, at two
// depths and sound speeds, in 2D and 3D; a column released without stress settles to the
// shortening its equation of state gives, at two bulk moduli; a tank sloshes at the period of
// linear wave theory, at two depths; a column collapses along a floor (the dam break) as Martin &
// Moyce measured, at two resolutions.
#include "talus/output/frame_totals.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>
#include <string>
#include <vector>

namespace talus {
namespace {

constexpr double g = 9.81, rho = 1000.0;

// Water of depth H in a tank W wide (and deep in 3D) with slip walls, sound speed c, on cells h.
std::string tank(int dim, double W, double H, double c, double h, bool hydrostatic,
                 double damping = 0.0) {
  const bool three = dim == 3;
  return fmt::format(R"(
[simulation]
dimension = {0}
end_time = 10.0
cfl = 0.4
gravity = {1}
scheme = "musl"
flip = 0.99
damping = {7}
[grid]
extent = {2}
cell_size = {3}
shape_function = "gimp"
[grid.boundary]
x_min = "slip"
x_max = "slip"
y_min = "slip"
{9}
[[material]]
name = "water"
model = "fluid"
density = 1000.0
sound_speed = {4}
viscosity = 1.0e-3
[[body]]
name = "water"
material = "water"
box = {{ min = {5}, max = {6} }}
{8}
)",
                     dim, three ? "[0.0, 0.0, -9.81]" : "[0.0, -9.81]",
                     three ? fmt::format("[{0}, {0}, {1}]", W, 1.5 * H)
                           : fmt::format("[{}, {}]", W, 1.5 * H),
                     h, c, three ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]",
                     three ? fmt::format("[{0}, {0}, {1}]", W, H) : fmt::format("[{}, {}]", W, H),
                     damping, hydrostatic ? "[initial_state]\nmethod = \"k0\"" : "",
                     three ? "y_max = \"slip\"\nz_min = \"slip\"" : "");
}

// The least-squares line p = a + b z through the particles' pressures (z: up) and the RMS of
// the particles' pressures about it; the largest particle speed.
struct PressureFit {
  double a = 0.0, b = 0.0, rms = 0.0, max_speed = 0.0, rms_speed = 0.0;
};

template <int D>
PressureFit fit(const Simulation<D>& sim) {
  const auto& P = sim.particles();
  double n = 0, sz = 0, sp = 0, szz = 0, szp = 0, m = 0, mv2 = 0;
  PressureFit f;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double z = P.x[p][D - 1], pr = -mean_stress(P.stress[p]);
    n += 1, sz += z, sp += pr, szz += z * z, szp += z * pr;
    f.max_speed = std::max(f.max_speed, P.v[p].norm());
    m += P.m[p], mv2 += P.m[p] * P.v[p].squaredNorm();
  }
  f.rms_speed = std::sqrt(mv2 / m);
  f.b = (n * szp - sz * sp) / (n * szz - sz * sz);
  f.a = (sp - f.b * sz) / n;
  double r2 = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double r = -mean_stress(P.stress[p]) - (f.a + f.b * P.x[p][D - 1]);
    r2 += r * r;
  }
  f.rms = std::sqrt(r2 / n);
  return f;
}

// Started hydrostatic: the bottom pressure rho g H within 1 % (the line's value at z = 0), its
// gradient -rho g within 1 %, the particles' scatter about the line under 2 % of rho g H, at
// release and after `end` seconds (no drift), and the water still (its mass-weighted RMS speed
// below 1e-3 sqrt(g H); single particles jitter at a few times that).
template <int D>
void hydrostatic_tank(double W, double H, double c, double h, double end) {
  const Case cs = test::case_from(tank(D, W, H, c, h, true));
  Simulation<D> sim(cs);
  const double pb = rho * g * H;
  auto check = [&](const char* when) {
    const PressureFit f = fit(sim);
    const std::string figures =
        fmt::format("{}D, H {} m, c {} m/s, h {} m, {}: p(0) {:.1f} Pa against {:.1f}, dp/dz "
                    "{:.1f} against {:.1f}, scatter {:.1f} Pa, speed rms {:.2e}, max {:.2e} m/s",
                    D, H, c, h, when, f.a, pb, f.b, -rho * g, f.rms, f.rms_speed, f.max_speed);
    std::printf("%s\n", figures.c_str());
    SCOPED_TRACE(figures);
    EXPECT_NEAR(f.a, pb, 0.01 * pb);
    EXPECT_NEAR(f.b, -rho * g, 0.01 * rho * g);
    EXPECT_LT(f.rms, 0.02 * pb);
    EXPECT_LT(f.rms_speed, 1e-3 * std::sqrt(g * H));
  };
  check("at release");
  while (sim.time() < end - 1e-12)
    sim.step(end - sim.time());
  check("at the end");
}

TEST(Fluid, HydrostaticTankKeepsItsPressureAndStaysStill) {
  hydrostatic_tank<2>(1.0, 1.0, 30.0, 0.05, 10.0);
  hydrostatic_tank<2>(2.0, 2.0, 20.0, 0.1, 10.0);
  hydrostatic_tank<3>(0.5, 0.5, 20.0, 0.05, 4.0);
}

// Released without stress and damped to rest, a column shortens by what its equation of state
// gives, p = K (1 / J - 1) with p = rho g (H - Z) at reference height Z: the top particle (at
// Z = H - h / 4) sinks by d = int_0^Z p / (K + p) dZ', within 1 %, for two bulk moduli.
TEST(Fluid, ColumnShortensAsItsEquationOfStateGives) {
  const double H = 1.0, h = 0.05;
  for (const double c : {20.0, 40.0}) {
    Case cs = test::case_from(tank(2, 1.0, H, c, h, false, 0.2));
    Simulation<2> sim(cs);
    const double K = rho * c * c, Z = H - h / 4;
    double d = 0.0;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
      const double p = rho * g * (H - (i + 0.5) * Z / n);
      d += p / (K + p) * Z / n;
    }
    while (sim.time() < 4.0 - 1e-12)
      sim.step(4.0 - sim.time());
    const auto& P = sim.particles();
    double top = 0.0, top0 = 0.0;
    int count = 0;
    for (std::size_t p = 0; p < P.size(); ++p)
      if (P.x0[p][1] > H - h / 2) top += P.x[p][1], top0 += P.x0[p][1], ++count;
    const double sink = (top0 - top) / count;
    std::printf("column, c %g m/s: the top sinks %.6g m against %.6g (%+.3f %%)\n", c, sink, d,
                100.0 * (sink / d - 1.0));
    EXPECT_NEAR(sink, d, 0.01 * d)
        << "c " << c << " m/s: the top sinks " << sink << " m against " << d
        << " (rho g H^2 / 2K = " << rho * g * H * H / (2 * K) << ")";
  }
}

// The first sloshing mode of a tank L long with water h deep, released from the surface
// h + a cos(pi x / L) with its hydrostatic pressure: its period within 2 % of linear wave
// theory's, omega^2 = g k tanh(k h) with k = pi / L, at two depths. The period is twice the
// mean time between the zero crossings of the surface at the left wall (a [[gauge]] there, less
// its mean).
TEST(Fluid, SloshingPeriodIsLinearWaveTheorys) {
  const double L = 1.0, a = 0.01, cell = 0.025, k = std::numbers::pi / L;
  for (const double depth : {0.5, 0.25}) {
    std::string surface;
    for (int i = 40; i >= 0; --i) {
      const double x = L * i / 40.0;
      surface += fmt::format(", [{:.17g}, {:.17g}]", x, depth + a * std::cos(k * x));
    }
    std::string text = tank(2, L, depth, 20.0, cell, true);
    const std::size_t box = text.find("box = ");
    text.replace(box, text.find('\n', box) - box,
                 fmt::format("polygon = [[0.0, 0.0], [{}, 0.0]{}]", L, surface));
    text += "[[gauge]]\nname = \"wall\"\nbody = \"water\"\nat = 0.0\n";
    const Case cs = test::case_from(text);
    Simulation<2> sim(cs);
    // The surface at the left wall: a [[gauge]] there (waves.csv's elevation).
    auto surface_at_wall = [&] { return frame_totals(sim, {}).gauges[0]; };
    const double T = 2.0 * std::numbers::pi / std::sqrt(g * k * std::tanh(k * depth));
    std::vector<double> t, y;
    while (sim.time() < 3.5 * T) {
      sim.step(3.5 * T - sim.time());
      t.push_back(sim.time()), y.push_back(surface_at_wall());
    }
    double mean = 0.0;
    for (const double v : y)
      mean += v / y.size();
    std::vector<double> crossings;
    for (std::size_t i = 1; i < y.size(); ++i)
      if ((y[i - 1] - mean) * (y[i] - mean) < 0.0)
        crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * (mean - y[i - 1]) / (y[i] - y[i - 1]));
    ASSERT_GE(crossings.size(), 5u) << "depth " << depth;
    const double measured = 2.0 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
    std::printf("sloshing, depth %g m: period %.4f s against %.4f (%+.2f %%), %zu crossings\n",
                depth, measured, T, 100.0 * (measured / T - 1.0), crossings.size());
    EXPECT_NEAR(measured, T, 0.02 * T) << "depth " << depth;
  }
}

// The dam break: a column a wide and 2a high (Martin & Moyce 1952, Phil. Trans. R. Soc. A 244,
// 312-324, their 2D column with n^2 = 2 and a = 2.25 in) released on a frictionless floor. Its
// front Z = x / a against T = t sqrt(2 g / a), at a / 20 and a / 40 with c = 25 m/s (Mach < 0.1):
// - never faster than Ritter's front of an ideal dam break, dx/dt = 2 sqrt(g H0), dZ/dT = 2;
// - converged: the two resolutions within 3 % of each other;
// - against the experiment (their tabulated front): measured, not tuned. The model leads it, by
//   7-18 % (docs/verification.md, "Dam break"): the experiment's floor and its gate's removal
//   slow its front, and FLIP's dissipation alone moves ours by several per cent (FLIP 0.9 lands
//   within 7 %). The bounds below hold the known miss (ahead by no more than 20 %, behind by no
//   more than 5 %) so that a change for the worse fails; the issue's 5 % is not met.
TEST(Fluid, DamBreakFrontAgainstMartinAndMoyce) {
  const double a = 0.05715, s = std::sqrt(2.0 * g / a);
  const std::vector<double> T = {0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20,
                                 2.32, 2.51, 2.65, 2.83, 2.98, 3.11, 3.33};
  const std::vector<double> Z = {1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56,
                                 2.78, 3.00, 3.22, 3.44, 3.67, 3.89, 4.11};
  std::vector<std::vector<double>> fronts;
  for (const int cells : {20, 40}) {
    const double h = a / cells;
    const Case cs = test::case_from(fmt::format(R"(
[simulation]
dimension = 2
end_time = 0.2
cfl = 0.4
gravity = [0.0, -9.81]
scheme = "musl"
flip = 0.99
[grid]
extent = [{0}, {1}]
cell_size = {2}
shape_function = "gimp"
[grid.boundary]
x_min = "slip"
x_max = "slip"
y_min = "slip"
[initial_state]
method = "k0"
[[material]]
name = "water"
model = "fluid"
density = 1000.0
sound_speed = 25.0
viscosity = 1.0e-3
[[body]]
name = "water"
material = "water"
box = {{ min = [0.0, 0.0], max = [{3}, {4}] }}
)",
                                                6 * a, 2.5 * a, h, a, 2 * a));
    Simulation<2> sim(cs);
    // The front: the leading particle's far edge (2 particles a cell: h / 4 beyond its centre).
    auto front = [&] {
      double x = 0.0;
      for (const auto& xp : sim.particles().x)
        x = std::max(x, xp[0]);
      return (x + h / 4) / a;
    };
    std::vector<double> at;
    double fastest = 0.0, last_t = 0.0, last_z = front();
    for (const double Ti : T) {
      const double t = Ti / s;
      while (sim.time() < t - 1e-12) {
        sim.step(std::min(t, last_t + 0.002) - sim.time());
        if (sim.time() >= last_t + 0.002 - 1e-12 || sim.time() >= t - 1e-12) {
          const double z = front();
          fastest = std::max(fastest, (z - last_z) / ((sim.time() - last_t) * s));
          last_t = sim.time(), last_z = z;
        }
      }
      at.push_back(front());
    }
    std::printf("dam break, a / %d: fastest front dZ/dT %.3f (Ritter's 2)\n", cells, fastest);
    EXPECT_LT(fastest, 2.0) << "a / " << cells;
    fronts.push_back(at);
  }
  for (std::size_t i = 0; i < T.size(); ++i) {
    const double z20 = fronts[0][i], z40 = fronts[1][i];
    std::printf("T %.2f: Z %.3f (a/20), %.3f (a/40) against %.2f measured (%+.1f %%)\n", T[i], z20,
                z40, Z[i], 100.0 * (z40 / Z[i] - 1.0));
    EXPECT_NEAR(z20, z40, 0.03 * z40) << "T " << T[i];
    EXPECT_LT(z40, 1.20 * Z[i]) << "T " << T[i];
    EXPECT_GT(z40, 0.95 * Z[i]) << "T " << T[i];
  }
}

// A water body below a [water] level with a saturated block resting on the tank's floor (a
// rigid body): the block's weight is buoyant below the level and its stress effective, and the
// water's hydrostatic load on it is held where they meet (Simulation::hold_hydrostatic_load), so
// the floor carries (rho_s - rho_w) g V, Archimedes, within 1 %, for densities 1500 to 2600 and
// a block at two depths (measured: +0.03 to +0.10 %). Without the hold the water's pressure on the
// block's top would press it down by rho_w g d A more (1 to 6 times the buoyant weight here).
// Under PIC, and under FLIP with XPIC(2): under FLIP 0.99 alone the water's particles creep into
// the block's (docs/formulation.md, the floating body) and the load grows, +1.3 % after 1 s and
// +4 % after 2 s at 0.3 m, 1500; XPIC(2) holds it within 0.1 % to 2 s.
// A 2D case's [simulation] table: 2 s under MUSL with the given FLIP share and XPIC order.
std::string simulation_2d(double flip, int xpic = 0) {
  return fmt::format("[simulation]\ndimension = 2\nend_time = 2.0\ncfl = 0.4\n"
                     "gravity = [0.0, -9.81]\nscheme = \"musl\"\nflip = {}\nxpic = {}\n",
                     flip, xpic);
}

// A tank 1 m long and `height` high on 2.5 cm cells, slip walls and floor, and the water
// material (c = 20 m/s) as the case's first.
std::string tank_and_water(double height) {
  return fmt::format(R"(
[grid]
extent = [1.0, {}]
cell_size = 0.025
shape_function = "gimp"
[grid.boundary]
x_min = "slip"
x_max = "slip"
y_min = "slip"
[[material]]
name = "water"
model = "fluid"
density = 1000.0
sound_speed = 20.0
viscosity = 1.0e-3
)",
                     height);
}

std::string block_in_tank(double rho_s, double depth, int xpic = 0) {
  return simulation_2d(xpic > 0 ? 1.0 : 0.0, xpic) + tank_and_water(0.2 + depth + 0.2) +
         fmt::format(R"(
[initial_state]
method = "k0"
[water]
level = {1}
[[material]]
name = "rock"
density = {0}
youngs_modulus = 5.0e6
poisson_ratio = 0.3
[[body]]
name = "floor"
material = "rock"
rigid = true
box = {{ min = [0.0, 0.0], max = [1.0, 0.1] }}
[[body]]
name = "block"
material = "rock"
box = {{ min = [0.4, 0.1], max = [0.6, 0.2] }}
[[body]]
name = "water"
material = "water"
box = {{ min = [0.0, 0.1], max = [1.0, {1}] }}
fill_around = true
[[contact]]
bodies = ["block", "floor"]
friction = 0.5
[[contact]]
friction = 0.0
)",
                     rho_s, 0.2 + depth);
}

// The floor's mean load from 0.5 s (the start's transient left out) to `end` s.
double floor_load(double rho_s, double depth, int xpic, double end) {
  Simulation<2> sim(test::case_from(block_in_tank(rho_s, depth, xpic)));
  while (sim.time() < 0.5 - 1e-12)
    sim.step(0.5 - sim.time());
  sim.reset_force_means();
  while (sim.time() < end - 1e-12)
    sim.step(end - sim.time());
  return sim.contact_record().mean_force(1, 0)[1];
}

TEST(Fluid, ASubmergedBlockOnTheFloorCarriesItsBuoyantWeight) {
  // PIC to 1 s at 3 densities x 2 depths; FLIP with XPIC(2) to 2 s at the two extremes.
  struct Run {
    double rho_s, depth;
    int xpic;
    double end;
  };
  std::vector<Run> runs;
  for (const double depth : {0.1, 0.3})
    for (const double rho_s : {1500.0, 2000.0, 2600.0})
      runs.push_back({rho_s, depth, 0, 1.0});
  runs.push_back({1500.0, 0.3, 2, 2.0});
  runs.push_back({2600.0, 0.1, 2, 2.0});
  for (const auto& [rho_s, depth, xpic, end] : runs) {
    const double carried = floor_load(rho_s, depth, xpic, end);
    const double expected = (rho_s - rho) * g * 0.2 * 0.1;
    const std::string figures = fmt::format(
        "{} to {} s, rho_s {}, {} m under water: the floor carries {:.3f} N/m, (rho_s - rho_w) "
        "g V = {:.3f} ({:+.2f} %), the water's load on its top rho_w g d A = {:.3f}",
        xpic > 0 ? "FLIP, XPIC(2)" : "PIC", end, rho_s, depth, carried, expected,
        100.0 * (carried / expected - 1.0), rho * g * depth * 0.2);
    std::printf("%s\n", figures.c_str());
    SCOPED_TRACE(figures);
    EXPECT_NEAR(carried, expected, 0.01 * expected);
  }
}

// An outflow face lets a fluid body's particles out of the run: a column collapsing toward it
// (x_max = "outflow") pours out and the run goes on, the particles that crossed keep no mass,
// speed or stress and stay on the face, and until the front arrives the run is bitwise the one
// with a free face; through a free face the first particle stops the run, and a solid body
// through an outflow face has left the grid.
std::string column_to_the_edge(const char* face, const char* model, double x0 = 0.0) {
  return simulation_2d(0.99) + fmt::format(R"(
[grid]
extent = [0.6, 0.5]
cell_size = 0.025
shape_function = "gimp"
[grid.boundary]
x_min = "slip"
y_min = "slip"
x_max = {0}
[[material]]
name = "water"
{1}
density = 1000.0
[[body]]
name = "water"
material = "water"
box = {{ min = [{2}, 0.0], max = [{3}, 0.4] }}
)",
                                           face, model, x0, x0 + 0.2);
}

TEST(Fluid, WaterLeavesThroughAnOutflowFace) {
  const char* water = "model = \"fluid\"\nsound_speed = 20.0\nviscosity = 1.0e-3";
  Simulation<2> out(test::case_from(column_to_the_edge("\"outflow\"", water)));
  Simulation<2> free(test::case_from(column_to_the_edge("\"free\"", water)));
  const auto& P = out.particles();
  double m0 = 0.0;
  for (const double m : P.m)
    m0 += m;
  // Until the front reaches the face the two runs are the same bits.
  while (out.time() < 0.15 - 1e-12)
    out.step(0.15 - out.time()), free.step(0.15 - free.time());
  ASSERT_EQ(P.x, free.particles().x);
  EXPECT_THROW(
      {
        while (free.time() < 1.0 - 1e-12)
          free.step(1.0 - free.time());
      },
      SimulationError);
  ASSERT_NO_THROW({
    while (out.time() < 1.0 - 1e-12)
      out.step(1.0 - out.time());
  });
  double m = 0.0;
  std::size_t gone = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    m += P.m[p];
    if (P.m[p] == 0.0) {
      ++gone;
      EXPECT_DOUBLE_EQ(P.x[p][0], 0.6); // on the face
      EXPECT_EQ(P.v[p].norm(), 0.0);
      EXPECT_EQ(P.stress[p].norm(), 0.0);
    }
  }
  std::printf("outflow: %zu of %zu particles, %.1f %% of the water, left in 1 s\n", gone, P.size(),
              100.0 * (1.0 - m / m0));
  EXPECT_GT(gone, P.size() / 10); // the column pours out over the edge
  EXPECT_NEAR(m0 - m, static_cast<double>(gone) * m0 / static_cast<double>(P.size()), 1e-9 * m0);
  // A solid through an outflow face has left the grid.
  Simulation<2> solid(test::case_from(
      column_to_the_edge("\"outflow\"", "youngs_modulus = 1.0e6\npoisson_ratio = 0.3", 0.3),
      {"simulation.gravity=[20.0, -9.81]"}));
  EXPECT_THROW(
      {
        while (solid.time() < 1.0 - 1e-12)
          solid.step(1.0 - solid.time());
      },
      SimulationError);
}

// A barge 0.4 x 0.1 m of density rho_s on water 0.3 m deep in a tank 1 m long (2.5 cm cells),
// its bottom at `bottom`: an impermeable body, buoyed by the water's pressure through contact.
std::string barge(double rho_s, double bottom) {
  return simulation_2d(0.0) + tank_and_water(0.6) +
         fmt::format(R"(
[[material]]
name = "wood"
density = {0}
youngs_modulus = 1.0e6
poisson_ratio = 0.3
[[body]]
name = "barge"
material = "wood"
box = {{ min = [0.3, {1}], max = [0.7, {2}] }}
[[body]]
name = "water"
material = "water"
box = {{ min = [0.0, 0.0], max = [1.0, 0.3] }}
fill_around = true
[[contact]]
friction = 0.0
)",
                     rho_s, bottom, bottom + 0.1);
}

// Archimedes through contact for a body lighter than water: a barge started at the draft its
// density gives, d = (rho_s / rho_w) H_b, stays there within 1 % for 3 s, at densities 250, 500
// and 750 (1, 2 and 3 cells of draft: particles are seeded on the lattice of half cells, so a
// bottom between its rows would start the barge off its draft), under PIC. The draft is read as the
// water's level less the barge's bottom: the bottom from its centroid (it shortens by 0.05 % of the
// draft under its own weight), the level from the water's particle volumes, L = (A_w - W_b bottom)
// / (W - W_b), so that the water's compression (0.4 % at the floor) is not read as the barge
// sinking. A barge whose weight the water carried wrongly by 1 % would settle 1 % off within the
// first second (PIC brings one released 31 mm high from -62 % to -19 % of its draft in 1 s).
// Measured: within 0.4 %. Known limits (docs/formulation.md, the floating body): released off its
// draft it creeps toward it under PIC (-5.6 % at 6 s from a release 31 mm high, density 500),
// heaves and sinks under FLIP 0.99, and rises under XPIC(2).
TEST(Fluid, ABargeFloatsAtTheDraftItsDensityGives) {
  for (const double rho_s : {250.0, 500.0, 750.0}) {
    const double H = 0.1, W = 1.0, Wb = 0.4, d0 = rho_s / rho * H;
    Simulation<2> sim(test::case_from(barge(rho_s, 0.3 - d0)));
    const auto& P = sim.particles();
    for (const double t : {1.0, 2.0, 3.0}) {
      while (sim.time() < t - 1e-12)
        sim.step(t - sim.time());
      double m = 0.0, my = 0.0, water = 0.0;
      for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
        m += P.m[p], my += P.m[p] * P.x[p][1];
      for (std::size_t p = P.body_begin[1]; p < P.body_begin[2]; ++p)
        water += P.vol[p];
      const double bottom = my / m - 0.5 * H, level = (water - Wb * bottom) / (W - Wb);
      const double draft = level - bottom;
      std::printf("rho_s %.0f at %.0f s: draft %.2f mm against %.2f (%+.2f %%)\n", rho_s, t,
                  1e3 * draft, 1e3 * d0, 100.0 * (draft / d0 - 1.0));
      EXPECT_NEAR(draft, d0, 0.01 * d0) << "rho_s " << rho_s << " at " << t << " s";
    }
  }
}

} // namespace
} // namespace talus
