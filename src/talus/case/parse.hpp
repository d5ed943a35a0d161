// Reading a case file: TOML -> Case, with every error naming the file, the key path and the line.
#pragma once

#include "talus/case/case.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus {

// A case-file error. what() reads "FILE:LINE: KEY: message" and suggests the nearest key.
class CaseError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// The memory a case may take on this machine, which the parser refuses to exceed body by body.
// On several processes each holds its slab of the particles and fields with its ghosts: the
// processes on this machine hold share(columns) of them (columns: the grid's cells along x) and
// each holds the whole grid. The default is one process with the whole machine;
// parallel/processes.hpp gives a run's (this_machine_budget).
struct MemoryBudget {
  double bytes = 0.0; // 0: this machine's memory (case/size.hpp machine_memory)
  int processes = 1, processes_here = 1;
  std::function<double(double columns)> share; // empty: 1 (everything on this process)
};

// Parses the case at path, applying "key.path=value" overrides first (--set). Throws CaseError.
Case parse_case_file(const std::string& path, const std::vector<std::string>& overrides = {},
                     const MemoryBudget& budget = {});

// Parses case text as if read from `path` (relative files resolve beside it). Throws CaseError.
Case parse_case_text(const std::string& text, const std::string& path,
                     const std::vector<std::string>& overrides = {},
                     const MemoryBudget& budget = {});

// Reads a polygon CSV (columns x,y or x,z; an optional header line). Throws CaseError.
std::vector<std::array<double, 2>> read_polygon_csv(const std::string& path);

// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b);

} // namespace talus
