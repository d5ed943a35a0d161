// The interface laws at parameters spread over their range, not at one point (docs/verification.md,
// "General parameters"): a block on a plane with an excess pore pressure p on its interface, over
// angles x frictions x pressure ratios, in 2D and 3D, driven by gravity down the plane and
// launched along a level one. Friction acts on the effective normal force, mu (N - p A): the wet
// block moves as the dry block at the friction mu (1 - p / sigma_n), and both are compared with
// the rigid block's a = g (sin - mu (1 - p / sigma_n) cos).
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>
#include <string>
#include <vector>

namespace talus {
namespace {

constexpr double g = 9.81;
constexpr double density = 2000.0, height = 0.5; // the block's; its base is 1 m (x 1 m in 3D)

// A block 1 m long and 0.5 m high (1 m wide in 3D; 2000 kg/m^3, 100 MPa) on a rigid plane, the
// two lattice-aligned and level; gravity tilted by theta, so "down the plane" is +x. The
// interface has constant friction mu, cohesion c and pore pressure p. The block first settles
// under its weight with the interface held (0.2 s), so that the run starts from the equilibrium
// stress the closed form assumes; the clock starts at release.
template <int D>
std::string block_on_plane(double theta_deg, double mu, double p, double c = 0.0, double flip = 1.0,
                           int xpic = 0) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  const bool three = D == 3;
  const std::string gravity =
      three ? fmt::format("[{:.17g}, 0.0, {:.17g}]", g * std::sin(t), -g * std::cos(t))
            : fmt::format("[{:.17g}, {:.17g}]", g * std::sin(t), -g * std::cos(t));
  return fmt::format(R"(
[simulation]
dimension = {0}
end_time = 1.0
cfl = 0.4
gravity = {1}
scheme = "musl"
flip = {11:.3f}
xpic = {12}
[grid]
extent = {2}
cell_size = 0.1
shape_function = "gimp"
[[material]]
name = "rock"
density = {6:.17g}
youngs_modulus = 1.0e8
poisson_ratio = 0.3
[[body]]
name = "block"
material = "rock"
box = {{ min = {3}, max = {4} }}
[[body]]
name = "plane"
material = "rock"
rigid = true
box = {{ min = {5}, max = {7} }}
[[interface]]
bodies = ["block", "plane"]
friction = {{ initial = {8}, residual = {8}, slip = 1.0 }}
cohesion = {{ initial = {10:.17g}, residual = {10:.17g}, slip = 1.0 }}
pore_pressure = {9:.17g}
[initial_state]
settle_time = 0.2
)",
                     D, gravity, three ? "[6.0, 1.6, 1.2]" : "[6.0, 1.2]",
                     three ? "[0.5, 0.3, 0.4]" : "[0.5, 0.4]",
                     three ? "[1.5, 1.3, 0.9]" : "[1.5, 0.9]",
                     three ? "[0.1, 0.1, 0.2]" : "[0.1, 0.2]", density,
                     three ? "[5.9, 1.5, 0.4]" : "[5.9, 0.4]", mu, p, c, flip, xpic);
}

// The block's mass-weighted velocity along x.
template <int D>
double velocity(const Simulation<D>& sim) {
  const auto& P = sim.particles();
  double m = 0.0, mv = 0.0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    m += P.m[p], mv += P.m[p] * P.v[p][0];
  return mv / m;
}

// The block's motion after release: its acceleration down the plane, the slope of a
// least-squares line through its mean velocity every 0.01 s from 0.2 to 0.8 s (the elastic
// block's start-up, its first waves and its seating on the plane, left out), and its speed at
// 0.8 s.
struct Motion {
  double a = 0.0, v_end = 0.0;
};

// A block settled, released and (v0 > 0) launched along x at v0.
template <int D>
Motion run_block(double theta, double mu, double ratio, double v0, double cohesion = 0.0,
                 double flip = 1.0, int xpic = 0) {
  const double t = theta * std::numbers::pi / 180.0;
  const double sigma_n = density * height * g * std::cos(t);
  const Case c =
      test::case_from(block_on_plane<D>(theta, mu, ratio * sigma_n, cohesion, flip, xpic));
  Simulation<D> sim(c);
  test::settle(sim, c);
  const double t0 = sim.time();
  if (v0 != 0.0) {
    auto& P = sim.particles_mut();
    for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
      P.v[p][0] = v0;
  }
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0, v = 0;
  for (int k = 20; k <= 80; ++k) {
    const double at = 0.01 * k;
    while (sim.time() - t0 < at - 1e-12)
      sim.step(t0 + at - sim.time());
    v = velocity(sim);
    n += 1, st += at, sv += v, stt += at * at, stv += at * v;
  }
  return {(n * stv - st * sv) / (n * stt - st * st), v};
}

