// SPDX-License-Identifier: GPL-3.0-or-later
// The segmentation's flat-array neighbour searches (filters/segmentation/core/SegmentationGrid.h) against brute force:
// the 3 x 3 x 3 blocks hold every point within a cell's side, and a ball's covariance summed from cell moments equals
// the exact covariance of the points whose cell mean is in the ball (of the points in the ball, when a cell holds one).
#include "SegmentationGrid.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

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
