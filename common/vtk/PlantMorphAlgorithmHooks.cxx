// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphAlgorithmHooks.h"

#include "vtkAlgorithm.h"
#include "vtkSMPTools.h"

#include <cstddef>

namespace plantmorph
{

ParallelFor SMPFor(vtkIdType grain)
{
  return [grain](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    vtkSMPTools::For(0, static_cast<vtkIdType>(count), grain, [&body](vtkIdType begin, vtkIdType end) {
      body(static_cast<std::size_t>(begin), static_cast<std::size_t>(end));
    });
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
