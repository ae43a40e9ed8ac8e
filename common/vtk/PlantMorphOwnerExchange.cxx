// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphOwnerExchange.h"

#include "PlantMorphLeafExchange.h"
#include "PlantMorphLayer.h" // AnyRank

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <limits>

namespace plantmorph
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
double* Data(std::vector<double>& v)
{
  static thread_local double dummy = 0.0;
  return v.empty() ? &dummy : v.data();
}
} // namespace

OwnerExchange::OwnerExchange(vtkMultiProcessController* controller, const LocalGroups& local)
{
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    this->Controller = controller;
    this->RankCount = controller->GetNumberOfProcesses();
    this->MyRank = controller->GetLocalProcessId();
  }
  std::map<vtkTypeInt64, vtkIdType> mine;
  for (const auto& group : local)
    mine[group.first] = static_cast<vtkIdType>(group.second.size());
  const std::vector<std::map<vtkTypeInt64, vtkIdType>> ranks = LeafCountsOfRanks(this->Controller, mine);
  std::vector<vtkIdType> points;
  SumLeafCounts(ranks, this->GroupIds, points);
  this->Counts.assign(static_cast<std::size_t>(this->RankCount), std::vector<vtkIdType>(this->GroupIds.size(), 0));
  for (std::size_t q = 0; q < ranks.size(); ++q)
    for (const auto& group : ranks[q])
    {
      const auto at = std::lower_bound(this->GroupIds.begin(), this->GroupIds.end(), group.first);
      this->Counts[q][static_cast<std::size_t>(at - this->GroupIds.begin())] = group.second;
    }
  this->Owners = LeafOwners(points, this->RankCount);
}

bool OwnerExchange::AnyRank(bool failed) const
{
  return plantmorph::AnyRank(this->Controller, failed);
}

std::vector<std::size_t> OwnerExchange::OwnedBy(int rank) const
{
  std::vector<std::size_t> owned;
  for (std::size_t group = 0; group < this->GroupIds.size(); ++group)
    if (this->Owners[group] == rank)
      owned.push_back(group);
  return owned;
}

vtkIdType OwnerExchange::CountFor(int q, int rank) const
{
  vtkIdType count = 0;
  for (std::size_t group : this->OwnedBy(rank))
    count += this->Counts[q][group];
  return count;
}

void OwnerExchange::Layout(int owner, int width, std::vector<vtkIdType>& lengths, std::vector<vtkIdType>& offsets) const
{
  lengths.assign(static_cast<std::size_t>(this->RankCount), 0);
  for (int q = 0; q < this->RankCount; ++q)
    lengths[q] = width * this->CountFor(q, owner);
  offsets = Offsets(lengths);
}

std::vector<std::vector<double>> OwnerExchange::SendValues(
  const LocalGroups& local, const std::vector<double>& values, int width) const
{
  std::vector<std::vector<double>> result;
  for (int owner = 0; owner < this->RankCount; ++owner)
  {
    const std::vector<std::size_t> owned = this->OwnedBy(owner);
    std::vector<double> send;
    std::size_t size = 0; // reserved first: one allocation, not one per doubling
    for (std::size_t group : owned)
    {
      const auto it = local.find(this->GroupIds[group]);
      size += it != local.end() ? it->second.size() * static_cast<std::size_t>(width) : 0;
    }
    send.reserve(size);
    for (std::size_t group : owned)
    {
      const auto it = local.find(this->GroupIds[group]);
      if (it != local.end())
        for (vtkIdType i : it->second)
          send.insert(send.end(), values.begin() + i * width, values.begin() + (i + 1) * width);
    }
    std::vector<vtkIdType> lengths, offsets;
    this->Layout(owner, width, lengths, offsets);
    std::vector<double> received;
    if (this->Controller)
    {
      if (owner == this->MyRank)
        received.assign(static_cast<std::size_t>(offsets.back() + lengths.back()), 0.0);
      this->Controller->GatherV(
        Data(send), Data(received), static_cast<vtkIdType>(send.size()), lengths.data(), offsets.data(), owner);
    }
    else
      received.swap(send); // serially the buffer is the received one: no copy
    if (owner != this->MyRank)
      continue;
    // Rank q's part holds its points of each owned group in turn; a group's points are its parts in rank order.
    result.assign(owned.size(), {});
    if (this->RankCount == 1 && owned.size() == 1)
    {
      result[0].swap(received); // one group on one rank: the buffer is its values
      continue;
    }
    for (int q = 0; q < this->RankCount; ++q)
    {
      auto at = received.begin() + offsets[q];
      for (std::size_t k = 0; k < owned.size(); ++k)
      {
        const vtkIdType count = width * this->Counts[q][owned[k]];
        result[k].insert(result[k].end(), at, at + count);
        at += count;
      }
    }
  }
  return result;
}

