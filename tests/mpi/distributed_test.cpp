// Runs under mpirun on any number of processes: every golden case (verification/golden_cases.hpp:
// one and two deformable bodies, contact, cohesive interfaces across the cuts, a fixed body's
// held field, orphans, the wet Vaiont's pore pool, a 3D case) stepped by Distributed gives the
// committed hash of one process, with the slabs rebalanced inside the run; and a run on fewer
// processes, checkpointed mid-way, continues on all of them to the same hash.
#include "talus/output/simulation_archive.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/distributed.hpp"
#include "talus/parallel/processes.hpp"
#include "talus/parallel/seed_share.hpp"
#include "verification/golden_cases.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace talus {
namespace golden {
void PrintTo(const GoldenCase& g, std::ostream* os) {
  *os << g.name;
}
} // namespace golden

namespace {

using golden::GoldenCase;

// Slabs start with equal numbers of columns, which the rebalance every 40 steps corrects to
// equal numbers of particles: the slabs move inside every run.
constexpr std::int64_t rebalance_every = 40;
template <int D>
constexpr auto start = Distributed<D>::Start::even_columns;

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int world_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

struct Outcome {
  std::uint64_t hash = 0;
  std::int64_t rebalances = 0; // on world's rank 0
  std::size_t fewest_own = 0;  // the fewest particles any process owned at the end
  bool boxes_in_reach = true;  // every process's field boxes inside its slab's reach
  double box_share = 1.0;      // the most nodes a process stores over the frames' nodes
};

// Whether each body field this process stores stays within its slab, the ghosts' columns and the
// shape functions' reach beyond them (one column of slack for a step's motion), and the most
// field nodes any process stores as a share of the bodies' whole frames.
template <int D>
void check_boxes(const Distributed<D>& dist, const Simulation<D>& sim, Outcome& out) {
  const std::int64_t lo = dist.bounds()[dist.rank()] - dist.ghost_width() - 2;
  const std::int64_t hi = dist.bounds()[dist.rank() + 1] + dist.ghost_width() + 4;
  int inside = 1;
  double stored = 0.0, framed = 0.0;
  for (const BodyField<D>& N : sim.fields()) {
    stored += static_cast<double>(N.box.num_nodes());
    framed += static_cast<double>(N.frame.num_nodes());
    if (N.box.num_nodes() <= 1) continue; // the body has no particles here
    inside &= N.offset[0] >= lo && N.offset[0] + N.box.nodes[0] <= hi;
  }
  double share = stored / framed;
  MPI_Allreduce(MPI_IN_PLACE, &inside, 1, MPI_INT, MPI_MIN, dist.comm());
  MPI_Allreduce(MPI_IN_PLACE, &share, 1, MPI_DOUBLE, MPI_MAX, dist.comm());
  out.boxes_in_reach = inside != 0;
  out.box_share = share;
}

// Steps [from, to) of the golden schedule (settling, release, then the run).
template <int D>
void advance(Distributed<D>& dist, const GoldenCase& g, int from, int to) {
  for (int s = from; s < to; ++s) {
    if (s == g.settle_steps && g.settle_steps > 0) dist.release();
    dist.step(1.0);
  }
}

// The golden hash of the whole state, formed on rank 0 and sent to every process.
template <int D>
Outcome finish(Distributed<D>& dist) {
  Outcome out;
  dist.with_whole_state([&](Simulation<D>& sim) { out.hash = golden::state_hash(sim); });
  MPI_Bcast(&out.hash, 1, MPI_UINT64_T, 0, dist.comm());
  out.rebalances = dist.rebalances();
  unsigned long own = dist.own_particles(), fewest = 0;
  MPI_Allreduce(&own, &fewest, 1, MPI_UNSIGNED_LONG, MPI_MIN, dist.comm());
  out.fewest_own = fewest;
  return out;
}

// The case seeded on every process's slab; or, with `split` > 0, its first `split` steps on the
// first max(size - 1, 1) processes from the whole state, a checkpoint of the whole state (bytes,
// as a checkpoint file holds them), and the rest on every process, each reading its slab of that
// checkpoint.
template <int D>
Outcome run_distributed(const Case& c, const GoldenCase& g, int split) {
  const int total = g.settle_steps + g.steps;
  if (split <= 0) { // seeded on each slab alone, as `talus run` starts a new case
    SharedSeeding<D> seeding = seed_share<D>(c, MPI_COMM_WORLD, start<D>);
    Simulation<D> sim(c, std::move(seeding.seeded));
    if (g.settle_steps > 0) sim.set_settling(true);
    Distributed<D> dist(sim, MPI_COMM_WORLD, std::move(seeding.bounds),
                        std::move(seeding.body_begin), rebalance_every);
    advance(dist, g, 0, total);
    Outcome out;
    check_boxes(dist, sim, out);
    const Outcome whole = finish(dist);
    out.hash = whole.hash, out.rebalances = whole.rebalances, out.fewest_own = whole.fewest_own;
    return out;
  }
  const int first_size = std::max(world_size() - 1, 1);
  MPI_Comm first = MPI_COMM_NULL;
  MPI_Comm_split(MPI_COMM_WORLD, world_rank() < first_size ? 0 : MPI_UNDEFINED, world_rank(),
                 &first);
  std::string bytes;
  if (first != MPI_COMM_NULL) {
    Simulation<D> sim(c);
    if (g.settle_steps > 0) sim.set_settling(true);
    Distributed<D> dist(sim, first, rebalance_every, start<D>);
    advance(dist, g, 0, split);
    dist.with_whole_state([&](Simulation<D>& whole) {
      SaveArchive ar;
      serialize_state(ar, whole, "memory");
      bytes = ar.bytes();
    });
    MPI_Comm_free(&first);
  }
  unsigned long n = bytes.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG, 0, MPI_COMM_WORLD);
  bytes.resize(n);
  MPI_Bcast(bytes.data(), static_cast<int>(n), MPI_BYTE, 0, MPI_COMM_WORLD);
  // Restored as `talus run --restart` restores on several processes: each process seeds its
  // slab of the case, then reads its slab of the checkpoint's particles alone.
  SharedSeeding<D> seeding = seed_share<D>(c, MPI_COMM_WORLD, start<D>);
  Simulation<D> sim(c, std::move(seeding.seeded));
  LoadArchive in(bytes, "memory");
  RestoredShare share;
  choose_slab<D>(in, sim.grid(), ghost_columns(sim.setup().normal_smoothing, sim.setup().xpic),
                 MPI_COMM_WORLD, share, start<D>);
  serialize_state(in, sim, "memory");
  EXPECT_TRUE(in.done());
  Distributed<D> dist(sim, MPI_COMM_WORLD, std::move(share.bounds), std::move(seeding.body_begin),
                      rebalance_every, std::move(share.rows));
  advance(dist, g, split, total);
  return finish(dist);
}

