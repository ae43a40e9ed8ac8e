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
} // namespace

CellGrid::CellGrid(const std::vector<Eigen::Vector3d>& points, double cell)
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
  std::vector<std::pair<std::uint64_t, int>> keyed(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Array3i c = this->CellOf(points[i]);
    keyed[i] = { Key(c[0], c[1], c[2]), static_cast<int>(i) };
  }
  std::sort(keyed.begin(), keyed.end());
  this->Order.resize(n);
  this->PointCell.resize(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    if (k == 0 || keyed[k].first != keyed[k - 1].first)
    {
      this->Keys.push_back(keyed[k].first);
      this->Start.push_back(static_cast<int>(k));
    }
    this->Order[k] = keyed[k].second;
    this->PointCell[static_cast<std::size_t>(keyed[k].second)] = static_cast<int>(this->Keys.size() - 1);
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
std::vector<Eigen::Vector3d> CellMeans(const std::vector<Eigen::Vector3d>& points, const CellGrid& grid)
{
  std::vector<Eigen::Vector3d> means(grid.CellCount());
  for (std::size_t c = 0; c < means.size(); ++c)
  {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int* j = grid.Begin(c); j != grid.End(c); ++j)
      sum += points[static_cast<std::size_t>(*j)];
    means[c] = sum / static_cast<double>(grid.End(c) - grid.Begin(c));
  }
  return means;
}
} // namespace

BallMoments::BallMoments(const std::vector<Eigen::Vector3d>& points, double cell, double radius)
  : Radius(radius)
  , Grid(points, cell)
  , Mean(CellMeans(points, Grid))
  , MeanGrid(Mean, radius)
{
  this->Packed.resize(this->Mean.size());
  for (std::size_t k = 0; k < this->Packed.size(); ++k)
  {
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
  }
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
