// SPDX-License-Identifier: GPL-3.0-or-later
// TrajectoryMatching (filters/comparison/core): paper 001 Table 1 gives the per-sample distances 1.76, 0.69, 2.52, 1.89,
// 2.92 cm, the x/y/z differences the paper prints, and the 6.1 degree angle between the motion directions (the
// paper prints 19.1; its own unit vectors give 6.1). The monotone matching is checked against brute-force
// enumeration of every increasing assignment, and differs from closest-sample matching where it must.
#include "TrajectoryMatching.h"

#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace plantmorph
{
namespace
{
// Table 1 of paper 001 (docs/references.md; as in data/cucumber-wilting-tip.csv), cm.
const std::vector<double> Measured = { 0.46, 19.58, -2.13, -1.26, 18.51, -3.43, -1.30, 13.45, -9.87, 0.10, 8.90, -14.10,
  0.60, 4.20, -18.40 };
const std::vector<double> PaperSimulated = { -1.06, 20.41, -1.79, -0.86, 19.03, -3.22, 1.12, 12.85, -9.49, 1.27, 9.90,
  -15.20, 1.50, 1.70, -19.60 };

TEST(TrajectoryMatching, ReproducesPaper001Table1)
{
  const TrajectoryComparison c = CompareTrajectories(Measured.data(), 5, PaperSimulated.data(), 5);
  ASSERT_EQ(c.error, "");
  // The paper's distances 1.764908, 0.688884, 2.522063, 1.891798, 2.915476 (its second one is 0.688840 from the
  // table's own two-decimal coordinates: the table was rounded after the distances were computed).
  const double paper[5] = { 1.764908, 0.688884, 2.522063, 1.891798, 2.915476 };
  const double rounded[5] = { 1.76, 0.69, 2.52, 1.89, 2.92 };
  for (std::size_t i = 0; i < 5; ++i)
  {
    EXPECT_EQ(c.closest.simulatedIndex[i], i);
    EXPECT_NEAR(c.closest.distance[i], paper[i], 5e-5);
    EXPECT_NEAR(std::round(c.closest.distance[i] * 100) / 100, rounded[i], 1e-12);
  }
  // |x|, |y|, |z| differences as the paper prints them (1.52, 0.4, 2.42, 1.17, 0.9 ...).
  const double dx[5] = { 1.52, 0.40, 2.42, 1.17, 0.90 };
  const double dy[5] = { 0.83, 0.52, 0.60, 1.00, 2.50 };
  const double dz[5] = { 0.34, 0.21, 0.38, 1.10, 1.20 };
  for (std::size_t i = 0; i < 5; ++i)
  {
    EXPECT_NEAR(std::fabs(c.closest.delta[3 * i]), dx[i], 1e-9);
    EXPECT_NEAR(std::fabs(c.closest.delta[3 * i + 1]), dy[i], 1e-9);
    EXPECT_NEAR(std::fabs(c.closest.delta[3 * i + 2]), dz[i], 1e-9);
  }
  EXPECT_NEAR(c.closest.meanDistance, (1.764908 + 0.688884 + 2.522063 + 1.891798 + 2.915476) / 5, 1e-5);
  EXPECT_NEAR(c.closest.maxDistance, 2.915476, 1e-6);
  EXPECT_NEAR(c.closest.directionAngle, 6.1, 0.05);
  // Recomputed from the paper's printed unit vectors, the same angle.
  const double measuredUnit[3] = { 0.006253, -0.68694, -0.72669 };
  const double simulatedUnit[3] = { 0.098621, -0.72078, -0.68611 };
  EXPECT_NEAR(AngleBetween(measuredUnit, simulatedUnit), c.closest.directionAngle, 0.01);
  // Five against five: the monotone matching is the identity too.
  ASSERT_TRUE(c.hasMonotone);
  EXPECT_EQ(c.monotone.simulatedIndex, c.closest.simulatedIndex);
}

TEST(TrajectoryMatching, MonotoneMatchingIsTheBestIncreasingAssignment)
{
  RandomStream random(4);
  for (int trial = 0; trial < 30; ++trial)
  {
    // Two samples at least: a single one has no direction and is refused.
    const std::size_t n = 2 + static_cast<std::size_t>(random.Integer(0, 3));
    const std::size_t m = n + static_cast<std::size_t>(random.Integer(0, 5));
    std::vector<double> measured(3 * n);
    std::vector<double> simulated(3 * m);
    for (double& x : measured)
    {
      x = random.Uniform(-1, 1);
    }
    for (double& x : simulated)
    {
      x = random.Uniform(-1, 1);
    }
    const TrajectoryComparison c = CompareTrajectories(measured.data(), n, simulated.data(), m);
    ASSERT_TRUE(c.hasMonotone);
    // Brute force over all strictly increasing index sequences.
    double best = std::numeric_limits<double>::infinity();
    std::vector<std::size_t> current(n);
    std::function<void(std::size_t, std::size_t, double)> enumerate = [&](std::size_t i, std::size_t from, double sum) {
      if (i == n)
      {
        best = std::min(best, sum);
        return;
      }
      for (std::size_t j = from; j < m; ++j)
      {
        const double d = std::sqrt(std::pow(measured[3 * i] - simulated[3 * j], 2) +
          std::pow(measured[3 * i + 1] - simulated[3 * j + 1], 2) +
          std::pow(measured[3 * i + 2] - simulated[3 * j + 2], 2));
        enumerate(i + 1, j + 1, sum + d);
      }
    };
    enumerate(0, 0, 0.0);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      sum += c.monotone.distance[i];
      if (i > 0)
      {
        EXPECT_LT(c.monotone.simulatedIndex[i - 1], c.monotone.simulatedIndex[i]);
      }
    }
    EXPECT_NEAR(sum, best, 1e-12);
    // Closest-sample is never worse per sample.
    for (std::size_t i = 0; i < n; ++i)
    {
      EXPECT_LE(c.closest.distance[i], c.monotone.distance[i] + 1e-15);
    }
  }
}

TEST(TrajectoryMatching, MonotoneKeepsTimeOrderWhereClosestDoesNot)
{
  // The simulated tip passes the same place twice (down then back up); measurements 0 and 2 are both nearest to
  // simulated sample 0, but in time the third measurement belongs to the return.
  const std::vector<double> simulated = { 0, 0, 0, 0, -1, 0, 0, -2, 0, 0, -1, 0, 0, 0.1, 0 };
  const std::vector<double> measured = { 0, 0, 0, 0, -2, 0, 0, 0.03, 0 };
  const TrajectoryComparison c = CompareTrajectories(measured.data(), 3, simulated.data(), 5);
  EXPECT_EQ(c.closest.simulatedIndex, (std::vector<std::size_t>{ 0, 2, 0 }));
  EXPECT_EQ(c.monotone.simulatedIndex, (std::vector<std::size_t>{ 0, 2, 4 }));
}

TEST(TrajectoryMatching, BadInput)
{
  EXPECT_NE(CompareTrajectories(Measured.data(), 0, PaperSimulated.data(), 5).error, "");
  EXPECT_NE(CompareTrajectories(Measured.data(), 5, PaperSimulated.data(), 0).error, "");
  std::vector<double> nan = Measured;
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(CompareTrajectories(nan.data(), 5, PaperSimulated.data(), 5).error.find("sample 2"), std::string::npos);
  const TrajectoryComparison fewer = CompareTrajectories(Measured.data(), 5, PaperSimulated.data(), 3);
  EXPECT_EQ(fewer.error, "");
  EXPECT_FALSE(fewer.hasMonotone);
  // One sample: the direction is undefined, so it is refused (it used to give a NaN angle).
  EXPECT_NE(CompareTrajectories(Measured.data(), 1, PaperSimulated.data(), 5).error.find("measured trajectory has 1"),
    std::string::npos);
  EXPECT_NE(
    CompareTrajectories(Measured.data(), 5, PaperSimulated.data(), 1).error.find("at least 2"), std::string::npos);
  EXPECT_EQ(CompareTrajectories(Measured.data(), 2, PaperSimulated.data(), 2).error, "");
}

} // namespace
} // namespace plantmorph