Outcome run_golden_distributed(const GoldenCase& g, int split) {
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g.file, g.overrides);
  return c.simulation.dimension == 2 ? run_distributed<2>(c, g, split)
                                     : run_distributed<3>(c, g, split);
}

class OnProcesses : public ::testing::TestWithParam<GoldenCase> {};

// The same hash as one process, on this many processes, and across a checkpoint written on one
// process fewer.
TEST_P(OnProcesses, HashOfOneProcessAndAcrossACheckpointFromFewerProcesses) {
  const GoldenCase& g = GetParam();
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g.file, g.overrides);
  if (std::any_of(c.contact.pairs.begin(), c.contact.pairs.end(),
                  [](const ContactPair& p) { return p.surface; }))
    GTEST_SKIP() << g.name << ": the surface law runs on one process (Distributed refuses it)";
  const Outcome whole = run_golden_distributed(g, 0);
  EXPECT_EQ(whole.hash, g.hash) << g.name
                                << fmt::format(": hash 0x{:016x}ull on {} processes", whole.hash,
                                               world_size());
  const Outcome restarted = run_golden_distributed(g, (g.settle_steps + g.steps) / 2 + 1);
  EXPECT_EQ(restarted.hash, g.hash)
      << g.name
      << fmt::format(": continued on {} processes from a checkpoint of {}", world_size(),
                     std::max(world_size() - 1, 1));
  if (world_rank() == 0)
    fmt::print("  {}: {} processes, {} rebalances, fewest own particles {}, field "
               "nodes {:.0f} % of the frames'\n",
               g.name, world_size(), whole.rebalances, whole.fewest_own, 100 * whole.box_share);
  // Each process stores only the part of a body's field its own and ghost particles reach.
  EXPECT_TRUE(whole.boxes_in_reach) << g.name << ": a field box reaches past the slab's ghosts";
  // The column stands in the grid's corner: the even first slabs leave processes without
  // particles, and the rebalance moves the slabs onto it.
  if (world_size() > 1 && std::string(g.name).starts_with("column_")) {
    EXPECT_GT(whole.rebalances, 0) << "no rebalance happened inside the run";
  }
}

