// SPDX-License-Identifier: GPL-3.0-or-later
#include "SegmentationGrid.h"

#include <cmath>
#include <numeric>

namespace plantmorph
{
namespace segmentation
{
namespace
{
/// Cells per axis a key holds (21 bits), less the one-cell margin on each side that the 3 x 3 x 3 blocks read.
constexpr double MaximumCells = double((1 << 21) - 4);

/// The bits needed to hold `value`.
int BitsFor(std::uint64_t value)
{
  int bits = 0;
  while (bits < 64 && (std::uint64_t(1) << bits) <= value)
    ++bits;
  return bits;
}
} // namespace

CellGrid::CellGrid(const std::vector<Eigen::Vector3d>& points, double cell, const ParallelFor& parallel)
{
  Eigen::Vector3d low = Eigen::Vector3d::Constant(0.0), high = low;
  if (!points.empty())
  {
    low = high = points.front();
    for (const Eigen::Vector3d& p : points)
    {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  }
  this->Side = std::max(cell, (high - low).maxCoeff() / MaximumCells);
  if (!(this->Side > 0.0))
    this->Side = 1.0;
  this->Origin = low - Eigen::Vector3d::Constant(this->Side); // a margin cell: the blocks never go below 0
  const std::size_t n = points.size();
  std::vector<Eigen::Array3i> cells(n);
  ForEachIndex(parallel, n, [&](std::size_t i) { cells[i] = this->CellOf(points[i]); });
  Eigen::Array3i first = Eigen::Array3i::Zero(), last = first;
  if (n > 0)
  {
    first = last = cells.front();
    for (const Eigen::Array3i& c : cells)
    {
      first = first.min(c);
      last = last.max(c);
    }
  }
  // The cells numbered within the cloud's box, in the keys' order (i, then j, then k), above the point's index: the
  // radix sort of these gives the (key, index) order in linear time.
  const int bitsJ = BitsFor(static_cast<std::uint64_t>(last[1] - first[1]));
  const int bitsK = BitsFor(static_cast<std::uint64_t>(last[2] - first[2]));
  const int cellBits = BitsFor(static_cast<std::uint64_t>(last[0] - first[0])) + bitsJ + bitsK;
  const int indexBits = BitsFor(n);
  this->Order.resize(n);
  if (cellBits + indexBits <= 64)
  {
    std::vector<std::uint64_t> packed(n);
    ForEachIndex(parallel, n, [&](std::size_t i) {
      const Eigen::Array3i c = cells[i] - first;
      const std::uint64_t number = (static_cast<std::uint64_t>(c[0]) << (bitsJ + bitsK)) |
        (static_cast<std::uint64_t>(c[1]) << bitsK) | static_cast<std::uint64_t>(c[2]);
      packed[i] = indexBits < 64 ? (number << indexBits) | i : i;
    });
    SortKeysInParallel(parallel, packed, indexBits, indexBits + cellBits);
    const std::uint64_t mask = indexBits < 64 ? (std::uint64_t(1) << indexBits) - 1 : ~std::uint64_t(0);
    ForEachIndex(parallel, n, [&](std::size_t k) { this->Order[k] = static_cast<int>(packed[k] & mask); });
  }
  else
  {
    std::vector<std::pair<std::uint64_t, int>> keyed(n);
    ForEachIndex(parallel, n, [&](std::size_t i) {
      keyed[i] = { Key(cells[i][0], cells[i][1], cells[i][2]), static_cast<int>(i) };
    });
    SortInParallel(parallel, keyed, std::less<std::pair<std::uint64_t, int>>());
    ForEachIndex(parallel, n, [&](std::size_t k) { this->Order[k] = keyed[k].second; });
  }
  this->PointCell.resize(n);
  std::uint64_t previous = 0;
  for (std::size_t k = 0; k < n; ++k)
  {
    const Eigen::Array3i& c = cells[static_cast<std::size_t>(this->Order[k])];
    const std::uint64_t key = Key(c[0], c[1], c[2]);
    if (k == 0 || key != previous)
    {
      this->Keys.push_back(key);
      this->Start.push_back(static_cast<int>(k));
      previous = key;
    }
    this->PointCell[static_cast<std::size_t>(this->Order[k])] = static_cast<int>(this->Keys.size() - 1);
  }
  this->Start.push_back(static_cast<int>(n));
}

Eigen::Array3i CellGrid::CellOf(const Eigen::Vector3d& q) const
{
  const Eigen::Array3d c = ((q - this->Origin) / this->Side).array().floor();
  return c.max(1.0).min(MaximumCells + 2.0).cast<int>(); // queries outside the cloud's box read its border cells
}

namespace
{
std::vector<Eigen::Vector3d> CellMeans(
  const std::vector<Eigen::Vector3d>& points, const CellGrid& grid, const ParallelFor& parallel)
{
  std::vector<Eigen::Vector3d> means(grid.CellCount());
  ForEachIndex(parallel, means.size(), [&](std::size_t c) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int* j = grid.Begin(c); j != grid.End(c); ++j)
      sum += points[static_cast<std::size_t>(*j)];
    means[c] = sum / static_cast<double>(grid.End(c) - grid.Begin(c));
  });
  return means;
}
} // namespace

BallMoments::BallMoments(
  const std::vector<Eigen::Vector3d>& points, double cell, double radius, const ParallelFor& parallel)
  : Radius(radius)
  , Grid(points, cell, parallel)
  , Mean(CellMeans(points, Grid, parallel))
  , MeanGrid(Mean, radius, parallel)
{
  this->Packed.resize(this->Mean.size());
  ForEachIndex(parallel, this->Packed.size(), [&](std::size_t k) {
    const auto c = static_cast<std::size_t>(this->MeanGrid.Ordered()[k]);
    Moment& m = this->Packed[k];
    m.count = static_cast<double>(this->Grid.End(c) - this->Grid.Begin(c));
    m.mean = this->Mean[c];
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for (const int* j = this->Grid.Begin(c); j != this->Grid.End(c); ++j)
    {
      const Eigen::Vector3d d = points[static_cast<std::size_t>(*j)] - m.mean;
      s += d * d.transpose();
    }
    const double upper[6] = { s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2) };
    std::copy(upper, upper + 6, m.scatter);
  });
}

