// A run folder held by the one run that writes it (docs/reliability.md, "Run folders").
//
// Talus proves a folder is its own by a marker, `.talus-run`, that only it writes: a folder
// without one is never emptied, whatever it holds. The run that writes a folder holds an
// exclusive lock on its marker (flock: it dies with the process, so a kill -9 leaves no stale
// lock), so that a second run or a restart into the folder is refused, naming the first. And
// the run notices if its folder is removed or replaced under it, instead of writing a partial
// folder and calling it done.
#pragma once

#include "talus/output/files.hpp"

#include <string>
#include <sys/types.h>
#include <vector>

namespace talus {

inline constexpr const char* run_folder_marker = ".talus-run";

class RunFolder {
public:
  enum class Use {
    fresh,     // absent or empty
    overwrite, // or an earlier run's folder, whose files talus wrote are removed first
    restart,   // an earlier run's folder, continued
  };
  // Takes `dir` for this run (creating it if absent). Throws RunFolderError if the folder is in
  // use by another talus process, is not a run folder (for overwrite and restart), holds an
  // earlier run (fresh), or holds files talus did not write (overwrite: nothing is removed).
  RunFolder(std::string dir, Use use);
  RunFolder(RunFolder&& other) noexcept;
  RunFolder& operator=(RunFolder&&) = delete;
  RunFolder(const RunFolder&) = delete;
  ~RunFolder();

  const std::string& dir() const { return dir_; }
  // Throws OutputError if the folder was removed, or replaced by another, since it was taken.
  void check_still_here() const;

private:
  void take(Use use);            // the constructor's checks, refusals and emptying
  void take_marker(bool create); // opens (or creates) the marker and locks it
  std::string dir_;
  int marker_fd_ = -1;
  int dir_fd_ = -1; // the folder held open: files.hpp's anchor_folder
  dev_t dev_ = 0;
  ino_t dir_ino_ = 0, marker_ino_ = 0;
};

// The entries of a run folder (names relative to it) that talus did not write: what
// --overwrite refuses to remove. Empty for a folder of talus's files alone.
std::vector<std::string> foreign_entries(const std::string& dir);

} // namespace talus
