// ResultsMonitor (output/results_monitor.hpp): the headline figures of summary.json's results,
// tracked step by step: the peak mean speed and its time, the run-out duration, the probes'
// peak speeds, and the energy budget's identities.
#include "talus/output/results_monitor.hpp"
#include "talus/solver/diagnostics.hpp"
#include "two_bodies.hpp"

#include <gtest/gtest.h>

using namespace talus;

namespace {

const char* tracked = R"(
[results]
body = "upper"
stop_speed = 0.5
[[probe]]
name = "top"
body = "upper"
near = [0.8, 0.6]
)";

results::StepFigures figures(double mean_speed, double probe_speed) {
  results::StepFigures f;
  f.mass = 4.0, f.mass_speed = 4.0 * mean_speed;
  f.probe_speed = {probe_speed};
  f.pore_peak = {-inf}, f.temperature_peak = {-inf};
  return f;
}

} // namespace

// The step's figures: the results body's mass and mass-weighted speed, the probe's speed.
TEST(ResultsMonitor, FiguresSumTheResultsBody) {
  Simulation<2> sim(test::case_from(test::two_blocks(tracked)));
  Particles<2>& P = sim.particles_mut();
  for (std::size_t p = 0; p < P.size(); ++p)
    P.v[p] = Vec<2>(3.0 * P.x[p][0], 4.0 * P.x[p][0]); // |v| = 5 x
  const std::vector<std::uint32_t> ids = probe_ids(sim);
  results::ResultsMonitor<2> monitor(sim, ids, frame_totals(sim, ids));
  EXPECT_EQ(monitor.body(), 1);
  const results::StepFigures f = monitor.figures(sim);
  double m = 0.0, ms = 0.0;
  for (std::size_t p = P.body_begin[1]; p < P.body_begin[2]; ++p)
    m += P.m[p], ms += P.m[p] * 5.0 * P.x[p][0];
  EXPECT_NEAR(f.mass, m, 1e-12 * m);
  EXPECT_NEAR(f.mass_speed / f.mass, ms / m, 1e-12);
  ASSERT_EQ(f.probe_speed.size(), 1u);
  EXPECT_DOUBLE_EQ(f.probe_speed[0], P.v[sim.index_of(ids[0])].norm());
}

