// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK side of the algorithm layers' two hooks (header-only, for the VTK modules):
// - SMPFor(): vtkSMPTools behind plantmorph::ParallelFor (common/include/plantmorph/ParallelFor.h), so the plain C++
//   algorithms run threaded inside ParaView with the thread count and backend it is configured with;
// - Progress(): the progress callback every long algorithm takes (a fraction in [0, 1] in, "go on" out), reporting
//   to the filter's progress bar over [begin, end] and answering false once the user presses Abort.
#pragma once

#include "vtkAlgorithm.h"
#include "vtkSMPTools.h"

#include "plantmorph/ParallelFor.h"

#include <cstddef>
#include <functional>

namespace plantmorph
{

/// vtkSMPTools::For behind a ParallelFor. `grain` is vtkSMPTools' grain (0: the backend chooses); the algorithms
/// give the same results however the range is cut, so it is a speed setting only.
inline ParallelFor SMPFor(vtkIdType grain = 0)
{
  return [grain](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    vtkSMPTools::For(0, static_cast<vtkIdType>(count), grain, [&body](vtkIdType begin, vtkIdType end) {
      body(static_cast<std::size_t>(begin), static_cast<std::size_t>(end));
    });
  };
}

/// A progress callback for `algorithm`: fraction f of the work done shows as begin + (end - begin) * f; the callback
/// returns false (stop) once the algorithm's AbortExecute flag is set.
inline std::function<bool(double)> Progress(vtkAlgorithm* algorithm, double begin = 0.0, double end = 1.0)
{
  return [algorithm, begin, end](double fraction) {
    algorithm->UpdateProgress(begin + (end - begin) * fraction);
    return !algorithm->GetAbortExecute();
  };
}

} // namespace plantmorph
