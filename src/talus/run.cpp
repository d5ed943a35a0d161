#include "talus/run.hpp"

#include "talus/output/run_writer.hpp"
#include "talus/solver.hpp"

#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {

int set_threads(int threads) {
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(threads);
  return omp_get_max_threads();
#else
  (void)threads;
  return 1;
#endif
}

namespace {

using Clock = std::chrono::steady_clock;

// A progress bar on a terminal; a plain line every 10 % or 30 s otherwise.
class Progress {
public:
  Progress(std::ostream* out, double end_time)
      : out_(out), end_(end_time), tty_(out && ::isatty(STDOUT_FILENO)), start_(Clock::now()) {}

  void update(double t, std::int64_t steps, bool final = false) {
    if (!out_) return;
    const double wall = std::chrono::duration<double>(Clock::now() - start_).count();
    const double frac = std::min(1.0, t / end_);
    const bool due =
        tty_ ? wall - last_wall_ >= 0.2 : (frac >= next_frac_ || wall - last_wall_ >= 30.0);
    if (!due && !final) return;
    last_wall_ = wall;
    while (next_frac_ <= frac)
      next_frac_ += 0.1;
    const double eta = frac > 0 ? wall * (1.0 - frac) / frac : 0.0;
    const std::string text =
        fmt::format("t = {:.4g} / {:.4g} s  {:5.1f} %  {} steps  {:.0f} steps/s  ETA {:.0f} s", t,
                    end_, 100.0 * frac, steps, wall > 0 ? steps / wall : 0.0, eta);
    if (tty_) {
      const int width = 30;
      const int filled = static_cast<int>(frac * width);
      *out_ << "\r[" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << text
            << (final ? "\n" : "") << std::flush;
    } else {
      *out_ << text << "\n" << std::flush;
    }
  }

private:
  std::ostream* out_;
  double end_;
  bool tty_;
  Clock::time_point start_;
  double last_wall_ = -1e9;
  double next_frac_ = 0.0;
};

template <int D>
RunResult run_dim(const Case& c, const RunOptions& opt) {
  const auto wall0 = Clock::now();
  const int threads = set_threads(opt.threads);
  Simulation<D> sim(c);
  RunWriter<D> writer(opt.out_dir, sim);
  writer.write_frame(sim);
  RunResult r;
  r.particles = sim.particles().size();
  if (opt.log)
    *opt.log << fmt::format("talus: {} particles, {} nodes, {} threads -> {}\n", r.particles,
                            sim.grid().num_nodes(), threads, opt.out_dir);

  const double end = c.simulation.end_time;
  const double every = c.output.every > 0 ? c.output.every : end;
  std::int64_t frame = 1;
  Progress progress(opt.log, end);
  double stepping = 0.0;
  r.status = "completed";
  try {
    while (end - sim.time() > 1e-12 * end) {
      if (opt.max_steps && sim.steps() >= *opt.max_steps) break;
      const double next_output = std::min(end, every * static_cast<double>(frame));
      const auto t0 = Clock::now();
      sim.step(next_output - sim.time());
      stepping += std::chrono::duration<double>(Clock::now() - t0).count();
      if (sim.time() >= next_output - 1e-12 * end) {
        writer.write_frame(sim);
        ++frame;
      }
      progress.update(sim.time(), sim.steps());
    }
  } catch (const SimulationError& e) {
    r.status = "failed";
    r.message = e.what();
  }
  progress.update(sim.time(), sim.steps(), true);
  r.steps = sim.steps();
  r.simulated_time = sim.time();
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  r.particle_updates_per_second =
      stepping > 0 ? static_cast<double>(r.particles) * static_cast<double>(r.steps) / stepping
                   : 0.0;
  writer.write_summary(sim, r.status, r.wall_seconds, stepping, threads, r.message);
  return r;
}

} // namespace

RunResult run_case(const Case& c, const RunOptions& opt) {
  return c.simulation.dimension == 2 ? run_dim<2>(c, opt) : run_dim<3>(c, opt);
}

} // namespace talus
