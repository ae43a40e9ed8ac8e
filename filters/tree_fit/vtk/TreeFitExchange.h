// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFitFilter under MPI (pvbatch, pvserver): each tree is fitted whole on one owner rank, as LeafFitFilter's leaves.
//
// Every rank holds a piece of the input, and a tree's points may be spread over several pieces. The plan, the same on
// every rank (it depends only on the trees' ids and point counts, which every rank learns): each tree gets one owner
// rank by plantmorph::LeafOwners (common/vtk/PlantMorphLeafExchange.h), the rule every per-leaf filter shares: largest
// first, each to the least loaded rank. Every rank sends its points of each tree to the tree's owner (in rank order,
// each rank's points in its input order; the fit itself does not depend on the order, TreeFit.h); the owner fits the
// tree and sends each point's results back to the rank that holds the point, where the Scan output stays. The fitted
// trees (cylinders, branches, traits: small next to the points) are gathered on rank 0 in TreeId order, which writes
// Cylinders, Skeleton, Trees and Branches exactly as a serial run. Serially the same code runs without communication.
//
// Every function marked collective must be called by every rank, in the same order.
#pragma once

#include "TreeFit.h"

#include "vtkType.h"

#include <map>
#include <vector>

class vtkMultiProcessController;

namespace plantmorph
{
namespace treefitvtk
{

/// One rank's trees: TreeId -> ids of its points in the local piece, in input order.
using LocalTrees = std::map<int, std::vector<vtkIdType>>;

class TreeExchange
{
public:
  /// Collective: learns every rank's trees and point counts and assigns each tree its owner. `controller` null or
  /// of one process: serial.
  TreeExchange(vtkMultiProcessController* controller, const LocalTrees& local);

  /// Collective: true on every rank when `failed` is true on any rank.
  bool AnyRank(bool failed) const;

  /// Every tree's id over all ranks, ascending.
  const std::vector<int>& TreeIds() const { return this->Ids; }
  /// Indices (into TreeIds()) of the trees this rank owns, ascending.
  std::vector<std::size_t> Owned() const { return this->OwnedBy(this->MyRank); }
  int Rank() const { return this->MyRank; }
  int Ranks() const { return this->RankCount; }

  /// Collective: `width` values per local point (point i's at i * width) sent to the owners of their trees; returns,
  /// per owned tree (Owned() order), the values of its points: each rank's in turn, in rank order.
  std::vector<std::vector<double>> SendValues(
    const LocalTrees& local, const std::vector<double>& values, int width) const;

  /// Collective, the way back: `owned[k]` holds `width` values per point of the k-th owned tree, in SendValues'
  /// order; returns every local point's `width` values (NaN for points of no tree).
  std::vector<double> ReturnValues(
    const LocalTrees& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const;

  /// Collective: one block of any length per owned tree (Owned() order) onto rank 0, there one per tree in TreeIds()
  /// order; empty on the other ranks.
  std::vector<std::vector<double>> GatherBlocks(const std::vector<std::vector<double>>& owned) const;

  /// Collective: rank 0's `values` (any length) on every rank.
  void Broadcast(std::vector<double>& values) const;

private:
  std::vector<std::size_t> OwnedBy(int rank) const;
  /// Points rank `q` holds of the trees `rank` owns.
  vtkIdType CountFor(int q, int rank) const;

  vtkMultiProcessController* Controller = nullptr; // null when serial
  int RankCount = 1;
  int MyRank = 0;
  std::vector<int> Ids;
  std::vector<int> Owners;
  std::vector<std::vector<vtkIdType>> Counts; // Counts[q][tree]: points rank q holds of the tree
};

/// A tree's fit without its per-point vectors, as numbers (to travel between ranks), and back.
std::vector<double> PackFit(const TreeFitResult& fit);
TreeFitResult UnpackFit(const std::vector<double>& packed);

} // namespace treefitvtk
} // namespace plantmorph