Eigen::Matrix3d BallMoments::Covariance(const Eigen::Vector3d& q, double& count, CellGrid::Block& block) const
{
  // Sums about q (the means are near it: no cancellation), then the covariance about the ball's mean.
  count = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  double second[6] = { 0, 0, 0, 0, 0, 0 };
  const double r2 = this->Radius * this->Radius;
  this->MeanGrid.BlockAround(q, block);
  for (int run = 0; run < block.runs; ++run)
    for (std::size_t k = block.begin[run]; k < block.end[run]; ++k)
    {
      const Moment& m = this->Packed[k];
      const Eigen::Vector3d d = m.mean - q;
      if (d.squaredNorm() > r2)
        continue;
      const double w = m.count;
      count += w;
      first += w * d;
      second[0] += m.scatter[0] + w * d.x() * d.x();
      second[1] += m.scatter[1] + w * d.x() * d.y();
      second[2] += m.scatter[2] + w * d.x() * d.z();
      second[3] += m.scatter[3] + w * d.y() * d.y();
      second[4] += m.scatter[4] + w * d.y() * d.z();
      second[5] += m.scatter[5] + w * d.z() * d.z();
    }
  if (count <= 0.0)
    return Eigen::Matrix3d::Zero();
  const Eigen::Vector3d mean = first / count;
  Eigen::Matrix3d c;
  c << second[0], second[1], second[2], second[1], second[3], second[4], second[2], second[4], second[5];
  return c / count - mean * mean.transpose();
}

} // namespace segmentation
} // namespace plantmorph
