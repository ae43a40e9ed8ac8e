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
  /// Indexes `points` (kept by reference: they must outlive the grid) in cubes of side `cell` (> 0).
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell);

  /// The k nearest points to q (excluding index `skip`, if >= 0) as (squared distance, index), nearest first.
  /// Only points within `reach` are looked for: fewer than k come back when fewer lie that close (the search cost
  /// grows with the cube of the distance searched, so far outliers must not search the whole grid).
  std::vector<std::pair<double, int>> Nearest(const Eigen::Vector3d& q, int k, int skip = -1,
    double reach = std::numeric_limits<double>::infinity()) const;

  /// Indices of every point within `radius` of q.
  void Within(const Eigen::Vector3d& q, double radius, std::vector<int>& out) const;

  /// A cell size giving about `perCell` points per occupied cell for points spread over a surface of the given
  /// bounding box (its two largest extents).
  static double CellFor(const std::vector<Eigen::Vector3d>& points, double perCell);

private:
  using Key = std::int64_t;
  Key KeyOf(std::int64_t i, std::int64_t j, std::int64_t k) const;
  Eigen::Vector3i CellOf(const Eigen::Vector3d& p) const;

  const std::vector<Eigen::Vector3d>& Points;
  double Cell;
  Eigen::Vector3d Origin;
  std::vector<int> Order;                                  // point ids sorted by cell
  std::unordered_map<Key, std::pair<int, int>> Ranges;     // cell -> [begin, end) in Order
  Eigen::Vector3i Extent = Eigen::Vector3i::Zero();        // cells per axis
};

} // namespace plantmorph
