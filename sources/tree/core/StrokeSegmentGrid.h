// SPDX-License-Identifier: GPL-3.0-or-later
// A uniform grid over the image-plane segments of a tree's centre lines, for eq. (2) of TreeStrokes.h: the segments
// nearest to a stroke's first point without visiting every segment (plain C++, no VTK).
//
// Each segment (a, b) is registered in every cell it crosses (with 1e-4 cells of margin, so rounding cannot lose it);
// a segment crossing more than kMaxCellsPerSegment cells, or outside the grid's domain (2^30 cells either way), is
// kept in a list that every query reads. A query visits square rings of cells around the point's cell, clipped to
// the occupied cells, until the ring's distance exceeds the nearest distance found plus the margin: it returns the
// smallest distance D (the same PointSegmentDistance on the same coordinates as the exhaustive search) and the
// branches holding a segment within D + margin. When a query would visit more cells than a few times the segments
// (points far from everything) it gives up, and the caller searches exhaustively: never much slower than that.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace plantmorph
{

class StrokeSegmentGrid
{
public:
  /// The cell size follows the extent of `points` (every stroke point and existing centre-line point) and the
  /// expected number of segments: about one segment's worth of area per cell.
  StrokeSegmentGrid(const std::vector<Eigen::Vector2d>& points, std::size_t expectedSegments);

  /// Registers segment (a, b) of branch `branch`.
  void Add(std::size_t branch, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

  /// Segment (a, b) of branch `branch` became (a, c) and (c, b) (a point inserted into its centre line).
  void Split(std::size_t branch, const Eigen::Vector2d& a, const Eigen::Vector2d& c, const Eigen::Vector2d& b);

  /// The nearest distance D to p and the branches (sorted, unique) with a segment within D + margin. False when the
  /// query gave up or D is not finite: the caller then searches exhaustively.
  bool Nearest(const Eigen::Vector2d& p, double margin, double& nearest, std::vector<std::size_t>& branches);

  static constexpr std::size_t kMaxCellsPerSegment = 4096;

private:
  struct Entry
  {
    std::size_t branch;
    Eigen::Vector2d a, b;
    bool alive;
  };

  bool Cell(const Eigen::Vector2d& p, std::int64_t& ix, std::int64_t& iy) const;
  static std::uint64_t Key(std::int64_t ix, std::int64_t iy);
  void Visit(std::uint32_t entry, const Eigen::Vector2d& p, double margin, double& nearest);

  Eigen::Vector2d Origin = Eigen::Vector2d::Zero();
  double Size = 1.0;
  std::vector<Entry> Entries;
  std::vector<std::vector<std::uint32_t>> ByBranch;
  std::vector<std::uint32_t> Everywhere; ///< segments read by every query
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> Cells;
  std::int64_t Low[2] = { 0, 0 }, High[2] = { -1, -1 }; ///< the occupied cells' bounding box
  std::vector<std::uint32_t> Stamp;
  std::uint32_t Query = 0;
  std::vector<std::pair<double, std::size_t>> Found; ///< (distance, branch) within the margin so far
};

} // namespace plantmorph
