// Cohesive-frictional interfaces (paper sections 2.4 and 3.3) against closed forms: the cohesive
// sliding block, a block held by cohesion alone, and a block whose friction and cohesion degrade
// with slip (integrated here through the degradation).
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>
#include <utility>

namespace talus {
namespace {

constexpr double g = 9.81, m = 2000.0, A = 1.0;
const double theta = std::numbers::pi / 6.0;

struct BlockRun {
  std::vector<double> x;     // block centroid displacement along the plane at each time
  double max_interface_slip; // largest displacement of an interface particle along the plane
  // The slip the interface particles recorded (their history variable): mean and largest at
  // each time, and the largest excess over the particle's own displacement along the plane.
  std::vector<double> mean_slip, max_slip, max_slip_excess;
  double mean_cohesive, mean_frictional, mean_normal; // time-averaged interface forces
};

BlockRun run_block(const std::vector<std::string>& overrides, const std::vector<double>& times) {
  const Case c = parse_case_file(
      std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/cohesive_block.toml", overrides);
  Simulation<2> sim(c);
  test::settle(sim, c); // damped, interfaces held
  const auto& P = sim.particles();
  const Vec<2> dir(std::cos(theta), -std::sin(theta));
  auto centroid = [&] {
    double mass = 0;
    Vec<2> mx = Vec<2>::Zero();
    for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
      mass += P.m[p], mx += P.m[p] * P.x[p];
    return Vec<2>(mx / mass);
  };
  const Vec<2> x0 = centroid();
  BlockRun r{{}, 0, {}, {}, {}, 0, 0, 0};
  for (double t : times) {
    while (sim.time() < t - 1e-12) {
      sim.step(t - sim.time());
      const InterfaceForce& F = sim.contact_record().interface_force[0];
      r.mean_cohesive += F.cohesive * sim.last_dt();
      r.mean_frictional += F.frictional * sim.last_dt();
      r.mean_normal += F.normal * sim.last_dt();
    }
    r.x.push_back((centroid() - x0).dot(dir));
    double sum = 0, most = 0, excess = -1e300;
    int n = 0;
    for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
      if (P.iface[p] >= 0) {
        sum += P.slip[p], ++n, most = std::max(most, P.slip[p]);
        excess = std::max(excess, P.slip[p] - std::abs((P.x[p] - P.x0[p]).dot(dir)));
      }
    r.mean_slip.push_back(sum / n), r.max_slip.push_back(most);
    r.max_slip_excess.push_back(excess);
  }
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    if (P.iface[p] >= 0)
      r.max_interface_slip = std::max(r.max_interface_slip, std::abs((P.x[p] - P.x0[p]).dot(dir)));
  r.mean_cohesive /= sim.time(), r.mean_frictional /= sim.time(), r.mean_normal /= sim.time();
  return r;
}

TEST(CohesiveBlock, SlidesWithTheClosedFormAndItsForces) {
  const double mu = 0.174, c = 100.0;
  const std::vector<double> times = {0.5, 1.0, 1.5, 2.0};
  const BlockRun r = run_block({}, times);
  const double a = g * (std::sin(theta) - mu * std::cos(theta)) - c * A / m;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double exact = 0.5 * a * times[i] * times[i];
    std::printf("cohesive block t %.1f s: %.5f m (closed form %.5f), error %+.4f %%\n", times[i],
                r.x[i], exact, 100 * (r.x[i] - exact) / exact);
    EXPECT_NEAR(r.x[i], exact, 0.005 * exact);
    // The slip history is the sliding (eq. 38-39 as tangential slip): the interface particles'
    // recorded slip is the block's displacement (100.01-100.03 % of it; the old sum over every
    // contact node's N_I recorded about half), and none records more than it has moved.
    std::printf("  recorded slip: mean %.5f m (%.2f %% of the displacement), largest %.5f m, "
                "largest excess over the particle's own displacement %+.2e m\n",
                r.mean_slip[i], 100 * r.mean_slip[i] / r.x[i], r.max_slip[i], r.max_slip_excess[i]);
    EXPECT_NEAR(r.mean_slip[i], r.x[i], 0.01 * r.x[i]);
    EXPECT_LT(r.max_slip_excess[i], 0.005 * r.x[i]);
  }
  // Time-averaged interface forces: cohesion c A, friction mu N with N = m g cos(theta).
  const double N = m * g * std::cos(theta);
  std::printf(
      "cohesive block forces: cohesive %.2f N (c A = %.2f), frictional %.1f N (mu N = %.1f), "
      "total %.1f N (%.1f), normal %.1f N (%.1f)\n",
      r.mean_cohesive, c * A, r.mean_frictional, mu * N, r.mean_cohesive + r.mean_frictional,
      c * A + mu * N, r.mean_normal, N);
  EXPECT_NEAR(r.mean_cohesive + r.mean_frictional, c * A + mu * N, 0.01 * (c * A + mu * N));
  EXPECT_NEAR(r.mean_cohesive, c * A, 0.01 * c * A);
}

// The block held by its bond (resistance over drive 1.07): c 2 kPa and mu 0.5 that do not
// degrade, settled 0.3 s with the interface at its own strength (the last entry).
std::vector<std::string> held_block() {
  return {"interface.0.friction.initial=0.5",  "interface.0.friction.residual=0.5",
          "interface.0.cohesion.initial=2000", "interface.0.cohesion.residual=2000",
          "initial_state.settle_time=0.3",     "initial_state.hold_interfaces=false"};
}

// Held: mu = 0.5 and c = 2 kPa give c A + mu m g cos(theta) = 10495 N >= m g sin(theta) = 9810 N.
// The closed form (a rigid block) does not move at all. The elastic block is not uniformly loaded:
// the weight's moment about the base unloads the upslope end, where the local traction exceeds
// the local bond and the interface slips a little until the load moves downslope. A held block
// has done that before the clock starts: it settles 0.3 s (damped) with its interface at its own
// strength (initial_state.hold_interfaces = false; nothing degrades while settling), then is
// released and must move less than 1e-4 m in 2 s (the issue's figure). With the interface held
// outright while settling, that partial slip happens after release instead: 1.9e-4 m, recorded
// here and in docs/verification.md. Started unstressed with no settling it is 2.4 mm.
TEST(CohesiveBlock, HeldByCohesionStaysPut) {
  const std::vector<std::string> held = held_block();
  const BlockRun r = run_block(held, {2.0});
  std::vector<std::string> held_outright = held;
  held_outright.back() = "initial_state.hold_interfaces=true";
  const BlockRun outright = run_block(held_outright, {2.0});
  std::vector<std::string> unbonded_case = held;
  unbonded_case.push_back("interface.0.cohesion.initial=0");
  unbonded_case.push_back("interface.0.cohesion.residual=0");
  const BlockRun unbonded = run_block(unbonded_case, {2.0});
  const double exact = 0.5 * g * (std::sin(theta) - 0.5 * std::cos(theta)) * 4.0;
  std::printf("held block: centroid moved %.3e m and interface particles at most %.3e m in 2 s "
              "after release (settled with the interface held outright: %.3e m); without "
              "cohesion the block slides %.4f m (closed form %.4f)\n",
              r.x[0], r.max_interface_slip, outright.x[0], unbonded.x[0], exact);
  EXPECT_LT(std::abs(r.x[0]), 1e-4);
  // No interface particle creeps either: 1.5e-6 m at most. While the strain pass applied the
  // bonds a second time the upslope corner particle crept 0.65 mm and recorded 1.13 mm of slip
  // (docs/verification.md); both are held to the block's own 1e-4 m.
  EXPECT_LT(r.max_interface_slip, 1e-4);
  std::printf("held block: largest recorded interface slip %.3e m\n", r.max_slip[0]);
  EXPECT_LT(r.max_slip[0], 1e-4);
  // The partial slip, when it comes after release: about the block's elastic shear scale
  // (m g sin / (G A) x h / 2 = 1.3e-4 m), far below any sliding.
  EXPECT_LT(std::abs(outright.x[0]), 3e-4);
  // Unbonded, mu = 0.5 near tan(theta): recorded in docs/verification.md, not asserted here.
  EXPECT_GT(unbonded.x[0], 0.5 * exact);
}

// The same held block under the transfers and shape functions that drop FLIP's noise, and with a
// bond ten times stronger in tension. MUSL's and USF's second contact pass (on the velocity the
// strain is taken from) used to apply the bond's capacity a second time, holding nodes the
// momentum pass had let slide or open: the strain then was not the particles' motion, and the
// block crept 4.6 mm in 2 s under PIC, 6.6 mm under XPIC(2) and 0.13 mm with B-splines, and left
// the plane at 2.5 cm/s under PIC with a 20 kPa bond (docs/formulation.md, "Contact and the
// strain's velocity"). Now each holds within the 1e-4 m the closed form allows.
TEST(CohesiveBlock, HeldUnderEveryTransferAndShape) {
  const std::vector<std::string> held = held_block();
  const std::vector<std::pair<std::string, std::vector<std::string>>> variants = {
      {"PIC", {"simulation.flip=0"}},
      {"XPIC(2)", {"simulation.xpic=2"}},
      {"B-spline", {"grid.shape_function=\"bspline\""}},
      {"B-spline, PIC", {"grid.shape_function=\"bspline\"", "simulation.flip=0"}},
      {"PIC, 20 kPa in tension", {"simulation.flip=0", "interface.0.tensile_strength=20000"}},
      {"USF, PIC", {"simulation.scheme=\"usf\"", "simulation.flip=0"}}};
  for (const auto& [name, extra] : variants) {
    std::vector<std::string> set = held;
    set.insert(set.end(), extra.begin(), extra.end());
    const BlockRun r = run_block(set, {2.0});
    std::printf("held block, %s: centroid moved %.3e m in 2 s\n", name.c_str(), r.x[0]);
    EXPECT_LT(std::abs(r.x[0]), 1e-4) << name;
  }
}

// Lift of the block's centre (m) after 0.1 s of the pull, and its interface particles' least and
// largest cohesion (Pa) and recorded slip (m).
std::array<double, 5> pull_off(const std::string& tensile_strength,
                               const std::string& plane_density) {
  const Vec<2> out_normal(std::sin(theta), std::cos(theta));
  const Case c = parse_case_file(
      std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/cohesive_block.toml",
      {"simulation.gravity=[4.905, 8.495709]", "interface.0.cohesion.residual=0",
       "interface.0.cohesion.slip=0.01", "interface.0.tensile_strength=" + tensile_strength,
       "material.1.density=" + plane_density});
  Simulation<2> sim(c);
  const auto& P = sim.particles();
  Vec<2> x0 = Vec<2>::Zero();
  double mass = 0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    x0 += P.m[p] * P.x[p], mass += P.m[p];
  while (sim.time() < 0.1 - 1e-12)
    sim.step(0.1 - sim.time());
  Vec<2> x = Vec<2>::Zero();
  double c_max = 0, c_min = 1e300, s_min = 1e300, s_max = 0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p) {
    x += P.m[p] * P.x[p];
    if (P.iface[p] < 0) continue;
    c_max = std::max(c_max, P.cohesion[p]), c_min = std::min(c_min, P.cohesion[p]);
    s_max = std::max(s_max, P.slip[p]), s_min = std::min(s_min, P.slip[p]);
  }
  const double lift = ((x - x0) / mass).dot(out_normal);
  std::printf("pulled off, tensile strength %s Pa, plane density %s: lifted %.5f m in 0.1 s "
              "(free flight %.5f), interface cohesion %.1f-%.1f Pa, recorded slip %.2e-%.2e m\n",
              tensile_strength.c_str(), plane_density.c_str(), lift, 0.5 * g * 0.01, c_min, c_max,
              s_min, s_max);
  return std::array<double, 5>{lift, c_min, c_max, s_min, s_max};
}

// A bond pulled straight off the plane (gravity turned to the plane's outward normal; the
// block's weight, 17 kN per metre, against a tensile capacity of 100 Pa x 1 m, the default: the
// cohesion) opens at once; the opening counts as the interface's relative displacement, so the
// bond breaks (cohesion 100 -> 0 over 1 cm) and the block leaves as in free flight, 0.5 g t^2.
// With a tensile strength of 1 MPa (1 MN per metre) the same pull is held: the block stays and
// the bond keeps (most of) its cohesion.
TEST(CohesiveBlock, PulledOffItsBondBreaksUnlessItHolds) {
  auto pull = [](const std::string& tension) { return pull_off(tension, "2000"); };
  const auto broken = pull("100");
  EXPECT_NEAR(broken[0], 0.5 * g * 0.01, 0.02 * 0.5 * g * 0.01); // free flight
  EXPECT_EQ(broken[2], 0.0);                                     // every bond broken
  // Each broken bond recorded the 1 cm that took its cohesion and tensile capacity to zero,
  // and nothing after: a bond that is gone is not an interface any more.
  EXPECT_NEAR(broken[3], 0.01, 1e-4);
  EXPECT_NEAR(broken[4], 0.01, 1e-4);
  const auto held = pull("1e6");
  EXPECT_LT(std::abs(held[0]), 1e-4);
  // Held, it keeps at least 90 % of its cohesion: the base contracts sideways under the pull
  // (Poisson) against 100 Pa of shear strength and slides 0.06-0.5 mm locally (94.8-99.4 Pa).
  EXPECT_GT(held[1], 90.0);
}

// A rigid body moves as prescribed and acts with infinite mass, so its density must change
// nothing. The degrading block of DegradationBlock (friction 0.2 -> 0.16, cohesion 3 kPa -> 0
// over 1 cm) on the rigid plane at 2,000 kg/m^3 and at 50,000 and 20 (the plane then lighter
// than the block: 135 kg against 2,000) slides, slips and loads its interface identically, and
// the pull-off bond breaks after the same 1 cm. Before session 11 the nodes' shares of the two
// bodies were by mass (at 50,000 the block fell under the 5 % cut at some nodes: 0.04 % slower
// at 0.5 s, with E = 1 GPa), and the bond was carried by the lighter body even if rigid (at 20: its
// particles record no slip, so the bond never degraded and the interface totals read zero).
TEST(CohesiveBlock, ARigidPlanesDensityChangesNothing) {
  auto slide = [](const std::string& density) {
    return run_block({"interface.0.friction.initial=0.2", "interface.0.friction.residual=0.16",
                      "interface.0.friction.slip=0.01", "interface.0.cohesion.initial=3000",
                      "interface.0.cohesion.residual=0", "interface.0.cohesion.slip=0.01",
                      "material.1.density=" + density},
                     {0.1, 0.2});
  };
  const BlockRun ref = slide("2000");
  EXPECT_GT(ref.max_slip[1], 0.01); // past s_c: fully degraded
  for (const std::string density : {"50000", "20"}) {
    SCOPED_TRACE("plane density " + density);
    const BlockRun r = slide(density);
    for (std::size_t i = 0; i < ref.x.size(); ++i) {
      EXPECT_NEAR(r.x[i], ref.x[i], 1e-12 * ref.x[i]);
      EXPECT_NEAR(r.mean_slip[i], ref.mean_slip[i], 1e-12 * ref.mean_slip[i]);
      EXPECT_NEAR(r.max_slip[i], ref.max_slip[i], 1e-12 * ref.max_slip[i]);
    }
    EXPECT_NEAR(r.mean_cohesive, ref.mean_cohesive, 1e-9 * ref.mean_cohesive);
    EXPECT_NEAR(r.mean_frictional, ref.mean_frictional, 1e-9 * ref.mean_frictional);
    EXPECT_NEAR(r.mean_normal, ref.mean_normal, 1e-9 * ref.mean_normal);
    const auto broken = pull_off("100", density);
    EXPECT_EQ(broken[2], 0.0); // every bond broken
    EXPECT_NEAR(broken[3], 0.01, 1e-4);
    EXPECT_NEAR(broken[4], 0.01, 1e-4);
  }
}

// Friction 0.2 -> 0.16 and cohesion 3 kPa -> 0 over 1 cm of slip (linear, Figure 11). The slip
// of a block on a rigid plane is its displacement, so x'' = g (sin - mu(x) cos) - c(x) A / m,
// integrated here with RK4 at a step far below the solver's.
TEST(DegradationBlock, FollowsThePiecewiseClosedForm) {
  const double mu0 = 0.2, mu_r = 0.16, c0 = 3000.0, s_c = 0.01;
  const std::vector<double> times = {0.5, 1.0, 1.5, 2.0};
  // A stiff block (E = 1 GPa): the closed form is a rigid block's, and a softer block's elastic
  // loading transient overlaps the 0.1 s of degradation (E = 100 MPa: +1.2 % at 0.5 s).
  const BlockRun r =
      run_block({"material.0.youngs_modulus=1e9", "interface.0.friction.initial=0.2",
                 "interface.0.friction.residual=0.16", "interface.0.friction.slip=0.01",
                 "interface.0.cohesion.initial=3000", "interface.0.cohesion.residual=0",
                 "interface.0.cohesion.slip=0.01"},
                times);
  auto accel = [&](double x) {
    const double f = std::min(1.0, std::max(x, 0.0) / s_c);
    return g * (std::sin(theta) - (mu0 + (mu_r - mu0) * f) * std::cos(theta)) -
           (c0 * (1.0 - f)) * A / m;
  };
  double x = 0, v = 0, t = 0;
  const double h = 1e-5;
  for (std::size_t i = 0; i < times.size(); ++i) {
    while (t < times[i] - 1e-12) {
      const double k1x = v, k1v = accel(x);
      const double k2x = v + 0.5 * h * k1v, k2v = accel(x + 0.5 * h * k1x);
      const double k3x = v + 0.5 * h * k2v, k3v = accel(x + 0.5 * h * k2x);
      const double k4x = v + h * k3v, k4v = accel(x + h * k3x);
      x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      t += h;
    }
    std::printf("degrading interface t %.1f s: %.5f m (closed form %.5f), error %+.3f %%\n",
                times[i], r.x[i], x, 100 * (r.x[i] - x) / x);
    EXPECT_NEAR(r.x[i], x, 0.01 * x);
  }
}

// Two interfaces of one body a node apart: a plate one cell thick, bonded to a rigid floor
// (1 MPa of cohesion, interface 0), under a rider that slides over it frictionless at 1 m/s
// (interface 1). The plate's base and top rows are the two interfaces' particles and share the
// node row between them. Each interface keeps its own nodal capacities and slip: the rider
// slides its 0.2 m in 0.2 s and the floor bond records no slip. Before session 11 a body had one
// set of interface arrays: the floor bond's cohesion, read at the row the rider touches, glued
// the rider (0.1 mm in 0.2 s), and the rider's slip leaked into the floor bond (0.35 mm; its
// cohesion fell to 0.965 MPa).
TEST(Interfaces, AThinBodysTwoBondsStayApart) {
  const std::string text = R"(
title = "Thin bonded plate under a sliding rider"
[simulation]
dimension = 2
end_time = 0.2
cfl = 0.4
gravity = [0.0, -9.81]
[grid]
origin = [-0.5, -0.5]
extent = [4.0, 1.5]
cell_size = 0.1
shape_function = "gimp"
[[material]]
name = "rock"
density = 2000.0
youngs_modulus = 100.0e6
poisson_ratio = 0.3
[[body]]
name = "plate"
material = "rock"
box = { min = [0.0, 0.0], max = [3.0, 0.1] }
particles_per_cell = 2
[[body]]
name = "rider"
material = "rock"
box = { min = [0.2, 0.1], max = [1.2, 0.4] }
particles_per_cell = 2
velocity = [1.0, 0.0]
[[body]]
name = "floor"
material = "rock"
rigid = true
box = { min = [-0.4, -0.3], max = [3.4, 0.0] }
particles_per_cell = 2
[[interface]]
bodies = ["plate", "floor"]
friction = { initial = 0.5, residual = 0.0, slip = 0.01 }
cohesion = { initial = 1.0e6, residual = 0.0, slip = 0.01 }
[[interface]]
bodies = ["plate", "rider"]
friction = { initial = 0.0, residual = 0.0, slip = 1.0 }
cohesion = { initial = 0.0, residual = 0.0, slip = 1.0 }
)";
  const Case c = parse_case_text(text, "junction.toml");
  Simulation<2> sim(c);
  while (sim.time() < 0.2 - 1e-12)
    sim.step(0.2 - sim.time());
  const auto& P = sim.particles();
  double rider = 0, mass = 0;
  for (std::size_t p = P.body_begin[1]; p < P.body_begin[2]; ++p)
    rider += P.m[p] * (P.x[p] - P.x0[p])[0], mass += P.m[p];
  rider /= mass;
  double floor_slip = 0, floor_cohesion = 1e300, top_slip = 0;
  int floor_bond = 0, top_bond = 0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p) {
    if (P.iface[p] == 0) {
      ++floor_bond;
      floor_slip = std::max(floor_slip, P.slip[p]);
      floor_cohesion = std::min(floor_cohesion, P.cohesion[p]);
    } else if (P.iface[p] == 1) {
      ++top_bond, top_slip = std::max(top_slip, P.slip[p]);
    }
  }
  std::printf("rider slid %.5f m; floor bond (%d particles): slip %.2e m, cohesion %.4g Pa; top "
              "(%d particles): slip up to %.4f m\n",
              rider, floor_bond, floor_slip, floor_cohesion, top_bond, top_slip);
  ASSERT_GT(floor_bond, 0);
  ASSERT_GT(top_bond, 0);
  EXPECT_NEAR(rider, 0.2, 0.002);
  EXPECT_LT(floor_slip, 1e-6);
  EXPECT_EQ(floor_cohesion, 1e6);
  EXPECT_NEAR(top_slip, 0.2, 0.002); // the top row under the rider all the way
}

} // namespace
} // namespace talus
