// `talus bench`: throughput of fixed problems (particle-updates per second), phase times and
// memory, for 1 and 2 threads. Output off; only the stepping loop is timed.
#pragma once

#include <string>
#include <vector>

namespace talus {

struct BenchOptions {
  std::string source_dir = "."; // where bench/ and cases/ are
  std::vector<int> threads{1, 2};
  std::vector<std::string> problems{"column", "column_4x", "vaiont"};
  std::string json_out; // write the figures here too (optional)
};

// The problems `talus bench` knows, by name.
std::vector<std::string> bench_problem_names();

int run_bench(const BenchOptions& opt);

} // namespace talus
