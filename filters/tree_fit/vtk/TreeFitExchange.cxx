// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeFitExchange.h"

#include "PlantMorphLeafExchange.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace plantmorph
{
namespace treefitvtk
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

TreeExchange::TreeExchange(vtkMultiProcessController* controller, const LocalTrees& local)
{
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    this->Controller = controller;
    this->RankCount = controller->GetNumberOfProcesses();
    this->MyRank = controller->GetLocalProcessId();
  }
  std::map<int, vtkIdType> mine;
  for (const auto& tree : local)
    mine[tree.first] = static_cast<vtkIdType>(tree.second.size());
  const std::vector<std::map<int, vtkIdType>> ranks = LeafCountsOfRanks(this->Controller, mine);
  std::vector<vtkIdType> points;
  SumLeafCounts(ranks, this->Ids, points);
  this->Counts.assign(static_cast<std::size_t>(this->RankCount), std::vector<vtkIdType>(this->Ids.size(), 0));
  for (std::size_t q = 0; q < ranks.size(); ++q)
    for (const auto& tree : ranks[q])
    {
      const auto at = std::lower_bound(this->Ids.begin(), this->Ids.end(), tree.first) - this->Ids.begin();
      this->Counts[q][static_cast<std::size_t>(at)] = tree.second;
    }
  this->Owners = LeafOwners(points, this->RankCount);
}

bool TreeExchange::AnyRank(bool failed) const
{
  if (!this->Controller)
    return failed;
  const int mine = failed ? 1 : 0;
  int any = 0;
  this->Controller->AllReduce(&mine, &any, 1, vtkCommunicator::MAX_OP);
  return any != 0;
}

std::vector<std::size_t> TreeExchange::OwnedBy(int rank) const
{
  std::vector<std::size_t> owned;
  for (std::size_t tree = 0; tree < this->Ids.size(); ++tree)
    if (this->Owners[tree] == rank)
      owned.push_back(tree);
  return owned;
}

vtkIdType TreeExchange::CountFor(int q, int rank) const
{
  vtkIdType count = 0;
  for (std::size_t tree : this->OwnedBy(rank))
    count += this->Counts[q][tree];
  return count;
}

std::vector<std::vector<double>> TreeExchange::SendValues(
  const LocalTrees& local, const std::vector<double>& values, int width) const
{
  std::vector<std::vector<double>> result;
  for (int owner = 0; owner < this->RankCount; ++owner)
  {
    const std::vector<std::size_t> owned = this->OwnedBy(owner);
    std::vector<double> send;
    for (std::size_t tree : owned)
    {
      const auto it = local.find(this->Ids[tree]);
      if (it != local.end())
        for (vtkIdType i : it->second)
          send.insert(send.end(), values.begin() + i * width, values.begin() + (i + 1) * width);
    }
    std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->RankCount), 0);
    for (int q = 0; q < this->RankCount; ++q)
      lengths[q] = width * this->CountFor(q, owner);
    const std::vector<vtkIdType> offsets = Offsets(lengths);
    std::vector<double> received;
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
    // Rank q's part holds its points of each owned tree in turn; a tree's points are its parts in rank order.
    result.assign(owned.size(), {});
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

std::vector<double> TreeExchange::ReturnValues(
  const LocalTrees& local, vtkIdType localPoints, const std::vector<std::vector<double>>& owned, int width) const
{
  std::vector<double> values(static_cast<std::size_t>(localPoints * width), std::numeric_limits<double>::quiet_NaN());
  for (int owner = 0; owner < this->RankCount; ++owner)
  {
    const std::vector<std::size_t> trees = this->OwnedBy(owner);
    std::vector<vtkIdType> lengths(static_cast<std::size_t>(this->RankCount), 0);
    for (int q = 0; q < this->RankCount; ++q)
      lengths[q] = width * this->CountFor(q, owner);
    const std::vector<vtkIdType> offsets = Offsets(lengths);
    std::vector<double> send;
    if (owner == this->MyRank)
      for (int q = 0; q < this->RankCount;
           ++q) // rank q's part: its points of each owned tree, after the ranks before q
        for (std::size_t k = 0; k < trees.size(); ++k)
        {
          vtkIdType before = 0;
          for (int p = 0; p < q; ++p)
            before += this->Counts[p][trees[k]];
          const auto first = owned[k].begin() + before * width;
          send.insert(send.end(), first, first + this->Counts[q][trees[k]] * width);
        }
    std::vector<double> received(static_cast<std::size_t>(lengths[this->MyRank]), 0.0);
    if (this->Controller)
      this->Controller->ScatterV(Data(send), Data(received), lengths.data(), const_cast<vtkIdType*>(offsets.data()),
        lengths[this->MyRank], owner);
    else
      received = send;
    std::size_t at = 0;
    for (std::size_t tree : trees)
    {
      const auto it = local.find(this->Ids[tree]);
      if (it == local.end())
        continue;
      for (vtkIdType i : it->second)
        for (int c = 0; c < width; ++c)
          values[static_cast<std::size_t>(i * width + c)] = received[at++];
    }
  }
  return values;
}

