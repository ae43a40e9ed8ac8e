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

} // namespace plantmorph
