// SPDX-License-Identifier: GPL-3.0-or-later
// Filters that need one whole leaf (VenationFilter, WiltingSimulator) on an input of several leaves: each leaf is
// processed on one MPI rank (pvbatch, pvserver) instead of all on rank 0. Module PlantMorph::VTKCommon.
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
// the one copy of the rule, which the fitters' exchange (PlantMorphOwnerExchange.h) uses too. A leaf held by one
// rank moves whole to its owner (nothing moves when that is its owner); a leaf whose points are on several ranks is
// gathered on its owner, the pieces appended in rank order and their exactly coincident points merged. A leaf taken
// out of a piece keeps the input's point and cell order and every point, cell and field array, so a leaf alone and
// the same leaf among others give the same dataset.
// Serially the same code runs without communication: rank 0 owns every leaf.
//
// Every function marked collective must be called by every rank, in the same order.
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro
#include "PlantMorphWholeInput.h"

// What the per-leaf filters used to get from here.
#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
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
#include "vtkType.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace plantmorph
{

/// A LeafId: a 64-bit integer, read exactly from any integer array (a LeafId above 2^31 is its own leaf) and rounded
/// from a floating-point one.
using LeafIdType = vtkTypeInt64;

/// The LeafId of a point that belongs to no leaf.
constexpr LeafIdType NoLeaf = std::numeric_limits<LeafIdType>::min();

/// Value `i` of a one-component LeafId array as a LeafId: exact for integer arrays, rounded for floating-point ones
/// (NoLeaf for a value that is not finite or is beyond the 64-bit range).
PLANTMORPHVTKCOMMON_EXPORT LeafIdType LeafIdValue(vtkDataArray* ids, vtkIdType i);

/// Each point's LeafId by the rules above; an error message for a LeafId array of more than one component.
PLANTMORPHVTKCOMMON_EXPORT std::string IdentifyLeaves(vtkPolyData* piece, std::vector<LeafIdType>& leafOf);

/// The leaves `wanted` (ascending) of `piece`, each with its points (in the piece's order) and the cells all of
/// whose points are in it (in the piece's order, by type), with every point, cell and field array. One pass over the
/// piece for all of them.
PLANTMORPHVTKCOMMON_EXPORT std::map<LeafIdType, vtkSmartPointer<vtkPolyData>> ExtractLeaves(
  vtkPolyData* piece, const std::vector<LeafIdType>& leafOf, const std::vector<LeafIdType>& wanted);

/// Collective: every rank's (LeafId, point count) pairs, on every rank: element q is rank q's `mine`. `controller`
/// null (serial): just `mine`.
PLANTMORPHVTKCOMMON_EXPORT std::vector<std::map<vtkTypeInt64, vtkIdType>> LeafCountsOfRanks(
  vtkMultiProcessController* controller, const std::map<vtkTypeInt64, vtkIdType>& mine);

/// The leaves of every rank's counts (LeafCountsOfRanks) in ascending LeafId: their ids and their point counts summed
/// over the ranks, appended to `ids` and `points` (the input of LeafOwners).
PLANTMORPHVTKCOMMON_EXPORT void SumLeafCounts(const std::vector<std::map<vtkTypeInt64, vtkIdType>>& ranks,
  std::vector<vtkTypeInt64>& ids, std::vector<vtkIdType>& points);

/// The owner plan, the one rule of every per-leaf filter (LeafPlan here, the fitters' OwnerExchange of
/// PlantMorphOwnerExchange.h):
/// `points[k]` is leaf k's point count over all ranks, the leaves in ascending LeafId; returns each leaf's owner
/// rank. The leaves are taken largest first (ties: the smaller LeafId first), each given to the least loaded rank so
/// far (ties: the lower rank), a rank's load being the points of the leaves it owns.
PLANTMORPHVTKCOMMON_EXPORT std::vector<int> LeafOwners(const std::vector<vtkIdType>& points, int ranks);

/// The owner plan and the exchanges (see the top of this file).
class PLANTMORPHVTKCOMMON_EXPORT LeafPlan
{
public:
  /// Collective: splits this rank's `piece` into leaves, learns every rank's leaves and point counts and assigns
  /// each leaf its owner. `error` (empty when fine) is this rank's; check it with AnyRank.
  explicit LeafPlan(vtkPolyData* piece);

  /// Collective: true on every rank when `failed` is true on any rank.
  bool AnyRank(bool failed) const;

  const std::string& Error() const { return this->ErrorText; }
  /// Every leaf's id over all ranks, ascending.
  const std::vector<LeafIdType>& LeafIds() const { return this->Ids; }
  int Owner(std::size_t leaf) const { return this->Owners[leaf]; }
  /// The ids of the leaves this rank owns, ascending.
  std::vector<LeafIdType> Owned() const;
  /// True when a LeafId is beyond the int range: the LeafId arrays the filters add (MarkLeaf, WithLeafColumn) are
  /// then 64-bit for every leaf, else int as before.
  bool WideIds() const;
  /// True when rule 3 made the input gather on rank 0 first.
  bool GatheredFirst() const { return this->Gathered; }

  /// Collective: the whole leaves this rank owns, in Owned() order, from this rank's piece (the constructor's).
  std::vector<vtkSmartPointer<vtkPolyData>> Leaves() const { return this->Distribute(this->Piece, this->LeafOf); }

  /// Collective: another dataset split by its LeafId point array (`leafOf` per point, NoLeaf for none; e.g. the
  /// veins of the leaves), each leaf's part sent to that leaf's owner: one dataset per owned leaf, in Owned() order
  /// (empty where no rank holds a part). Parts of leaves the plan does not know are dropped.
  std::vector<vtkSmartPointer<vtkPolyData>> Distribute(vtkPolyData* piece, const std::vector<LeafIdType>& leafOf) const;

  /// Collective: `rows` (the rows of the leaves this rank owns, in Owned() order; its first column a LeafId) from
  /// every rank onto rank 0, the rows in LeafId order; an empty table on the other ranks.
  vtkSmartPointer<vtkTable> GatherRows(vtkTable* rows) const;

private:
  /// Every rank's (LeafId, count) pairs, then the owners (LeafOwners).
  void Plan(const std::map<LeafIdType, vtkIdType>& counts);

  vtkMultiProcessController* Controller = nullptr; // null when serial
  int Ranks = 1;
  int MyRank = 0;
  bool Gathered = false;
  std::string ErrorText;
  vtkSmartPointer<vtkPolyData> Piece = vtkSmartPointer<vtkPolyData>::New();
  std::vector<LeafIdType> LeafOf;
  std::vector<LeafIdType> Ids;
  std::vector<int> Owners;
};

/// Each point's LeafId from a dataset's one-component LeafId point array (NoLeaf where it has none); false when it
/// has points but no such array.
PLANTMORPHVTKCOMMON_EXPORT bool LeafIdsOfPoints(vtkPolyData* data, std::vector<LeafIdType>& leafOf);

/// Adds a one-component point array and cell array LeafId of value `leaf` to `data` (where it has none): int, or
/// 64-bit with `wide` (LeafPlan::WideIds).
PLANTMORPHVTKCOMMON_EXPORT void MarkLeaf(vtkDataSet* data, LeafIdType leaf, bool wide = false);

/// A copy of `table` with a first column LeafId of value `leaf` (one row per row of the table): int, or 64-bit with
/// `wide`.
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkTable> WithLeafColumn(
  vtkTable* table, LeafIdType leaf, bool wide = false);

/// Appends the rows of `from` to `into` (which takes `from`'s columns when it has none).
PLANTMORPHVTKCOMMON_EXPORT void AppendRows(vtkTable* into, vtkTable* from);

} // namespace plantmorph
