// SPDX-License-Identifier: GPL-3.0-or-later
// The parallel-loop hook's helpers (common/include/plantmorph/ParallelFor.h): SortInParallel gives std::sort's
// order on threads, whatever the number of pieces and however the pieces are handed out.
#include <plantmorph/ParallelFor.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
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

} // namespace
} // namespace plantmorph
