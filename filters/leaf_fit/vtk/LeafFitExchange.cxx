// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafFitExchange.h"

#include "PlantMorphLeafExchange.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace plantmorph
{
namespace fitmpi
{
namespace
{
/// Offsets (prefix sums) of per-rank lengths.
std::vector<vtkIdType> Offsets(const std::vector<vtkIdType>& lengths)
{
  std::vector<vtkIdType> offsets(lengths.size(), 0);
  for (std::size_t q = 1; q < lengths.size(); ++q)
    offsets[q] = offsets[q - 1] + lengths[q - 1];
  return offsets;
}

/// A buffer's data, never null (MPI implementations may reject null buffers even of length 0).
template <typename T>
T* Data(std::vector<T>& v)
{
  static thread_local T dummy{};
  return v.empty() ? &dummy : v.data();
}
} // namespace

LeafExchange::LeafExchange(vtkMultiProcessController* controller, const LocalLeaves& local)
{
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    this->Controller = controller;
    this->Ranks = controller->GetNumberOfProcesses();
    this->MyRank = controller->GetLocalProcessId();
  }
  // Every rank's (LeafId, count) pairs, then the owners: the common rule (PlantMorphLeafExchange.h).
  std::map<int, vtkIdType> mine;
  for (const auto& leaf : local)
    mine[leaf.first] = static_cast<vtkIdType>(leaf.second.size());
  const std::vector<std::map<int, vtkIdType>> ranks = LeafCountsOfRanks(this->Controller, mine);
  std::vector<vtkIdType> points;
  SumLeafCounts(ranks, this->Ids, points);
  this->Counts.assign(static_cast<std::size_t>(this->Ranks), std::vector<vtkIdType>(this->Ids.size(), 0));
  for (std::size_t q = 0; q < ranks.size(); ++q)
    for (const auto& leaf : ranks[q])
    {
      const auto at = std::lower_bound(this->Ids.begin(), this->Ids.end(), leaf.first) - this->Ids.begin();
      this->Counts[q][static_cast<std::size_t>(at)] = leaf.second;
    }
  this->Owners = LeafOwners(points, this->Ranks);
}

bool LeafExchange::AnyRank(bool failed) const
{
  if (!this->Controller)
    return failed;
  const int mine = failed ? 1 : 0;
  int any = 0;
  this->Controller->AllReduce(&mine, &any, 1, vtkCommunicator::MAX_OP);
  return any != 0;
}

std::vector<std::size_t> LeafExchange::OwnedBy(int rank) const
{
  std::vector<std::size_t> owned;
  for (std::size_t leaf = 0; leaf < this->Ids.size(); ++leaf)
    if (this->Owners[leaf] == rank)
      owned.push_back(leaf);
  return owned;
}

vtkIdType LeafExchange::CountFor(int q, int rank) const
{
  vtkIdType count = 0;
  for (std::size_t leaf : this->OwnedBy(rank))
    count += this->Counts[q][leaf];
  return count;
}

std::vector<std::vector<Eigen::Vector3d>> LeafExchange::SendPoints(
  const LocalLeaves& local, const std::vector<Eigen::Vector3d>& points) const
{
  std::vector<std::vector<Eigen::Vector3d>> result;
  for (int owner = 0; owner < this->Ranks; ++owner)
  {
    const std::vector<std::size_t> owned = this->OwnedBy(owner);
    std::vector<double> send;
    for (std::size_t leaf : owned)
    {
      const auto it = local.find(this->Ids[leaf]);
      if (it != local.end())
        for (vtkIdType i : it->second)
          send.insert(send.end(), points[i].data(), points[i].data() + 3);
    }
    std::vector<double> received;
    std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->Ranks), 0);
    for (int q = 0; q < this->Ranks; ++q)
      lengths[q] = 3 * this->CountFor(q, owner);
    const std::vector<vtkIdType> offsets = Offsets(lengths);
    if (this->Controller)
    {
      if (owner == this->MyRank)
        received.assign(static_cast<std::size_t>(offsets.back() + lengths.back()), 0.0);
      this->Controller->GatherV(Data(send), Data(received), static_cast<vtkIdType>(send.size()), lengths.data(),
        const_cast<vtkIdType*>(offsets.data()), owner);
    }
    else
      received = send;
    if (owner != this->MyRank)
      continue;
    // Rank q's part holds its points of each owned leaf in turn; a leaf's points are its parts in rank order.
    result.assign(owned.size(), {});
    for (int q = 0; q < this->Ranks; ++q)
    {
      vtkIdType at = offsets[q];
      for (std::size_t k = 0; k < owned.size(); ++k)
        for (vtkIdType j = 0; j < this->Counts[q][owned[k]]; ++j, at += 3)
          result[k].emplace_back(received[at], received[at + 1], received[at + 2]);
    }
  }
  return result;
}

