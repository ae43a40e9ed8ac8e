// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphAlgorithmHooks.h"

#include "vtkAlgorithm.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>
#include <vector>
#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace plantmorph
{
namespace
{
/// Whether our loops must open a threaded scope of their own: the backend in use is Sequential only because nobody
/// chose one (pvpython, pvbatch and the GUI start on it unless VTK_SMP_BACKEND_IN_USE says otherwise), and this is
/// not a loop nested in another (that one already runs on the threads). A backend the user set in the environment
/// is kept, Sequential included, and so is a thread count of 1 (VTK_SMP_MAX_THREADS=1, or a filter's
/// NumberOfThreads 1 through RunThreaded).
bool NeedsThreadedScope(int threads)
{
  const char* backend = vtkSMPTools::GetBackend();
  return threads != 1 && backend && std::strcmp(backend, "Sequential") == 0 && !std::getenv("VTK_SMP_BACKEND_IN_USE") &&
    !vtkSMPTools::IsParallelScope();
}

/// vtkSMPTools::For on the backend in use. An exception thrown on a worker thread (std::bad_alloc from an allocation
/// in the body) would end the process (std::terminate): it is caught there, the remaining chunks are skipped, and the
/// first one is thrown again on the calling thread, where RunRequestData reports it.
void RunFor(vtkIdType grain, std::size_t count, const std::function<void(std::size_t, std::size_t)>& body)
{
  std::atomic<bool> failed{ false };
  std::exception_ptr first;
  std::mutex lock;
  vtkSMPTools::For(0, static_cast<vtkIdType>(count), grain, [&](vtkIdType begin, vtkIdType end) {
    if (failed.load(std::memory_order_relaxed))
      return;
    try
    {
      body(static_cast<std::size_t>(begin), static_cast<std::size_t>(end));
    }
    catch (...)
    {
      std::lock_guard<std::mutex> guard(lock);
      if (!first)
        first = std::current_exception();
      failed = true;
    }
  });
  if (first)
    std::rethrow_exception(first);
}
} // namespace

ParallelFor SMPFor(vtkIdType grain)
{
  return [grain](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    // The thread count vtkSMPTools is set to, else VTK_SMP_MAX_THREADS, else 0: every core.
    int threads = vtk::detail::smp::vtkSMPToolsAPI::GetInstance().GetInternalDesiredNumberOfThread();
    const char* maxThreads = std::getenv("VTK_SMP_MAX_THREADS");
    if (threads == 0 && maxThreads)
      threads = std::max(std::atoi(maxThreads), 0);
    if (count < 2 || !NeedsThreadedScope(threads))
    {
      RunFor(grain, count, body);
      return;
    }
    // Our loops run threaded whatever the process-wide default is, within a scope that puts the backend back after
    // the loop (other filters keep theirs).
    const vtkSMPTools::Config threaded{ threads, "STDThread", vtkSMPTools::GetNestedParallelism() };
    vtkSMPTools::LocalScope(threaded, [&] { RunFor(grain, count, body); });
  };
}

#if defined(__GLIBC__)
namespace
{
/// Grows the main heap by about `bytes` of untouched memory (blocks taken and freed at once: virtual only, nothing
/// resident until written) and asks for transparent huge pages on it (madvise; the kernel's "madvise" mode, Debian's
/// default, backs such memory with 2 MiB pages): the first touch of a 10^6-point fit's arrays is then one fault per
/// 2 MiB instead of one per 4 KiB. The heap stays that large as the trim threshold is above it.
void HugePagesOnHeapTop(std::size_t bytes)
{
  constexpr std::size_t Block = std::size_t(31) << 20; // under the 32 MB mapping threshold: from the heap
  constexpr std::uintptr_t Huge = std::uintptr_t(2) << 20;
  const auto before = reinterpret_cast<std::uintptr_t>(sbrk(0));
  std::vector<void*> blocks;
  for (std::size_t held = 0; held < bytes; held += Block)
    if (void* block = std::malloc(Block))
      blocks.push_back(block);
  const auto after = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const std::uintptr_t begin = (before + Huge - 1) / Huge * Huge;
  const std::uintptr_t end = after / Huge * Huge;
  if (end > begin)
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  for (void* block : blocks)
    std::free(block);
}
} // namespace
#endif

bool KeepFreedMemory()
{
#if defined(__GLIBC__)
  static const bool done = [] {
    for (const char* name :
      { "MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES", "PLANTMORPH_MALLOC_DEFAULTS" })
      if (std::getenv(name))
        return false;
    constexpr int Megabyte = 1 << 20;
    // 32 MB is the largest mapping threshold glibc accepts on 64-bit systems.
    const bool set = mallopt(M_MMAP_THRESHOLD, 32 * Megabyte) == 1 && mallopt(M_TRIM_THRESHOLD, 512 * Megabyte) == 1;
    if (set)
      HugePagesOnHeapTop(std::size_t(256) * Megabyte);
    return set;
  }();
  return done;
#else
  return false;
#endif
}

std::function<bool(double)> Progress(vtkAlgorithm* algorithm, double begin, double end)
{
  return [algorithm, begin, end](double fraction) {
    algorithm->UpdateProgress(begin + (end - begin) * fraction);
    return !algorithm->GetAbortExecute();
  };
}

} // namespace plantmorph
