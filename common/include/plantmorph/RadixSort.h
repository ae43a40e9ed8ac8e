// SPDX-License-Identifier: GPL-3.0-or-later
// The linear sort of 64-bit keys behind SortKeysInParallel (ParallelFor.h), for any allocator of the key vector: the
// point grids' std::vector and the distance queries' uninitialised vector share one implementation.
#pragma once

#include <plantmorph/ParallelFor.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace plantmorph
{

/// Sorts `keys` by their bits [lowBit, highBit) through `parallel`, stably, as SortKeysInParallel documents: an
/// LSD radix sort, 11 bits a pass, each pass counting and then scattering fixed blocks of the keys, so the order is
/// the serial sort's however the blocks are spread over threads. A pass where every key has the same digit moves
/// nothing.
template <class Allocator>
void SortKeysInParallel(
  const ParallelFor& parallel, std::vector<std::uint64_t, Allocator>& keys, int lowBit, int highBit)
{
  constexpr int DigitBits = 11;
  constexpr std::size_t Digits = std::size_t(1) << DigitBits;
  const std::size_t n = keys.size();
  if (n < 2 || highBit <= lowBit)
    return;
  const std::size_t blockSize = std::max<std::size_t>(std::size_t(1) << 14, (n + 63) / 64);
  const std::size_t blocks = (n + blockSize - 1) / blockSize;
  std::vector<std::uint64_t, Allocator> other(n);
  std::vector<std::size_t> counts(blocks * Digits);
  for (int shift = lowBit; shift < highBit; shift += DigitBits)
  {
    const int width = std::min(DigitBits, highBit - shift);
    const std::uint64_t mask = (std::uint64_t(1) << width) - 1;
    const auto digit = [&](std::uint64_t key) { return static_cast<std::size_t>((key >> shift) & mask); };
    parallel(blocks, [&](std::size_t first, std::size_t last) {
      for (std::size_t b = first; b < last; ++b)
      {
        std::size_t* count = counts.data() + b * Digits;
        std::fill(count, count + Digits, 0);
        for (std::size_t i = b * blockSize, end = std::min(n, (b + 1) * blockSize); i < end; ++i)
          ++count[digit(keys[i])];
      }
    });
    // Offsets: digit by digit, block by block within a digit (that keeps the sort stable).
    std::size_t total = 0;
    bool moves = true;
    for (std::size_t d = 0; d < Digits; ++d)
      for (std::size_t b = 0; b < blocks; ++b)
      {
        std::size_t& count = counts[b * Digits + d];
        moves = moves && count != n;
        const std::size_t here = count;
        count = total;
        total += here;
      }
    if (!moves)
      continue; // every key has the same digit here: nothing to move
    parallel(blocks, [&](std::size_t first, std::size_t last) {
      for (std::size_t b = first; b < last; ++b)
      {
        std::size_t* offset = counts.data() + b * Digits;
        for (std::size_t i = b * blockSize, end = std::min(n, (b + 1) * blockSize); i < end; ++i)
          other[offset[digit(keys[i])]++] = keys[i];
      }
    });
    keys.swap(other);
  }
}

} // namespace plantmorph
