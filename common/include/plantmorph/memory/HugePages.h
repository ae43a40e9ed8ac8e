// SPDX-License-Identifier: GPL-3.0-or-later
// Memory for big arrays on transparent huge pages (Linux, where enabled "madvise"): an array written into fresh
// memory faults once per 4 KiB page on its first write, and for arrays of millions of numbers those faults were a
// tenth of a filter's time (a scanned cloud of 10^7 points) or most of a first update's extra cost (10^6 distances).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace plantmorph
{

/// The size of a transparent huge page on x86-64 Linux.
constexpr std::size_t HugePageBytes = std::size_t(2) << 20;

/// True for arrays worth putting on huge pages: 4 MiB or more (below that the rounding would waste too much).
constexpr bool WorthHugePages(std::size_t bytes)
{
  return bytes >= 2 * HugePageBytes;
}

/// Memory for `bytes`, aligned to 2 MiB and asked for transparent huge pages, freed with std::free (so a VTK array
/// may adopt it); std::bad_alloc when there is none. The memory is rounded up to whole huge pages: the kernel backs
/// only whole aligned 2 MiB pages with huge pages, so the tail of an array of 8,000,000 bytes (1.6 MiB) would
/// otherwise still fault once per 4 KiB. Plain std::malloc where there are no transparent huge pages.
inline void* AllocateOnHugePages(std::size_t bytes)
{
  void* memory = nullptr;
#ifdef __linux__
  bytes = (bytes + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
  if (posix_memalign(&memory, HugePageBytes, bytes) != 0)
    memory = nullptr;
  else
    madvise(memory, bytes, MADV_HUGEPAGE);
#else
  memory = std::malloc(bytes);
#endif
  if (!memory)
    throw std::bad_alloc();
  return memory;
}

} // namespace plantmorph
