// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphLeafExchange.h"

#include "PlantMorphWholeInput.h"
#include "PlantMorphLayer.h" // AnyRank
#include <plantmorph/DataContract.h>

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkTypeInt64Array.h"
#include "vtkVariant.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace plantmorph
{

LeafIdType LeafIdValue(vtkDataArray* ids, vtkIdType i)
{
  if (ids->GetDataType() != VTK_FLOAT && ids->GetDataType() != VTK_DOUBLE) // an integer array: exact
  {
    bool valid = false;
    const LeafIdType value = ids->GetVariantValue(i).ToTypeInt64(&valid);
    return valid ? value : NoLeaf;
  }
  const double value = ids->GetComponent(i, 0);
  // 2^63 is the first double beyond the range; -2^63 is NoLeaf itself.
  return std::isfinite(value) && std::abs(value) < 9223372036854775808.0 ? static_cast<LeafIdType>(std::llround(value))
                                                                         : NoLeaf;
}

std::string IdentifyLeaves(vtkPolyData* piece, std::vector<LeafIdType>& leafOf)
{
  const vtkIdType n = piece->GetNumberOfPoints();
  leafOf.assign(static_cast<std::size_t>(n), NoLeaf);
  if (vtkDataArray* ids = piece->GetPointData()->GetArray(plantmorph::arrays::LeafId))
  {
    if (ids->GetNumberOfComponents() != 1)
      return "Input: the point array LeafId must have one component";
    for (vtkIdType i = 0; i < n; ++i)
      leafOf[static_cast<std::size_t>(i)] = LeafIdValue(ids, i);
    return {};
  }
  vtkDataArray* cellIds = piece->GetCellData()->GetArray(plantmorph::arrays::LeafId);
  if (cellIds && cellIds->GetNumberOfComponents() != 1)
    return "Input: the cell array LeafId must have one component";
  // Rule 2 (first cell wins) or rule 3 (union-find over the cells' points).
  std::vector<vtkIdType> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](vtkIdType i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<bool> used(static_cast<std::size_t>(n), false);
  vtkNew<vtkIdList> points;
  for (vtkIdType c = 0; c < piece->GetNumberOfCells(); ++c)
  {
    piece->GetCellPoints(c, points);
    for (vtkIdType k = 0; k < points->GetNumberOfIds(); ++k)
    {
      const vtkIdType p = points->GetId(k);
      if (cellIds && !used[p])
        leafOf[p] = LeafIdValue(cellIds, c);
      used[p] = true;
      if (!cellIds && k > 0)
        parent[root(p)] = root(points->GetId(0));
    }
  }
  if (cellIds)
    return {};
  std::map<vtkIdType, LeafIdType> blade; // root -> number, in the order of the blades' first points
  for (vtkIdType i = 0; i < n; ++i)
    if (used[i])
      leafOf[i] = blade.emplace(root(i), static_cast<LeafIdType>(blade.size())).first->second;
  return {};
}

namespace
{
/// One wanted leaf's parts while ExtractLeaves walks the piece: its points' ids in the piece, its cells by type
/// (verts, lines, polys, strips) and their ids in the piece.
struct LeafParts
{
  vtkSmartPointer<vtkIdList> pointIds = vtkSmartPointer<vtkIdList>::New();
  std::array<vtkSmartPointer<vtkCellArray>, 4> cells = { vtkSmartPointer<vtkCellArray>::New(),
    vtkSmartPointer<vtkCellArray>::New(), vtkSmartPointer<vtkCellArray>::New(), vtkSmartPointer<vtkCellArray>::New() };
  vtkSmartPointer<vtkIdList> cellIds = vtkSmartPointer<vtkIdList>::New();
};

/// Each cell of `piece` all of whose points are in one wanted leaf (`slot` per point, -1 for none), renumbered by
/// `newId`, into that leaf's cells; by type (vtkPolyData numbers its cells verts, lines, polys, strips), each type in
/// the piece's order.
void SortCells(
  vtkPolyData* piece, const std::vector<int>& slot, const std::vector<vtkIdType>& newId, std::vector<LeafParts>& parts)
{
  vtkCellArray* kinds[4] = { piece->GetVerts(), piece->GetLines(), piece->GetPolys(), piece->GetStrips() };
  vtkIdType cellId = 0;
  std::vector<vtkIdType> mapped;
  for (int kind = 0; kind < 4; ++kind)
  {
    if (!kinds[kind])
      continue;
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    auto it = vtk::TakeSmartPointer(kinds[kind]->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      it->GetCurrentCell(size, ids);
      const int k = size > 0 ? slot[ids[0]] : -1;
      bool inside = k >= 0;
      mapped.resize(static_cast<std::size_t>(size));
      for (vtkIdType j = 0; inside && j < size; ++j)
      {
        inside = slot[ids[j]] == k;
        mapped[j] = newId[ids[j]];
      }
      if (!inside)
        continue;
      parts[k].cells[kind]->InsertNextCell(size, mapped.data());
      parts[k].cellIds->InsertNextId(cellId);
    }
  }
}

/// `from`'s tuples `ids` copied, in that order, into `to` (allocated like `from`).
void CopyTuples(vtkDataSetAttributes* from, vtkIdList* ids, vtkDataSetAttributes* to)
{
  to->CopyAllocate(from, ids->GetNumberOfIds());
  to->SetNumberOfTuples(ids->GetNumberOfIds());
  vtkNew<vtkIdList> order;
  order->SetNumberOfIds(ids->GetNumberOfIds());
  std::iota(order->GetPointer(0), order->GetPointer(0) + order->GetNumberOfIds(), vtkIdType{ 0 });
  to->CopyData(from, ids, order);
}

/// The leaf of `parts` as a dataset with the piece's point, cell and field arrays.
vtkSmartPointer<vtkPolyData> AssembleLeaf(vtkPolyData* piece, const LeafParts& parts)
{
  auto leaf = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(piece->GetPoints() ? piece->GetPoints()->GetDataType() : VTK_FLOAT);
  points->SetNumberOfPoints(parts.pointIds->GetNumberOfIds());
  if (piece->GetPoints())
    piece->GetPoints()->GetData()->GetTuples(parts.pointIds, points->GetData());
  leaf->SetPoints(points);
  CopyTuples(piece->GetPointData(), parts.pointIds, leaf->GetPointData());
  leaf->SetVerts(parts.cells[0]);
  leaf->SetLines(parts.cells[1]);
  leaf->SetPolys(parts.cells[2]);
  leaf->SetStrips(parts.cells[3]);
  CopyTuples(piece->GetCellData(), parts.cellIds, leaf->GetCellData());
  leaf->GetFieldData()->PassData(piece->GetFieldData());
  return leaf;
}
} // namespace

std::map<LeafIdType, vtkSmartPointer<vtkPolyData>> ExtractLeaves(
  vtkPolyData* piece, const std::vector<LeafIdType>& leafOf, const std::vector<LeafIdType>& wanted)
{
  std::map<LeafIdType, vtkSmartPointer<vtkPolyData>> result;
  if (wanted.empty())
    return result;
  const auto indexOf = [&](LeafIdType leaf) {
    const auto at = std::lower_bound(wanted.begin(), wanted.end(), leaf);
    return at != wanted.end() && *at == leaf ? static_cast<int>(at - wanted.begin()) : -1;
  };
  const vtkIdType n = piece->GetNumberOfPoints();
  std::vector<int> slot(static_cast<std::size_t>(n), -1);
  std::vector<vtkIdType> newId(static_cast<std::size_t>(n), -1);
  std::vector<LeafParts> parts(wanted.size());
  for (vtkIdType i = 0; i < n; ++i)
    if ((slot[i] = indexOf(leafOf[i])) >= 0)
    {
      newId[i] = parts[slot[i]].pointIds->GetNumberOfIds();
      parts[slot[i]].pointIds->InsertNextId(i);
    }
  SortCells(piece, slot, newId, parts);
  for (std::size_t k = 0; k < wanted.size(); ++k)
    result[wanted[k]] = AssembleLeaf(piece, parts[k]);
  return result;
}

std::vector<std::map<vtkTypeInt64, vtkIdType>> LeafCountsOfRanks(
  vtkMultiProcessController* controller, const std::map<vtkTypeInt64, vtkIdType>& mine)
{
  if (!controller || controller->GetNumberOfProcesses() < 2)
    return { mine };
  std::vector<long long> flat;
  for (const auto& leaf : mine)
  {
    flat.push_back(leaf.first);
    flat.push_back(static_cast<long long>(leaf.second));
  }
  const vtkIdType length = static_cast<vtkIdType>(flat.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(controller->GetNumberOfProcesses()), 0);
  std::vector<vtkIdType> offsets(lengths.size(), 0);
  controller->AllGather(&length, lengths.data(), 1);
  for (std::size_t q = 1; q < lengths.size(); ++q)
    offsets[q] = offsets[q - 1] + lengths[q - 1];
  std::vector<long long> all(static_cast<std::size_t>(offsets.back() + lengths.back()) + 1, 0); // +1: never null
  flat.push_back(0);
  controller->AllGatherV(flat.data(), all.data(), length, lengths.data(), offsets.data());
  std::vector<std::map<vtkTypeInt64, vtkIdType>> result(lengths.size());
  for (std::size_t q = 0; q < lengths.size(); ++q)
    for (vtkIdType k = offsets[q]; k + 1 < offsets[q] + lengths[q]; k += 2)
      result[q][static_cast<vtkTypeInt64>(all[k])] += static_cast<vtkIdType>(all[k + 1]);
  return result;
}

void SumLeafCounts(const std::vector<std::map<vtkTypeInt64, vtkIdType>>& ranks, std::vector<vtkTypeInt64>& ids,
  std::vector<vtkIdType>& points)
{
  std::map<vtkTypeInt64, vtkIdType> total;
  for (const auto& rank : ranks)
    for (const auto& leaf : rank)
      total[leaf.first] += leaf.second;
  for (const auto& leaf : total) // ascending LeafId
  {
    ids.push_back(leaf.first);
    points.push_back(leaf.second);
  }
}

std::vector<int> LeafOwners(const std::vector<vtkIdType>& points, int ranks)
{
  std::vector<std::size_t> index(points.size());
  std::iota(index.begin(), index.end(), 0);
  std::stable_sort(index.begin(), index.end(), [&](std::size_t a, std::size_t b) { return points[a] > points[b]; });
  std::vector<vtkIdType> load(static_cast<std::size_t>(std::max(ranks, 1)), 0);
  std::vector<int> owners(points.size(), 0);
  for (std::size_t leaf : index)
  {
    const auto least = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    owners[leaf] = least;
    load[least] += points[leaf];
  }
  return owners;
}

LeafPlan::LeafPlan(vtkPolyData* piece)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    this->Controller = controller;
    this->Ranks = controller->GetNumberOfProcesses();
    this->MyRank = controller->GetLocalProcessId();
  }
  vtkSmartPointer<vtkPolyData> owned = vtkPolyData::SafeDownCast(detail::WithoutGhostCells(piece));
  // Rule 3 needs whole blades: gather on rank 0 when several ranks hold points and one has no LeafId array.
  const bool holds = owned && owned->GetNumberOfPoints() > 0;
  const bool byArray = holds &&
    (owned->GetPointData()->GetArray(plantmorph::arrays::LeafId) ||
      owned->GetCellData()->GetArray(plantmorph::arrays::LeafId));
  const int mine[2] = { holds ? 1 : 0, holds && !byArray ? 1 : 0 };
  int all[2] = { mine[0], mine[1] };
  if (this->Controller)
    this->Controller->AllReduce(mine, all, 2, vtkCommunicator::SUM_OP);
  this->Gathered = all[0] > 1 && all[1] > 0;
  if (this->Gathered)
    owned = GatherOnFirstRank(owned.Get());
  std::map<LeafIdType, vtkIdType> counts;
  if (owned && owned->GetNumberOfPoints() > 0)
  {
    this->ErrorText = IdentifyLeaves(owned, this->LeafOf);
    if (this->ErrorText.empty())
    {
      for (LeafIdType leaf : this->LeafOf)
        if (leaf != NoLeaf)
          ++counts[leaf];
      this->Piece = owned;
    }
  }
  this->Plan(counts);
}

