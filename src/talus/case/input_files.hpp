// The files a case reads (polygon CSVs, rasters, footprints), resolved against the case file and
// recorded so that a run folder keeps a copy of each under inputs/ and its case.toml reads the
// copies.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace talus {

// One file a case read: where it was read from, and its copy's path in a run folder.
struct InputFile {
  std::string source; // the path read (the case file's folder joined with the name written)
  std::string copy;   // "inputs/NAME", relative to the run folder
};

namespace case_reading {

// The largest input a case may read: a polygon CSV, and a raster or vector file.
inline constexpr std::uintmax_t max_polygon_csv_bytes = std::uintmax_t{256} << 20;
inline constexpr std::uintmax_t max_input_bytes = std::uintmax_t{16} << 30;

// Throws CaseError unless `path` is a regular file (a link to one counts) of at most max_bytes
// that a run folder can copy whole: no device, FIFO or folder (a read that never ends), and no
// GDAL virtual raster (VRT), whose sources lie elsewhere or on the network.
void check_input_file(const std::string& path, std::uintmax_t max_bytes);

// Resolves the file names a case writes. Each [[run]] entry's `files` table renames a file
// (written name -> name read), in order; the result is relative to the case file's folder.
class InputFiles {
public:
  explicit InputFiles(std::filesystem::path base_dir) : base_dir_(std::move(base_dir)) {}

  // Adds a [[run]] entry's renames (applied after the earlier entries').
  void add_renames(std::map<std::string, std::string> renames) {
    renames_.push_back(std::move(renames));
  }

  // The path to read for a name the case writes; records the file and names its copy.
  std::string resolve(const std::string& written);

  // Records the files GDAL reads beside a raster or vector file already resolved (`read`): its
  // coordinate system (.prj, .aux.xml), a shapefile's index and attributes (.shx, .dbf, .cpg),
  // a world file (.tfw), those that exist, each copied under its file's copy name.
  void add_sidecars(const std::string& read);

  const std::vector<InputFile>& files() const { return files_; }

  // The renames a copy of the case in a run folder needs to read its copies in inputs/: name as
  // resolved by the earlier renames -> copy, for each file whose copy has another name.
  std::map<std::string, std::string> renames_to_copies() const;

private:
  std::filesystem::path base_dir_;
  std::vector<std::map<std::string, std::string>> renames_;
  std::vector<InputFile> files_;
  std::vector<std::pair<std::string, std::size_t>> named_; // name after the renames, file
};

} // namespace case_reading

} // namespace talus
