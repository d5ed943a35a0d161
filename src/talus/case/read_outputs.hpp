// Reading the tables of a case file that say what a run reports: [results], [[probe]], [[gauge]],
// [[run_up]], [output], [checkpoint], [maps], [[check]] (talus verify) and [verify].
#pragma once

#include "talus/case/case.hpp"
#include "talus/case/toml_reader.hpp"

namespace talus::case_reading {

void read_results(TableReader& root, Case& c);
void read_probes(TableReader& root, Case& c);
void read_gauges(TableReader& root, Case& c);
void read_run_ups(TableReader& root, Case& c);
void read_output(TableReader& root, Case& c);
void read_checkpoint(TableReader& root, Case& c);
void read_maps(TableReader& root, Case& c);
void read_checks(TableReader& root, Case& c);
void read_verify(TableReader& root, Case& c);

} // namespace talus::case_reading
