// SPDX-License-Identifier: GPL-3.0-or-later
// RandomStream: one seed gives the same numbers every time, streams are independent, and the distributions have
// the right range and moments.
#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace plantmorph
{
namespace
{
std::vector<std::uint64_t> Draw(std::uint64_t seed, std::uint64_t stream, int count)
{
  RandomStream random(seed, stream);
  std::vector<std::uint64_t> values;
  for (int i = 0; i < count; ++i)
    values.push_back(random.Bits());
  return values;
}

TEST(RandomStream, SameSeedAndStreamGiveTheSameNumbers)
{
  EXPECT_EQ(Draw(7, 0, 1000), Draw(7, 0, 1000));
  EXPECT_EQ(Draw(7, 3, 1000), Draw(7, 3, 1000));
}

TEST(RandomStream, OtherSeedsAndStreamsShareNoNumbers)
{
  const std::vector<std::uint64_t> a = Draw(7, 0, 200), b = Draw(7, 1, 200), c = Draw(8, 0, 200);
  for (int i = 0; i < 200; ++i)
  {
    for (int j = 0; j < 200; ++j)
    {
      EXPECT_NE(a[i], b[j]);
      EXPECT_NE(a[i], c[j]);
    }
  }
}

TEST(RandomStream, UniformAndIntegerStayInRangeWithTheRightMean)
{
  RandomStream random(42);
  const int n = 200000;
  double sum = 0.0, sumSquares = 0.0;
  std::vector<int> counts(6, 0);
  for (int i = 0; i < n; ++i)
  {
    const double x = random.Uniform();
    ASSERT_GE(x, 0.0);
    ASSERT_LT(x, 1.0);
    sum += x;
    sumSquares += x * x;
    const std::int64_t k = random.Integer(-2, 3);
    ASSERT_GE(k, -2);
    ASSERT_LE(k, 3);
    ++counts[k + 2];
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  EXPECT_NEAR(sumSquares / n - 0.25, 1.0 / 12.0, 0.002); // variance of U(0, 1)
  for (int c : counts)
    EXPECT_NEAR(c, n / 6.0, 5.0 * std::sqrt(n / 6.0));
  EXPECT_EQ(random.Integer(5, 5), 5);
  EXPECT_EQ(random.Integer(5, 4), 5);
  const double y = random.Uniform(-3.0, -1.0);
  EXPECT_TRUE(y >= -3.0 && y < -1.0);
}

TEST(RandomStream, NormalHasMeanZeroAndUnitVariance)
{
  RandomStream random(1);
  const int n = 200000;
  double sum = 0.0, sumSquares = 0.0, sumFourth = 0.0;
  for (int i = 0; i < n; ++i)
  {
    const double x = random.Normal();
    sum += x;
    sumSquares += x * x;
    sumFourth += x * x * x * x;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sumSquares / n, 1.0, 0.01);
  EXPECT_NEAR(sumFourth / n, 3.0, 0.06); // kurtosis of a normal
  RandomStream shifted(1);
  EXPECT_EQ(shifted.Normal(2.0, 0.5), 2.0 + 0.5 * RandomStream(1).Normal());
}

} // namespace
} // namespace plantmorph
