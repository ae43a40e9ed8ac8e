// SPDX-License-Identifier: GPL-3.0-or-later
// CloudArray (common/include/plantmorph/memory/CloudArray.h) against std::vector: the same numbers after the same
// growing operations, and memory that can be handed over.
#include <plantmorph/memory/CloudArray.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

namespace
{
using plantmorph::CloudArray;

template <class T, bool HugePages>
std::vector<T> AsVector(const CloudArray<T, HugePages>& a)
{
  return std::vector<T>(a.begin(), a.end());
}

TEST(CloudArray, PushBackAndEmplaceBackGrowLikeAVector)
{
  CloudArray<int, false> a;
  std::vector<int> expected;
  for (int i = 0; i < 10000; ++i)
  {
    if (i % 3 == 0)
      EXPECT_EQ(a.emplace_back(i * 7), i * 7);
    else
      a.push_back(i * 7);
    expected.push_back(i * 7);
    ASSERT_EQ(a.back(), i * 7);
  }
  EXPECT_EQ(AsVector(a), expected);
  EXPECT_GE(a.capacity(), a.size());
  EXPECT_LE(a.capacity(), 2 * a.size()); // doubling: no quadratic growth, no more than twice the room
}

TEST(CloudArray, PushBackOfAHeldNumberSurvivesTheGrowth)
{
  CloudArray<double, false> a{ 1.5, 2.5 };
  while (a.size() < 100)
    a.push_back(a[0]); // the reference points into the memory that the growth frees
  EXPECT_EQ(a[1], 2.5);
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (i != 1)
    {
      ASSERT_EQ(a[i], 1.5) << "number " << i;
    }
  }
}

TEST(CloudArray, InsertAnywhereMatchesVector)
{
  std::mt19937 random(3);
  CloudArray<int> a;
  std::vector<int> expected;
  for (int round = 0; round < 200; ++round)
  {
    const std::size_t at = expected.empty() ? 0 : random() % (expected.size() + 1);
    const std::vector<int> values{ round, -round, 2 * round };
    const std::size_t n = random() % 4; // 0 to 3 numbers
    int* where = a.insert(a.begin() + at, values.data(), values.data() + n);
    EXPECT_EQ(where, a.begin() + at);
    expected.insert(expected.begin() + static_cast<std::ptrdiff_t>(at), values.begin(),
      values.begin() + static_cast<std::ptrdiff_t>(n));
    ASSERT_EQ(AsVector(a), expected) << "round " << round;
  }
  a.insert(a.end(), { 5, 6, 7 });
  expected.insert(expected.end(), { 5, 6, 7 });
  EXPECT_EQ(AsVector(a), expected);
}

TEST(CloudArray, ClearKeepsTheRoomAndReleaseHandsTheMemoryOver)
{
  CloudArray<float, false> a;
  a.resize(1000);
  const std::size_t room = a.capacity();
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.capacity(), room);
  a.insert(a.end(), { 1.0f, 2.0f });
  float* held = a.Release();
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(held[0], 1.0f);
  EXPECT_EQ(held[1], 2.0f);
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.capacity(), 0u);
  std::free(held);
  EXPECT_EQ(a.Release(), nullptr); // nothing held: nothing to hand over
}
} // namespace
