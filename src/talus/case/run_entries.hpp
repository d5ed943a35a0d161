// The [[run]] entries of a run folder's case.toml: what talus adds to a case as the user wrote
// it when it copies it into a run folder (the run's --set overrides and the renames of the files
// it copied into inputs/), taken out when the case is read back.
#pragma once

#include "talus/case/input_files.hpp"
#include "talus/case/toml_reader.hpp"

#include <string>
#include <toml++/toml.h>
#include <vector>

namespace talus::case_reading {

// Takes the [[run]] entries out of the document: their renames go to `files`, in order; returns
// their overrides in order, each with its line.
std::vector<Override> take_run_entries(toml::table& doc, const Where& where, InputFiles& files);

// The case text a run folder keeps: the text as written, then a [[run]] entry with this run's
// overrides and the renames its copy needs to read inputs/ (none if there is nothing to add).
std::string text_as_run(std::string text, const std::vector<std::string>& overrides,
                        const InputFiles& files);

} // namespace talus::case_reading
