// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK side of the algorithm layers' two hooks (module PlantMorph::VTKCommon):
// - SMPFor(): vtkSMPTools behind plantmorph::ParallelFor (common/include/plantmorph/ParallelFor.h), so the plain C++
//   algorithms run threaded inside ParaView with the thread count and backend it is configured with, and threaded
//   on STDThread when it is left on its default Sequential backend;
// - Progress(): the progress callback every long algorithm takes (a fraction in [0, 1] in, "go on" out), reporting
//   to the filter's progress bar over [begin, end] and answering false once the user presses Abort;
// - KeepFreedMemory(): the allocator told up front to reuse freed memory from one array to the next, as it learns to
//   do by itself only after the first update.
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

#include "vtkAlgorithm.h" // callers of SMPFor/Progress used to get these two from here
#include "vtkSMPTools.h"
#include "vtkType.h"

#include "plantmorph/ParallelFor.h"

#include <functional>

namespace plantmorph
{

/// vtkSMPTools::For behind a ParallelFor. `grain` is vtkSMPTools' grain (0: the backend chooses); the algorithms
/// give the same results however the range is cut, so it is a speed setting only. When the backend in use is
/// Sequential and the environment does not ask for it (VTK_SMP_BACKEND_IN_USE unset: pvpython, pvbatch and the GUI
/// start so), the loop runs on STDThread within a vtkSMPTools::LocalScope, with the thread count vtkSMPTools is set
/// to (every core, or VTK_SMP_MAX_THREADS); the process-wide backend is left as it is. A thread count of 1, a backend
/// set in the environment and a loop nested in a parallel one run on the backend in use. An exception the body throws on
/// a worker thread (std::bad_alloc) is thrown again on the calling thread once the loop ends (the chunks not yet
/// started are skipped), never left to end the process.
PLANTMORPHVTKCOMMON_EXPORT ParallelFor SMPFor(vtkIdType grain = 0);

/// A progress callback for `algorithm`: fraction f of the work done shows as begin + (end - begin) * f; the callback
/// returns false (stop) once the algorithm's AbortExecute flag is set.
PLANTMORPHVTKCOMMON_EXPORT std::function<bool(double)> Progress(
  vtkAlgorithm* algorithm, double begin = 0.0, double end = 1.0);

/// Once per process, before the first PlantMorph update: glibc's malloc is set to serve blocks below 32 MB from its
/// heap and to keep up to 512 MB of freed memory there (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD), instead of mapping each
/// large block fresh from the system and unmapping it when freed; and the heap is grown at once by 256 MB of memory
/// asked for transparent huge pages (virtual until written). The system hands fresh memory out a page at a time, each
/// page's first touch a page fault, so every temporary array of the first update paid its size in faults again
/// (63,700 faults on the first update of a 10^6-point LeafFitFilter with glibc's defaults; 32,500 with the
/// thresholds; 6,300 with the huge pages too). glibc raises its mapping threshold by itself once large blocks are
/// freed, which is why later updates were cheaper; this makes the first one like them. Nothing is done when the user
/// tuned malloc (MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_ or GLIBC_TUNABLES set), when
/// PLANTMORPH_MALLOC_DEFAULTS is set, or on a C library other than glibc. Returns whether the setting was made (by
/// this call or an earlier one).
PLANTMORPHVTKCOMMON_EXPORT bool KeepFreedMemory();

} // namespace plantmorph