struct Sweep {
  int cells = 0, misses = 0, known = 0, skipped = 0;
  double worst = 0.0, worst_closed = 0.0;
};

// Where FLIP's transfer makes the block miss the rigid block's closed form, the wet block is
// reported and not held to 1 % (docs/verification.md, "General parameters"):
// - near the friction limit, mu (1 - ratio) / tan(theta) from 0.75 to 1.25: the elastic block
//   creeps where the rigid one would hold or barely move (dry at 20 deg, mu 0.35: +80 %);
// - mu 0.5 and above with p / sigma_n 0.6 and above, where the contact carries 40 % or less of
//   the normal force: 1-3.7 %.
// Under PIC every one of these cells is within 0.3 % (TheLawIsExactWhereTheTransferAddsNoNoise):
// the particles' FLIP velocities keep the contact layer's noise from step to step, and a node
// that noise brings near rest sticks (or slips backwards, and friction pushes it forward).
bool known_miss(double theta, double mu, double ratio) {
  const double t = theta * std::numbers::pi / 180.0;
  const double limit = theta > 0.0 ? mu * (1.0 - ratio) / std::tan(t) : 0.0;
  return (limit > 0.75 && limit < 1.25) || (mu >= 0.5 && ratio >= 0.6);
}

// One wet cell (friction mu, p = ratio sigma_n) against the dry block at the effective friction
// mu (1 - ratio): the same acceleration within 1 % of the closed form's
// a = g (sin - mu (1 - ratio) cos), or both held (or stopped) within 1 mm/s of rest. A launched
// block starts at v0 = 1.2 s x |a|, so that it decelerates over the whole window.
template <int D>
void wet_against_dry(double theta, double mu, double ratio, Sweep& sweep) {
  // A known cell asserts nothing, so CI does not run it; TALUS_SWEEP_ALL=1 runs the whole table
  // of docs/verification.md (the 2D cells are also checks of `talus verify`, general_blocks).
  if (known_miss(theta, mu, ratio) && !std::getenv("TALUS_SWEEP_ALL")) {
    ++sweep.cells, ++sweep.skipped;
    std::printf(
        "%dD theta %2.0f mu %.1f p/sigma_n %.1f: a known region, not run (TALUS_SWEEP_ALL=1 "
        "runs it)\n",
        D, theta, mu, ratio);
    return;
  }
  const double t = theta * std::numbers::pi / 180.0;
  const double a = g * (std::sin(t) - mu * (1.0 - ratio) * std::cos(t));
  const double v0 = theta == 0.0 ? -1.2 * a : 0.0;
  const Motion wet = run_block<D>(theta, mu, ratio, v0);
  const Motion dry = run_block<D>(theta, mu * (1.0 - ratio), 0.0, v0);
  const bool slides = a > 0.0 || v0 > 0.0;
  const double error = slides ? (wet.a - dry.a) / a : 0.0;
  const bool ok =
      slides ? std::abs(error) < 0.01 : std::abs(wet.v_end) < 1e-3 && std::abs(dry.v_end) < 1e-3;
  std::printf("%dD theta %2.0f mu %.1f p/sigma_n %.1f: a wet %+.4f, dry at mu %.2f %+.4f m/s^2, "
              "closed form %+.4f: wet - dry %s, wet against the closed form %s\n",
              D, theta, mu, ratio, wet.a, mu * (1.0 - ratio), dry.a, a,
              slides ? fmt::format("{:+.2f} %", 100 * error).c_str()
                     : fmt::format("held, v {:.4f} / {:.4f} m/s", wet.v_end, dry.v_end).c_str(),
              slides ? fmt::format("{:+.2f} %", 100 * (wet.a / a - 1.0)).c_str() : "-");
  ++sweep.cells;
  if (known_miss(theta, mu, ratio)) {
    std::printf("  (a known miss of the contact law there: reported, not held to 1 %%)\n");
    sweep.known += !ok;
    return;
  }
  sweep.misses += !ok;
  if (slides) {
    sweep.worst = std::max(sweep.worst, std::abs(error));
    sweep.worst_closed = std::max(sweep.worst_closed, std::abs(wet.a / a - 1.0));
  }
  EXPECT_TRUE(ok) << D << "D theta " << theta << ", mu " << mu << ", ratio " << ratio;
}

