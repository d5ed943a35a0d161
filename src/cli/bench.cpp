#include "bench.hpp"

#include "talus/case/parse.hpp"
#include "talus/core/memory_usage.hpp"
#include "talus/core/threads.hpp"
#include "talus/output/files.hpp"
#include "talus/parallel/processes.hpp"
#include "talus/parallel/stepper.hpp"
#include "talus/run/run.hpp"

#include <chrono>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace talus {

namespace {

struct Problem {
  std::string name, file;
  std::vector<std::string> overrides;
  int steps;
};

const std::vector<Problem>& problems() {
  static const std::vector<Problem> all = {
      {"column", "bench/column.toml", {}, 300},
      {"column_4x", "bench/column.toml", {"grid.cell_size=0.001"}, 300},
      {"vaiont",
       "cases/vaiont/three_bodies.toml",
       {"grid.cell_size=4", "initial_state.settle_time=0", "interface.0.friction.slip=0.02",
        "interface.0.cohesion.slip=0.02"},
       200},
      {"vaiont_3d", "cases/vaiont/rigid_boundary_3d.toml", {"initial_state.settle_time=0"}, 100},
      // The quadratic B-spline's cost: the column and the Vaiont as above with it.
      {"column_bspline", "bench/column.toml", {"grid.shape_function=\"bspline\""}, 300},
      {"vaiont_bspline",
       "cases/vaiont/three_bodies.toml",
       {"grid.cell_size=4", "initial_state.settle_time=0", "interface.0.friction.slip=0.02",
        "interface.0.cohesion.slip=0.02", "grid.shape_function=\"bspline\""},
       200},
      // The wet Vaiont: the reservoir's level, the clay band's pore pressure and heating.
      {"vaiont_wet",
       "cases/vaiont/three_bodies_wet.toml",
       {"grid.cell_size=4", "initial_state.settle_time=0", "interface.0.friction.slip=0.02",
        "interface.0.cohesion.slip=0.02"},
       200},
      // Water as a body: a block entering a tank at 2 m/s (a fluid, contact, 88,000 particles).
      {"tank",
       "cases/examples/slide_into_tank.toml",
       {"grid.cell_size=0.00625",
        "body.slide.polygon=[[0.55, 0.35], [0.691421, 0.208579], [0.762132, 0.279289], "
        "[0.620711, 0.420711]]",
        "body.slide.velocity=[1.414214, -1.414214]"},
       200},
      // The Vaiont with its reservoir as a body (the flagship: a fluid body beside three rock
      // bodies, the level, the band; 60,000 particles).
      {"vaiont_reservoir",
       "cases/vaiont/three_bodies_reservoir.toml",
       {"initial_state.settle_time=0"},
       200},
      // XPIC(2)'s cost: the flagship's problem with the extra gather and scatter and v_c's
      // contact pass.
      {"vaiont_reservoir_xpic",
       "cases/vaiont/three_bodies_reservoir.toml",
       {"initial_state.settle_time=0", "simulation.xpic=2"},
       200},
      // A real DEM in 3D: the volcano slide on its rigid flank and band (the step alone).
      {"volcano", "cases/examples/volcano_slide.toml", {"initial_state.settle_time=0"}, 400},
  };
  return all;
}

} // namespace

std::vector<std::string> bench_problem_names() {
  std::vector<std::string> names;
  for (const Problem& pb : problems())
    names.push_back(pb.name);
  return names;
}

