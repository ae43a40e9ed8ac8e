// SPDX-License-Identifier: GPL-3.0-or-later
// Filters that need one whole leaf (VenationFilter, WiltingSimulator) on an input of several leaves: each leaf is
// processed on one MPI rank (pvbatch, pvserver) instead of all on rank 0. Header-only, for the VTK modules.
//
// Which leaf a point belongs to (IdentifyLeaves):
// 1. a one-component point array named LeafId (rounded to an integer), else
// 2. a one-component cell array named LeafId (a point takes the LeafId of the first cell that uses it), else
// 3. the connected blades: points joined by any cell (polygon, strip, line, vertex) are one leaf, the leaves
//    numbered 0, 1, ... in the order of their first point (LeafOutlineSource's outputs appended in a pipeline:
//    the leaves in the order they were appended).
// Points no cell uses (rule 3) and non-finite LeafIds belong to no leaf and are left out. Under MPI, rule 3 needs a
// leaf whole on one rank: when several ranks hold points and some hold no LeafId array, the input is first gathered
// on rank 0 (PlantMorphWholeInput.h) and the blades found there.
//
// The plan (LeafPlan), the same on every rank: every leaf gets one owner rank, the leaves taken largest first (by
// points; ties: the smaller LeafId first), each to the least loaded rank so far (ties: the lower rank): LeafOwners,
// the one copy of the rule, which LeafFitFilter's exchange (filters/leaf_fit/vtk/LeafFitExchange.h) uses too. A leaf held by one
// rank moves whole to its owner (nothing moves when that is its owner); a leaf whose points are on several ranks is
// gathered on its owner, the pieces appended in rank order and their exactly coincident points merged. A leaf taken
// out of a piece keeps the input's point and cell order and every point, cell and field array, so a leaf alone and
// the same leaf among others give the same dataset.
// Serially the same code runs without communication: rank 0 owns every leaf.
//
// Every function marked collective must be called by every rank, in the same order.
#pragma once

#include "PlantMorphWholeInput.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace plantmorph
{

/// The LeafId of a point that belongs to no leaf.
constexpr int NoLeaf = INT_MIN;

/// Each point's LeafId by the rules above; an error message for a LeafId array of more than one component.
inline std::string IdentifyLeaves(vtkPolyData* piece, std::vector<int>& leafOf)
{
  const vtkIdType n = piece->GetNumberOfPoints();
  leafOf.assign(static_cast<std::size_t>(n), NoLeaf);
  const auto id = [](double value) { return std::isfinite(value) ? static_cast<int>(std::lround(value)) : NoLeaf; };
  if (vtkDataArray* ids = piece->GetPointData()->GetArray("LeafId"))
  {
    if (ids->GetNumberOfComponents() != 1)
      return "Input: the point array LeafId must have one component";
    for (vtkIdType i = 0; i < n; ++i)
      leafOf[static_cast<std::size_t>(i)] = id(ids->GetComponent(i, 0));
    return {};
  }
  vtkDataArray* cellIds = piece->GetCellData()->GetArray("LeafId");
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
        leafOf[p] = id(cellIds->GetComponent(c, 0));
      used[p] = true;
      if (!cellIds && k > 0)
        parent[root(p)] = root(points->GetId(0));
    }
  }
  if (cellIds)
    return {};
  std::map<vtkIdType, int> blade; // root -> number, in the order of the blades' first points
  for (vtkIdType i = 0; i < n; ++i)
    if (used[i])
      leafOf[i] = blade.emplace(root(i), static_cast<int>(blade.size())).first->second;
  return {};
}

