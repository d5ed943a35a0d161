// Reading a body's shape from the case file: a box, a disk or sphere, or a polygon given inline
// or as a CSV file beside the case (checked: enough vertices, finite, not crossing itself).
#pragma once

#include "talus/case/input_files.hpp"
#include "talus/case/toml_reader.hpp"

#include <filesystem>

namespace talus::case_reading {

// The `box`, `disk`/`sphere` or `polygon` key of a [[body]] (exactly one of them).
Geometry read_geometry(TableReader& r, int dim, InputFiles& files);

} // namespace talus::case_reading