// A speed history that rises, peaks, dips below the stop speed, moves again and stops: the peak
// and its time, the run-out duration (the last time the mean speed was at or above stop_speed),
// and the probe's peak; a history that ends moving has no run-out duration.
TEST(ResultsMonitor, PeakAndRunoutFollowTheSpeedHistory) {
  Simulation<2> sim(test::case_from(test::two_blocks(tracked)));
  const std::vector<std::uint32_t> ids = probe_ids(sim);
  const FrameTotals<2> totals = frame_totals(sim, ids);
  const double speeds[] = {0.1, 1.0, 3.0, 2.0, 0.4, 0.6, 0.2, 0.1};
  const double probe[] = {0.0, 1.5, 4.0, 7.5, 1.0, 0.5, 0.0, 0.0};
  for (const bool stops : {true, false}) {
    results::ResultsMonitor<2> monitor(sim, ids, totals);
    const int n = stops ? 8 : 6; // the second history ends at 0.6 m/s
    for (int i = 0; i < n; ++i)
      monitor.update(figures(speeds[i], probe[i]), 0.1 * i, 0.5);
    const nlohmann::json j = monitor.json(sim, totals, 0.0);
    EXPECT_EQ(j["body"], "upper");
    EXPECT_DOUBLE_EQ(j["peak_mean_speed_m_s"].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(j["peak_time_s"].get<double>(), 0.2);
    EXPECT_DOUBLE_EQ(j["probes"]["top"]["peak_speed_m_s"].get<double>(), 7.5);
    EXPECT_EQ(j["still_moving_at_end"], !stops);
    if (stops)
      EXPECT_DOUBLE_EQ(j["runout_duration_s"].get<double>(), 0.5);
    else
      EXPECT_TRUE(j["runout_duration_s"].is_null());
    EXPECT_DOUBLE_EQ(j["centroid_displacement_x_m"].get<double>(), 0.0); // nothing moved
  }
}

// The energy budget's derived terms: plastic work is the stress work less the elastic change, and
// the unbalanced energy is gravity's and contact's work less the stress work and kinetic energy,
// after the blocks have moved under gravity.
TEST(ResultsMonitor, EnergyBudgetTermsAreConsistent) {
  Simulation<2> sim(test::case_from(test::two_blocks(tracked)));
  for (int i = 0; i < 40; ++i)
    sim.step();
  const FrameTotals<2> totals = frame_totals(sim, {});
  for (int b = 0; b < 2; ++b) {
    const nlohmann::json e = results::energy_budget(sim, totals, b);
    const double gravity = e["gravity_work_J"], ke = e["kinetic_J"], contact = e["contact_work_J"];
    const double stress = e["stress_work_J"], elastic = e["elastic_change_J"];
    EXPECT_GT(gravity, 0.0) << "body " << b; // the blocks fall onto the grid's floor
    EXPECT_DOUBLE_EQ(ke, totals.bodies[b].kinetic_energy);
    EXPECT_DOUBLE_EQ(e["plastic_work_J"].get<double>(), stress - elastic);
    EXPECT_DOUBLE_EQ(e["unbalanced_J"].get<double>(), gravity + contact - stress - ke);
  }
}

// A run-up probe ([[run_up]]) tracks the highest particle of its body over its region of the
// plan: a block thrown up at v0 (1 m/s across, 5 m/s up) reaches v0^2 / (2 g) above its top
// particle's start at t = v0 / g, within the step's error (v0 dt); a probe whose region the
// block never enters reports null; the level is subtracted.
TEST(ResultsMonitor, RunUpIsTheHighestPointOverItsRegion) {
  Simulation<2> sim(test::case_from(R"(
[simulation]
dimension = 2
end_time = 1.0
gravity = [0, -9.81]
[grid]
extent = [2.0, 3.0]
cell_size = 0.1
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
[[body]]
name = "ball"
material = "m"
box = { min = [0.2, 0.4], max = [0.4, 0.6] }
velocity = [1.0, 5.0]
[[run_up]]
name = "all"
body = "ball"
level = 0.5
[[run_up]]
name = "east"
body = "ball"
min = 1.5
max = 2.0
)"));
  const double g = 9.81, v0 = 5.0;
  const auto& P = sim.particles();
  double top0 = -inf;
  for (std::size_t p = 0; p < P.size(); ++p)
    top0 = std::max(top0, P.x[p][1]);
  results::ResultsMonitor<2> monitor(sim, {}, frame_totals(sim, {}));
  double dt = 0.0;
  while (sim.time() < 0.8) {
    const double t0 = sim.time();
    sim.step();
    dt = sim.time() - t0;
    monitor.update(monitor.figures(sim), sim.time(), 0.5);
  }
  const nlohmann::json j = monitor.json(sim, frame_totals(sim, {}), 0.0)["run_up"];
  const double rise = v0 * v0 / (2.0 * g);
  EXPECT_NEAR(j["all"]["elevation_m"].get<double>(), top0 + rise, v0 * dt);
  EXPECT_NEAR(j["all"]["above_level_m"].get<double>(), top0 + rise - 0.5, v0 * dt);
  EXPECT_NEAR(j["all"]["time_s"].get<double>(), v0 / g, 2.0 * dt);
  EXPECT_EQ(j["all"]["body"], "ball");
  const double x = j["all"]["x_m"].get<double>(), shift = 1.0 * v0 / g;
  EXPECT_GT(x, 0.2 + shift - dt);
  EXPECT_LT(x, 0.4 + shift + dt);
  EXPECT_TRUE(j["east"]["elevation_m"].is_null());
  EXPECT_DOUBLE_EQ(j["east"]["level_m"].get<double>(), 0.0);
}
