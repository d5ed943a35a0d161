// Reading the tables of a case file that `talus sweep` uses and `talus run` ignores: [sweep]
// (the ensemble: its parameters, design and probability thresholds) and [observed] (what a
// back-analysis scores each run against).
#pragma once

#include "talus/case/case.hpp"
#include "talus/case/toml_reader.hpp"

namespace talus::case_reading {

void read_sweep(TableReader& root, Case& c);
void read_observed(TableReader& root, Case& c, InputFiles& files);

} // namespace talus::case_reading
