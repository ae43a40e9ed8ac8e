// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphWholeInput.h"

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
vtkSmartPointer<vtkDataObject> WithoutGhostCells(vtkPointSet* piece)
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

/// What this rank ends up with after the collective part of a gather.
enum class Gathered
{
  Piece,   ///< serial, or rank 0 when no other rank holds data: `piece` itself is the whole dataset
  Nothing, ///< a rank other than 0: an empty dataset
  Pieces   ///< rank 0 when other ranks hold data: `pieces` has every rank's piece, ghost cells removed, to merge
};

/// Collective over the global controller's ranks: finds who holds data (AllGather) and, only when a rank other than
/// 0 does, gathers every rank's piece onto rank 0.
Gathered GatherPieces(vtkPointSet* piece, std::vector<vtkSmartPointer<vtkDataObject>>& pieces)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return Gathered::Piece;
  }
  const int ranks = controller->GetNumberOfProcesses();
  const bool rankZero = controller->GetLocalProcessId() == 0;
  const int holds = piece && piece->GetNumberOfPoints() > 0 ? 1 : 0;
  std::vector<int> holders(static_cast<std::size_t>(ranks), 0);
  controller->AllGather(&holds, holders.data(), 1);
  bool others = false;
  for (int rank = 1; rank < ranks; ++rank)
  {
    others = others || holders[static_cast<std::size_t>(rank)] != 0;
  }
  if (!others)
  {
    return rankZero ? Gathered::Piece : Gathered::Nothing;
  }
  controller->Gather(WithoutGhostCells(piece), pieces, 0);
  return rankZero ? Gathered::Pieces : Gathered::Nothing;
}
/// Polygonal pieces appended in the given order, coincident points merged (tolerance 0), cells kept as they are.
vtkSmartPointer<vtkPolyData> MergePolyPieces(
  const std::vector<vtkSmartPointer<vtkDataObject>>& pieces, bool mergePoints)
{
  vtkNew<vtkAppendPolyData> append;
  for (const auto& received : pieces)
  {
    auto* polyData = vtkPolyData::SafeDownCast(received);
    if (polyData && polyData->GetNumberOfPoints() > 0)
    {
      append->AddInputData(polyData);
    }
  }
  if (!mergePoints)
  {
    append->Update();
    return append->GetOutput();
  }
  vtkNew<vtkCleanPolyData> merge;
  merge->SetInputConnection(append->GetOutputPort());
  merge->PointMergingOn();
  merge->SetTolerance(0.0);
  merge->ConvertLinesToPointsOff();
  merge->ConvertPolysToLinesOff();
  merge->ConvertStripsToPolysOff();
  merge->Update();
  return merge->GetOutput();
}

} // namespace detail

namespace
{
/// GatherOnFirstRank and AppendOnFirstRank (PlantMorphWholeInput.h): the pieces gathered on rank 0, appended in rank
/// order, their coincident points merged when `mergePoints`.
vtkSmartPointer<vtkPolyData> CollectOnFirstRank(vtkPolyData* piece, bool mergePoints)
{
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  switch (detail::GatherPieces(piece, pieces))
  {
    case detail::Gathered::Piece:
      return piece;
    case detail::Gathered::Nothing:
      return vtkSmartPointer<vtkPolyData>::New();
    case detail::Gathered::Pieces:
      break;
  }
  return detail::MergePolyPieces(pieces, mergePoints);
}
} // namespace

vtkSmartPointer<vtkPolyData> GatherOnFirstRank(vtkPolyData* piece)
{
  return CollectOnFirstRank(piece, true);
}

vtkSmartPointer<vtkPolyData> AppendOnFirstRank(vtkPolyData* piece)
{
  return CollectOnFirstRank(piece, false);
}

/// The same for any point set (a measured cloud may come as an unstructured grid): polygonal data as above, other
/// point sets appended into an unstructured grid with coincident points merged.
vtkSmartPointer<vtkPointSet> GatherOnFirstRank(vtkPointSet* piece)
{
  if (auto* polyData = vtkPolyData::SafeDownCast(piece))
  {
    return GatherOnFirstRank(polyData);
  }
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  switch (detail::GatherPieces(piece, pieces))
  {
    case detail::Gathered::Piece:
      return piece;
    case detail::Gathered::Nothing:
      return vtkSmartPointer<vtkUnstructuredGrid>::New();
    case detail::Gathered::Pieces:
      break;
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
  return append->GetOutput();
}

/// The same for a table (a reader's table split over the ranks by rows): collective; the whole table on rank 0, its
/// rows in rank order (the columns of rank 0's piece, or of the first piece with rows, matched by name), an empty
/// table on the other ranks. In serial, or when only rank 0 holds rows, `piece` itself.
vtkSmartPointer<vtkTable> GatherRowsOnFirstRank(vtkTable* piece)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return piece;
  }
  const int ranks = controller->GetNumberOfProcesses();
  const int holds = piece && piece->GetNumberOfRows() > 0 ? 1 : 0;
  std::vector<int> holders(static_cast<std::size_t>(ranks), 0);
  controller->AllGather(&holds, holders.data(), 1);
  bool others = false;
  for (int rank = 1; rank < ranks; ++rank)
  {
    others = others || holders[static_cast<std::size_t>(rank)] != 0;
  }
  const bool rankZero = controller->GetLocalProcessId() == 0;
  if (!others)
  {
    return rankZero ? vtkSmartPointer<vtkTable>(piece) : vtkSmartPointer<vtkTable>::New();
  }
  vtkNew<vtkTable> empty;
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(piece ? static_cast<vtkDataObject*>(piece) : empty.Get(), pieces, 0);
  auto whole = vtkSmartPointer<vtkTable>::New();
  if (!rankZero)
  {
    return whole;
  }
  vtkTable* first = nullptr;
  for (const auto& received : pieces)
  {
    auto* table = vtkTable::SafeDownCast(received);
    first = !first && table && table->GetNumberOfRows() > 0 ? table : first;
  }
  for (vtkIdType c = 0; first && c < first->GetNumberOfColumns(); ++c)
  {
    vtkAbstractArray* column = first->GetColumn(c);
    vtkSmartPointer<vtkAbstractArray> joined = vtk::TakeSmartPointer(column->NewInstance());
    joined->SetName(column->GetName());
    joined->SetNumberOfComponents(column->GetNumberOfComponents());
    for (const auto& received : pieces)
    {
      auto* table = vtkTable::SafeDownCast(received);
      vtkAbstractArray* part = table && column->GetName() ? table->GetColumnByName(column->GetName()) : nullptr;
      if (part && part->GetNumberOfTuples() > 0)
      {
        joined->InsertTuples(joined->GetNumberOfTuples(), part->GetNumberOfTuples(), 0, part);
      }
    }
    whole->AddColumn(joined);
  }
  return whole;
}

/// True in serial and on rank 0: where a gathered input is whole. A filter whose gathered input is empty there
/// says so (a warning naming the input), while the other ranks' empty pieces are expected and stay silent.
bool IsFirstRank()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return !controller || controller->GetNumberOfProcesses() < 2 || controller->GetLocalProcessId() == 0;
}

} // namespace plantmorph
