// SPDX-License-Identifier: GPL-3.0-or-later
// Filters that need the whole leaf (its venation, its subdivision, its simulation, a distance to all of it) gather
// their input on rank 0 when ParaView runs them on several MPI ranks (pvbatch, pvserver). Our sources make the leaf
// on rank 0 only, so usually nothing moves; a leaf split over ranks (D3, RedistributeDataSet, a partitioned reader)
// is gathered onto rank 0, its coincident points merged, and the filter runs once there: no rank duplicates or loses
// a part of the result. Module PlantMorph::VTKCommon (the rest of common/ is VTK-free); a wrapper declaring the
// WholeOnFirstRank policy (PlantMorphLayer.h) gets its inputs gathered so without calling these.
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

// What the filters gathering their input used to get from here.
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include <vector>

namespace plantmorph
{

namespace detail
{
/// A piece without the ghost cells a partitioner (D3, RedistributeDataSet) adds along its seams: each cell then
/// comes from the one rank that owns it. The piece itself when it has none.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkDataObject> WithoutGhostCells(vtkPointSet* piece);

/// Polygonal pieces appended in the given order, coincident points merged (tolerance 0) unless `mergePoints` is
/// false, cells kept as they are.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkPolyData> MergePolyPieces(
  const std::vector<vtkSmartPointer<vtkDataObject>>& pieces, bool mergePoints = true);
} // namespace detail

/// Collective over the global controller's ranks (every rank must call it, as every rank runs the filter): returns
/// the whole dataset on rank 0 and an empty one on the other ranks. In serial, or when only rank 0 holds data, it
/// returns `piece` itself (no copy), so the result is bit-identical to a serial run. Pieces from several ranks are
/// appended in rank order and their exactly coincident points merged (their point order then differs from the
/// unsplit dataset's).
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkPolyData> GatherOnFirstRank(vtkPolyData* piece);

/// The same gather with the pieces only appended, no point merged: every cell keeps its own corners and their point
/// data. For a surface that is only looked at cell by cell (VirtualScanner's rays): a tube's seam has two points at
/// one place with two texture coordinates (0 and 1 around it), which merging would make one.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkPolyData> AppendOnFirstRank(vtkPolyData* piece);

/// The same for any point set (a measured cloud may come as an unstructured grid): polygonal data as above, other
/// point sets appended into an unstructured grid with coincident points merged.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkPointSet> GatherOnFirstRank(vtkPointSet* piece);

/// The same for a table (a reader's table split over the ranks by rows): collective; the whole table on rank 0, its
/// rows in rank order (the columns of rank 0's piece, or of the first piece with rows, matched by name), an empty
/// table on the other ranks. In serial, or when only rank 0 holds rows, `piece` itself.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkTable> GatherRowsOnFirstRank(vtkTable* piece);

/// True in serial and on rank 0: where a gathered input is whole. A filter whose gathered input is empty there
/// says so (a warning naming the input), while the other ranks' empty pieces are expected and stay silent.
PLANTMORPHVTKCOMMON_EXPORT bool IsFirstRank();

} // namespace plantmorph
