// SPDX-License-Identifier: GPL-3.0-or-later
// The parallel-loop hook's helpers (common/include/plantmorph/ParallelFor.h): SortInParallel gives std::sort's
// order on threads, whatever the number of pieces and however the pieces are handed out; SortKeysInParallel is
// std::stable_sort by the chosen bits.
#include <plantmorph/ParallelFor.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace plantmorph
{
namespace
{
/// Every task on a thread of its own, the last task first.
ParallelFor ThreadPerTask()
{
  return [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::vector<std::thread> threads;
    for (std::size_t i = count; i-- > 0;)
      threads.emplace_back(body, i, i + 1);
    for (auto& thread : threads)
      thread.join();
  };
}

TEST(ParallelFor, SortInParallelIsStdSort)
{
  // Many equal keys (a key in [0, 50)), ties broken by the index: a total order, so one sorted sequence.
  std::mt19937 random(3);
  std::uniform_int_distribution<int> key(0, 49);
  for (std::size_t n : { std::size_t{ 10 }, std::size_t{ 8191 }, std::size_t{ 8192 }, std::size_t{ 100003 } })
  {
    std::vector<std::pair<int, std::size_t>> values(n);
    for (std::size_t i = 0; i < n; ++i)
      values[i] = { key(random), n - i };
    std::vector<std::pair<int, std::size_t>> expected = values;
    std::sort(expected.begin(), expected.end());
    for (std::size_t pieces : { 1, 2, 3, 16, 37 })
    {
      std::vector<std::pair<int, std::size_t>> sorted = values;
      SortInParallel(ThreadPerTask(), sorted, std::less<std::pair<int, std::size_t>>(), pieces);
      EXPECT_EQ(sorted, expected) << n << " values, " << pieces << " pieces";
    }
    std::vector<std::pair<int, std::size_t>> serial = values;
    SortInParallel(SerialFor, serial, std::less<std::pair<int, std::size_t>>());
    EXPECT_EQ(serial, expected);
  }
}

TEST(ParallelFor, SortKeysInParallelIsStableSortByTheBits)
{
  // Random 64-bit keys (every bit set at random, so the bits outside [low, high) must not move anything), sorted
  // by bit ranges that start and end inside a pass's 11 bits and across several passes, on threads and serially.
  std::mt19937_64 random(7);
  for (std::size_t n : { std::size_t{ 0 }, std::size_t{ 1 }, std::size_t{ 1000 }, std::size_t{ 300007 } })
  {
    std::vector<std::uint64_t> keys(n);
    for (std::uint64_t& key : keys)
      key = random();
    for (const auto& [low, high] : { std::pair<int, int>{ 0, 64 }, { 32, 40 }, { 32, 56 }, { 5, 7 }, { 13, 50 } })
    {
      const std::uint64_t mask = high - low == 64 ? ~std::uint64_t(0) : ((std::uint64_t(1) << (high - low)) - 1);
      std::vector<std::uint64_t> expected = keys;
      std::stable_sort(expected.begin(), expected.end(),
        [&](std::uint64_t a, std::uint64_t b) { return ((a >> low) & mask) < ((b >> low) & mask); });
      std::vector<std::uint64_t> threaded = keys, serial = keys;
      SortKeysInParallel(ThreadPerTask(), threaded, low, high);
      SortKeysInParallel(SerialFor, serial, low, high);
      EXPECT_EQ(threaded, expected) << n << " keys, bits " << low << " to " << high;
      EXPECT_EQ(serial, expected) << n << " keys, bits " << low << " to " << high;
    }
  }
  // Keys that share their digits in a pass (nothing to move there) still come out sorted.
  std::vector<std::uint64_t> keys = { 5ull << 40 | 3, 5ull << 40 | 1, 4ull << 40 | 2 };
  SortKeysInParallel(SerialFor, keys, 0, 64);
  EXPECT_EQ(keys, (std::vector<std::uint64_t>{ 4ull << 40 | 2, 5ull << 40 | 1, 5ull << 40 | 3 }));
}

} // namespace
} // namespace plantmorph
