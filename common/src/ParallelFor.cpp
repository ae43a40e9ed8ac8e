// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/ParallelFor.h>
#include <plantmorph/RadixSort.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace plantmorph
{

void SerialFor(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body)
{
  if (count > 0)
    body(0, count);
}

void SortKeysInParallel(const ParallelFor& parallel, std::vector<std::uint64_t>& keys, int lowBit, int highBit)
{
  SortKeysInParallel<std::allocator<std::uint64_t>>(parallel, keys, lowBit, highBit);
}

} // namespace plantmorph
