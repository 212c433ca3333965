// core/format.cpp: how durations read in every summary line.
#include "tricot/core/format.hpp"

#include <gtest/gtest.h>

TEST(Console, DurationsReadNaturally) {
  using tricot::format_duration;
  EXPECT_EQ(format_duration(0.085), "85 ms");
  EXPECT_EQ(format_duration(12.34), "12.3 s");
  EXPECT_EQ(format_duration(200), "3 min 20 s");
  EXPECT_EQ(format_duration(3720), "1 h 02 min");
}
