// Reading the [[material]] entries of a case file.
#pragma once

#include "talus/case/case.hpp"
#include "talus/case/toml_reader.hpp"

namespace talus::case_reading {

void read_materials(TableReader& root, Case& c);

} // namespace talus::case_reading
