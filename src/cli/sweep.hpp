// `talus sweep CASE`: an ensemble of runs of one case (its [sweep] table), side by side, then a
// table of their figures, probability maps and, with [observed], a back-analysis ranking. This
// side validates the case and each varied key; tools/sweep.py runs and gathers the ensemble.
#pragma once

#include <string>
#include <vector>

namespace talus {

struct SweepOptions {
  std::string case_file;
  std::vector<std::string> overrides; // --set, for every run
  std::string out_dir;                // default runs/<case stem>_sweep
  int jobs = 0;                       // runs at once (default: the cores / threads)
  int threads = 1;                    // OpenMP threads per run
  std::string launcher;               // e.g. "mpirun -np 2": each run under it
  std::string source_dir;             // where tools/sweep.py is
  std::string self;                   // this program's path
};

// Validates and hands over to tools/sweep.py (does not return unless it cannot start it).
// Throws CaseError for a bad case or sweep.
int run_sweep(const SweepOptions& opt);

} // namespace talus
