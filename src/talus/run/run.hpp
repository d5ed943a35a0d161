// Running a case: the time loop, output at its interval, progress, and the summary.
#pragma once

#include "talus/case/case.hpp"

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

namespace talus {

struct RunOptions {
  std::string out_dir;
  int threads = 0;                       // 0: by the problem's size (set_threads)
  std::optional<std::int64_t> max_steps; // stop after this many steps (of this start or restart)
  bool overwrite = false;                // a fresh run may empty an earlier run's folder
  bool force = false;                    // run even if the output cannot fit on the disk
  std::ostream* log = nullptr;           // progress and messages; null: silent
  // Fault injection for the restart tests: raise this signal right after this step.
  int inject_signal = 0;
  std::int64_t inject_signal_step = -1;
};

struct RunResult {
  std::string status;  // completed, stopped (max_steps), failed, interrupted
  int signal = 0;      // the signal that interrupted the run
  std::string message; // why it failed
  std::int64_t steps = 0;
  double simulated_time = 0.0;
  double wall_seconds = 0.0;
  double particle_updates_per_second = 0.0;
  std::size_t particles = 0;
};

// Runs the case into opt.out_dir, which must be absent or empty (or, with opt.overwrite, an earlier
// run's folder, emptied first: prepare_run_folder). Errors in the physics end the run with status
// "failed" and a summary naming the step, time and particle; output errors throw OutputError.
RunResult run_case(const Case& c, const RunOptions& opt);

// Continues the run in opt.out_dir from its newest readable checkpoint (older ones if the newest
// is damaged), into the same folder. Throws CheckpointError if there is none, or if the checkpoint
// is of another case than the folder's case.toml.
RunResult restart_run(const RunOptions& opt);

} // namespace talus
