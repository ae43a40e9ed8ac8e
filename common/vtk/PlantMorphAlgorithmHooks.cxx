// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphAlgorithmHooks.h"

#include "vtkAlgorithm.h"
#include "vtkSMPTools.h"

#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>

namespace plantmorph
{

ParallelFor SMPFor(vtkIdType grain)
{
  // An exception thrown on a worker thread (std::bad_alloc from an allocation in the body) would end the process
  // (std::terminate): it is caught there, the remaining chunks are skipped, and the first one is thrown again on the
  // calling thread, where RunRequestData reports it.
  return [grain](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
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
  };
}

std::function<bool(double)> Progress(vtkAlgorithm* algorithm, double begin, double end)
{
  return [algorithm, begin, end](double fraction) {
    algorithm->UpdateProgress(begin + (end - begin) * fraction);
    return !algorithm->GetAbortExecute();
  };
}

} // namespace plantmorph