std::vector<std::vector<double>> TreeExchange::GatherBlocks(const std::vector<std::vector<double>>& owned) const
{
  // Each rank's blocks as one buffer: (length, values...) per owned tree.
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
  std::vector<std::vector<double>> blocks(this->Ids.size());
  for (int q = 0; q < this->RankCount; ++q)
  {
    auto at = received.begin() + offsets[q];
    for (std::size_t tree : this->OwnedBy(q))
    {
      const auto length = static_cast<std::ptrdiff_t>(*at++);
      blocks[tree].assign(at, at + length);
      at += length;
    }
  }
  return blocks;
}

void TreeExchange::Broadcast(std::vector<double>& values) const
{
  if (!this->Controller)
    return;
  vtkIdType length = static_cast<vtkIdType>(values.size());
  this->Controller->Broadcast(&length, 1, 0);
  values.resize(static_cast<std::size_t>(length));
  this->Controller->Broadcast(Data(values), length, 0);
}

namespace
{
/// Appends and reads numbers in one order (PackFit, UnpackFit).
struct Reader
{
  const std::vector<double>& data;
  std::size_t at = 0;
  double Next()
  {
    if (at >= data.size())
      throw std::runtime_error("a packed tree fit ended early");
    return data[at++];
  }
  int Int() { return static_cast<int>(this->Next()); }
  Eigen::Vector3d Vector()
  {
    const double x = this->Next(), y = this->Next();
    return { x, y, this->Next() };
  }
};
} // namespace

std::vector<double> PackFit(const TreeFitResult& fit)
{
  std::vector<double> out{ static_cast<double>(fit.error.size()) };
  for (char c : fit.error)
    out.push_back(static_cast<unsigned char>(c));
  out.push_back(static_cast<double>(fit.cylinders.size()));
  for (const TreeCylinder& c : fit.cylinders)
  {
    out.insert(out.end(), c.start.data(), c.start.data() + 3);
    out.insert(out.end(), c.end.data(), c.end.data() + 3);
    out.insert(out.end(),
      { c.radius, c.length, c.fittedRadius, static_cast<double>(c.parent), static_cast<double>(c.branch),
        static_cast<double>(c.order), static_cast<double>(c.segment), static_cast<double>(c.points), c.fitRMS,
        c.support, c.coverage, c.measured ? 1.0 : 0.0, c.growthLength });
  }
  out.push_back(static_cast<double>(fit.branches.size()));
  for (const TreeBranchRow& b : fit.branches)
  {
    out.insert(out.end(),
      { static_cast<double>(b.id), static_cast<double>(b.parent), static_cast<double>(b.order), b.length, b.volume,
        b.baseDiameter, b.angle, b.azimuth, b.inclination, b.height, static_cast<double>(b.cylinders.size()) });
    out.insert(out.end(), b.cylinders.begin(), b.cylinders.end());
  }
  const std::vector<double> traits = TreeTraitValues(fit.traits);
  out.insert(out.end(), traits.begin(), traits.end());
  return out;
}

TreeFitResult UnpackFit(const std::vector<double>& packed)
{
  TreeFitResult fit;
  Reader in{ packed };
  for (int k = 0, n = in.Int(); k < n; ++k)
    fit.error.push_back(static_cast<char>(in.Int()));
  fit.cylinders.resize(static_cast<std::size_t>(in.Int()));
  for (TreeCylinder& c : fit.cylinders)
  {
    c.start = in.Vector();
    c.end = in.Vector();
    c.radius = in.Next(), c.length = in.Next(), c.fittedRadius = in.Next();
    c.parent = in.Int(), c.branch = in.Int(), c.order = in.Int(), c.segment = in.Int(), c.points = in.Int();
    c.fitRMS = in.Next(), c.support = in.Next(), c.coverage = in.Next();
    c.measured = in.Next() != 0.0;
    c.growthLength = in.Next();
  }
  fit.branches.resize(static_cast<std::size_t>(in.Int()));
  for (TreeBranchRow& b : fit.branches)
  {
    b.id = in.Int(), b.parent = in.Int(), b.order = in.Int();
    b.length = in.Next(), b.volume = in.Next(), b.baseDiameter = in.Next(), b.angle = in.Next();
    b.azimuth = in.Next(), b.inclination = in.Next(), b.height = in.Next();
    b.cylinders.resize(static_cast<std::size_t>(in.Int()));
    for (int& k : b.cylinders)
      k = in.Int();
  }
  TreeTraits& t = fit.traits;
  for (double* value :
    { &t.height, &t.dbh, &t.trunkVolume, &t.branchVolume, &t.totalVolume, &t.trunkLength, &t.totalBranchLength,
      &t.branchCount, &t.order1, &t.order2, &t.order3, &t.order4Plus, &t.crownProjectedArea, &t.crownBaseHeight,
      &t.points, &t.woodPoints, &t.cylinders, &t.fitRMS, &t.spacing, &t.noise, &t.measuredVolumeFraction })
    *value = in.Next();
  return fit;
}

} // namespace treefitvtk
} // namespace plantmorph
