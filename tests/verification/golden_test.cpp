// Golden hashes: about 200 steps of small cases, every particle array and the contact, interface
// and energy totals hashed (FNV-1a 64 over their bytes), on 1 and 2 threads and across an
// in-memory restart. A refactor of the solver must keep every hash: the results are bitwise the
// same or the refactor changed the physics. The hashes hold for the release preset's compiler
// and flags (g++ 12, -O3 -march=x86-64-v2, Debian 12); other builds compute other round-off, so
// this file is in the verification label, which only the release preset runs.
//
// To print the current hashes (after a change that is meant to alter results, with the reason
// in the commit): TALUS_GOLDEN_PRINT=1 build/release/tests/talus_verification_tests
// --gtest_filter='Golden*'.
#include "verification/golden_cases.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fmt/format.h>
#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace talus {
namespace golden {
void PrintTo(const GoldenCase& g, std::ostream* os) {
  *os << g.name;
}
} // namespace golden

namespace {

using golden::golden_cases;
using golden::GoldenCase;
using golden::run_golden;

class Golden : public ::testing::TestWithParam<GoldenCase> {};

// The hash on 1 and 2 threads and across a restart equals the committed one.
TEST_P(Golden, HashUnchangedOnOneAndTwoThreadsAndAcrossARestart) {
  const GoldenCase& g = GetParam();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::uint64_t one = run_golden(g, -1);
  omp_set_num_threads(2);
  const std::uint64_t two = run_golden(g, -1);
  const std::uint64_t restarted = run_golden(g, (g.settle_steps + g.steps) / 2 + 1);
  omp_set_num_threads(threads);
  if (std::getenv("TALUS_GOLDEN_PRINT")) fmt::print("golden {} 0x{:016x}ull\n", g.name, one);
  EXPECT_EQ(one, two) << g.name << ": 1 and 2 threads differ";
  EXPECT_EQ(one, restarted) << g.name << ": the restarted run differs";
  EXPECT_EQ(one, g.hash) << g.name << fmt::format(": hash 0x{:016x}ull", one);
}

INSTANTIATE_TEST_SUITE_P(Cases, Golden, ::testing::ValuesIn(golden_cases()),
                         [](const auto& info) { return std::string(info.param.name); });

// contact.node_law = "centre_of_mass", the paper's law at a node three or more bodies share, is
// the law as it was before such nodes were resolved pair by pair: the cases that have such
// nodes give their hashes from before that change, to the bit.
TEST(Golden, PaperNodeLawGivesTheHashesFromBeforePairs) {
  const std::pair<const char*, std::uint64_t> before[] = {{"vaiont_three", 0x7bc2defec9830a6cull},
                                                          {"vaiont_five", 0xb53751c393f0925bull}};
  for (const auto& [name, hash] : before) {
    const auto g = std::find_if(golden_cases().begin(), golden_cases().end(),
                                [&](const GoldenCase& c) { return std::string(c.name) == name; });
    ASSERT_NE(g, golden_cases().end()) << name;
    Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g->file, g->overrides);
    c.contact.pairwise_nodes = false;
    const std::uint64_t h = c.simulation.dimension == 2 ? golden::run_case<2>(c, *g, -1)
                                                        : golden::run_case<3>(c, *g, -1);
    EXPECT_EQ(h, hash) << name << fmt::format(": hash 0x{:016x}ull", h);
    EXPECT_NE(h, g->hash) << name << ": the pairwise law should change this case";
  }
}

} // namespace
} // namespace talus
