// SPDX-License-Identifier: GPL-3.0-or-later
// The parallel-loop hook of the algorithm layers: plain C++ code takes a ParallelFor and runs its loops through
// it, so the VTK layer can hand in vtkSMPTools (or tests a thread pool) while the algorithm stays VTK-free and its
// results do not depend on how the range is cut.
#pragma once

#include <cstddef>
#include <functional>

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

} // namespace plantmorph
