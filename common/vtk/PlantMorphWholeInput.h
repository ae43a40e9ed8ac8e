// Filters that need the whole leaf (its venation, its subdivision, its simulation, a distance to all of it) gather
// their input on rank 0 when ParaView runs them on several MPI ranks (pvbatch, pvserver). Our sources make the leaf
// on rank 0 only, so usually nothing moves; a leaf split over ranks (D3, RedistributeDataSet, a partitioned reader)
// is gathered onto rank 0, its coincident points merged, and the filter runs once there: no rank duplicates or loses
// a part of the result. Header-only, for the VTK modules (the rest of common/ is VTK-free).
#pragma once

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCellData.h"
#include "vtkCleanPolyData.h"
#include "vtkDataObject.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"
#include "vtkSmartPointer.h"

#include <vector>

namespace plantmorph
{

namespace detail
{
/// Collective: whether every rank's piece must be gathered (true) or rank 0 already holds all there is (false).
inline bool PiecesOnOtherRanks(vtkMultiProcessController* controller, vtkDataSet* piece)
{
  const int ranks = controller->GetNumberOfProcesses();
  const int holds = piece && piece->GetNumberOfPoints() > 0 ? 1 : 0;
  std::vector<int> holders(static_cast<std::size_t>(ranks), 0);
  controller->AllGather(&holds, holders.data(), 1);
  for (int rank = 1; rank < ranks; ++rank)
  {
    if (holders[static_cast<std::size_t>(rank)])
    {
      return true;
    }
  }
  return false;
}
/// A piece without the ghost cells a partitioner (D3, RedistributeDataSet) adds along its seams: each cell then
/// comes from the one rank that owns it. The piece itself when it has none.
inline vtkSmartPointer<vtkDataObject> WithoutGhostCells(vtkPointSet* piece)
{
  if (!piece || !piece->HasAnyGhostCells())
  {
    return piece;
  }
  vtkSmartPointer<vtkPointSet> owned;
  owned.TakeReference(piece->NewInstance());
  owned->DeepCopy(piece);
  if (auto* polyData = vtkPolyData::SafeDownCast(owned))
  {
    polyData->RemoveGhostCells();
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(owned))
  {
    grid->RemoveGhostCells();
  }
  owned->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  owned->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  return owned;
}
} // namespace detail

/// Collective over the global controller's ranks (every rank must call it, as every rank runs the filter): returns
/// the whole dataset on rank 0 and an empty one on the other ranks. In serial, or when only rank 0 holds data, it
/// returns `piece` itself (no copy), so the result is bit-identical to a serial run. Pieces from several ranks are
/// appended in rank order and their exactly coincident points merged (their point order then differs from the
/// unsplit dataset's).
inline vtkSmartPointer<vtkPolyData> GatherOnFirstRank(vtkPolyData* piece)
{
  vtkSmartPointer<vtkPolyData> whole = piece;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return whole;
  }
  const bool rankZero = controller->GetLocalProcessId() == 0;
  if (!detail::PiecesOnOtherRanks(controller, piece))
  {
    return rankZero ? whole : vtkSmartPointer<vtkPolyData>::New();
  }
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(detail::WithoutGhostCells(piece), pieces, 0);
  if (!rankZero)
  {
    return vtkSmartPointer<vtkPolyData>::New();
  }
  vtkNew<vtkAppendPolyData> append;
  for (const auto& received : pieces)
  {
    auto* polyData = vtkPolyData::SafeDownCast(received);
    if (polyData && polyData->GetNumberOfPoints() > 0)
    {
      append->AddInputData(polyData);
    }
  }
  vtkNew<vtkCleanPolyData> merge;
  merge->SetInputConnection(append->GetOutputPort());
  merge->PointMergingOn();
  merge->SetTolerance(0.0);
  merge->ConvertLinesToPointsOff();
  merge->ConvertPolysToLinesOff();
  merge->ConvertStripsToPolysOff();
  merge->Update();
  whole = merge->GetOutput();
  return whole;
}

/// The same for any point set (a measured cloud may come as an unstructured grid): polygonal data as above, other
/// point sets appended into an unstructured grid with coincident points merged.
inline vtkSmartPointer<vtkPointSet> GatherOnFirstRank(vtkPointSet* piece)
{
  if (auto* polyData = vtkPolyData::SafeDownCast(piece))
  {
    return GatherOnFirstRank(polyData);
  }
  vtkSmartPointer<vtkPointSet> whole = piece;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return whole;
  }
  const bool rankZero = controller->GetLocalProcessId() == 0;
  if (!detail::PiecesOnOtherRanks(controller, piece))
  {
    return rankZero ? whole : vtkSmartPointer<vtkPointSet>(vtkSmartPointer<vtkUnstructuredGrid>::New());
  }
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(detail::WithoutGhostCells(piece), pieces, 0);
  if (!rankZero)
  {
    return vtkSmartPointer<vtkUnstructuredGrid>::New();
  }
  vtkNew<vtkAppendFilter> append;
  append->MergePointsOn();
  for (const auto& received : pieces)
  {
    auto* pointSet = vtkPointSet::SafeDownCast(received);
    if (pointSet && pointSet->GetNumberOfPoints() > 0)
    {
      append->AddInputData(pointSet);
    }
  }
  append->Update();
  whole = append->GetOutput();
  return whole;
}

} // namespace plantmorph