/// The leaves `wanted` (ascending) of `piece`, each with its points (in the piece's order) and the cells all of
/// whose points are in it (in the piece's order, by type), with every point, cell and field array. One pass over the
/// piece for all of them.
inline std::map<int, vtkSmartPointer<vtkPolyData>> ExtractLeaves(
  vtkPolyData* piece, const std::vector<int>& leafOf, const std::vector<int>& wanted)
{
  std::map<int, vtkSmartPointer<vtkPolyData>> result;
  if (wanted.empty())
    return result;
  const auto indexOf = [&](int leaf) {
    const auto at = std::lower_bound(wanted.begin(), wanted.end(), leaf);
    return at != wanted.end() && *at == leaf ? static_cast<int>(at - wanted.begin()) : -1;
  };
  const vtkIdType n = piece->GetNumberOfPoints();
  std::vector<int> slot(static_cast<std::size_t>(n), -1);
  std::vector<vtkIdType> newId(static_cast<std::size_t>(n), -1);
  std::vector<vtkSmartPointer<vtkIdList>> pointIds(wanted.size());
  for (auto& ids : pointIds)
    ids = vtkSmartPointer<vtkIdList>::New();
  for (vtkIdType i = 0; i < n; ++i)
    if ((slot[i] = indexOf(leafOf[i])) >= 0)
    {
      newId[i] = pointIds[slot[i]]->GetNumberOfIds();
      pointIds[slot[i]]->InsertNextId(i);
    }
  // Cells by type (vtkPolyData numbers its cells verts, lines, polys, strips), each type in the piece's order.
  std::vector<std::array<vtkSmartPointer<vtkCellArray>, 4>> cells(wanted.size());
  std::vector<vtkSmartPointer<vtkIdList>> cellIds(wanted.size());
  for (std::size_t k = 0; k < wanted.size(); ++k)
  {
    for (auto& c : cells[k])
      c = vtkSmartPointer<vtkCellArray>::New();
    cellIds[k] = vtkSmartPointer<vtkIdList>::New();
  }
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
      cells[k][kind]->InsertNextCell(size, mapped.data());
      cellIds[k]->InsertNextId(cellId);
    }
  }
  for (std::size_t k = 0; k < wanted.size(); ++k)
  {
    auto leaf = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    points->SetDataType(piece->GetPoints() ? piece->GetPoints()->GetDataType() : VTK_FLOAT);
    points->SetNumberOfPoints(pointIds[k]->GetNumberOfIds());
    if (piece->GetPoints())
      piece->GetPoints()->GetData()->GetTuples(pointIds[k], points->GetData());
    leaf->SetPoints(points);
    leaf->GetPointData()->CopyAllocate(piece->GetPointData(), pointIds[k]->GetNumberOfIds());
    leaf->GetPointData()->SetNumberOfTuples(pointIds[k]->GetNumberOfIds());
    vtkNew<vtkIdList> to;
    to->SetNumberOfIds(pointIds[k]->GetNumberOfIds());
    std::iota(to->GetPointer(0), to->GetPointer(0) + to->GetNumberOfIds(), vtkIdType{ 0 });
    leaf->GetPointData()->CopyData(piece->GetPointData(), pointIds[k], to);
    leaf->SetVerts(cells[k][0]);
    leaf->SetLines(cells[k][1]);
    leaf->SetPolys(cells[k][2]);
    leaf->SetStrips(cells[k][3]);
    leaf->GetCellData()->CopyAllocate(piece->GetCellData(), cellIds[k]->GetNumberOfIds());
    leaf->GetCellData()->SetNumberOfTuples(cellIds[k]->GetNumberOfIds());
    to->SetNumberOfIds(cellIds[k]->GetNumberOfIds());
    std::iota(to->GetPointer(0), to->GetPointer(0) + to->GetNumberOfIds(), vtkIdType{ 0 });
    leaf->GetCellData()->CopyData(piece->GetCellData(), cellIds[k], to);
    leaf->GetFieldData()->PassData(piece->GetFieldData());
    result[wanted[k]] = leaf;
  }
  return result;
}

/// Collective: every rank's (LeafId, point count) pairs, on every rank: element q is rank q's `mine`. `controller`
/// null (serial): just `mine`.
inline std::vector<std::map<int, vtkIdType>> LeafCountsOfRanks(
  vtkMultiProcessController* controller, const std::map<int, vtkIdType>& mine)
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
  std::vector<std::map<int, vtkIdType>> result(lengths.size());
  for (std::size_t q = 0; q < lengths.size(); ++q)
    for (vtkIdType k = offsets[q]; k + 1 < offsets[q] + lengths[q]; k += 2)
      result[q][static_cast<int>(all[k])] += static_cast<vtkIdType>(all[k + 1]);
  return result;
}

/// The leaves of every rank's counts (LeafCountsOfRanks) in ascending LeafId: their ids and their point counts summed
/// over the ranks, appended to `ids` and `points` (the input of LeafOwners).
inline void SumLeafCounts(
  const std::vector<std::map<int, vtkIdType>>& ranks, std::vector<int>& ids, std::vector<vtkIdType>& points)
{
  std::map<int, vtkIdType> total;
  for (const auto& rank : ranks)
    for (const auto& leaf : rank)
      total[leaf.first] += leaf.second;
  for (const auto& leaf : total) // ascending LeafId
  {
    ids.push_back(leaf.first);
    points.push_back(leaf.second);
  }
}