bool LeafPlan::AnyRank(bool failed) const
{
  return plantmorph::AnyRank(this->Controller, failed);
}

std::vector<LeafIdType> LeafPlan::Owned() const
{
  std::vector<LeafIdType> owned;
  for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
    if (this->Owners[leaf] == this->MyRank)
      owned.push_back(this->Ids[leaf]);
  return owned;
}

bool LeafPlan::WideIds() const
{
  return std::any_of(this->Ids.begin(), this->Ids.end(),
    [](LeafIdType id) { return id < std::numeric_limits<int>::min() || id > std::numeric_limits<int>::max(); });
}

std::vector<vtkSmartPointer<vtkPolyData>> LeafPlan::Distribute(
  vtkPolyData* piece, const std::vector<LeafIdType>& leafOf) const
{
  std::vector<vtkSmartPointer<vtkPolyData>> result;
  // Which ranks hold points of which leaf.
  std::vector<int> mine(this->Ids.size(), 0), holders(this->Ids.size() * this->Ranks, 0);
  for (LeafIdType leaf : leafOf)
  {
    const auto at = std::lower_bound(this->Ids.begin(), this->Ids.end(), leaf);
    if (leaf != NoLeaf && at != this->Ids.end() && *at == leaf)
      mine[at - this->Ids.begin()] = 1;
  }
  if (this->Controller && !mine.empty())
    this->Controller->AllGather(mine.data(), holders.data(), static_cast<vtkIdType>(mine.size()));
  else
    holders = mine;
  std::vector<LeafIdType> held;
  for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
    if (mine[leaf])
      held.push_back(this->Ids[leaf]);
  std::map<LeafIdType, vtkSmartPointer<vtkPolyData>> parts = ExtractLeaves(piece, leafOf, held);
  for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
  {
    const int owner = this->Owners[leaf];
    std::vector<int> from;
    for (int q = 0; q < this->Ranks; ++q)
      if (holders[q * this->Ids.size() + leaf])
        from.push_back(q);
    vtkSmartPointer<vtkPolyData> part = mine[leaf] ? parts[this->Ids[leaf]] : nullptr;
    vtkSmartPointer<vtkPolyData> whole;
    if (from.size() == 1 && from[0] == owner)
      whole = part; // the usual case: nothing moves
    else if (from.size() == 1)
    {
      const int tag = 8721;
      if (this->MyRank == from[0])
        this->Controller->Send(part.Get(), owner, tag);
      else if (this->MyRank == owner)
      {
        whole = vtkSmartPointer<vtkPolyData>::New();
        this->Controller->Receive(whole.Get(), from[0], tag);
      }
    }
    else if (from.size() > 1)
    {
      auto empty = vtkSmartPointer<vtkPolyData>::New();
      std::vector<vtkSmartPointer<vtkDataObject>> pieces;
      this->Controller->Gather(part ? part.Get() : empty.Get(), pieces, owner);
      if (this->MyRank == owner)
        whole = detail::MergePolyPieces(pieces);
    }
    if (owner == this->MyRank)
      result.push_back(whole ? whole : vtkSmartPointer<vtkPolyData>::New());
  }
  return result;
}

