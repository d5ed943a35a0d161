// The pore pool (core/pore_pool.hpp): records of a header and a band's profiles, at fixed offsets,
// read and written through their named fields.
#include "talus/core/pore_pool.hpp"

#include <gtest/gtest.h>

using namespace talus;

// Records are laid end to end, each header then its band; every record starts zeroed; a field
// written through one record is read back through it and leaves its neighbours alone.
TEST(PorePool, RecordsAreLaidEndToEndAndNamed) {
  PorePool pool;
  const std::size_t a = pool.add(0, 0), b = pool.add(2, 5), c = pool.add(1, 0);
  EXPECT_EQ(a, 0u);
  EXPECT_EQ(b, PoreRecord::header);
  EXPECT_EQ(c, 2 * PoreRecord::header + 5);
  EXPECT_EQ(pool.data.size(), 3 * PoreRecord::header + 5);
  ASSERT_EQ(pool.entries.size(), 3u);
  EXPECT_EQ(pool.entries[1], (std::pair<std::size_t, int>{b, 2}));
  for (const double v : pool.data)
    EXPECT_EQ(v, 0.0);

  PoreRecord r = pool.at(static_cast<std::int64_t>(b));
  r.temperature_rise() = 12.0;
  r.pressure_rise() = 3e5;
  r.normal_stress() = 2e6;
  for (int k = 0; k < 5; ++k)
    r.band()[k] = 100.0 + k;
  const PorePool& read = pool;
  const ConstPoreRecord s = read.at(static_cast<std::int64_t>(b));
  EXPECT_EQ(s.temperature_rise(), 12.0);
  EXPECT_EQ(s.pressure_rise(), 3e5);
  EXPECT_EQ(s.normal_stress(), 2e6);
  EXPECT_EQ(s.band()[4], 104.0);
  EXPECT_EQ(read.at(static_cast<std::int64_t>(a)).normal_stress(), 0.0); // neighbours untouched
  EXPECT_EQ(read.at(static_cast<std::int64_t>(c)).temperature_rise(), 0.0);
}
