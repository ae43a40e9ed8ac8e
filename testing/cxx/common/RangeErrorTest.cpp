// SPDX-License-Identifier: GPL-3.0-or-later
// RangeError: every bad-parameter message has the same shape, so users (and tests) can rely on it.
#include <plantmorph/RangeError.h>

#include <gtest/gtest.h>

namespace plantmorph
{
namespace
{
TEST(RangeError, NamesPropertyValueAndRange)
{
  EXPECT_EQ(OutOfRange("Sides", 2, "[3, 256]"), "Sides = 2 is outside the accepted range [3, 256]");
  EXPECT_EQ(OutOfRange("Length", -0.5, "(0, 1e6]", "the blade's length, base to apex"),
    "Length = -0.5 is outside the accepted range (0, 1e6] (the blade's length, base to apex)");
}

TEST(RangeError, CheckRangeIsEmptyOnlyWhenAccepted)
{
  EXPECT_TRUE(CheckRange(true, "Lobes", 4, "{3, 5}").empty());
  EXPECT_EQ(CheckRange(false, "Lobes", 4, "{3, 5}"), "Lobes = 4 is outside the accepted range {3, 5}");
}
} // namespace
} // namespace plantmorph
