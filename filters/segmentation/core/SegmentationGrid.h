// SPDX-License-Identifier: GPL-3.0-or-later
// The segmentation's neighbour searches on flat arrays (PlantSegmentation.h): a grid whose cells are sorted by key,
// so that a 3 x 3 x 3 block of cells is nine runs of consecutive keys found by binary search, and the cells'
// moments (count, mean, scatter) from which the covariance of any ball is summed cell by cell. Internal to the
// method; plain C++17 (Eigen), deterministic (every sum runs in key order).
#pragma once

#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace plantmorph
{
namespace segmentation
{

/// Points bucketed in cubes of side `cell` (widened when the cloud spans more than 2^21 cells on an axis), stored
/// cell by cell in ascending key, then ascending index. The keys and their sort (a linear radix sort of the cells
/// numbered within the cloud's box, above the index, when both fit in 64 bits) run through `parallel`; the grid is
/// the same on any number of threads.
class CellGrid
{
public:
  CellGrid(const std::vector<Eigen::Vector3d>& points, double cell, const ParallelFor& parallel = SerialFor);

  std::size_t CellCount() const { return this->Keys.size(); }
  double Cell() const { return this->Side; }
  /// The points of cell c (indices into the points given), in ascending index.
  const int* Begin(std::size_t c) const { return this->Order.data() + this->Start[c]; }
  const int* End(std::size_t c) const { return this->Order.data() + this->Start[c + 1]; }
  /// The cell of point i.
  int CellOfPoint(std::size_t i) const { return this->PointCell[i]; }

  /// The points of the 3 x 3 x 3 block of cells around a cell: up to nine runs of positions in the cell order
  /// (Ordered()[begin, end)), in ascending key. Kept by the caller: a query in the same cell as the last one reuses
  /// it (queries made in cell order mostly do).
  struct Block
  {
    Eigen::Array3i cell = Eigen::Array3i::Constant(-1);
    int runs = 0;
    std::size_t begin[9], end[9];
  };

  /// The block around q's cell, into `block` (unchanged when q is in block.cell already).
  void BlockAround(const Eigen::Vector3d& q, Block& block) const
  {
    const Eigen::Array3i c = this->CellOf(q);
    if ((c == block.cell).all())
      return;
    block.cell = c;
    block.runs = 0;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
      {
        const std::uint64_t low = Key(c[0] + di, c[1] + dj, c[2] - 1);
        const auto first = std::lower_bound(this->Keys.begin(), this->Keys.end(), low);
        auto last = first;
        while (last != this->Keys.end() && *last <= low + 2)
          ++last;
        if (first == last)
          continue;
        block.begin[block.runs] =
          static_cast<std::size_t>(this->Start[static_cast<std::size_t>(first - this->Keys.begin())]);
        block.end[block.runs++] =
          static_cast<std::size_t>(this->Start[static_cast<std::size_t>(last - this->Keys.begin())]);
      }
  }

  /// The point indices in cell order.
  const std::vector<int>& Ordered() const { return this->Order; }

private:
  static std::uint64_t Key(int i, int j, int k)
  {
    return (static_cast<std::uint64_t>(i) << 42) | (static_cast<std::uint64_t>(j) << 21) |
      static_cast<std::uint64_t>(k);
  }
  Eigen::Array3i CellOf(const Eigen::Vector3d& q) const;

  double Side = 1.0;
  Eigen::Vector3d Origin = Eigen::Vector3d::Zero();
  std::vector<std::uint64_t> Keys; ///< the non-empty cells' keys, ascending
  std::vector<int> Start;          ///< cell c's points: Order[Start[c], Start[c + 1])
  std::vector<int> Order;
  std::vector<int> PointCell;
};

/// The covariance of the points in any ball of a fixed radius, summed from the moments (count, mean, scatter) of
/// the cells of side `cell` whose points' mean lies in the ball: about 50 cells on a surface when the cell is a
/// quarter of the radius, whatever the density. The moments are stored in the order of a grid of side `radius` over
/// the means, so a query reads nine contiguous runs.
class BallMoments
{
public:
  /// The grids and the cells' moments built through `parallel` (the same on any number of threads).
  BallMoments(
    const std::vector<Eigen::Vector3d>& points, double cell, double radius, const ParallelFor& parallel = SerialFor);

  /// The covariance about their mean of the points whose cell's mean is within the radius of q; their number in
  /// `count` (0: a zero matrix).
  Eigen::Matrix3d Covariance(const Eigen::Vector3d& q, double& count, CellGrid::Block& block) const;

  /// The cells (of Cells()) in an order where neighbours follow each other: the order to query them in.
  const std::vector<int>& QueryOrder() const { return this->MeanGrid.Ordered(); }

  /// The cells of side `cell` (their means are the natural places to query).
  const CellGrid& Cells() const { return this->Grid; }
  const std::vector<Eigen::Vector3d>& Means() const { return this->Mean; }

private:
  struct Moment
  {
    double count;
    Eigen::Vector3d mean;
    double scatter[6]; // xx, xy, xz, yy, yz, zz about the mean
  };
  double Radius;
  CellGrid Grid;
  std::vector<Eigen::Vector3d> Mean; ///< per cell of Grid
  CellGrid MeanGrid;                 ///< over Mean, cells of side Radius
  std::vector<Moment> Packed;        ///< in MeanGrid's order
};

} // namespace segmentation
} // namespace plantmorph