std::vector<double> LeafExchange::ReturnValues(
  const LocalLeaves& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const
{
  std::vector<double> values(static_cast<std::size_t>(localPoints * width), std::numeric_limits<double>::quiet_NaN());
  for (int owner = 0; owner < this->Ranks; ++owner)
  {
    const std::vector<std::size_t> leaves = this->OwnedBy(owner);
    std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->Ranks), 0);
    for (int q = 0; q < this->Ranks; ++q)
      lengths[q] = width * this->CountFor(q, owner);
    const std::vector<vtkIdType> offsets = Offsets(lengths);
    std::vector<double> send;
    if (owner == this->MyRank)
    {
      // Rank q's part: its points of each owned leaf in turn, which start in the leaf's values after the parts of
      // the ranks before q.
      for (int q = 0; q < this->Ranks; ++q)
        for (std::size_t k = 0; k < leaves.size(); ++k)
        {
          vtkIdType before = 0;
          for (int p = 0; p < q; ++p)
            before += this->Counts[p][leaves[k]];
          const auto first = owned[k].begin() + before * width;
          send.insert(send.end(), first, first + this->Counts[q][leaves[k]] * width);
        }
    }
    std::vector<double> received(static_cast<std::size_t>(lengths[this->MyRank]), 0.0);
    if (this->Controller)
      this->Controller->ScatterV(Data(send), Data(received), lengths.data(), const_cast<vtkIdType*>(offsets.data()),
        lengths[this->MyRank], owner);
    else
      received = send;
    std::size_t at = 0;
    for (std::size_t leaf : leaves)
    {
      const auto it = local.find(this->Ids[leaf]);
      if (it == local.end())
        continue;
      for (vtkIdType i : it->second)
        for (int c = 0; c < width; ++c)
          values[static_cast<std::size_t>(i * width + c)] = received[at++];
    }
  }
  return values;
}

std::vector<double> LeafExchange::GatherRows(const std::vector<double>& rows, int width) const
{
  if (!this->Controller)
    return rows;
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->Ranks), 0);
  for (int q = 0; q < this->Ranks; ++q)
    lengths[q] = width * static_cast<vtkIdType>(this->OwnedBy(q).size());
  const std::vector<vtkIdType> offsets = Offsets(lengths);
  std::vector<double> send = rows, received;
  if (this->MyRank == 0)
    received.assign(static_cast<std::size_t>(offsets.back() + lengths.back()), 0.0);
  this->Controller->GatherV(Data(send), Data(received), static_cast<vtkIdType>(send.size()), lengths.data(),
    const_cast<vtkIdType*>(offsets.data()), 0);
  if (this->MyRank != 0)
    return {};
  // Rank q's part holds the rows of its leaves in LeafId order: put every row at its leaf's place.
  std::vector<double> ordered(received.size(), 0.0);
  for (int q = 0; q < this->Ranks; ++q)
  {
    vtkIdType at = offsets[q];
    for (std::size_t leaf : this->OwnedBy(q))
    {
      std::copy(received.begin() + at, received.begin() + at + width, ordered.begin() + leaf * width);
      at += width;
    }
  }
  return ordered;
}

} // namespace fitmpi
} // namespace plantmorph