void summary(int D, const Sweep& s) {
  std::printf("%dD: %d of %d cells within 1 %% of the dry block at the effective friction, %d "
              "known misses, %d known cells not run (the others: worst %.2f %%, the closed form "
              "within %.2f %%)\n",
              D, s.cells - s.misses - s.known - s.skipped, s.cells, s.known, s.skipped,
              100 * s.worst, 100 * s.worst_closed);
}

// 2D: 3 angles x 3 frictions x p / sigma_n 0.3, 0.6, 0.9 driven down the plane (the blocks that
// hold included), and 3 frictions x 3 ratios launched along a level plane.
TEST(InterfaceLaws, PorePressureIsFrictionOnTheEffectiveNormalForce2D) {
  Sweep sweep;
  for (const double ratio : {0.3, 0.6, 0.9})
    for (const double theta : {0.0, 20.0, 35.0, 50.0})
      for (const double mu : {0.2, 0.5, 0.8})
        wet_against_dry<2>(theta, mu, ratio, sweep);
  summary(2, sweep);
}

// 3D: 3 angles x 3 frictions at p / sigma_n 0.6, and the ratios 0.3 and 0.9 at 35 deg.
TEST(InterfaceLaws, PorePressureIsFrictionOnTheEffectiveNormalForce3D) {
  Sweep sweep;
  for (const double theta : {20.0, 35.0, 50.0})
    for (const double mu : {0.2, 0.5, 0.8})
      wet_against_dry<3>(theta, mu, 0.6, sweep);
  for (const double ratio : {0.3, 0.9})
    wet_against_dry<3>(35.0, 0.5, ratio, sweep);
  summary(3, sweep);
}

// Cohesion on an interface that lies on a grid line: the block's base row of interface particles
// reaches the node row at the plane and the row above it, which the plane does not reach; all of
// c A must act where the two meet, a = g (sin - mu cos) - c A / m within 1 %, or the block held.
// c = 1 kPa (c A / m = 1 m/s^2); 3 angles at mu 0.2 and 0.5, less the two cells whose
// resistance over drive is near 1 (0.85 at 20 deg, mu 0.2; 0.89 at 35 deg, mu 0.5: the elastic
// block's near-limit creep, general_blocks). The held cell (20 deg, mu 0.5) would hold on its
// friction alone.
// With the capacity scattered over every node of the support, a quarter of it was lost: the
// blocks gained 0.25 m/s^2.
TEST(InterfaceLaws, CohesionActsWholeOnAGridAlignedInterface) {
  constexpr double c = 1000.0, per_mass = c / (density * height); // c A / m
  for (const double theta : {20.0, 35.0, 50.0})
    for (const double mu : {0.2, 0.5}) {
      const double t = theta * std::numbers::pi / 180.0;
      const double a = g * (std::sin(t) - mu * std::cos(t)) - per_mass;
      const double resistance = (g * mu * std::cos(t) + per_mass) / (g * std::sin(t));
      if (resistance > 0.75 && resistance < 1.25 && a > 0.0) continue; // near the limit
      const Motion m = run_block<2>(theta, mu, 0.0, 0.0, c);
      std::printf("theta %2.0f mu %.1f c 1 kPa: a %+.4f against %+.4f m/s^2 (%s)\n", theta, mu, m.a,
                  a, a > 0.0 ? fmt::format("{:+.2f} %", 100 * (m.a / a - 1.0)).c_str() : "held");
      if (a > 0.0)
        EXPECT_NEAR(m.a / a, 1.0, 0.01) << "theta " << theta << ", mu " << mu;
      else
        EXPECT_LT(std::abs(m.v_end), 1e-3) << "theta " << theta << ", mu " << mu;
    }
}