vtkSmartPointer<vtkTable> LeafPlan::GatherRows(vtkTable* rows) const
{
  if (!this->Controller)
    return rows;
  std::vector<vtkSmartPointer<vtkDataObject>> tables;
  this->Controller->Gather(rows, tables, 0);
  auto result = vtkSmartPointer<vtkTable>::New();
  if (this->MyRank != 0)
    return result;
  // (LeafId, table, row), sorted stably by LeafId: a leaf's rows are contiguous in its owner's table.
  std::vector<std::pair<LeafIdType, std::pair<vtkTable*, vtkIdType>>> order;
  vtkTable* model = nullptr;
  for (const auto& object : tables)
  {
    auto* table = vtkTable::SafeDownCast(object);
    if (!table || table->GetNumberOfColumns() == 0 || table->GetNumberOfRows() == 0)
      continue;
    model = model ? model : table;
    vtkDataArray* ids = vtkDataArray::SafeDownCast(table->GetColumn(0));
    for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r)
      order.push_back({ ids ? LeafIdValue(ids, r) : 0, { table, r } });
  }
  if (!model)
    return result;
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (vtkIdType c = 0; c < model->GetNumberOfColumns(); ++c)
  {
    vtkSmartPointer<vtkAbstractArray> column;
    column.TakeReference(model->GetColumn(c)->NewInstance());
    column->SetName(model->GetColumn(c)->GetName());
    column->SetNumberOfComponents(model->GetColumn(c)->GetNumberOfComponents());
    for (const auto& row : order)
      column->InsertNextTuple(row.second.second, row.second.first->GetColumn(c));
    result->AddColumn(column);
  }
  return result;
}

