// Helpers shared by the tests: cases from inline TOML, settling, stepping to a time, and a
// temporary folder.
#pragma once

#include "talus/case/parse.hpp"

#include <filesystem>
#include <string>

namespace talus::test {

inline Case case_from(const std::string& toml, const std::vector<std::string>& overrides = {}) {
  return parse_case_text(toml, std::string(TALUS_SOURCE_DIR) + "/tests/inline.toml", overrides);
}

// The case's settling phase (initial_state.settle_time; nothing if 0), then the release: time 0
// and displacements from there, as `talus run` does.
template <class Sim>
void settle(Sim& sim, const Case& c) {
  const double T = c.initial_state.settle_time;
  if (T <= 0.0) return;
  sim.set_settling(true);
  while (sim.time() < T - 1e-12)
    sim.step(T - sim.time());
  sim.release();
}

// Steps to time t (the last step shortened to land on it).
template <class Sim>
void run_to(Sim& sim, double t) {
  while (sim.time() < t - 1e-12)
    sim.step(t - sim.time());
}

inline std::string temp_dir(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / ("talus_test_" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

} // namespace talus::test
