// ContactRecord: rows summed in row order into the step's totals, work accumulated across steps,
// time means as impulse over time.
#include "talus/solver/contact_record.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(ContactRecord, RowsSumIntoTheTotalsAndTheMeans) {
  ContactRecord<2> rec;
  rec.resize(2, 1);
  rec.begin(3, true, {1, 2}); // pairs 0-1 and 1-0 (a * B + b) can meet
  rec.add_force(0, 1, 0, Vec<2>(1.0, 2.0));
  rec.add_force(2, 1, 0, Vec<2>(0.5, -1.0));
  rec.add_work(1, 1, 3.0);
  rec.add_interface(2, 0, 10.0, 20.0, 30.0);
  rec.add_node(1, ContactNodeForce<2>{});
  rec.end();
  EXPECT_EQ(rec.force(1, 0), Vec<2>(1.5, 1.0));
  EXPECT_EQ(rec.force(0, 1), Vec<2>::Zero());
  EXPECT_DOUBLE_EQ(rec.work[1], 3.0);
  EXPECT_DOUBLE_EQ(rec.interface_force[0].frictional, 20.0);
  EXPECT_EQ(rec.nodes().size(), 1u);
  rec.accumulate(0.1);
  // A second step: the forces restart, the work goes on, the means weigh each step by its dt.
  rec.begin(1, true, {1, 2});
  rec.add_force(0, 1, 0, Vec<2>(3.5, 0.0));
  rec.add_work(0, 1, 1.0);
  rec.end();
  rec.accumulate(0.3);
  EXPECT_EQ(rec.force(1, 0), Vec<2>(3.5, 0.0));
  EXPECT_DOUBLE_EQ(rec.work[1], 4.0);
  EXPECT_TRUE(rec.nodes().empty());
  EXPECT_NEAR(rec.mean_force(1, 0)[0], (0.1 * 1.5 + 0.3 * 3.5) / 0.4, 1e-15);
  EXPECT_NEAR(rec.mean_interface_force(0).frictional, 0.1 * 20.0 / 0.4, 1e-15);
  rec.reset_means();
  EXPECT_EQ(rec.mean_force(1, 0), rec.force(1, 0)); // no time yet: the last step's
}

// Rows hold only the pairs that can meet: of 2,000 bodies, two pairs cost two slots per row, and
// their totals land at their places in the B x B table; a force between bodies that cannot meet
// is a logic error, not a write out of bounds.
TEST(ContactRecord, RowsHoldOnlyThePairsThatCanMeet) {
  ContactRecord<3> rec;
  const int B = 2000;
  rec.resize(B, 0);
  const std::int64_t a = 7 * B + 1999, b = 1999 * B + 7;
  rec.begin(1000, false, {a, b});
  for (std::int64_t r = 0; r < 1000; ++r)
    rec.add_force(r, 7, 1999, Vec<3>(1.0, 0.0, -1.0));
  rec.add_force(500, 1999, 7, Vec<3>(0.0, 2.0, 0.0));
  EXPECT_THROW(rec.add_force(3, 7, 8, Vec<3>::Ones()), std::logic_error);
  rec.end();
  EXPECT_EQ(rec.force(7, 1999), Vec<3>(1000.0, 0.0, -1000.0));
  EXPECT_EQ(rec.force(1999, 7), Vec<3>(0.0, 2.0, 0.0));
  EXPECT_EQ(rec.force(7, 8), Vec<3>::Zero());
}

} // namespace
} // namespace talus