int run_bench(const BenchOptions& opt) {
  const std::vector<Problem>& all = problems();
  nlohmann::json out = nlohmann::json::array();
  if (process_rank() == 0)
    fmt::print(
        "{:<10} {:>8} {:>9} {:>6} {:>9} {:>12} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>9} {:>9}\n",
        "problem", "threads", "particles", "steps", "wall s", "updates/s", "p2g", "grid", "contact",
        "g2p", "stress", "other", "B/part.", "RSS/part.");
  for (const Problem& pb : all) {
    if (std::find(opt.problems.begin(), opt.problems.end(), pb.name) == opt.problems.end())
      continue;
    const Case c =
        parse_case_file(opt.source_dir + "/" + pb.file, pb.overrides, this_machine_budget());
    // One thread count's measurement, in the case's dimension.
    auto measure = [&]<int D>(int threads) {
      reset_peak_rss();
      const double rss_before = read_rss().now;
      // Under mpirun, each process seeds and steps its slab (parallel/stepper.hpp).
      const std::unique_ptr<Stepper<D>> stepper = make_stepper<D>(c);
      stepper->distribute();
      const Simulation<D>& sim = stepper->sim();
      const double n = static_cast<double>(sim.case_particles());
      stepper->step(inf); // warm-up: first sort and field allocation
      const PhaseTimes before = sim.phase_times();
      const ShareCounters share0 = stepper->share_counters().value_or(ShareCounters{});
      wait_for_processes();
      const auto t0 = std::chrono::steady_clock::now();
      for (int s = 0; s < pb.steps; ++s)
        stepper->step(inf);
      wait_for_processes();
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      PhaseTimes T = sim.phase_times();
      T.p2g -= before.p2g, T.grid -= before.grid, T.contact -= before.contact, T.g2p -= before.g2p;
      T.stress -= before.stress, T.other -= before.other;
      const double rate = n * pb.steps / wall;
      // Memory: the rise of the peak resident set over the set-up and the run (particles, grid
      // fields and every other array the problem allocates), and the whole process's peak
      // (which adds the program, its libraries and the parsed case).
      const Rss rss = read_rss();
      double rise = rss.peak - rss_before, peak = rss.peak;
      nlohmann::json processes = nullptr;
      if (const auto share = stepper->share_counters()) {
        // Every process's memory, ghosts and exchange bytes per step, summed; the rebuilds' most.
        double figures[5] = {rise, peak, (share->ghost_bytes - share0.ghost_bytes) / pb.steps,
                             (share->migration_bytes - share0.migration_bytes) / pb.steps,
                             share->ghost_particles};
        double rebuilds = static_cast<double>(share->rebuilds - share0.rebuilds);
        sum_over_processes(figures, 5);
        max_over_processes(&rebuilds, 1);
        rise = figures[0], peak = figures[1];
        const double ghosts = figures[4];
        processes = {{"processes", share->processes},
                     {"ghost_particles", ghosts},
                     {"ghost_bytes_per_step", figures[2]},
                     {"migration_bytes_per_step", figures[3]},
                     {"share_rebuilds", rebuilds}};
        if (process_rank() == 0)
          fmt::print("  {} processes: {:.0f} ghost particles ({:.1f} % of the particles), "
                     "{:.0f} kB of ghosts and {:.0f} B of migration a step; the share merged "
                     "anew after {:.0f} of {} steps (sorts and rebalances aside); {} rebalances\n",
                     share->processes, ghosts, 100.0 * ghosts / n, figures[2] / 1e3, figures[3],
                     rebuilds, pb.steps, share->rebalances);
      }
      const double bytes = rise / n, process_bytes = peak / n;
      if (process_rank() == 0)
        fmt::print(
            "{:<10} {:>8} {:>9} {:>6} {:>9.2f} {:>12.3e} {:>7.2f} {:>7.2f} {:>7.2f} {:>7.2f} "
            "{:>7.2f} {:>7.2f} {:>9.0f} {:>9.0f}\n",
            pb.name, threads, static_cast<std::size_t>(n), pb.steps, wall, rate, T.p2g, T.grid,
            T.contact, T.g2p, T.stress, T.other, bytes, process_bytes);
      out.push_back({{"problem", pb.name},
                     {"threads", threads},
                     {"particles", static_cast<std::size_t>(n)},
                     {"steps", pb.steps},
                     {"wall_seconds", wall},
                     {"particle_updates_per_second", rate},
                     {"phase_seconds",
                      {{"p2g", T.p2g},
                       {"grid", T.grid},
                       {"contact", T.contact},
                       {"g2p", T.g2p},
                       {"stress", T.stress},
                       {"other", T.other}}},
                     {"peak_rss_bytes_per_particle", bytes},
                     {"process_peak_rss_bytes_per_particle", process_bytes},
                     {"processes", processes}});
    };
    for (const int threads : opt.threads) {
      set_threads(threads, 0);
      if (c.simulation.dimension == 3)
        measure.template operator()<3>(threads);
      else
        measure.template operator()<2>(threads);
    }
  }
  if (!opt.json_out.empty() && process_rank() == 0)
    write_file_atomic(opt.json_out, out.dump(2) + "\n");
  return 0;
}

} // namespace talus
