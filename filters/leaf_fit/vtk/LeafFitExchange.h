// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFitFilter under MPI (pvbatch, pvserver): each rank fits its own leaves.
//
// Every rank holds a piece of the input, and a leaf's points may be spread over several pieces. The plan, the same
// on every rank (it depends only on the leaves' ids and point counts, which every rank learns): each leaf gets one
// owner rank, the leaves taken largest first (ties: smaller LeafId first) and each given to the least loaded rank so
// far (ties: the lower rank), the load being the points a rank fits: plantmorph::LeafOwners of
// common/vtk/PlantMorphLeafExchange.h, the rule every per-leaf filter shares. Every rank sends its points of each leaf to the
// leaf's owner (in rank order, each rank's points in its input order); the owner fits the leaf and sends each point's
// per-point results (FitDistance, Inlier) back to the rank that holds the point, where the Scan output stays. Blade
// and Outline stay on the owner. The Traits rows are gathered onto rank 0 in LeafId order. Serially (no controller,
// or one process) the same code runs without communication: rank 0 owns every leaf.
//
// Every function marked collective must be called by every rank, in the same order.
#pragma once

#include "vtkType.h"

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

class vtkMultiProcessController;

namespace plantmorph
{
namespace fitmpi
{

/// One rank's leaves: LeafId -> ids of its points in the local piece, in input order.
using LocalLeaves = std::map<int, std::vector<vtkIdType>>;

class LeafExchange
{
public:
  /// Collective: learns every rank's leaves and point counts and assigns each leaf its owner.
  explicit LeafExchange(vtkMultiProcessController* controller, const LocalLeaves& local);

  /// Collective: true on every rank when `failed` is true on any rank.
  bool AnyRank(bool failed) const;

  /// Every leaf's id over all ranks, ascending.
  const std::vector<int>& LeafIds() const { return this->Ids; }
  /// Indices (into LeafIds()) of the leaves this rank owns, ascending.
  std::vector<std::size_t> Owned() const { return this->OwnedBy(this->MyRank); }
  int Owner(std::size_t leaf) const { return this->Owners[leaf]; }
  int Rank() const { return this->MyRank; }

  /// Collective: the points of every leaf this rank owns (in Owned() order), each the concatenation over ranks, in
  /// rank order, of that rank's points of the leaf in its input order. `points` are the local piece's points.
  std::vector<std::vector<Eigen::Vector3d>> SendPoints(
    const LocalLeaves& local, const std::vector<Eigen::Vector3d>& points) const;

  /// Collective: per-point values computed by the owners (`owned[k]`: `width` values per point of the k-th owned
  /// leaf, in the order SendPoints gave them) back to the ranks holding the points; returns, for every local
  /// point, its `width` values (NaN for points of no leaf).
  std::vector<double> ReturnValues(
    const LocalLeaves& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const;

  /// Collective: rows of `width` values, one per owned leaf in Owned() order, gathered onto rank 0 in LeafId order
  /// (every leaf's row); empty on the other ranks.
  std::vector<double> GatherRows(const std::vector<double>& rows, int width) const;

private:
  std::vector<std::size_t> OwnedBy(int rank) const;
  /// Points rank `q` holds of the leaves `rank` owns.
  vtkIdType CountFor(int q, int rank) const;

  vtkMultiProcessController* Controller = nullptr; // null when serial
  int Ranks = 1;
  int MyRank = 0;
  std::vector<int> Ids;
  std::vector<int> Owners;
  std::vector<std::vector<vtkIdType>> Counts; // Counts[q][leaf]: points rank q holds of the leaf
};

} // namespace fitmpi
} // namespace plantmorph
