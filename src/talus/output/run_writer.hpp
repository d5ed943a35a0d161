// The run folder: case.toml, summary.json, energy.csv, bodies.csv, probes.csv and the ParaView
// series. Every file is rewritten atomically, so a reader (or a crash) never sees half a file.
#pragma once

#include "talus/output/frame_totals.hpp"
#include "talus/output/run_folder.hpp"
#include "talus/output/vtu.hpp"
#include "talus/solver/simulation.hpp"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace talus {

// The run folder `dir` taken for a fresh run (RunFolder: held until the returned object goes),
// with the case's input files copied into its inputs/ (with their permissions), read before the
// folder is emptied (the case may be an earlier run's own case.toml, run again into its folder
// with --overwrite).
RunFolder prepare_run_inputs(const Case& c, const std::string& dir, bool overwrite);

template <int D>
class RunWriter {
public:
  // A writer that writes nothing: reads a checkpoint's tables on a process that does not write.
  RunWriter() = default;
  // The run folder `dir` of sim's case; probes.csv follows the particles of `probe_ids`.
  RunWriter(std::string dir, const Simulation<D>& sim, std::vector<std::uint32_t> probe_ids);

  // A frame's particles (output.particles), particles_NNNNNN.vtu, are written first, by all
  // processes together: write_particles() to next_particle_frame() (an empty path on the
  // processes that do not write). Then write_frame() appends a row to the CSVs, lists the frame
  // in particles.pvd and, if enabled, writes contact_nodes_NNNNNN.vtu and contact_nodes.pvd
  // (the last step's nodal contact forces: `contact_nodes`, every process's).
  //
  // A case with fixed bodies (rigid, at rest: nothing a frame shows of them changes) beside
  // others writes the fixed bodies' particles once, into `fixed_part` at its first frame, and the
  // others at every frame; particles.pvd lists both parts at each time. Otherwise a frame is one
  // part, every particle.
  struct FrameParts {
    ParticleOrder::Spans moving, fixed; // fixed: empty if the frames are not split
  };
  static FrameParts frame_parts(const Simulation<D>& sim);
  static constexpr const char* fixed_part = "particles_fixed.vtu";
  std::string next_particle_frame() const;
  static void write_particles(const std::string& path, const Simulation<D>& sim,
                              ParticleOrder& order, const ParticleOrder::Spans& spans);
  void write_frame(const Simulation<D>& sim, const FrameTotals<D>& totals,
                   const std::vector<ContactNodeForce<D>>& contact_nodes);
  // summary.json with the run's status ("completed", "failed", "interrupted").
  void write_summary(const Simulation<D>& sim, const std::string& status, double wall_seconds,
                     double stepping_seconds, int threads, const std::string& message,
                     const nlohmann::json& results = nlohmann::json::object());

  // Rewrites the CSVs and particles.pvd from the tables held in memory (after a restart, this
  // drops any row a killed run wrote after its last checkpoint).
  void write_tables(const Simulation<D>& sim) const;

  // The frames the tables list (particles and contact nodes) that are not in the run folder: a
  // restart refuses to continue a folder whose earlier frames are gone.
  std::vector<std::string> missing_frames() const;

  // The tables and frame list, for checkpoints.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.io(probe_ids_), ar.io(energy_), ar.io(bodies_), ar.io(probes_), ar.io(contacts_);
    ar.io(waves_);
    ar.io(interfaces_), ar.io(frames_), ar.io(contact_frames_);
  }

  const std::string& dir() const { return dir_; }

private:
  void write_rows(const Simulation<D>& sim, const FrameTotals<D>& totals); // a row in each CSV

  std::string dir_;
  bool split_ = false; // the frames are in two parts (frame_parts)
  std::vector<std::uint32_t> probe_ids_;
  std::string energy_, bodies_, probes_, contacts_, interfaces_, waves_;
  std::vector<std::pair<double, std::string>> frames_;
  std::vector<std::pair<double, std::string>> contact_frames_; // contact_nodes_NNNNNN.vtu
};

} // namespace talus