// The law where the transfer adds no noise: every cell the FLIP sweeps above leave out as known
// (near the friction limit; mu 0.5 and above with p / sigma_n 0.6 and above), and the dry block
// near its limit, run under PIC (flip 0) against the rigid block's closed form within 1 %, or
// held. Under FLIP these cells miss by 1-150 %: the particles keep the contact layer's velocity
// noise from step to step, and a node whose relative velocity that noise brings near zero sticks
// or pushes forward (docs/verification.md, "General parameters"). Under PIC they are within
// 0.3 % (and general_blocks at flip 0 within 1 %, 41 of its 42 checks within 0.17 %), so the
// misses are the transfer's, not the law's.
// The cells FLIP leaves out as known, and the dry block near its limit, under the transfer
// (flip, xpic), each against the rigid block's closed form: its error, or held.
struct LawCell {
  int dim;
  double theta, mu, ratio;
  double resistance() const { // mu (1 - ratio) cos / sin: 1 at the friction limit
    const double t = theta * std::numbers::pi / 180.0;
    return theta > 0.0 ? mu * (1.0 - ratio) / std::tan(t) : 0.0;
  }
};

std::vector<LawCell> flips_known_cells() {
  std::vector<LawCell> cells = {{2, 20.0, 0.35, 0.0}, {3, 20.0, 0.8, 0.6}};
  for (const double ratio : {0.3, 0.6, 0.9})
    for (const double theta : {0.0, 20.0, 35.0, 50.0})
      for (const double mu : {0.2, 0.5, 0.8})
        if (known_miss(theta, mu, ratio)) cells.push_back({2, theta, mu, ratio});
  return cells;
}

// Runs cell k under (flip, xpic) and returns m.a / a - 1 (0 for a block that holds, checked
// against 1 mm/s of rest).
double law_error(const LawCell& k, double flip, int xpic, const char* label) {
  const double t = k.theta * std::numbers::pi / 180.0;
  const double a = g * (std::sin(t) - k.mu * (1.0 - k.ratio) * std::cos(t));
  const double v0 = k.theta == 0.0 ? -1.2 * a : 0.0;
  const Motion m = k.dim == 2 ? run_block<2>(k.theta, k.mu, k.ratio, v0, 0.0, flip, xpic)
                              : run_block<3>(k.theta, k.mu, k.ratio, v0, 0.0, flip, xpic);
  const bool slides = a > 0.0 || v0 > 0.0;
  std::printf("%s %dD theta %2.0f mu %.2f p/sigma_n %.1f (resistance / drive %.2f): a %+.4f "
              "against %+.4f m/s^2 (%s)\n",
              label, k.dim, k.theta, k.mu, k.ratio, k.resistance(), m.a, a,
              slides ? fmt::format("{:+.2f} %", 100 * (m.a / a - 1.0)).c_str()
                     : fmt::format("held, v {:.4f} m/s", m.v_end).c_str());
  if (!slides) {
    EXPECT_LT(std::abs(m.v_end), 1e-3) << k.dim << "D theta " << k.theta << ", mu " << k.mu;
    return 0.0;
  }
  return m.a / a - 1.0;
}

// The law where the transfer adds no noise: every cell the FLIP sweeps above leave out as known
// (near the friction limit; mu 0.5 and above with p / sigma_n 0.6 and above), and the dry block
// near its limit, run under PIC (flip 0) against the rigid block's closed form within 1 %, or
// held. Under FLIP these cells miss by 1-150 %: the particles keep the contact layer's velocity
// noise from step to step, and a node whose relative velocity that noise brings near zero sticks
// or pushes forward (docs/verification.md, "General parameters"). Under PIC they are within
// 0.3 % (and general_blocks at flip 0 within 1 %, 41 of its 42 checks within 0.17 %), so the
// misses are the transfer's, not the law's.
TEST(InterfaceLaws, TheLawIsExactWhereTheTransferAddsNoNoise) {
  for (const LawCell& k : flips_known_cells())
    EXPECT_NEAR(law_error(k, 0.0, 0, "PIC"), 0.0, 0.01)
        << k.dim << "D theta " << k.theta << ", mu " << k.mu << ", ratio " << k.ratio;
}

// XPIC(2) (Hammerquist & Nairn 2017) on the same cells: the particles carry the part of their
// velocity the grid represents, so the contact layer's noise goes as under PIC while a smooth
// field keeps FLIP's; momentum is kept. Every cell within 1 % of the closed form, the two at
// resistance / drive 0.96 included (measured: within 0.46 %, 18 of the 20 within 0.2 %).
TEST(InterfaceLaws, XpicKeepsTheLawWhereFlipMissesIt) {
  for (const LawCell& k : flips_known_cells())
    EXPECT_NEAR(law_error(k, 1.0, 2, "XPIC(2)"), 0.0, 0.01)
        << k.dim << "D theta " << k.theta << ", mu " << k.mu << ", ratio " << k.ratio;
}

} // namespace
} // namespace talus