std::vector<double> OwnerExchange::ReturnValues(
  const LocalGroups& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const
{
  std::vector<double> values(static_cast<std::size_t>(localPoints * width), std::numeric_limits<double>::quiet_NaN());
  for (int owner = 0; owner < this->RankCount; ++owner)
  {
    const std::vector<std::size_t> groups = this->OwnedBy(owner);
    std::vector<vtkIdType> lengths, offsets;
    this->Layout(owner, width, lengths, offsets);
    std::vector<double> send;
    if (owner == this->MyRank)
    {
      // Rank q's part: its points of each owned group in turn, which start in the group's values after the parts
      // of the ranks before q.
      send.reserve(static_cast<std::size_t>(offsets.back() + lengths.back()));
      for (int q = 0; q < this->RankCount; ++q)
        for (std::size_t k = 0; k < groups.size(); ++k)
        {
          vtkIdType before = 0;
          for (int p = 0; p < q; ++p)
            before += this->Counts[p][groups[k]];
          const auto first = owned[k].begin() + before * width;
          send.insert(send.end(), first, first + this->Counts[q][groups[k]] * width);
        }
    }
    std::vector<double> received;
    if (this->Controller)
    {
      received.assign(static_cast<std::size_t>(lengths[this->MyRank]), 0.0);
      this->Controller->ScatterV(
        Data(send), Data(received), lengths.data(), offsets.data(), lengths[this->MyRank], owner);
    }
    else
      received.swap(send); // serially the buffer is the received one: no copy
    std::size_t at = 0;
    for (std::size_t group : groups)
    {
      const auto it = local.find(this->GroupIds[group]);
      if (it == local.end())
        continue;
      for (vtkIdType i : it->second)
        for (int c = 0; c < width; ++c)
          values[static_cast<std::size_t>(i * width + c)] = received[at++];
    }
  }
  return values;
}

std::vector<double> OwnerExchange::GatherRows(const std::vector<double>& rows, int width) const
{
  if (!this->Controller)
    return rows;
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->RankCount), 0);
  for (int q = 0; q < this->RankCount; ++q)
    lengths[q] = width * static_cast<vtkIdType>(this->OwnedBy(q).size());
  std::vector<vtkIdType> offsets = Offsets(lengths);
  std::vector<double> send = rows, received;
  if (this->MyRank == 0)
    received.assign(static_cast<std::size_t>(offsets.back() + lengths.back()), 0.0);
  this->Controller->GatherV(
    Data(send), Data(received), static_cast<vtkIdType>(send.size()), lengths.data(), offsets.data(), 0);
  if (this->MyRank != 0)
    return {};
  // Rank q's part holds the rows of its groups in id order: put every row at its group's place.
  std::vector<double> ordered(received.size(), 0.0);
  for (int q = 0; q < this->RankCount; ++q)
  {
    vtkIdType at = offsets[q];
    for (std::size_t group : this->OwnedBy(q))
    {
      std::copy(received.begin() + at, received.begin() + at + width, ordered.begin() + group * width);
      at += width;
    }
  }
  return ordered;
}

std::vector<std::vector<double>> OwnerExchange::GatherBlocks(const std::vector<std::vector<double>>& owned) const
{
  // Each rank's blocks as one buffer: (length, values...) per owned group.
  std::vector<double> send;
  for (const auto& block : owned)
  {
    send.push_back(static_cast<double>(block.size()));
    send.insert(send.end(), block.begin(), block.end());
  }
  std::vector<double> received = send;
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->RankCount), static_cast<vtkIdType>(send.size()));
  std::vector<vtkIdType> offsets = Offsets(lengths);
  if (this->Controller)
  {
    const vtkIdType length = static_cast<vtkIdType>(send.size());
    this->Controller->Gather(&length, lengths.data(), 1, 0);
    offsets = Offsets(lengths);
    received.assign(this->MyRank == 0 ? static_cast<std::size_t>(offsets.back() + lengths.back()) : 0, 0.0);
    this->Controller->GatherV(Data(send), Data(received), length, lengths.data(), offsets.data(), 0);
  }
  if (this->MyRank != 0)
    return {};
  std::vector<std::vector<double>> blocks(this->GroupIds.size());
  for (int q = 0; q < this->RankCount; ++q)
  {
    auto at = received.begin() + offsets[q];
    for (std::size_t group : this->OwnedBy(q))
    {
      const auto length = static_cast<std::ptrdiff_t>(*at++);
      blocks[group].assign(at, at + length);
      at += length;
    }
  }
  return blocks;
}

void OwnerExchange::Broadcast(std::vector<double>& values) const
{
  if (!this->Controller)
    return;
  vtkIdType length = static_cast<vtkIdType>(values.size());
  this->Controller->Broadcast(&length, 1, 0);
  values.resize(static_cast<std::size_t>(length));
  this->Controller->Broadcast(Data(values), length, 0);
}

} // namespace plantmorph