// Each process's own particles, seeded on its slab alone, are bit for bit the particles of the
// same ids that one process seeds (K0 stresses, interface marks, pore offsets' order), every
// particle is some process's once, and the masses, warnings and body ranges are one process's.
template <int D>
void check_seeding(const Case& c, const std::string& name) {
  const Seeded<D> whole = seed_case<D>(c);
  SharedSeeding<D> shared = seed_share<D>(c, MPI_COMM_WORLD);
  Particles<D>& mine = shared.seeded.particles;
  Particles<D> all = whole.particles;
  long mismatched = 0, count = static_cast<long>(mine.size());
  Particles<D>::for_each_array_pair(mine, all, [&](auto& m, auto& a) {
    using T = typename std::decay_t<decltype(m)>::value_type;
    for (std::size_t p = 0; p < mine.size(); ++p)
      mismatched += std::memcmp(&m[p], &a[mine.id[p]], sizeof(T)) != 0;
  });
  MPI_Allreduce(MPI_IN_PLACE, &mismatched, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(mismatched, 0) << name << ": particle values differ from one process's";
  EXPECT_EQ(count, static_cast<long>(whole.total)) << name << ": particles owned once each";
  EXPECT_EQ(shared.seeded.total, whole.total);
  EXPECT_EQ(shared.body_begin, whole.particles.body_begin) << name;
  EXPECT_EQ(shared.seeded.pore_particles, whole.pore_particles) << name;
  EXPECT_EQ(shared.seeded.warnings, whole.warnings) << name;
  ASSERT_EQ(shared.seeded.body_mass.size(), whole.body_mass.size());
  for (std::size_t b = 0; b < whole.body_mass.size(); ++b)
    EXPECT_EQ(std::memcmp(&shared.seeded.body_mass[b], &whole.body_mass[b], sizeof(double)), 0)
        << name << ": body " << b << " mass";
  if (world_size() > 1) {
    EXPECT_LT(mine.size(), whole.total) << name << ": one process took all";
  }
}

TEST_P(OnProcesses, EachSlabSeededAloneIsOneProcesssSeeding) {
  const GoldenCase& g = GetParam();
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g.file, g.overrides);
  if (c.simulation.dimension == 2)
    check_seeding<2>(c, g.name);
  else
    check_seeding<3>(c, g.name);
}

INSTANTIATE_TEST_SUITE_P(Golden, OnProcesses, ::testing::ValuesIn(golden::golden_cases()),
                         [](const auto& info) { return std::string(info.param.name); });

