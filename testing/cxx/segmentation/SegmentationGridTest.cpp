// SPDX-License-Identifier: GPL-3.0-or-later
// The segmentation's flat-array neighbour searches (filters/segmentation/core/SegmentationGrid.h) against brute force:
// the 3 x 3 x 3 blocks hold every point within a cell's side, and a ball's covariance summed from cell moments equals
// the exact covariance of the points whose cell mean is in the ball (of the points in the ball, when a cell holds one).
#include "SegmentationGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <set>
#include <tuple>

namespace
{
std::vector<Eigen::Vector3d> RandomCloud(std::size_t n, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points(n);
  for (Eigen::Vector3d& p : points)
    p = Eigen::Vector3d(u(random), u(random), 0.2 * u(random));
  return points;
}
} // namespace

TEST(SegmentationGrid, BlocksHoldEveryPointWithinTheCellSide)
{
  const auto points = RandomCloud(4000, 3);
  const double side = 0.07;
  const plantmorph::segmentation::CellGrid grid(points, side);
  plantmorph::segmentation::CellGrid::Block block;
  for (std::size_t i = 0; i < points.size(); i += 7)
  {
    grid.BlockAround(points[i], block);
    std::set<int> found, expected;
    for (int run = 0; run < block.runs; ++run)
      for (std::size_t k = block.begin[run]; k < block.end[run]; ++k)
        if ((points[static_cast<std::size_t>(grid.Ordered()[k])] - points[i]).norm() <= side)
          found.insert(grid.Ordered()[k]);
    for (std::size_t j = 0; j < points.size(); ++j)
      if ((points[j] - points[i]).norm() <= side)
        expected.insert(static_cast<int>(j));
    ASSERT_EQ(found, expected) << "point " << i;
  }
  // A query far outside the cloud reads its border cells and finds nothing within the side.
  grid.BlockAround(Eigen::Vector3d(50.0, 0.0, 0.0), block);
  for (int run = 0; run < block.runs; ++run)
    for (std::size_t k = block.begin[run]; k < block.end[run]; ++k)
      EXPECT_GT((points[static_cast<std::size_t>(grid.Ordered()[k])] - Eigen::Vector3d(50.0, 0.0, 0.0)).norm(), side);
}

TEST(SegmentationGrid, BallCovarianceFromMomentsIsTheExactOne)
{
  const auto points = RandomCloud(3000, 5);
  const double radius = 0.3;
  // Cells far smaller than the spacing: one point each, so the ball is exactly the points within the radius.
  const plantmorph::segmentation::BallMoments exact(points, 1e-5, radius);
  // Cells of a quarter radius: the points whose cell's mean lies in the ball.
  const plantmorph::segmentation::BallMoments coarse(points, radius / 4.0, radius);
  plantmorph::segmentation::CellGrid::Block block;
  for (std::size_t i = 0; i < points.size(); i += 97)
  {
    const Eigen::Vector3d q = points[i];
    for (const auto* moments : { &exact, &coarse })
    {
      std::vector<Eigen::Vector3d> inside;
      for (std::size_t c = 0; c < moments->Cells().CellCount(); ++c)
        if ((moments->Means()[c] - q).norm() <= radius)
          for (const int* j = moments->Cells().Begin(c); j != moments->Cells().End(c); ++j)
            inside.push_back(points[static_cast<std::size_t>(*j)]);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& p : inside)
        mean += p;
      mean /= static_cast<double>(inside.size());
      Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
      for (const Eigen::Vector3d& p : inside)
        expected += (p - mean) * (p - mean).transpose();
      expected /= static_cast<double>(inside.size());
      double count = 0.0;
      block = {};
      const Eigen::Matrix3d got = moments->Covariance(q, count, block);
      EXPECT_EQ(count, static_cast<double>(inside.size()));
      EXPECT_LT((got - expected).norm(), 1e-12) << "point " << i;
    }
  }
}

namespace
{
/// A ParallelFor that hands out ranges of three indices, last range first: any dependence on how the range is cut
/// or in which order the pieces run shows.
void ReversedSmallRanges(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body)
{
  for (std::size_t end = count; end > 0;)
  {
    const std::size_t begin = end > 3 ? end - 3 : 0;
    body(begin, end);
    end = begin;
  }
}

/// The grid's cells and order against brute force: the points ordered by their cell (i, then j, then k, each
/// floor((p - low) / side)), ties by index, every cell's points together.
void ExpectCellOrder(const std::vector<Eigen::Vector3d>& points, const plantmorph::segmentation::CellGrid& grid)
{
  Eigen::Vector3d low = points.front();
  for (const Eigen::Vector3d& p : points)
    low = low.cwiseMin(p);
  std::vector<std::tuple<long long, long long, long long, int>> expected;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::Vector3d c = ((points[i] - low) / grid.Cell()).array().floor();
    expected.emplace_back(
      static_cast<long long>(c.x()), static_cast<long long>(c.y()), static_cast<long long>(c.z()), static_cast<int>(i));
  }
  std::sort(expected.begin(), expected.end());
  ASSERT_EQ(grid.Ordered().size(), points.size());
  std::size_t cells = 0;
  for (std::size_t k = 0; k < expected.size(); ++k)
  {
    ASSERT_EQ(grid.Ordered()[k], std::get<3>(expected[k])) << "position " << k;
    const bool newCell = k == 0 ||
      std::make_tuple(std::get<0>(expected[k]), std::get<1>(expected[k]), std::get<2>(expected[k])) !=
        std::make_tuple(std::get<0>(expected[k - 1]), std::get<1>(expected[k - 1]), std::get<2>(expected[k - 1]));
    cells += newCell ? 1 : 0;
    const auto c = static_cast<std::size_t>(grid.CellOfPoint(static_cast<std::size_t>(grid.Ordered()[k])));
    ASSERT_EQ(c, cells - 1) << "position " << k;
    ASSERT_TRUE(grid.Begin(c) <= grid.Ordered().data() + k && grid.Ordered().data() + k < grid.End(c));
  }
  EXPECT_EQ(grid.CellCount(), cells);
}
} // namespace

TEST(SegmentationGrid, ThreadedGridIsTheSerialOneInCellThenIndexOrder)
{
  // Cells of a small side (the cells numbered in the cloud's box fit 64 bits with the index: the radix sort) and a
  // cloud spread over the whole key range (2^21 cells an axis: the sort by comparisons).
  std::vector<Eigen::Vector3d> wide = RandomCloud(300, 7);
  wide[0] = Eigen::Vector3d(-1e7, -1e7, -1e7);
  wide[1] = Eigen::Vector3d(1e7, 1e7, 1e7);
  for (const auto& [points, side] : { std::make_pair(RandomCloud(5000, 11), 0.01), std::make_pair(wide, 1e-9) })
  {
    const plantmorph::segmentation::CellGrid serial(points, side);
    const plantmorph::segmentation::CellGrid threaded(points, side, ReversedSmallRanges);
    ExpectCellOrder(points, threaded);
    EXPECT_EQ(threaded.Ordered(), serial.Ordered());
    EXPECT_EQ(threaded.CellCount(), serial.CellCount());
    for (std::size_t i = 0; i < points.size(); ++i)
      ASSERT_EQ(threaded.CellOfPoint(i), serial.CellOfPoint(i));
  }
}
