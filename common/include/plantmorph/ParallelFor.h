// SPDX-License-Identifier: GPL-3.0-or-later
// The parallel-loop hook of the algorithm layers: plain C++ code takes a ParallelFor and runs its loops through
// it, so the VTK layer can hand in vtkSMPTools (or tests a thread pool) while the algorithm stays VTK-free and its
// results do not depend on how the range is cut.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace plantmorph
{

/// Runs body(begin, end) over sub-ranges covering [0, count), possibly concurrently; each index in exactly one range.
using ParallelFor =
  std::function<void(std::size_t count, const std::function<void(std::size_t begin, std::size_t end)>& body)>;

/// The default ParallelFor: one call body(0, count) on the calling thread.
void SerialFor(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);

/// Runs f(i) for every i in [0, count) through `parallel`, `block` consecutive indices a task (the hook is called
/// per block, so a hook that hands out single indices costs nothing per index). f(i) must write only what belongs
/// to i: the result is then the same however the blocks are spread over threads.
template <typename F>
void ForEachIndex(const ParallelFor& parallel, std::size_t count, F&& f, std::size_t block = 4096)
{
  const std::size_t blocks = (count + block - 1) / block;
  parallel(blocks, [&](std::size_t first, std::size_t last) {
    const std::size_t end = last * block < count ? last * block : count;
    for (std::size_t i = first * block; i < end; ++i)
      f(i);
  });
}

/// Sorts `values` by `less` through `parallel`: `pieces` slices sorted each on its own, then merged pairwise, the
/// merges of a round side by side. `less` must be a strict total order (no two values equivalent: break ties by an
/// index), so that the result is the one std::sort gives, however the work is spread over threads.
template <typename T, typename Less>
void SortInParallel(const ParallelFor& parallel, std::vector<T>& values, Less less, std::size_t pieces = 16)
{
  const std::size_t n = values.size();
  if (n < 8192 || pieces < 2)
  {
    std::sort(values.begin(), values.end(), less);
    return;
  }
  std::vector<std::size_t> bounds(pieces + 1);
  for (std::size_t k = 0; k <= pieces; ++k)
    bounds[k] = n * k / pieces;
  parallel(pieces, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k)
      std::sort(values.begin() + bounds[k], values.begin() + bounds[k + 1], less);
  });
  std::vector<T> buffer(n);
  std::vector<T>*from = &values, *to = &buffer;
  for (std::size_t width = 1; width < pieces; width *= 2)
  {
    const auto at = [&](std::size_t k) { return bounds[std::min(k, pieces)]; };
    parallel((pieces + 2 * width - 1) / (2 * width), [&](std::size_t first, std::size_t last) {
      for (std::size_t m = first; m < last; ++m)
      {
        const std::size_t lo = at(2 * m * width), mid = at((2 * m + 1) * width), hi = at((2 * m + 2) * width);
        std::merge(
          from->begin() + lo, from->begin() + mid, from->begin() + mid, from->begin() + hi, to->begin() + lo, less);
      }
    });
    std::swap(from, to);
  }
  if (from != &values)
    values.swap(buffer);
}

/// Sorts 64-bit `keys` by their bits [lowBit, highBit) through `parallel`, stably (keys equal there keep their
/// order): a least-significant-digit radix sort, 11 bits a pass, each pass counting and then scattering fixed blocks
/// of the keys side by side, so the order is the serial sort's however the blocks are spread over threads. Linear
/// in the keys (std::sort's comparisons were a visible part of building a 10^6-point grid). With the bits below
/// lowBit already ascending (an index), the result is the sort by the whole key. Any allocator of the key vector
/// will do (the distance queries sort an uninitialised one).
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