// A ghost at the far edge of a share reads nodes that lack particles only other processes
// hold. A bad value there (a NaN stress put into this process's farthest ghost before every
// step) is dropped with the ghost after the step: it stops nothing, changes no own particle, and
// the run ends on the one-process hash.
TEST(Ghosts, ABadGhostAtTheShareEdgeStopsNothingAndChangesNothing) {
  if (world_size() < 2) GTEST_SKIP() << "one process has no ghosts";
  const auto& cases = golden::golden_cases();
  const GoldenCase& g = *std::find_if(cases.begin(), cases.end(), [](const GoldenCase& k) {
    return std::string(k.name) == "vaiont_three";
  });
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g.file, g.overrides);
  Simulation<2> sim(c);
  sim.set_settling(true);
  Distributed<2> dist(sim, MPI_COMM_WORLD, rebalance_every, start<2>);
  int spoiled = 0;
  for (int s = 0; s < g.settle_steps + g.steps; ++s) {
    if (s == g.settle_steps) dist.release();
    const std::int64_t lo = dist.bounds()[dist.rank()], hi = dist.bounds()[dist.rank() + 1];
    const Particles<2>& P = sim.particles();
    std::size_t far = P.size();
    std::int64_t farthest = 0; // columns beyond the slab
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (dist.is_own(p)) continue;
      const std::int64_t col = sim.grid().cell_of(P.x[p])[0];
      const std::int64_t beyond = col < lo ? lo - col : col - (hi - 1);
      if (beyond > farthest) farthest = beyond, far = p;
    }
    if (far < P.size()) {
      sim.particles_mut().stress[far].setConstant(std::numeric_limits<double>::quiet_NaN());
      ++spoiled;
    }
    ASSERT_NO_THROW(dist.step(1.0)) << "step " << s;
  }
  EXPECT_GT(spoiled, 0);
  EXPECT_EQ(finish(dist).hash, g.hash) << "a bad ghost changed the run";
}

// Bodies that overlap across every cut stop every process with the error one process gives: the
// first overlapping particle by id, wherever its slab is.
TEST(Seeding, OverlapIsOneProcesssErrorOnEveryProcess) {
  const std::string file = std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/cohesive_block.toml";
  const Case c = parse_case_file(file, {"body.0.polygon=[[1.0, 0.2], [12.0, 0.2], [12.0, 7.0], "
                                        "[1.0, 7.0]]"});
  std::string serial, shared;
  try {
    seed_case<2>(c);
  } catch (const CaseError& e) {
    serial = e.what();
  }
  ASSERT_NE(serial.find("overlap"), std::string::npos) << serial;
  try {
    seed_share<2>(c, MPI_COMM_WORLD);
  } catch (const CaseError& e) {
    shared = e.what();
  }
  EXPECT_EQ(shared, serial);
}

// A restart's read that fails on one process alone (here the last process's checkpoint bytes
// are cut short) stops every process with that process's error, before any of them goes on
// into the collectives that the failing one would never reach.
TEST(Restart, AReadThatFailsOnOneProcessFailsOnAll) {
  const std::string file = std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/cohesive_block.toml";
  const Case c = parse_case_file(file, {});
  std::string bytes;
  {
    Simulation<2> whole(c);
    SaveArchive ar;
    serialize_state(ar, whole, "memory");
    bytes = ar.bytes();
  }
  if (world_rank() == world_size() - 1) bytes.resize(bytes.size() / 2);
  SharedSeeding<2> seeding = seed_share<2>(c, MPI_COMM_WORLD);
  Simulation<2> sim(c, std::move(seeding.seeded));
  LoadArchive in(bytes, "memory");
  RestoredShare share;
  choose_slab<2>(in, sim.grid(), ghost_columns(sim.setup().normal_smoothing), MPI_COMM_WORLD,
                 share);
  std::string error;
  try {
    agreed<CheckpointError>([&] { serialize_state(in, sim, "memory"); });
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("memory: corrupt checkpoint"), std::string::npos) << error;
}

// A grid with fewer cell columns than the processes' slabs need is refused, on every process,
// with the figures.
TEST(Decomposition, NarrowGridIsRefusedOnEveryProcess) {
  if (world_size() < 2) GTEST_SKIP() << "one process takes any grid";
  const std::string file = std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/column_collapse.toml";
  const Case probe = parse_case_file(file, {});
  // 2 x ghost width (8 + normal smoothing 1) - 1 columns across the grid's width.
  const double cell = probe.grid.extent[0] / 17.0;
  const Case c = parse_case_file(file, {fmt::format("grid.cell_size={:.17g}", cell)});
  Simulation<2> sim(c);
  try {
    Distributed<2> dist(sim, MPI_COMM_WORLD);
    FAIL() << "a grid of " << sim.grid().cells[0] << " columns was taken";
  } catch (const DecompositionError& e) {
    EXPECT_NE(std::string(e.what()).find("cell columns"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace talus

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  ::testing::InitGoogleTest(&argc, argv);
  if (talus::world_rank() != 0) { // one process reports
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}