void LeafPlan::Plan(const std::map<LeafIdType, vtkIdType>& counts)
{
  std::vector<vtkIdType> points;
  SumLeafCounts(LeafCountsOfRanks(this->Controller, counts), this->Ids, points);
  this->Owners = LeafOwners(points, this->Ranks);
}

bool LeafIdsOfPoints(vtkPolyData* data, std::vector<LeafIdType>& leafOf)
{
  const vtkIdType n = data ? data->GetNumberOfPoints() : 0;
  leafOf.assign(static_cast<std::size_t>(n), NoLeaf);
  vtkDataArray* ids = n > 0 ? data->GetPointData()->GetArray(plantmorph::arrays::LeafId) : nullptr;
  if (n > 0 && (!ids || ids->GetNumberOfComponents() != 1))
    return false;
  for (vtkIdType i = 0; i < n; ++i)
    leafOf[i] = LeafIdValue(ids, i);
  return true;
}

namespace
{
/// `count` values `leaf` in an array LeafId: int, or 64-bit when `wide`.
vtkSmartPointer<vtkDataArray> LeafIdArray(LeafIdType leaf, vtkIdType count, bool wide)
{
  vtkSmartPointer<vtkDataArray> ids;
  if (wide)
  {
    auto wideIds = vtkSmartPointer<vtkTypeInt64Array>::New();
    wideIds->SetNumberOfTuples(count);
    wideIds->FillValue(leaf);
    ids = wideIds;
  }
  else
  {
    auto intIds = vtkSmartPointer<vtkIntArray>::New();
    intIds->SetNumberOfTuples(count);
    intIds->FillValue(static_cast<int>(leaf));
    ids = intIds;
  }
  ids->SetName(plantmorph::arrays::LeafId);
  return ids;
}
} // namespace

