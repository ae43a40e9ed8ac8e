// SPDX-License-Identifier: GPL-3.0-or-later
// The shared containers against plain oracles. CloudArray (memory/CloudArray.h) against std::vector: the same
// numbers after the same growing operations, and memory that can be handed over. DisjointSets (graph/DisjointSets.h)
// against a breadth-first search of the same joins: the same components, each rooted at its lowest member.
#include <plantmorph/graph/DisjointSets.h>
#include <plantmorph/memory/CloudArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <deque>
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

namespace
{
/// Components of the graph with these edges, by breadth-first search: each vertex's lowest reachable vertex.
std::vector<int> LowestReachable(int n, const std::vector<std::pair<int, int>>& edges)
{
  std::vector<std::vector<int>> next(n);
  for (const auto& [a, b] : edges)
  {
    next[a].push_back(b);
    next[b].push_back(a);
  }
  std::vector<int> lowest(n, -1);
  for (int start = 0; start < n; ++start) // ascending: the first vertex to reach a component is its lowest
    if (lowest[start] < 0)
    {
      std::deque<int> queue{ start };
      lowest[start] = start;
      for (; !queue.empty(); queue.pop_front())
        for (int v : next[queue.front()])
          if (lowest[v] < 0)
            queue.push_back(v), lowest[v] = start;
    }
  return lowest;
}

TEST(DisjointSets, GiveTheComponentsOfABreadthFirstSearchRootedAtTheirLowestMember)
{
  std::mt19937 random(7);
  for (int trial = 0; trial < 20; ++trial)
  {
    const int n = 1 + static_cast<int>(random() % 400);
    std::vector<std::pair<int, int>> edges(random() % (2 * n));
    for (auto& e : edges)
      e = { static_cast<int>(random() % n), static_cast<int>(random() % n) };
    plantmorph::DisjointSets<int> sets(static_cast<std::size_t>(n));
    int joins = 0;
    for (const auto& [a, b] : edges)
      joins += sets.Join(a, b) ? 1 : 0;
    const std::vector<int> lowest = LowestReachable(n, edges);
    for (int i = 0; i < n; ++i)
      ASSERT_EQ(sets.Find(i), lowest[i]) << "vertex " << i << " of " << n;
    // each successful join removed exactly one set
    const auto roots = std::count_if(lowest.begin(), lowest.end(), [i = 0](int r) mutable { return r == i++; });
    EXPECT_EQ(n - joins, roots);
  }
}

TEST(DisjointSets, JoinSaysWhetherTheSetsWereApartAndTheRootIsTheSameInAnyJoinOrder)
{
  plantmorph::DisjointSets<std::size_t> forward(6), backward(6);
  EXPECT_TRUE(forward.Join(4, 5));
  EXPECT_TRUE(forward.Join(5, 2));
  EXPECT_FALSE(forward.Join(2, 4));
  EXPECT_TRUE(backward.Join(2, 5));
  EXPECT_TRUE(backward.Join(5, 4));
  EXPECT_FALSE(backward.JoinRoots(backward.Find(4), backward.Find(2)));
  for (std::size_t i : { 2, 4, 5 })
  {
    EXPECT_EQ(forward.Find(i), 2u);
    EXPECT_EQ(backward.Find(i), 2u);
  }
  for (std::size_t i : { 0, 1, 3 })
    EXPECT_EQ(forward.Find(i), i);
  EXPECT_EQ(forward.Size(), 6u);
}
} // namespace
