#include <gtest/gtest.h>

#include <cmath>

#include "core/duration_text.hpp"

TEST(DurationText, TwoUnitsAtMostRoundedToSeconds) {
  EXPECT_EQ(core::duration_text(0.4), "0 s");
  EXPECT_EQ(core::duration_text(45.4), "45 s");
  EXPECT_EQ(core::duration_text(725), "12 min 5 s");
  EXPECT_EQ(core::duration_text(5 * 3600 + 12 * 60 + 40), "5 h 12 min");
  EXPECT_EQ(core::duration_text(366379), "4 d 5 h");  // the coupled run's "ETA 366379 s" of issue 21
  EXPECT_EQ(core::duration_text(NAN), "unknown");
  EXPECT_EQ(core::duration_text(-1), "unknown");
}
