// SPDX-License-Identifier: GPL-3.0-or-later
// A uniform grid over 3-D points for nearest-neighbour queries (the leaf fit's cleaning, spacing and Support).
// Plain C++17 (Eigen), no VTK. Queries are const and thread-safe; results are exact (not approximate).
#pragma once

#include <Eigen/Core>

#include <plantmorph/ParallelFor.h>

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace plantmorph
{

class PointGrid
{
public:
  /// Indexes a copy of `points` in cubes of side `cell` (> 0), stored cell by cell so that a query reads
  /// contiguous memory (on 10^6 points, scattered reads made the queries memory-bound). The keys, their sort (a
  /// linear radix sort of key << 32 | index where the keys fit in 32 bits, else by comparisons) and the copy run
  /// through `parallel`; the grid is the same whatever it is.
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell, const ParallelFor& parallel = SerialFor);

  /// The k nearest points to q (excluding index `skip`, if >= 0) as (squared distance, index), nearest first (ties
  /// by index).
  /// Only points within `reach` are looked for: fewer than k come back when fewer lie that close (the search cost
  /// grows with the cube of the distance searched, so far outliers must not search the whole grid).
  std::vector<std::pair<double, int>> Nearest(
    const Eigen::Vector3d& q, int k, int skip = -1, double reach = std::numeric_limits<double>::infinity()) const;

  /// The id of a point within `reach` of q, or -1 when none is: the nearest of q's own cell when one there is that
  /// close (one cell read, which on a dense cloud answers nearly every query), else the nearest (Nearest).
  int Near(const Eigen::Vector3d& q, double reach) const;

  /// Indices of every point within `radius` of q.
  void Within(const Eigen::Vector3d& q, double radius, std::vector<int>& out) const;

  /// How many points lie within `radius` of q (Within's count, without the list).
  std::size_t CountWithin(const Eigen::Vector3d& q, double radius) const;

  /// Whether any point with flag[id] != 0 lies within `radius` of q (stops at the first).
  bool AnyWithin(const Eigen::Vector3d& q, double radius, const std::vector<unsigned char>& flag) const;

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
  /// The [begin, end) range in Order of cell (i, j, k), or nullptr when the cell holds no point.
  const std::pair<int, int>* Range(int i, int j, int k) const;
  /// Calls visit(o) for every position o in Order of a point in the cells that cover the box q +- radius.
  template <typename Visit>
  void ForCellsAround(const Eigen::Vector3d& q, double radius, Visit&& visit) const;

  double Cell;
  Eigen::Vector3d Origin;
  std::vector<int> Order;              // point ids sorted by cell
  std::vector<Eigen::Vector3d> Sorted; // the points in that order: a cell's points contiguous
  // The occupied cells in an open-addressing table on flat arrays (a node-based hash map made the lookups of 10^6
  // points cache misses): SlotKey -1 is an empty slot, SlotRange the cell's [begin, end) in Order.
  std::vector<Key> SlotKey;
  std::vector<std::pair<int, int>> SlotRange;
  std::uint64_t SlotMask = 0;
  int SlotShift = 64;
  // Occupancy bits of blocks of 2^BlockShift cells a side (the smallest blocks whose bits take at most 8 bytes a
  // point): an empty cell is mostly told by one bit, without a probe of the table (a sheet of points leaves most
  // cells of its box empty, and an outlier's search visits thousands of them).
  std::vector<std::uint64_t> Occupied;
  int BlockShift = 0;
  Eigen::Vector3i Blocks = Eigen::Vector3i::Zero();
  std::size_t BlockOf(int i, int j, int k) const;
  Eigen::Vector3i Extent = Eigen::Vector3i::Zero(); // cells per axis
};

/// A deterministic sample of about `target` of the points (all of them when there are no more): point i is taken
/// when a hash of its coordinates' bits falls below target / size, so the sample depends neither on the points'
/// order nor on a thread count, and thins any arrangement (a scanner's lines, a grid) evenly, without aliasing.
/// Ids ascending.
std::vector<int> SampleIds(const std::vector<Eigen::Vector3d>& points, std::size_t target);

/// The point spacing: the median nearest-neighbour distance (0 excluded) over a deterministic sample of at most
/// 20000 of the points. 0 for fewer than 2 points.
double MedianSpacing(const std::vector<Eigen::Vector3d>& points);
/// The same on a grid already built over `points` (any cell size: the searches are exact), the searches through
/// `parallel`.
double MedianSpacing(
  const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const ParallelFor& parallel = SerialFor);

/// The points' spacing across their densest direction: the median, over the points (a subsample of at most 5000),
/// of the distance to the nearest neighbour lying more than 60 degrees away from the direction of the point's own
/// nearest neighbour. About the nearest-neighbour spacing on a regular grid, 1.7 times it on random points, and the
/// distance between the lines of a line scan whose points along a line are much closer than the lines (where the
/// nearest-neighbour spacing says nothing about the gaps the points leave). 0 for fewer than 3 points.
double CrossSpacing(const std::vector<Eigen::Vector3d>& points);
/// The same on a grid already built over `points` (any cell size), the searches through `parallel`.
double CrossSpacing(
  const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const ParallelFor& parallel = SerialFor);

} // namespace plantmorph
