#include <gtest/gtest.h>

#include <limits>

#include "shore/core/error.h"

TEST(Check, MessageNamesFieldValueAndRange) {
  const shore::Check c{"demo.Settings"};
  try {
    c.in_closed("alpha", 1.5, 0.0, 1.0);
    FAIL() << "no throw";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_EQ(e.field(), "demo.Settings.alpha");
    EXPECT_STREQ(e.what(), "demo.Settings.alpha = 1.5: must be in [0, 1]");
  }
}

TEST(Check, RejectsNaNAndInfinityEverywhere) {
  const shore::Check c{"x"};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(c.positive("a", nan), shore::InvalidSetting);
  EXPECT_THROW(c.positive("a", inf), shore::InvalidSetting);
  EXPECT_THROW(c.non_negative("a", nan), shore::InvalidSetting);
  EXPECT_THROW(c.in_closed("a", nan, 0.0, 1.0), shore::InvalidSetting);
  EXPECT_THROW(c.in_left_open("a", 0.0, 0.0, 1.0), shore::InvalidSetting);
  EXPECT_THROW(c.finite("a", inf), shore::InvalidSetting);
  EXPECT_NO_THROW(c.in_left_open("a", 1.0, 0.0, 1.0));
  EXPECT_NO_THROW(c.non_negative("a", 0.0));
}
