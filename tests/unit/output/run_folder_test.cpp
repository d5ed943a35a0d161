// RunFolder (output/run_folder.hpp): a folder is Talus's only by its marker, one run holds it at
// a time, --overwrite removes nothing of a folder holding files Talus did not write, and a folder
// removed under its run is noticed.
#include "talus/output/run_folder.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

using namespace talus;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// The message of the RunFolderError that taking `dir` for `use` throws; "" if it is taken.
std::string refusal(const std::string& dir, RunFolder::Use use) {
  try {
    RunFolder f(dir, use);
  } catch (const RunFolderError& e) {
    return e.what();
  }
  return "";
}

} // namespace

// A fresh folder gets the marker; while its run holds it a second run or a restart is refused;
// once the run lets go, a restart takes it and a fresh run does not (it holds an earlier run).
// A refusal lets the lock go (a constructor that throws runs no destructor).
TEST(RunFolder, MarkerAndLock) {
  const std::string dir = test::temp_dir("run_folder_lock") + "/run";
  {
    RunFolder first(dir, RunFolder::Use::fresh);
    EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / run_folder_marker));
    EXPECT_NE(refusal(dir, RunFolder::Use::restart).find("in use"), std::string::npos);
    EXPECT_NE(refusal(dir, RunFolder::Use::overwrite).find("in use"), std::string::npos);
  }
  EXPECT_EQ(refusal(dir, RunFolder::Use::restart), "");
  EXPECT_EQ(refusal(dir, RunFolder::Use::fresh), ""); // a marker alone: a run that wrote nothing
  write(fs::path(dir) / "summary.json", "{}\n");
  EXPECT_NE(refusal(dir, RunFolder::Use::fresh).find("holds an earlier run"), std::string::npos);
  EXPECT_NE(refusal(dir, RunFolder::Use::fresh).find("holds an earlier run"), std::string::npos);
  EXPECT_EQ(refusal(dir, RunFolder::Use::restart), ""); // the refusals let the lock go
}

// A folder without the marker is not a run folder, whatever it holds: --overwrite and --restart
// refuse it, every file stays and no marker is planted.
TEST(RunFolder, AFolderWithoutTheMarkerIsNeverTaken) {
  const fs::path dir = test::temp_dir("run_folder_project");
  write(dir / "case.toml", "[simulation]\n");
  write(dir / "summary.json", "{\"tool\": \"not talus\"}\n");
  write(dir / "notes.txt", "precious\n");
  for (const auto use : {RunFolder::Use::overwrite, RunFolder::Use::restart}) {
    const std::string refused = refusal(dir.string(), use);
    EXPECT_NE(refused.find("not a talus run folder"), std::string::npos) << refused;
    EXPECT_TRUE(fs::exists(dir / "notes.txt"));
    EXPECT_TRUE(fs::exists(dir / "case.toml"));
    EXPECT_FALSE(fs::exists(dir / run_folder_marker));
  }
}

// What Talus writes (its files, numbered frames, temporaries, inputs, checkpoints) is its own;
// anything else is foreign, and --overwrite then refuses, naming it, and removes nothing.
TEST(RunFolder, OverwriteRemovesOnlyTalusFiles) {
  const std::string dir = test::temp_dir("run_folder_overwrite") + "/run";
  { RunFolder f(dir, RunFolder::Use::fresh); }
  const fs::path d(dir);
  for (const char* name : {"case.toml", "summary.json", "energy.csv", "particles.pvd",
                           "particles_000012.vtu", "summary.json.tmp", "energy.csv.tmp.3",
                           "inputs/wedge.csv", "checkpoints/step_0000000100.ckpt"})
    write(d / name, "x");
  // The input copies are those the folder's case.toml names in its [[run]] files table.
  write(d / "case.toml", "[[run]]\n[run.files]\n'wedge.csv' = 'inputs/wedge.csv'\n");
  EXPECT_TRUE(foreign_entries(dir).empty());
  write(d / "inputs/mine.csv", "a user's file among the copies\n");
  EXPECT_EQ(foreign_entries(dir), std::vector<std::string>{"inputs/mine.csv"});
  fs::remove(d / "inputs/mine.csv");
  write(d / "notes.txt", "precious\n");
  write(d / "particles_final.vtu", "not a talus frame name\n");
  const auto foreign = foreign_entries(dir);
  EXPECT_EQ(foreign.size(), 2u);
  const std::string refused = refusal(dir, RunFolder::Use::overwrite);
  EXPECT_NE(refused.find("notes.txt"), std::string::npos) << refused;
  EXPECT_TRUE(fs::exists(d / "summary.json")); // nothing removed
  fs::remove(d / "notes.txt");
  fs::remove(d / "particles_final.vtu");
  {
    RunFolder f(dir, RunFolder::Use::overwrite);
    EXPECT_FALSE(fs::exists(d / "summary.json"));
    EXPECT_FALSE(fs::exists(d / "checkpoints/step_0000000100.ckpt"));
    EXPECT_TRUE(fs::exists(d / run_folder_marker));
  }
}

// The run notices its folder removed, or replaced by another of the same name.
TEST(RunFolder, AFolderRemovedUnderItsRunIsNoticed) {
  const std::string dir = test::temp_dir("run_folder_removed") + "/run";
  RunFolder f(dir, RunFolder::Use::fresh);
  EXPECT_NO_THROW(f.check_still_here());
  fs::remove_all(dir);
  EXPECT_THROW(f.check_still_here(), OutputError);
  fs::create_directories(dir);
  EXPECT_THROW(f.check_still_here(), OutputError);
}
