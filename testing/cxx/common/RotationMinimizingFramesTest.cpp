// SPDX-License-Identifier: GPL-3.0-or-later
// Rotation-minimising frames by double reflection: orthonormal, no twist on planar curves, and on a helix the
// normal turns against the Frenet frame by -(torsion * arc length), the RMF's defining property.
#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <cmath>

using namespace plantmorph;

TEST(RotationMinimizingFrames, AreOrthonormalAndRightHanded)
{
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 50; ++k)
  {
    points.emplace_back(std::cos(0.3 * k), 0.2 * k, std::sin(0.17 * k * k / 10.0));
  }
  const auto frames = RotationMinimizingFrames(points, PolylineTangents(points), Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(frames.size(), points.size());
  for (const auto& f : frames)
  {
    EXPECT_NEAR(f.tangent.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.normal.dot(f.tangent), 0.0, 1e-12);
    EXPECT_LT((f.normal.cross(f.tangent) - f.binormal).norm(), 1e-12);
  }
}

TEST(RotationMinimizingFrames, PlanarCurveKeepsTheBinormalOnThePlaneNormal)
{
  // A curve in the XY plane started with its normal in the plane: the binormal stays +-Z exactly (no twist).
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k <= 40; ++k)
  {
    const double t = 0.1 * k;
    points.emplace_back(t, std::sin(2.0 * t), 0.0);
  }
  const auto tangents = PolylineTangents(points);
  const Eigen::Vector3d normal0 = Eigen::Vector3d::UnitZ().cross(tangents[0]);
  const auto frames = RotationMinimizingFrames(points, tangents, normal0);
  for (const auto& f : frames)
  {
    EXPECT_NEAR(std::abs(f.binormal.z()), 1.0, 1e-12);
    EXPECT_NEAR(f.normal.z(), 0.0, 1e-12);
  }
}

TEST(RotationMinimizingFrames, HelixNormalTurnsByMinusTorsionTimesArcLength)
{
  // Helix (a cos t, a sin t, b t): curvature a/(a^2+b^2), torsion b/(a^2+b^2), speed sqrt(a^2+b^2). The RMF's
  // angle to the Frenet normal changes by -torsion * s: after parameter T, by -b*T/sqrt(a^2+b^2).
  const double a = 1.0, b = 0.5, T = 4.0;
  const int n = 4000;
  std::vector<Eigen::Vector3d> points, tangents;
  for (int k = 0; k <= n; ++k)
  {
    const double t = T * k / n;
    points.emplace_back(a * std::cos(t), a * std::sin(t), b * t);
    tangents.push_back(Eigen::Vector3d(-a * std::sin(t), a * std::cos(t), b).normalized());
  }
  const auto frenetNormal = [&](double t) { return Eigen::Vector3d(-std::cos(t), -std::sin(t), 0.0); };
  const auto frames = RotationMinimizingFrames(points, tangents, frenetNormal(0.0));
  const Eigen::Vector3d nT = frenetNormal(T);
  const Eigen::Vector3d bT = tangents.back().cross(nT);
  // Angle of the RMF normal measured from the Frenet normal towards the Frenet binormal.
  const double angle = std::atan2(frames.back().normal.dot(bT), frames.back().normal.dot(nT));
  const double expected = -b * T / std::sqrt(a * a + b * b);
  EXPECT_NEAR(angle, expected, 1e-5);
}

TEST(RotationMinimizingFrames, PolylineTangentsAreBisectors)
{
  const std::vector<Eigen::Vector3d> points = { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 1, 0 }, { 1, 1, 0 } };
  const auto t = PolylineTangents(points);
  EXPECT_LT((t[0] - Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);
  EXPECT_LT((t[3] - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
  // The duplicated point borrows the following direction: the bisector sits at the repeated vertex.
  EXPECT_LT((t[1] - Eigen::Vector3d(1, 1, 0).normalized()).norm(), 1e-15);
}
