// SPDX-License-Identifier: GPL-3.0-or-later
// Bezier curves and the stroke control-point rule (paper 004 sec. 3.1).
#include <plantmorph/BezierCurve.h>

#include <gtest/gtest.h>

#include <cmath>

using plantmorph::EvaluateBezier;

namespace
{
double Binomial(int n, int k)
{
  double r = 1.0;
  for (int i = 1; i <= k; ++i)
  {
    r = r * (n - k + i) / i;
  }
  return r;
}
} // namespace

TEST(BezierCurve, MatchesTheBernsteinFormAtEveryDegree)
{
  for (int degree = 1; degree <= 9; ++degree)
  {
    std::vector<Eigen::Vector3d> controls;
    for (int i = 0; i <= degree; ++i)
    {
      controls.emplace_back(std::sin(1.3 * i), std::cos(0.7 * i * i), 0.1 * i);
    }
    for (double t : { 0.0, 0.1, 0.37, 0.5, 0.9, 1.0 })
    {
      Eigen::Vector3d expected = Eigen::Vector3d::Zero();
      for (int i = 0; i <= degree; ++i)
      {
        expected += Binomial(degree, i) * std::pow(t, i) * std::pow(1.0 - t, degree - i) * controls[std::size_t(i)];
      }
      EXPECT_LT((EvaluateBezier<3>(controls, t) - expected).norm(), 1e-13) << degree << " " << t;
    }
    EXPECT_EQ(EvaluateBezier<3>(controls, 0.0), controls.front());
    EXPECT_EQ(EvaluateBezier<3>(controls, 1.0), controls.back());
  }
}

TEST(BezierCurve, ReproducesAStraightLineWithUniformSpeed)
{
  // Control points equally spaced on a line: the curve is the line at uniform speed, B(t) = P0 + t (P3 - P0).
  const std::vector<Eigen::Vector2d> controls = { { 0, 0 }, { 1, 2 }, { 2, 4 }, { 3, 6 } };
  const auto samples = plantmorph::SampleBezier<2>(controls, 6);
  ASSERT_EQ(samples.size(), 7u);
  for (int k = 0; k <= 6; ++k)
  {
    EXPECT_LT((samples[std::size_t(k)] - Eigen::Vector2d(3.0 * k / 6, 6.0 * k / 6)).norm(), 1e-14);
  }
}

TEST(BezierCurve, StrokeControlIndicesKeepBothEndsAndNeverOverflow)
{
  EXPECT_EQ(plantmorph::StrokeControlIndices(10, 4), (std::vector<int>{ 0, 3, 6, 9 }));
  EXPECT_EQ(plantmorph::StrokeControlIndices(5, 5), (std::vector<int>{ 0, 1, 2, 3, 4 }));
  EXPECT_EQ(plantmorph::StrokeControlIndices(3, 8), (std::vector<int>{ 0, 1, 2 })); // n clamped to m
  EXPECT_EQ(plantmorph::StrokeControlIndices(7, 2), (std::vector<int>{ 0, 6 }));
  for (int m = 2; m < 60; ++m)
  {
    for (int n = 2; n <= m; ++n)
    {
      const auto idx = plantmorph::StrokeControlIndices(m, n);
      ASSERT_EQ(int(idx.size()), n);
      EXPECT_EQ(idx.front(), 0);
      EXPECT_EQ(idx.back(), m - 1);
      for (std::size_t i = 1; i < idx.size(); ++i)
      {
        EXPECT_LT(idx[i - 1], idx[i]);
      }
    }
  }
}
