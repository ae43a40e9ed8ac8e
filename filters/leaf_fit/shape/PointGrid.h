// SPDX-License-Identifier: GPL-3.0-or-later
// A uniform grid over 3-D points for nearest-neighbour queries (the leaf fit's cleaning, spacing and Support).
// Plain C++17 (Eigen), no VTK. Queries are const and thread-safe; results are exact (not approximate).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace plantmorph
{

class PointGrid
{
public:
  /// Indexes a copy of `points` in cubes of side `cell` (> 0), stored cell by cell so that a query reads
  /// contiguous memory (on 10^6 points, scattered reads made the queries memory-bound).
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell);

  /// The k nearest points to q (excluding index `skip`, if >= 0) as (squared distance, index), nearest first.
  /// Only points within `reach` are looked for: fewer than k come back when fewer lie that close (the search cost
  /// grows with the cube of the distance searched, so far outliers must not search the whole grid).
  std::vector<std::pair<double, int>> Nearest(
    const Eigen::Vector3d& q, int k, int skip = -1, double reach = std::numeric_limits<double>::infinity()) const;

  /// Indices of every point within `radius` of q.
  void Within(const Eigen::Vector3d& q, double radius, std::vector<int>& out) const;

  /// The point ids sorted by cell: queries made in this order reuse the cells (and memory) the previous query
  /// touched, which on large clouds is most of their cost.
  const std::vector<int>& SortedIds() const { return this->Order; }

  /// A cell size giving about `perCell` points per occupied cell for points spread over a surface of the given
  /// bounding box (its two largest extents).
  static double CellFor(const std::vector<Eigen::Vector3d>& points, double perCell);

private:
  using Key = std::int64_t;
  Key KeyOf(std::int64_t i, std::int64_t j, std::int64_t k) const;
  Eigen::Vector3i CellOf(const Eigen::Vector3d& p) const;

  double Cell;
  Eigen::Vector3d Origin;
  std::vector<int> Order;                              // point ids sorted by cell
  std::vector<Eigen::Vector3d> Sorted;                 // the points in that order: a cell's points contiguous
  std::unordered_map<Key, std::pair<int, int>> Ranges; // cell -> [begin, end) in Order
  Eigen::Vector3i Extent = Eigen::Vector3i::Zero();    // cells per axis
};

} // namespace plantmorph