/// The owner plan, the one rule of every per-leaf filter (LeafPlan here, LeafFitFilter's filters/leaf_fit/vtk/LeafFitExchange):
/// `points[k]` is leaf k's point count over all ranks, the leaves in ascending LeafId; returns each leaf's owner
/// rank. The leaves are taken largest first (ties: the smaller LeafId first), each given to the least loaded rank so
/// far (ties: the lower rank), a rank's load being the points of the leaves it owns.
inline std::vector<int> LeafOwners(const std::vector<vtkIdType>& points, int ranks)
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

/// The owner plan and the exchanges (see the top of this file).
class LeafPlan
{
public:
  /// Collective: splits this rank's `piece` into leaves, learns every rank's leaves and point counts and assigns
  /// each leaf its owner. `error` (empty when fine) is this rank's; check it with AnyRank.
  explicit LeafPlan(vtkPolyData* piece)
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
    const bool byArray =
      holds && (owned->GetPointData()->GetArray("LeafId") || owned->GetCellData()->GetArray("LeafId"));
    const int mine[2] = { holds ? 1 : 0, holds && !byArray ? 1 : 0 };
    int all[2] = { mine[0], mine[1] };
    if (this->Controller)
      this->Controller->AllReduce(mine, all, 2, vtkCommunicator::SUM_OP);
    this->Gathered = all[0] > 1 && all[1] > 0;
    if (this->Gathered)
      owned = GatherOnFirstRank(owned.Get());
    std::map<int, vtkIdType> counts;
    if (owned && owned->GetNumberOfPoints() > 0)
    {
      this->ErrorText = IdentifyLeaves(owned, this->LeafOf);
      if (this->ErrorText.empty())
      {
        for (int leaf : this->LeafOf)
          if (leaf != NoLeaf)
            ++counts[leaf];
        this->Piece = owned;
      }
    }
    this->Plan(counts);
  }

  /// Collective: true on every rank when `failed` is true on any rank.
  bool AnyRank(bool failed) const
  {
    const int mine = failed ? 1 : 0;
    int any = mine;
    if (this->Controller)
      this->Controller->AllReduce(&mine, &any, 1, vtkCommunicator::MAX_OP);
    return any != 0;
  }

  const std::string& Error() const { return this->ErrorText; }
  /// Every leaf's id over all ranks, ascending.
  const std::vector<int>& LeafIds() const { return this->Ids; }
  int Owner(std::size_t leaf) const { return this->Owners[leaf]; }
  /// The ids of the leaves this rank owns, ascending.
  std::vector<int> Owned() const
  {
    std::vector<int> owned;
    for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
      if (this->Owners[leaf] == this->MyRank)
        owned.push_back(this->Ids[leaf]);
    return owned;
  }
  /// True when rule 3 made the input gather on rank 0 first.
  bool GatheredFirst() const { return this->Gathered; }

  /// Collective: the whole leaves this rank owns, in Owned() order, from this rank's piece (the constructor's).
  std::vector<vtkSmartPointer<vtkPolyData>> Leaves() const { return this->Distribute(this->Piece, this->LeafOf); }

  /// Collective: another dataset split by its LeafId point array (`leafOf` per point, NoLeaf for none; e.g. the
  /// veins of the leaves), each leaf's part sent to that leaf's owner: one dataset per owned leaf, in Owned() order
  /// (empty where no rank holds a part). Parts of leaves the plan does not know are dropped.
  std::vector<vtkSmartPointer<vtkPolyData>> Distribute(vtkPolyData* piece, const std::vector<int>& leafOf) const
  {
    std::vector<vtkSmartPointer<vtkPolyData>> result;
    // Which ranks hold points of which leaf.
    std::vector<int> mine(this->Ids.size(), 0), holders(this->Ids.size() * this->Ranks, 0);
    for (int leaf : leafOf)
    {
      const auto at = std::lower_bound(this->Ids.begin(), this->Ids.end(), leaf);
      if (leaf != NoLeaf && at != this->Ids.end() && *at == leaf)
        mine[at - this->Ids.begin()] = 1;
    }
    if (this->Controller && !mine.empty())
      this->Controller->AllGather(mine.data(), holders.data(), static_cast<vtkIdType>(mine.size()));
    else
      holders = mine;
    std::vector<int> held;
    for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
      if (mine[leaf])
        held.push_back(this->Ids[leaf]);
    std::map<int, vtkSmartPointer<vtkPolyData>> parts = ExtractLeaves(piece, leafOf, held);
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

  /// Collective: `rows` (the rows of the leaves this rank owns, in Owned() order; its first column a LeafId) from
  /// every rank onto rank 0, the rows in LeafId order; an empty table on the other ranks.
  vtkSmartPointer<vtkTable> GatherRows(vtkTable* rows) const
  {
    if (!this->Controller)
      return rows;
    std::vector<vtkSmartPointer<vtkDataObject>> tables;
    this->Controller->Gather(rows, tables, 0);
    auto result = vtkSmartPointer<vtkTable>::New();
    if (this->MyRank != 0)
      return result;
    // (LeafId, table, row), sorted stably by LeafId: a leaf's rows are contiguous in its owner's table.
    std::vector<std::pair<int, std::pair<vtkTable*, vtkIdType>>> order;
    vtkTable* model = nullptr;
    for (const auto& object : tables)
    {
      auto* table = vtkTable::SafeDownCast(object);
      if (!table || table->GetNumberOfColumns() == 0 || table->GetNumberOfRows() == 0)
        continue;
      model = model ? model : table;
      vtkDataArray* ids = vtkDataArray::SafeDownCast(table->GetColumn(0));
      for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r)
        order.push_back({ ids ? static_cast<int>(ids->GetComponent(r, 0)) : 0, { table, r } });
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

private:
  /// Every rank's (LeafId, count) pairs, then the owners (LeafOwners).
  void Plan(const std::map<int, vtkIdType>& counts)
  {
    std::vector<vtkIdType> points;
    SumLeafCounts(LeafCountsOfRanks(this->Controller, counts), this->Ids, points);
    this->Owners = LeafOwners(points, this->Ranks);
  }

  vtkMultiProcessController* Controller = nullptr; // null when serial
  int Ranks = 1;
  int MyRank = 0;
  bool Gathered = false;
  std::string ErrorText;
  vtkSmartPointer<vtkPolyData> Piece = vtkSmartPointer<vtkPolyData>::New();
  std::vector<int> LeafOf;
  std::vector<int> Ids;
  std::vector<int> Owners;
};

/// Each point's LeafId from a dataset's one-component LeafId point array (NoLeaf where it has none); false when it
/// has points but no such array.
inline bool LeafIdsOfPoints(vtkPolyData* data, std::vector<int>& leafOf)
{
  const vtkIdType n = data ? data->GetNumberOfPoints() : 0;
  leafOf.assign(static_cast<std::size_t>(n), NoLeaf);
  vtkDataArray* ids = n > 0 ? data->GetPointData()->GetArray("LeafId") : nullptr;
  if (n > 0 && (!ids || ids->GetNumberOfComponents() != 1))
    return false;
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double value = ids->GetComponent(i, 0);
    leafOf[i] = std::isfinite(value) ? static_cast<int>(std::lround(value)) : NoLeaf;
  }
  return true;
}

