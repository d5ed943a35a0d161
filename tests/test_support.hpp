// Helpers shared by the tests: cases from inline TOML, and a temporary folder.
#pragma once

#include "talus/case/parse.hpp"

#include <filesystem>
#include <string>

namespace talus::test {

inline Case case_from(const std::string& toml, const std::vector<std::string>& overrides = {}) {
  return parse_case_text(toml, std::string(TALUS_SOURCE_DIR) + "/tests/inline.toml", overrides);
}

inline std::string temp_dir(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / ("talus_test_" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

} // namespace talus::test