void MarkLeaf(vtkDataSet* data, LeafIdType leaf, bool wide)
{
  const auto add = [leaf, wide](vtkDataSetAttributes* attributes, vtkIdType count) {
    if (!attributes->GetArray(plantmorph::arrays::LeafId))
      attributes->AddArray(LeafIdArray(leaf, count, wide));
  };
  add(data->GetPointData(), data->GetNumberOfPoints());
  add(data->GetCellData(), data->GetNumberOfCells());
}

vtkSmartPointer<vtkTable> WithLeafColumn(vtkTable* table, LeafIdType leaf, bool wide)
{
  auto result = vtkSmartPointer<vtkTable>::New();
  result->AddColumn(LeafIdArray(leaf, table->GetNumberOfRows(), wide));
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
    result->AddColumn(table->GetColumn(c));
  return result;
}

void AppendRows(vtkTable* into, vtkTable* from)
{
  if (into->GetNumberOfColumns() == 0)
    for (vtkIdType c = 0; c < from->GetNumberOfColumns(); ++c)
    {
      vtkSmartPointer<vtkAbstractArray> column;
      column.TakeReference(from->GetColumn(c)->NewInstance());
      column->SetName(from->GetColumn(c)->GetName());
      column->SetNumberOfComponents(from->GetColumn(c)->GetNumberOfComponents());
      into->AddColumn(column);
    }
  for (vtkIdType c = 0; c < from->GetNumberOfColumns() && c < into->GetNumberOfColumns(); ++c)
    for (vtkIdType r = 0; r < from->GetNumberOfRows(); ++r)
      into->GetColumn(c)->InsertNextTuple(r, from->GetColumn(c));
}
} // namespace plantmorph
