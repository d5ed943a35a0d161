#include "talus/run/run.hpp"

#include "talus/case/parse.hpp"
#include "talus/case/size.hpp"
#include "talus/core/threads.hpp"
#include "talus/output/checkpoint.hpp"
#include "talus/output/frame_totals.hpp"
#include "talus/output/peak_maps.hpp"
#include "talus/output/progress.hpp"
#include "talus/output/results_monitor.hpp"
#include "talus/output/run_writer.hpp"
#include "talus/output/simulation_archive.hpp"
#include "talus/parallel/processes.hpp"
#include "talus/parallel/stepper.hpp"
#include "talus/solver/diagnostics.hpp"
#include "talus/solver/simulation.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <unistd.h>

namespace talus {

namespace {

using Clock = std::chrono::steady_clock;
using results::ResultsMonitor;

volatile std::sig_atomic_t stop_signal = 0;
extern "C" void on_stop_signal(int sig) {
  stop_signal = sig;
}

// SIGINT, SIGTERM and SIGHUP (the terminal closed) ask the run to stop after the current step
// (with a checkpoint); the handler resets itself, so a second Ctrl-C kills at once.
class StopSignals {
public:
  StopSignals() {
    stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
    sigaction(SIGHUP, &sa, &old_hup_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    sigaction(SIGHUP, &old_hup_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
  struct sigaction old_hup_ {};
};

// A run: the simulation (on this program's processes: stepper_), its settling phase, output at its
// interval, checkpoints, and what a checkpoint must carry besides the simulation (the run folder's
// tables, the tracked results).
template <int D>
class Runner {
public:
  // `folder`: the run folder, held by rank 0 (null on the other processes).
  Runner(const Case& c, const RunOptions& opt, const RunFolder* folder, bool restoring)
      : c_(c), opt_(opt), folder_(folder), stepper_(make_stepper<D>(c, restoring)),
        sim_(stepper_->sim()), root_(process_rank() == 0) {}

  RunResult run(LoadArchive* restore, const std::string& restored_from) {
    const auto wall0 = wall0_ = Clock::now();
    const int threads = threads_ = set_threads(opt_.threads, sim_.case_particles());
    StopSignals signals;
    RunResult r;
    r.particles = sim_.case_particles();
    if (restore) {
      stepper_->read_own_slab(*restore); // on several processes, each reads its slab alone
      agreed<CheckpointError>([&] {
        serialize(*restore);
        if (!restore->done()) throw CheckpointError(restored_from + ": trailing bytes");
        // A frame the checkpoint lists that is gone would leave particles.pvd pointing at
        // nothing in a run that says it completed.
        if (writer_)
          if (const auto gone = writer_->missing_frames(); !gone.empty())
            throw CheckpointError(fmt::format(
                "{}/{}: a frame the checkpoint lists is missing ({} of them); the run folder "
                "cannot be continued whole: run the case again into a new folder",
                opt_.out_dir, gone.front(), gone.size()));
      });
      if (writer_) writer_->write_tables(sim_);
      // Output had started (its first frame written, with the fixed part) unless the checkpoint
      // is from the settling: every process read the same flag.
      fixed_part_written_ = monitor_.has_value();
      last_checkpoint_ = restored_from;
    } else if (c_.initial_state.settle_time > 0.0) {
      sim_.set_settling(true);
    }
    stepper_->distribute();
    first_step_ = sim_.steps();
    if (opt_.log)
      *opt_.log << fmt::format(
          "talus: {} particles, {} nodes, {}{} threads -> {}{}\n", r.particles,
          sim_.grid().num_nodes(),
          process_count() > 1 ? fmt::format("{} processes x ", process_count()) : "", threads,
          opt_.out_dir,
          restore ? fmt::format(" (restarted at step {}, {} {:.6g} s)", sim_.steps(),
                                sim_.settling() ? "settling" : "time", sim_.time())
                  : "");
    if (opt_.log)
      for (const std::string& w : sim_.warnings())
        *opt_.log << "talus: warning: " << w << "\n";
    r.status = "completed";
    try {
      write_running_summary();
      loop(r);
    } catch (const SimulationError& e) {
      r.status = "failed";
      r.message =
          fmt::format("{}{}; last good checkpoint: {}", sim_.settling() ? "while settling: " : "",
                      e.what(), last_checkpoint_.empty() ? "none" : last_checkpoint_);
    } catch (const OutputError& e) {
      // Leave a summary if the disk still takes one; the files already written are intact.
      r.status = "failed";
      r.message = std::string("output: ") + e.what();
      try {
        finish(r, wall0, threads);
      } catch (const OutputError&) {
      }
      throw;
    }
    finish(r, wall0, threads);
    return r;
  }

  template <class Ar>
  void serialize(Ar& ar) {
    bool started = monitor_.has_value();
    auto state = [&] {
      serialize_state(ar, sim_, opt_.out_dir);
      ar.io(settle_ke_), ar.io(stepping_), ar.io(frame_);
      ar.io(started);
    };
    if constexpr (Ar::loading) {
      // Each process reads its own rows: a read that fails on one fails on all before they
      // distribute (collective); the rest is read with the processes' exchange.
      agreed<CheckpointError>(state);
      stepper_->distribute();
    } else {
      state();
    }
    if (!started) return;
    if (!monitor_) start_output(); // restoring: every process (its figures are then read)
    if (writer_) {
      writer_->serialize(ar);
    } else { // a process that writes nothing reads past the writer's tables
      RunWriter<D> tables;
      tables.serialize(ar);
    }
    monitor_->serialize(ar);
    if (maps_) maps_->serialize(ar);
  }

private:
  // The writer (rank 0) and the monitor (every process: its step figures are collective), from
  // the probes' particles and the totals of the state now (collective).
  void start_output() {
    std::vector<std::uint32_t> ids = probe_ids(sim_);
    const FrameTotals<D> totals = frame_totals(sim_, ids);
    on_rank_zero([&] {
      check_folder();
      if (!writer_) writer_.emplace(opt_.out_dir, sim_, ids);
    });
    if (!monitor_) monitor_.emplace(sim_, std::move(ids), totals);
    if (c_.maps.enabled && !maps_) maps_.emplace(c_, sim_);
  }

  // A row in every CSV (forces as time means since the previous row) and a frame. A kinetic
  // energy or momentum that is not finite (a speed whose square overflows) stops the run.
  // Nothing needs the whole state: the sums are combined, the particles stream to rank 0.
  void write_frame() {
    const FrameTotals<D> totals = frame_totals(sim_, monitor_->probe_ids());
    if (!std::isfinite(totals.kinetic_energy) || !totals.momentum.allFinite())
      throw SimulationError(fmt::format(
          "step {}, time {:.6g} s: the kinetic energy ({:.3g} J) or the momentum is not finite: "
          "a speed in the case is out of any physical range",
          sim_.steps(), sim_.time(), totals.kinetic_energy));
    on_rank_zero([&] { check_folder(); }); // every process stops before the frame if it went
    const std::vector<ContactNodeForce<D>> nodes = stepper_->contact_nodes();
    std::string error; // rank 0's, reported once every process has sent its particles
    if (c_.output.particles) {
      // The fixed bodies' part once, at the run folder's first frame, then the frame's own
      // (frame_parts). Each is collective: every process takes part in both, and rank 0's first
      // failure is reported after them.
      auto part = [&](const std::string& path, const ParticleOrder::Spans& spans) {
        try {
          RunWriter<D>::write_particles(path, sim_, stepper_->particle_order(), spans);
        } catch (const OutputError& e) {
          if (error.empty()) error = e.what();
        }
      };
      const auto parts = RunWriter<D>::frame_parts(sim_);
      if (!parts.fixed.empty() && !fixed_part_written_)
        part(root_ ? writer_->dir() + "/" + RunWriter<D>::fixed_part : std::string(), parts.fixed);
      fixed_part_written_ = true;
      part(root_ ? writer_->next_particle_frame() : std::string(), parts.moving);
    }
    on_rank_zero([&] {
      try {
        if (!error.empty()) throw OutputError(error);
        writer_->write_frame(sim_, totals, nodes);
      } catch (const OutputError&) {
        check_folder(); // a folder removed while the frame was written: say so
        throw;
      }
    });
    if (maps_) { // the peak fields so far and the deposit now
      const std::vector<double> deposit = maps_->deposit(sim_);
      const std::vector<std::vector<double>> each = maps_->body_deposits(sim_);
      on_rank_zero([&] { maps_->write(sim_, opt_.out_dir, deposit, each); });
    }
    sim_.reset_force_means();
    write_running_summary(&totals);
  }

  // The monitor's figures for summary.json, from `totals` or the state's (collective); none
  // before output starts.
  nlohmann::json results(const FrameTotals<D>* totals = nullptr) {
    if (!monitor_) return nlohmann::json::object();
    nlohmann::json j =
        totals ? monitor_->json(sim_, *totals, settle_ke_)
               : monitor_->json(sim_, frame_totals(sim_, monitor_->probe_ids()), settle_ke_);
    if (maps_) j["maps"] = maps_->figures(maps_->deposit(sim_)); // collective: the deposit
    return j;
  }

  // summary.json with status "running": from the first step on, updated at each frame and each
  // checkpoint, so that a run killed outright still says it started, how far it got and where
  // its newest checkpoint is. While settling (no frames yet) a temporary writer writes it.
  void write_running_summary(const FrameTotals<D>* totals = nullptr) {
    const double wall = std::chrono::duration<double>(Clock::now() - wall0_).count();
    const std::string message =
        last_checkpoint_.empty() ? std::string() : "newest checkpoint: " + last_checkpoint_;
    const nlohmann::json figures = results(totals);
    on_rank_zero([&] {
      check_folder();
      try {
        if (writer_)
          writer_->write_summary(sim_, "running", wall, stepping_, threads_, message, figures);
        else
          RunWriter<D>(opt_.out_dir, sim_, {})
              .write_summary(sim_, "running", wall, stepping_, threads_, message, figures);
      } catch (const OutputError&) {
        check_folder(); // removed while it was written: say so
        throw;
      }
    });
  }

  // One step; then the run stops (failed) if, at the step it took, reaching `until` would take
  // more than max_run_steps steps: a time step that collapsed (a speed or a scale out of any
  // physical range) would otherwise step forever.
  void timed_step(double dt_limit, double until) {
    const auto t0 = Clock::now();
    stepper_->step(dt_limit);
    stepping_ += std::chrono::duration<double>(Clock::now() - t0).count();
    const double dt = sim_.last_stable_dt(), remaining = (until - sim_.time()) / dt;
    if (!(remaining <= max_run_steps))
      throw SimulationError(fmt::format(
          "step {}, time {:.6g} s: the time step {:.3g} s would take {:.3g} more steps to reach "
          "{:.6g} s, more than the {:.0e} a run may take: a speed, a material constant or a time "
          "in the case is out of its physical range",
          sim_.steps(), sim_.time(), dt, remaining, until, max_run_steps));
  }

  // Settles (if the case does and the run is not past it), releases, then advances to the end;
  // both stages share one schedule of checkpoints and signals (after_step).
  void loop(RunResult& r) {
    const CheckpointSettings& ck = c_.checkpoint;
    checkpoint_time_ = next_checkpoint(ck);
    checkpoint_wall_ = Clock::now();
    if (sim_.settling()) {
      if (!settle(r)) return;
      release();
      checkpoint_time_ = next_checkpoint(ck);
    }
    if (!monitor_) { // (the monitor: every process has one once output started)
      start_output();
      write_frame();
    }
    advance(r);
  }

  // Damped steps up to initial_state.settle_time. False if a signal stopped the run.
  bool settle(RunResult& r) {
    const double T = c_.initial_state.settle_time;
    Progress progress(opt_.log, T, sim_.steps());
    while (T - sim_.time() > 1e-12 * T) {
      timed_step(T - sim_.time(), T);
      progress.update(sim_.time(), sim_.steps());
      if (!after_step(r)) return false;
    }
    progress.update(sim_.time(), sim_.steps(), true);
    return true;
  }

  // The end of settling: time restarts at 0, the run folder starts with its first frame.
  void release() {
    settle_ke_ = frame_totals(sim_, {}).kinetic_energy;
    if (opt_.log)
      *opt_.log << fmt::format("talus: settled for {} s, kinetic energy {:.4g} J; released\n",
                               c_.initial_state.settle_time, settle_ke_);
    stepper_->release();
    start_output();
    write_frame();
  }

  // Steps to simulation.end_time (or --max-steps), hitting each output time exactly.
  void advance(RunResult& r) {
    const double end = c_.simulation.end_time;
    const double every = c_.output.every > 0 ? c_.output.every : end;
    Progress progress(opt_.log, end, sim_.steps());
    while (end - sim_.time() > 1e-12 * end) {
      const double next_output = std::min(end, every * static_cast<double>(frame_));
      timed_step(next_output - sim_.time(), end);
      monitor_->update(monitor_->figures(sim_), sim_.time(), c_.results.stop_speed);
      if (maps_) maps_->accumulate(sim_, sim_.time());
      if (sim_.time() >= next_output - 1e-12 * end) {
        write_frame();
        ++frame_;
      }
      progress.update(sim_.time(), sim_.steps());
      if (!after_step(r)) return;
    }
    progress.update(sim_.time(), sim_.steps(), true);
  }

  // What follows every step, settling or not: an injected signal (the restart tests), a stop
  // signal (a checkpoint, then stop: false), a checkpoint when its simulated or wall time is due.
  bool after_step(RunResult& r) {
    if (sim_.steps() == opt_.inject_signal_step) std::raise(opt_.inject_signal);
    // Every process stops, and checkpoints, when any one is told to (mpirun passes signals on).
    const int stop = max_over_processes(static_cast<int>(stop_signal));
    if (stop) {
      save_checkpoint();
      r.status = "interrupted";
      r.signal = stop;
      r.message = fmt::format("stopped by signal {} at step {}, time {:.6g} s; checkpoint {}; "
                              "continue with: talus run --restart {}",
                              stop, sim_.steps(), sim_.time(), last_checkpoint_, opt_.out_dir);
      return false;
    }
    if (opt_.max_steps && sim_.steps() - first_step_ >= *opt_.max_steps &&
        c_.simulation.end_time - sim_.time() > 1e-12 * c_.simulation.end_time) {
      save_checkpoint();
      r.status = "stopped";
      r.message = fmt::format("stopped after {} steps (--max-steps){} at time {:.6g} s; "
                              "checkpoint {}; continue with: talus run --restart {}",
                              sim_.steps(), sim_.settling() ? " while settling" : "", sim_.time(),
                              last_checkpoint_, opt_.out_dir);
      return false;
    }
    const CheckpointSettings& ck = c_.checkpoint;
    // By wall time: every wall_minutes, the first after at most first_wall_minutes.
    const double minutes =
        checkpoints_written_ == 0 ? std::min(first_wall_minutes, ck.wall_minutes) : ck.wall_minutes;
    const bool wall_due = max_over_processes(static_cast<int>(
        ck.wall_minutes > 0 &&
        std::chrono::duration<double>(Clock::now() - checkpoint_wall_).count() >= 60.0 * minutes));
    if (sim_.time() >= checkpoint_time_ - 1e-12 * checkpoint_time_ || wall_due) {
      save_checkpoint();
      checkpoint_time_ = next_checkpoint(ck);
      checkpoint_wall_ = Clock::now();
      write_running_summary();
    }
    return true;
  }

  // The next multiple of checkpoint.every after the current time (inf: off).
  double next_checkpoint(const CheckpointSettings& ck) const {
    return ck.every > 0 ? ck.every * (std::floor(sim_.time() / ck.every + 1e-9) + 1.0) : inf;
  }

  // The whole state, written by rank 0 as it comes (on several processes the particles are
  // gathered chunk by chunk: SaveArchive::set_order), sized by a first pass that only counts. A
  // checkpoint restarts on any number of processes; no process holds the whole state.
  void save_checkpoint() {
    const auto t0 = Clock::now();
    const std::string path = checkpoint_path(opt_.out_dir, sim_.steps());
    auto save = [&](SaveArchive& ar) {
      stepper_->order_checkpoint(ar);
      int dim = D;
      std::string file = std::filesystem::absolute(c_.file).string(), text = c_.text;
      ar.io(dim), ar.io(file), ar.io(text);
      serialize(ar);
    };
    std::size_t bytes = 0;
    std::string error; // rank 0's, reported once every process has sent its particles
    auto write = [&] {
      std::optional<CheckpointFile> file;
      if (root_) {
        SaveArchive sizing(SaveArchive::Mode::count);
        save(sizing);
        bytes = sizing.size();
        try {
          check_folder();
          make_folder(opt_.out_dir + "/checkpoints"); // in the folder the run took
          file.emplace(path, bytes);
        } catch (const OutputError& e) {
          error = e.what();
        }
      }
      // Rank 0 writes (failed: drops what the others still send); the others send.
      SaveArchive ar(root_ ? SaveArchive::Mode::save : SaveArchive::Mode::send);
      ar.set_sink([&](const char* data, std::size_t n) {
        if (file) file->write(data, n);
      });
      save(ar);
      if (root_ && error.empty()) try {
          file->finish();
          prune_checkpoints(opt_.out_dir, c_.checkpoint.keep);
        } catch (const OutputError& e) {
          error = e.what();
        }
    };
    // A checkpoint is a good state, or none is written.
    stepper_->check_particles();
    stepper_->with_whole_tables(write);
    on_rank_zero([&] {
      if (!error.empty()) throw OutputError(error);
    });
    last_checkpoint_ = path;
    ++checkpoints_written_;
    if (opt_.log && !::isatty(STDOUT_FILENO)) // a terminal's progress line is redrawn: no line
      *opt_.log << fmt::format("talus: checkpoint {} ({:.1f} MB, {:.2f} s)\n", path,
                               static_cast<double>(bytes) / 1e6,
                               std::chrono::duration<double>(Clock::now() - t0).count());
  }

  // Rank 0: an OutputError if the run folder went away since the run took it.
  void check_folder() const {
    if (folder_) folder_->check_still_here();
  }

  void finish(RunResult& r, Clock::time_point wall0, int threads) {
    r.steps = sim_.steps();
    r.simulated_time = sim_.time();
    r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
    r.particle_updates_per_second =
        stepping_ > 0 ? static_cast<double>(r.particles) * static_cast<double>(r.steps) / stepping_
                      : 0.0;
    const nlohmann::json figures = results();
    on_rank_zero([&] {
      check_folder();
      if (!writer_) writer_.emplace(opt_.out_dir, sim_, std::vector<std::uint32_t>{});
      writer_->write_summary(sim_, r.status, r.wall_seconds, stepping_, threads, r.message,
                             figures);
    });
  }

  const Case& c_;
  const RunOptions& opt_;
  const RunFolder* folder_;
  std::unique_ptr<Stepper<D>> stepper_; // one process, or this one's slab of several
  Simulation<D>& sim_;                  // stepper_'s state
  bool root_;                           // rank 0: the process that writes the run folder
  std::optional<RunWriter<D>> writer_;
  std::optional<ResultsMonitor<D>> monitor_;
  std::optional<PeakMaps<D>> maps_; // [maps]: every process (its sums are collective)
  double settle_ke_ = 0.0;
  double stepping_ = 0.0; // wall seconds inside step(), settling included
  std::int64_t frame_ = 1;
  bool fixed_part_written_ = false; // a restart continues a folder that has it
  std::string last_checkpoint_;
  Clock::time_point wall0_{}; // the run's (this process's) start
  int threads_ = 1;
  int checkpoints_written_ = 0;         // by this process
  std::int64_t first_step_ = 0;         // the step this run (or restart) started from
  double checkpoint_time_ = inf;        // the next checkpoint by simulated time
  Clock::time_point checkpoint_wall_{}; // the last checkpoint (or the start) by wall time
};

template <int D>
RunResult run_dim(const Case& c, const RunOptions& opt, const std::optional<RunFolder>& folder,
                  LoadArchive* restore = nullptr, const std::string& restored_from = "") {
  Runner<D> runner(c, opt, folder ? &*folder : nullptr, restore != nullptr);
  return runner.run(restore, restored_from);
}

} // namespace

RunResult run_case(const Case& c, const RunOptions& opt) {
  // What talus check would say of the case, said again (from the particles the shapes give):
  // its warnings, and its refusals before anything is written.
  std::vector<std::size_t> particles;
  for (const BodySpec& b : c.bodies) {
    double n = 0.0; // a union of shapes: their sum, an upper bound
    for (const Geometry& g : b.geometry)
      n += estimate_particles(g, c.simulation.dimension, c.grid.cell_size, b.particles_per_cell);
    particles.push_back(static_cast<std::size_t>(n));
  }
  const RunPlan plan = plan_run(c, particles, opt.out_dir);
  if (!plan.refusal.empty()) throw CaseError(fmt::format("{}: {}", c.file, plan.refusal));
  if (opt.log)
    for (const std::string& w : plan.warnings)
      *opt.log << "talus: warning: " << w << "\n";
  std::optional<RunFolder> folder; // rank 0's, held to the end of the run
  on_rank_zero([&] {
    if (!plan.disk_full.empty() && !opt.force)
      throw RunFolderError(fmt::format("{}: {}", opt.out_dir, plan.disk_full));
    folder.emplace(prepare_run_inputs(c, opt.out_dir, opt.overwrite));
  });
  return c.simulation.dimension == 2 ? run_dim<2>(c, opt, folder) : run_dim<3>(c, opt, folder);
}

RunResult restart_run(const RunOptions& opt) {
  std::optional<RunFolder> folder; // rank 0's: no other run writes the folder meanwhile
  if (std::filesystem::is_directory(opt.out_dir))
    on_rank_zero([&] { folder.emplace(opt.out_dir, RunFolder::Use::restart); });
  const auto found = list_checkpoints(opt.out_dir);
  if (found.empty())
    throw CheckpointError(fmt::format("{}: no checkpoint to restart from (looked in "
                                      "{}/checkpoints)",
                                      opt.out_dir, opt.out_dir));
  std::string errors;
  for (const std::string& path : found) {
    // Rank 0 verifies the checksum; each process then reads only what it keeps (LoadArchive).
    std::optional<LoadArchive> ar;
    int dim = 0;
    std::string file, text;
    try {
      agreed<CheckpointError>([&] {
        ar.emplace(open_checkpoint(path, process_rank() == 0));
        ar->io(dim), ar->io(file), ar->io(text);
      });
    } catch (const CheckpointError& e) {
      if (opt.log) *opt.log << "talus: skipping " << e.what() << "\n";
      errors += std::string("\n  ") + e.what();
      continue;
    }
    // The case is the folder's own: its files are the copies in inputs/, wherever the run
    // folder and the original case now are.
    const std::string own_case = opt.out_dir + "/case.toml";
    if (std::ifstream in(own_case, std::ios::binary); in) {
      const std::string own((std::istreambuf_iterator<char>(in)), {});
      if (own != text)
        throw CheckpointError(fmt::format(
            "{}: the checkpoint is of another case than {} (a different case, or other --set "
            "values, ran into this folder): not restarted",
            path, own_case));
    }
    // Parsing checks the memory (this machine's processes' slabs, or the whole case), which
    // may fail on one machine alone.
    Case c;
    agreed<CaseError>([&] { c = parse_case_text(text, own_case, {}, this_machine_budget()); });
    c.file = file; // the original case file, for the summary
    if (dim != c.simulation.dimension) throw CheckpointError(path + ": dimension mismatch");
    return dim == 2 ? run_dim<2>(c, opt, folder, &*ar, path)
                    : run_dim<3>(c, opt, folder, &*ar, path);
  }
  throw CheckpointError(fmt::format("{}: no readable checkpoint:{}", opt.out_dir, errors));
}

} // namespace talus
