// SPDX-License-Identifier: GPL-3.0-or-later
// PlaneFit: a tilted, noisy-free planar point set gives its own plane exactly (normal up to rounding, zero
// deviation); a bumped set reports the bump as its largest deviation; the normal always points to +Z. Median and
// RobustScale (statistics/Median.h), the fitters' robust scale: the median of odd and even counts; the robust scale of
// a symmetric set in closed form, about any centre and with either sign of a residual; and of a normal sample (its
// exact quantiles) the normal's deviation.
#include <plantmorph/PlaneFit.h>
#include <plantmorph/statistics/Median.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace plantmorph
{
namespace
{
std::vector<Eigen::Vector3d> TiltedGrid(
  const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v)
{
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 4; ++j)
      points.push_back(origin + i * u + j * v);
  return points;
}
/// The standard normal quantile of `p` (0 < p < 1), by bisection on the distribution function.
double NormalQuantile(double p)
{
  double low = -10.0, high = 10.0;
  for (int i = 0; i < 200; ++i)
  {
    const double middle = 0.5 * (low + high);
    (0.5 * std::erfc(-middle / std::sqrt(2.0)) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}
} // namespace

TEST(PlaneFit, RecoversATiltedPlaneWithItsLongAxis)
{
  const Eigen::Vector3d u = Eigen::Vector3d(2.0, 0.0, 1.0), v = Eigen::Vector3d(-0.5, 1.0, 1.0); // orthogonal to u
  const std::vector<Eigen::Vector3d> points = TiltedGrid(Eigen::Vector3d(1.0, -2.0, 3.0), u, v);
  const FittedPlane plane = FitPlane(points);
  const Eigen::Vector3d expected = u.cross(v).normalized() * (u.cross(v).z() < 0.0 ? -1.0 : 1.0);
  EXPECT_NEAR((plane.normal - expected).norm(), 0.0, 1e-12);
  EXPECT_GT(plane.normal.z(), 0.0);
  EXPECT_NEAR(plane.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(plane.major.dot(u.normalized())), 1.0, 1e-12); // the grid is longest along u
  EXPECT_LT(plane.maxDeviation, 1e-12);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : points)
    mean += x / static_cast<double>(points.size());
  EXPECT_NEAR((plane.centroid - mean).norm(), 0.0, 1e-12);
}

TEST(PlaneFit, NormalTurnedUpAndDeviationOfABump)
{
  std::vector<Eigen::Vector3d> points =
    TiltedGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, -1.0, 0.0));
  EXPECT_TRUE(AllAtSameHeight(points));
  points[5].z() = 0.7;
  EXPECT_FALSE(AllAtSameHeight(points));
  const FittedPlane plane = FitPlane(points);
  EXPECT_GT(plane.normal.z(), 0.0);
  // Every point's distance from the fitted plane is at most the reported deviation, and one attains it.
  double largest = 0.0;
  for (const Eigen::Vector3d& x : points)
    largest = std::max(largest, std::abs((x - plane.centroid).dot(plane.normal)));
  EXPECT_EQ(largest, plane.maxDeviation);
  EXPECT_GT(plane.maxDeviation, 0.5); // the bump stands out of the plane the other 27 points pull flat
  EXPECT_LT(plane.maxDeviation, 0.7);
}
// Points on a quarter of a circle give its centre and radius back: the algebraic fit is exact on exact points.
TEST(PlaneFit, CircleFromAQuarterArc)
{
  std::vector<Eigen::Vector2d> arc;
  for (int k = 0; k <= 20; ++k)
  {
    const double angle = 0.3 + 0.5 * std::acos(-1.0) * k / 20.0;
    arc.emplace_back(2.0 + 3.0 * std::cos(angle), -1.0 + 3.0 * std::sin(angle));
  }
  Eigen::Vector3d circle;
  ASSERT_TRUE(FitCircle(arc, circle));
  EXPECT_NEAR(circle.x(), 2.0, 1e-9);
  EXPECT_NEAR(circle.y(), -1.0, 1e-9);
  EXPECT_NEAR(circle.z(), 3.0, 1e-9);
}

TEST(PlaneFit, ConvexHullAreaOfAPolygonWithPointsInside)
{
  // A regular hexagon of circumradius 2 (area 3 sqrt(3) / 2 * 4), its vertices shuffled among points inside and on
  // its edges, one vertex repeated: the hull is the hexagon. Points on a line and fewer than three have no area.
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < 6; ++k)
  {
    const double a = k * 3.14159265358979323846 / 3.0;
    const Eigen::Vector2d v(2.0 * std::cos(a), 2.0 * std::sin(a));
    points.push_back(0.5 * v);
    points.push_back(v);
    points.push_back(0.25 * v + Eigen::Vector2d(0.1, -0.05));
  }
  points.push_back(points[1]);
  points.push_back(0.5 * (points[1] + points[4])); // the middle of an edge
  EXPECT_NEAR(ConvexHullArea(points), 6.0 * std::sqrt(3.0), 1e-12);
  EXPECT_EQ(ConvexHullArea({ Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(3, 3) }), 0.0);
  EXPECT_EQ(ConvexHullArea({ Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1) }), 0.0);
}

TEST(Median, OddCountGivesTheMiddleEvenCountTheUpperMiddle)
{
  EXPECT_DOUBLE_EQ(Median({ 5.0, -1.0, 3.0 }), 3.0);
  EXPECT_DOUBLE_EQ(Median({ 4.0, 1.0, 3.0, 2.0 }), 3.0);
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_DOUBLE_EQ(Median({}, 7.0), 7.0);
}

TEST(RobustScale, SymmetricSetInClosedForm)
{
  // Deviations 0, 1, 1, 3, 3 about the centre: median absolute deviation 1.
  const double centre = 2.5;
  const std::vector<double> values = { centre - 3.0, centre - 1.0, centre, centre + 1.0, centre + 3.0 };
  EXPECT_NEAR(RobustScale(values, centre), 1.4826, 1e-12);
  EXPECT_NEAR(MadToDeviation, 1.0 / NormalQuantile(0.75), 1e-4); // the normal's consistency factor
  // Residuals about 0: their signs do not matter, only their magnitudes.
  EXPECT_DOUBLE_EQ(RobustScale({ -2.0, 0.5, 2.0, -0.5, 4.0 }), MadToDeviation * 2.0);
  EXPECT_DOUBLE_EQ(RobustScale({ 2.0, 0.5, 2.0, 0.5, 4.0 }), MadToDeviation * 2.0);
  // One wild value among many does not move it.
  EXPECT_DOUBLE_EQ(RobustScale({ -1.0, 1.0, -1.0, 1.0, 1e6 }), MadToDeviation);
  EXPECT_TRUE(std::isnan(RobustScale({})));
  EXPECT_DOUBLE_EQ(RobustScale({}, 0.0, 0.0), 0.0);
}

TEST(RobustScale, NormalSampleGivesItsDeviation)
{
  // The exact quantiles of a normal of mean 10 and deviation 0.3: the median absolute deviation is 0.3 x
  // Phi^-1(3/4), so the robust scale is 0.3 to the precision of the factor (and of the sample's size).
  const int n = 20001;
  const double mean = 10.0, deviation = 0.3;
  std::vector<double> sample;
  for (int i = 0; i < n; ++i)
    sample.push_back(mean + deviation * NormalQuantile((i + 0.5) / n));
  EXPECT_NEAR(RobustScale(sample, Median(sample)), deviation, 1e-4);
  EXPECT_NEAR(RobustScale(sample, mean), deviation, 1e-4);
}

} // namespace plantmorph
