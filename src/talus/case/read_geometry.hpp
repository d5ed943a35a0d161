// Reading a body's shape from the case file: a box, a disk or sphere, a polygon given inline or
// as a CSV file beside the case (checked: enough vertices, finite, not crossing itself), extruded
// in 3D, or a terrain body between two surfaces (rasters read by GDAL, or constants).
#pragma once

#include "talus/case/input_files.hpp"
#include "talus/case/toml_reader.hpp"

#include <filesystem>

namespace talus::case_reading {

// The `box`, `disk`/`sphere`, `polygon` (with `extrude` in 3D) or `terrain` key of a [[body]]
// (exactly one of them); `origin` is subtracted from what terrain files hold.
Geometry read_geometry(TableReader& r, int dim, InputFiles& files, const Vec3a& origin);

} // namespace talus::case_reading
