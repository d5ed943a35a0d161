// Fuzz target over everything a user's input reaches before the first step: the TOML case parser,
// the polygon CSV loader, the geometry filling, interface marking, the K0 stress, and one step of
// the solver on small cases. Input: a case file, optionally followed by a line "#%csv" and the
// content of "poly.csv" beside it (so a case can say polygon = "poly.csv").
//
// Any exception other than CaseError (bad input, reported to the user) or SimulationError (a run
// that went bad, reported with its particle) is a bug, as is any sanitizer report.
#include "talus/case/parse.hpp"
#include "talus/case/size.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

const std::string& scratch_dir() {
  static const std::string dir = [] {
    std::string d = "/tmp/talus-fuzz-" + std::to_string(::getpid());
    std::system(("mkdir -p " + d).c_str());
    return d;
  }();
  return dir;
}

template <int D>
void simulate(const talus::Case& c) {
  talus::Simulation<D> sim(c);
  if (sim.particles().size() <= 2000) sim.step();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string input(reinterpret_cast<const char*>(data), size);
  std::string csv;
  if (const auto cut = input.find("\n#%csv\n"); cut != std::string::npos) {
    csv = input.substr(cut + 7);
    input.resize(cut);
  }
  const std::string dir = scratch_dir();
  {
    std::ofstream out(dir + "/poly.csv", std::ios::binary | std::ios::trunc);
    out << csv;
  }
  try {
    const talus::Case c = talus::parse_case_text(input, dir + "/case.toml", {});
    // Keep each input fast and within the fuzzer's memory limit; the parser itself already
    // refused anything larger than the machine.
    const int dim = c.simulation.dimension;
    double particles = 0.0, fields = 0.0;
    for (const talus::BodySpec& b : c.bodies)
      particles +=
          talus::estimate_particles(b.geometry[0], dim, c.grid.cell_size, b.particles_per_cell);
    fields = talus::grid_nodes(c.grid, dim) * static_cast<double>(c.bodies.size());
    if (particles > 2e4 || fields > 2e6) return 0;
    if (dim == 2)
      simulate<2>(c);
    else
      simulate<3>(c);
  } catch (const talus::CaseError&) {
  } catch (const talus::SimulationError&) {
  }
  return 0;
}