/// Adds a one-component int point array and cell array LeafId of value `leaf` to `data` (where it has none).
inline void MarkLeaf(vtkDataSet* data, int leaf)
{
  const auto add = [leaf](vtkDataSetAttributes* attributes, vtkIdType count) {
    if (attributes->GetArray("LeafId"))
      return;
    vtkNew<vtkIntArray> ids;
    ids->SetName("LeafId");
    ids->SetNumberOfTuples(count);
    ids->FillValue(leaf);
    attributes->AddArray(ids);
  };
  add(data->GetPointData(), data->GetNumberOfPoints());
  add(data->GetCellData(), data->GetNumberOfCells());
}

/// A copy of `table` with a first column LeafId of value `leaf` (one row per row of the table).
inline vtkSmartPointer<vtkTable> WithLeafColumn(vtkTable* table, int leaf)
{
  auto result = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkIntArray> ids;
  ids->SetName("LeafId");
  ids->SetNumberOfTuples(table->GetNumberOfRows());
  ids->FillValue(leaf);
  result->AddColumn(ids);
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
    result->AddColumn(table->GetColumn(c));
  return result;
}

/// Appends the rows of `from` to `into` (which takes `from`'s columns when it has none).
inline void AppendRows(vtkTable* into, vtkTable* from)
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
