// SPDX-License-Identifier: GPL-3.0-or-later
// The owner exchange of the filters that fit each group of points (a leaf, a tree) whole on one MPI rank
// (LeafFitFilter, TreeFitFilter; pvbatch, pvserver). Module PlantMorph::VTKCommon.
//
// Every rank holds a piece of the input, and a group's points may be spread over several pieces. The plan, the same on
// every rank (it depends only on the groups' ids and point counts, which every rank learns): each group gets one owner
// rank by LeafOwners (PlantMorphLeafExchange.h), the rule every per-leaf filter shares: largest first (ties: the
// smaller id), each to the least loaded rank (ties: the lower rank). Every rank sends its values of each group's points
// to the group's owner (in rank order, each rank's points in its input order); the owner fits the group and sends
// each point's results back to the rank that holds the point. Per-group results (rows, blocks) are gathered on rank 0
// in id order. Group ids are 64-bit integers (a LeafId above 2^31 is its own group). Every buffer is laid out in a
// fixed order (ranks ascending, groups ascending) and the only reduction is a maximum of flags, so the results do not
// depend on the number of ranks. Serially (no controller, or one process) the same code runs without communication:
// rank 0 owns every group.
//
// Every function marked collective must be called by every rank, in the same order.
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

#include "vtkType.h"

#include <map>
#include <vector>

class vtkMultiProcessController;

namespace plantmorph
{

/// One rank's groups: group id -> ids of its points in the local piece, in input order.
using LocalGroups = std::map<vtkTypeInt64, std::vector<vtkIdType>>;

class PLANTMORPHVTKCOMMON_EXPORT OwnerExchange
{
public:
  /// Collective: learns every rank's groups and point counts and assigns each group its owner. `controller` null or
  /// of one process: serial.
  OwnerExchange(vtkMultiProcessController* controller, const LocalGroups& local);

  /// Collective: true on every rank when `failed` is true on any rank.
  bool AnyRank(bool failed) const;

  /// Every group's id over all ranks, ascending.
  const std::vector<vtkTypeInt64>& Ids() const { return this->GroupIds; }
  /// Indices (into Ids()) of the groups this rank owns, ascending.
  std::vector<std::size_t> Owned() const { return this->OwnedBy(this->MyRank); }
  int Owner(std::size_t group) const { return this->Owners[group]; }
  int Rank() const { return this->MyRank; }
  int Ranks() const { return this->RankCount; }

  /// Collective: `width` values per local point (point i's at i * width) sent to the owners of their groups; returns,
  /// per owned group (Owned() order), the values of its points: each rank's in turn, in rank order.
  std::vector<std::vector<double>> SendValues(
    const LocalGroups& local, const std::vector<double>& values, int width) const;

  /// Collective, the way back: `owned[k]` holds `width` values per point of the k-th owned group, in SendValues'
  /// order; returns every local point's `width` values (NaN for points of no group).
  std::vector<double> ReturnValues(
    const LocalGroups& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const;

  /// Collective: rows of `width` values, one per owned group in Owned() order, gathered onto rank 0 in id order
  /// (every group's row); empty on the other ranks.
  std::vector<double> GatherRows(const std::vector<double>& rows, int width) const;

  /// Collective: one block of any length per owned group (Owned() order) onto rank 0, there one per group in Ids()
  /// order; empty on the other ranks.
  std::vector<std::vector<double>> GatherBlocks(const std::vector<std::vector<double>>& owned) const;

  /// Collective: rank 0's `values` (any length) on every rank.
  void Broadcast(std::vector<double>& values) const;

private:
  std::vector<std::size_t> OwnedBy(int rank) const;
  /// Points rank `q` holds of the groups `rank` owns.
  vtkIdType CountFor(int q, int rank) const;
  /// Offsets (prefix sums) of the per-rank lengths of `width` values per point of the groups `owner` owns.
  void Layout(int owner, int width, std::vector<vtkIdType>& lengths, std::vector<vtkIdType>& offsets) const;

  vtkMultiProcessController* Controller = nullptr; // null when serial
  int RankCount = 1;
  int MyRank = 0;
  std::vector<vtkTypeInt64> GroupIds;
  std::vector<int> Owners;
  std::vector<std::vector<vtkIdType>> Counts; // Counts[q][group]: points rank q holds of the group
};

} // namespace plantmorph
