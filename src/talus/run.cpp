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
    if (final && !tty_ && steps == last_steps_) return; // this state is already on its own line
    last_wall_ = wall;
    last_steps_ = steps;
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
  std::int64_t last_steps_ = -1;
};

// The headline figures of a run (ResultsSpec), tracked every step.
template <int D>
class ResultsMonitor {
public:
  explicit ResultsMonitor(const Simulation<D>& sim)
      : body_(sim.case_().results.body), probe_ids_(sim.probe_ids()) {
    probe_peak_.assign(probe_ids_.size(), 0.0);
    if (body_ >= 0) centroid0_ = centroid(sim);
  }

  void update(const Simulation<D>& sim) {
    const auto& P = sim.particles();
    for (std::size_t k = 0; k < probe_ids_.size(); ++k)
      probe_peak_[k] = std::max(probe_peak_[k], P.v[sim.index_of(probe_ids_[k])].norm());
    if (body_ < 0) return;
    double m = 0.0, ms = 0.0;
    for (std::size_t p = P.body_begin[body_]; p < P.body_begin[body_ + 1]; ++p)
      m += P.m[p], ms += P.m[p] * P.v[p].norm();
    const double speed = ms / m;
    if (speed > peak_) peak_ = speed, peak_time_ = sim.time();
    if (speed >= sim.case_().results.stop_speed) last_moving_ = sim.time();
    last_speed_ = speed;
  }

  nlohmann::json json(const Simulation<D>& sim, double settle_ke) const {
    nlohmann::json j = nlohmann::json::object();
    const Case& c = sim.case_();
    const auto& P = sim.particles();
    if (c.initial_state.settle_time > 0.0) {
      j["settle_time_s"] = c.initial_state.settle_time;
      j["kinetic_energy_at_release_J"] = settle_ke;
    }
    nlohmann::json probes = nlohmann::json::object();
    for (std::size_t k = 0; k < probe_ids_.size(); ++k) {
      const std::size_t p = sim.index_of(probe_ids_[k]);
      probes[c.probes[k].name] = {{"peak_speed_m_s", probe_peak_[k]},
                                  {"displacement_x_m", P.x[p][0] - P.x0[p][0]},
                                  {"displacement_m", (P.x[p] - P.x0[p]).norm()}};
    }
    if (!probe_ids_.empty()) j["probes"] = probes;
    if (body_ < 0) return j;
    j["body"] = c.bodies[body_].name;
    j["peak_mean_speed_m_s"] = peak_;
    j["peak_time_s"] = peak_time_;
    const bool stopped = last_speed_ < c.results.stop_speed;
    j["runout_duration_s"] = stopped ? nlohmann::json(last_moving_) : nlohmann::json(nullptr);
    j["still_moving_at_end"] = !stopped;
    j["centroid_displacement_x_m"] = centroid(sim)[0] - centroid0_[0];
    return j;
  }

private:
  Vec<D> centroid(const Simulation<D>& sim) const {
    const auto& P = sim.particles();
    double m = 0.0;
    Vec<D> mx = Vec<D>::Zero();
    for (std::size_t p = P.body_begin[body_]; p < P.body_begin[body_ + 1]; ++p)
      m += P.m[p], mx += P.m[p] * P.x[p];
    return mx / m;
  }
  int body_;
  std::vector<std::uint32_t> probe_ids_;
  std::vector<double> probe_peak_;
  Vec<D> centroid0_ = Vec<D>::Zero();
  double peak_ = 0.0, peak_time_ = 0.0, last_moving_ = 0.0, last_speed_ = 0.0;
};

// The settling phase: damped, interfaces held, until settle_time; then release. Returns the
// kinetic energy at release.
template <int D>
double settle(Simulation<D>& sim, std::ostream* log) {
  const double T = sim.case_().initial_state.settle_time;
  if (T <= 0.0) return 0.0;
  sim.set_settling(true);
  Progress progress(log, T);
  while (T - sim.time() > 1e-12 * T) {
    sim.step(T - sim.time());
    progress.update(sim.time(), sim.steps());
  }
  progress.update(sim.time(), sim.steps(), true);
  double ke = 0.0;
  const auto& P = sim.particles();
  for (std::size_t p = 0; p < P.size(); ++p)
    ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
  if (log)
    *log << fmt::format("talus: settled for {} s, kinetic energy {:.4g} J; released\n", T, ke);
  sim.release();
  return ke;
}

template <int D>
RunResult run_dim(const Case& c, const RunOptions& opt) {
  const auto wall0 = Clock::now();
  const int threads = set_threads(opt.threads);
  Simulation<D> sim(c);
  RunResult r;
  r.particles = sim.particles().size();
  if (opt.log)
    *opt.log << fmt::format("talus: {} particles, {} nodes, {} threads -> {}\n", r.particles,
                            sim.grid().num_nodes(), threads, opt.out_dir);
  double settle_ke = 0.0;
  const auto settle0 = Clock::now();
  try {
    settle_ke = settle(sim, opt.log);
  } catch (const SimulationError& e) {
    r.status = "failed";
    r.message = std::string("while settling: ") + e.what();
  }
  RunWriter<D> writer(opt.out_dir, sim);
  writer.write_frame(sim);
  ResultsMonitor<D> monitor(sim);
  // The settling steps count as stepping: particle-updates per second covers every step.
  double stepping = std::chrono::duration<double>(Clock::now() - settle0).count();

  const double end = c.simulation.end_time;
  const double every = c.output.every > 0 ? c.output.every : end;
  std::int64_t frame = 1;
  Progress progress(opt.log, end);
  if (r.status.empty()) r.status = "completed";
  try {
    while (r.status == "completed" && end - sim.time() > 1e-12 * end) {
      if (opt.max_steps && sim.steps() >= *opt.max_steps) break;
      const double next_output = std::min(end, every * static_cast<double>(frame));
      const auto t0 = Clock::now();
      sim.step(next_output - sim.time());
      stepping += std::chrono::duration<double>(Clock::now() - t0).count();
      monitor.update(sim);
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
  writer.write_summary(sim, r.status, r.wall_seconds, stepping, threads, r.message,
                       monitor.json(sim, settle_ke));
  return r;
}

} // namespace

RunResult run_case(const Case& c, const RunOptions& opt) {
  return c.simulation.dimension == 2 ? run_dim<2>(c, opt) : run_dim<3>(c, opt);
}

} // namespace talus
