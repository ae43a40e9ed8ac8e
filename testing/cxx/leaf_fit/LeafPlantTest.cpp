// SPDX-License-Identifier: GPL-3.0-or-later
// LeafPlant (filters/leaf_fit/plant/): leaf ids read as the integers they are, separate blades found as leaves,
// Bending as out-of-plane bending only, the plant's inclination distribution (beta fit against known parameters),
// the checks of a fitted leaf and the columns' units.
#include "LeafFit.h"
#include "LeafPlant.h"
#include "ReversedLoops.h"
#include "PointGrid.h" // CrossSpacing

#include <plantmorph/MathConstants.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace plantmorph
{
namespace
{
using plantmorph::testing::ReversedOnTwoThreads;

/// Points on a flat ellipse of semi-axes a (along X) and b (along Y) centred at `centre` in the plane z = 0: a
/// jittered grid of step h, with noise of `noise` along Z.
std::vector<Eigen::Vector3d> Ellipse(
  const Eigen::Vector3d& centre, double a, double b, double h, double noise, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.3 * h, 0.3 * h);
  std::normal_distribution<double> normal(0.0, noise);
  std::vector<Eigen::Vector3d> points;
  for (double x = -a; x <= a; x += h)
    for (double y = -b; y <= b; y += h)
    {
      const Eigen::Vector3d p(x + jitter(random), y + jitter(random), normal(random));
      if ((p.x() / a) * (p.x() / a) + (p.y() / b) * (p.y() / b) <= 1.0)
        points.push_back(centre + p);
    }
  return points;
}

/// Points on a flat ellipse (semi-axes a along X, b along Y) along lines y = const `gap` apart, `step` apart on a line
/// (a line scanner's pattern: the nearest-neighbour spacing is the step, the gaps between lines are much wider).
std::vector<Eigen::Vector3d> LineScannedEllipse(
  const Eigen::Vector3d& centre, double a, double b, double step, double gap)
{
  std::vector<Eigen::Vector3d> points;
  for (double y = -b + 0.5 * gap; y < b; y += gap)
    for (double x = -a; x <= a; x += step)
      if ((x / a) * (x / a) + (y / b) * (y / b) <= 1.0)
        points.push_back(centre + Eigen::Vector3d(x, y, 0.0));
  return points;
}

TEST(LeafPlant, SampleIdsAreEvenAndDependOnThePointsOnly)
{
  // A regular grid of 500 x 400 points thinned to about 20000: the same points whatever their order, about the
  // target count, spread evenly (each 50 x 40 block keeps about 200) and without the grid's aliasing.
  std::vector<Eigen::Vector3d> grid;
  for (int i = 0; i < 500; ++i)
    for (int j = 0; j < 400; ++j)
      grid.emplace_back(0.1 * i, 0.1 * j, 0.0);
  const std::vector<int> ids = SampleIds(grid, 20000);
  EXPECT_NEAR(static_cast<double>(ids.size()), 20000.0, 600.0);
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
  std::vector<int> blocks(100, 0);
  for (int id : ids)
    ++blocks[(id / 400) / 50 * 10 + (id % 400) / 40];
  for (int count : blocks)
  {
    EXPECT_GT(count, 140);
    EXPECT_LT(count, 260);
  }
  const std::vector<Eigen::Vector3d> reversed(grid.rbegin(), grid.rend());
  std::vector<int> back;
  for (int id : SampleIds(reversed, 20000))
    back.push_back(static_cast<int>(grid.size()) - 1 - id);
  std::sort(back.begin(), back.end());
  EXPECT_EQ(back, ids);
  EXPECT_EQ(SampleIds(grid, grid.size()).size(), grid.size());
}

TEST(LeafPlant, ALineScannedLeafIsOneLeaf)
{
  // Lines 0.2 apart, points 0.02 apart along them: a radius from the nearest-neighbour spacing alone (6 x 0.02) cut
  // the leaf into its 50 lines; the spacing across the lines (0.2) keeps it one leaf. Two such leaves with margins
  // 3 apart stay two.
  std::vector<Eigen::Vector3d> points = LineScannedEllipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.2);
  EXPECT_NEAR(CrossSpacing(points), 0.2, 0.01);
  LeafSeparation cut = SeparateLeaves(points);
  EXPECT_EQ(cut.count, 1);
  EXPECT_EQ(cut.strayParts, 0);
  const std::vector<Eigen::Vector3d> second = LineScannedEllipse({ 7.0, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.2);
  points.insert(points.end(), second.begin(), second.end());
  cut = SeparateLeaves(points);
  EXPECT_EQ(cut.count, 2);
  EXPECT_LT(cut.radius, 3.0);
}

TEST(LeafPlant, ALineScannedLeafIsFittedWhole)
{
  // The line-scanned ellipse (semi-axes 2 and 5, lines 0.2 apart across it, points 0.02 apart along them): the
  // traced outline joins the lines (its discs from the spacing across them: from the 0.02 along them, it left the
  // lines' ends apart, Area 19.8). Length 10 and Area 10 pi within 3 % (the first and last lines are 0.1 inside the
  // tips), a mesh of a few thousand vertices.
  const std::vector<Eigen::Vector3d> points = LineScannedEllipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.2);
  const LeafFitResult fit = FitLeaf(points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_NEAR(fit.traits.length, 10.0, 0.3);
  EXPECT_NEAR(fit.traits.area, 10.0 * Pi, 0.03 * 10.0 * Pi);
  EXPECT_LT(fit.points.size(), 20000u);
}

TEST(LeafPlant, AMeshTooLargeForTheBladeIsRefused)
{
  // A round blade (radius 5) at Resolution 1000 would need about 10^6 vertices: refused before meshing, with a
  // message naming Resolution (the mesh's size is bounded by MaxBladeVertices, whatever the input).
  const std::vector<Eigen::Vector3d> points = LineScannedEllipse({ 0.0, 0.0, 0.0 }, 5.0, 5.0, 0.05, 0.1);
  LeafFitParameters options;
  options.resolution = 1000;
  const LeafFitResult fit = FitLeaf(points, options);
  EXPECT_NE(fit.error.find("Resolution 1000"), std::string::npos) << fit.error;
  EXPECT_NE(fit.error.find("lower Resolution"), std::string::npos) << fit.error;
  EXPECT_TRUE(fit.points.empty());
}

TEST(LeafPlant, TwoEllipsesThreeUnitsApartAreTwoLeavesOfTheRightArea)
{
  // Two 10 x 4 ellipses (semi-axes 5 and 2, area 10 pi) side by side, their margins 3 units apart.
  std::vector<Eigen::Vector3d> points = Ellipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.1, 0.005, 1);
  const std::vector<Eigen::Vector3d> second = Ellipse({ 7.0, 0.0, 0.0 }, 2.0, 5.0, 0.1, 0.005, 2);
  points.insert(points.end(), second.begin(), second.end());
  const LeafSeparation cut = SeparateLeaves(points);
  ASSERT_EQ(cut.count, 2);
  EXPECT_GT(cut.radius, 0.0);
  EXPECT_LT(cut.radius, 3.0);
  std::vector<std::vector<Eigen::Vector3d>> leaves(2);
  for (std::size_t i = 0; i < points.size(); ++i)
    leaves[cut.leafOf[i]].push_back(points[i]);
  // Numbered in the order of their first point: the first ellipse is leaf 0.
  EXPECT_EQ(leaves[0].size(), points.size() - second.size());
  for (const auto& leaf : leaves)
  {
    const LeafFitResult fit = FitLeaf(leaf, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    // Within the fit's documented accuracy on small scans (2 % under 5000 points), not the 478 of one invented leaf.
    EXPECT_NEAR(fit.traits.area / (10.0 * Pi), 1.0, 0.02);
    EXPECT_NEAR(fit.traits.length, 10.0, 0.1);
    EXPECT_NEAR(fit.traits.width, 4.0, 0.08);
  }
}

/// A flat 10 x 10 grid of step 1 (median spacing 1, so the joining radius is 6) at `corner`.
void AddSquare(std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& corner)
{
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      points.push_back(corner + Eigen::Vector3d(i, j, 0.0));
}

TEST(LeafPlant, SeparationOnThreadsIsTheSerialOne)
{
  // Three dense blades (2.3 x 10^5 points: the sorts and the joins cut into many pieces, the cubes into blocks),
  // two of them 0.2 apart across the joining radius's cubes, one tilted, and a few strays near the third.
  std::vector<Eigen::Vector3d> points = Ellipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.002, 11);
  for (const auto& p : Ellipse({ 4.2, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.002, 12))
    points.push_back(p);
  for (const auto& p : Ellipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.02, 0.002, 13))
    points.emplace_back(p.x() + 10.0, 0.6 * p.y() - 0.8 * p.z(), 0.8 * p.y() + 0.6 * p.z());
  for (int i = 0; i < 5; ++i)
    points.emplace_back(12.3 + 0.01 * i, 0.0, 0.5);
  const LeafSeparation serial = SeparateLeaves(points);
  const LeafSeparation threaded = SeparateLeaves(points, ReversedOnTwoThreads());
  EXPECT_EQ(serial.count, 3);
  EXPECT_EQ(serial.strayParts, 1);
  EXPECT_EQ(threaded.count, serial.count);
  EXPECT_EQ(threaded.strayParts, serial.strayParts);
  EXPECT_EQ(threaded.radius, serial.radius);
  EXPECT_TRUE(threaded.leafOf == serial.leafOf);
  // The spacings on a grid built once (any cell: the searches are exact) are the ones each builds for itself.
  const PointGrid grid(points, 0.37, ReversedOnTwoThreads());
  EXPECT_EQ(MedianSpacing(points, grid, ReversedOnTwoThreads()), MedianSpacing(points));
  EXPECT_EQ(CrossSpacing(points, grid, ReversedOnTwoThreads()), CrossSpacing(points));
}

TEST(LeafPlant, SeparationIsTheConnectedPartsAtItsRadius)
{
  // Square B 5.9 beyond A (joined), C 6.1 beyond B (apart), D diagonally off C's corner by (4.2, 4.2, 0.5), 5.96
  // apart (joined: cubes two apart along two axes are looked at), E 6.05 above D (apart).
  std::vector<Eigen::Vector3d> points;
  AddSquare(points, { 0.0, 0.0, 0.0 });    // A
  AddSquare(points, { 14.9, 0.0, 0.0 });   // B: 5.9 from A's last column (x = 9)
  AddSquare(points, { 30.0, 0.0, 0.0 });   // C: 6.1 from B's last column (x = 23.9)
  AddSquare(points, { 43.2, 13.2, 0.5 });  // D: from C's corner (39, 9, 0) by (4.2, 4.2, 0.5)
  AddSquare(points, { 43.2, 13.2, 6.55 }); // E: 6.05 above D
  const LeafSeparation cut = SeparateLeaves(points);
  EXPECT_DOUBLE_EQ(cut.radius, 6.0);
  // The oracle: every pair within the radius, joined.
  const int n = static_cast<int>(points.size());
  std::vector<int> label(n);
  for (int i = 0; i < n; ++i)
    label[i] = i;
  for (bool changed = true; changed;)
  {
    changed = false;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if ((points[i] - points[j]).norm() <= 6.0 && label[j] < label[i])
        {
          label[i] = label[j];
          changed = true;
        }
  }
  ASSERT_EQ(cut.count, 3); // A + B, C + D, E
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; j += 7)
      EXPECT_EQ(cut.leafOf[i] == cut.leafOf[j], label[i] == label[j]) << i << " " << j;
  EXPECT_EQ(cut.leafOf[0], 0);
  EXPECT_EQ(cut.leafOf[200], 1);
  EXPECT_EQ(cut.leafOf[400], 2);
}

TEST(LeafPlant, OneLeafWithStraysStaysOneLeaf)
{
  std::vector<Eigen::Vector3d> points = Ellipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.1, 0.005, 3);
  const std::size_t leaf = points.size();
  // A few stray points far away, and a band of missing points (a gap of 3 spacings) across the leaf.
  for (int i = 0; i < 5; ++i)
    points.emplace_back(20.0 + i, 20.0, 0.0);
  std::vector<Eigen::Vector3d> gapped;
  for (const auto& p : points)
    if (std::abs(p.y()) > 0.15)
      gapped.push_back(p);
  const LeafSeparation cut = SeparateLeaves(gapped);
  EXPECT_EQ(cut.count, 1);
  for (int id : cut.leafOf)
    EXPECT_EQ(id, 0);
  EXPECT_LT(gapped.size(), leaf + 5);
}

TEST(LeafPlant, LeafIdsAreReadAsTheIntegersTheyAre)
{
  std::int64_t a = -1, b = -1, c = -1;
  EXPECT_EQ(LeafIdOf(0.0, "Id", a), "");
  EXPECT_EQ(LeafIdOf(4294967296.0, "Id", b), ""); // 2^32: not 0 (an int cast would wrap it)
  EXPECT_EQ(LeafIdOf(2147483648.0, "Id", c), ""); // 2^31: not -2^31
  EXPECT_EQ(a, 0);
  EXPECT_EQ(b, std::int64_t(1) << 32);
  EXPECT_EQ(c, std::int64_t(1) << 31);
  EXPECT_NE(a, b);
  EXPECT_EQ(LeafIdOf(-7.0, "Id", a), "");
  EXPECT_EQ(a, -7);
  // Not integers: refused, naming the array and the value.
  std::int64_t id = 0;
  const std::string half = LeafIdOf(0.4, "Plant leaf", id);
  EXPECT_NE(half.find("'Plant leaf'"), std::string::npos) << half;
  EXPECT_NE(half.find("0.4"), std::string::npos) << half;
  const std::string nan = LeafIdOf(std::numeric_limits<double>::quiet_NaN(), "Plant leaf", id);
  EXPECT_NE(nan.find("'Plant leaf'"), std::string::npos) << nan;
  EXPECT_NE(nan.find("nan"), std::string::npos) << nan;
  EXPECT_NE(LeafIdOf(std::numeric_limits<double>::infinity(), "Id", id), "");
  EXPECT_NE(LeafIdOf(1e19, "Id", id), ""); // beyond 64 bits
}

/// A flat leaf whose midvein is a circular arc in its plane (a sickle): radius R, arc length L, half-width
/// w sin(pi s / L), sampled on a jittered grid in (s, t).
std::vector<Eigen::Vector3d> Sickle(double R, double L, double w)
{
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Eigen::Vector3d> points;
  const double h = 0.6;
  for (double s = 0.0; s <= L; s += h)
    for (double t = -w; t <= w; t += h)
    {
      const double ss = s + h * jitter(random), tt = t + h * jitter(random);
      if (ss < 0.0 || ss > L || std::abs(tt) > w * std::sin(Pi * ss / L))
        continue;
      const double angle = ss / R;
      // The arc's point and its inward normal, in the plane z = 0.
      const Eigen::Vector3d centre(R * std::sin(angle), R * (1.0 - std::cos(angle)), 0.0);
      const Eigen::Vector3d inward(-std::sin(angle), std::cos(angle), 0.0);
      points.push_back(centre + tt * inward + Eigen::Vector3d(0.0, 0.0, noise(random)));
    }
  return points;
}

TEST(LeafPlant, BendingIsZeroForAFlatLeafWithACurvedMidvein)
{
  // The midvein turns by L / R = 0.6 rad (34 degrees) within the plane: no out-of-plane bending at all.
  const LeafFitResult fit = FitLeaf(Sickle(100.0, 60.0, 8.0), LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_LT(fit.traits.bending, 1.0);
  EXPECT_LT(fit.traits.inclination, 1.0);
}

TEST(LeafPlant, BetaFitRecoversKnownParameters)
{
  // t = angle / 90 drawn from Beta(nu = 4, mu = 2.5) (t's exponent nu - 1, 1 - t's mu - 1), as gamma ratios.
  const double mu = 2.5, nu = 4.0;
  std::mt19937 random(11);
  std::gamma_distribution<double> x(nu, 1.0), y(mu, 1.0);
  std::vector<double> angles;
  for (int i = 0; i < 40000; ++i)
  {
    const double a = x(random), b = y(random);
    angles.push_back(90.0 * a / (a + b));
  }
  const BetaFit beta = FitBetaDistribution(angles);
  ASSERT_TRUE(beta.valid);
  EXPECT_NEAR(beta.mu / mu, 1.0, 0.04);
  EXPECT_NEAR(beta.nu / nu, 1.0, 0.04);
  // The density integrates to 1 over [0, 90] degrees and peaks at the mode 90 (nu - 1) / (mu + nu - 2).
  double integral = 0.0;
  for (int i = 0; i < 9000; ++i)
    integral += BetaDensity(beta, (i + 0.5) * 0.01) * 0.01;
  EXPECT_NEAR(integral, 1.0, 1e-3);
  const double mode = 90.0 * (beta.nu - 1.0) / (beta.mu + beta.nu - 2.0);
  EXPECT_GT(BetaDensity(beta, mode), BetaDensity(beta, mode - 5.0));
  EXPECT_GT(BetaDensity(beta, mode), BetaDensity(beta, mode + 5.0));
  // Exact moments: two angles give mean 45 and t variance 1/16, so mu = nu = 0.5 * (4 - 1) = 1.5... for {0, 90}
  // the variance is the largest any distribution on [0, 1] has: no beta fits it.
  EXPECT_FALSE(FitBetaDistribution({ 0.0, 90.0 }).valid);
  const BetaFit two = FitBetaDistribution({ 30.0, 60.0 }); // m = 1/2, v = 1/36: mu = nu = 0.5 (9 - 1) = 4
  ASSERT_TRUE(two.valid);
  EXPECT_NEAR(two.mu, 4.0, 1e-12);
  EXPECT_NEAR(two.nu, 4.0, 1e-12);
  EXPECT_FALSE(FitBetaDistribution({ 40.0 }).valid);
}

TEST(LeafPlant, PlantSummaryCountsFittedLeavesOnly)
{
  std::vector<LeafTraits> traits(4);
  const double areas[4] = { 10.0, 20.0, 1e9, 30.0 }, angles[4] = { 5.0, 15.0, 50.0, 90.0 };
  for (int i = 0; i < 4; ++i)
  {
    traits[i].area = areas[i];
    traits[i].inclination = angles[i];
  }
  const PlantSummary plant = SummarizePlant(traits, { true, true, false, true });
  EXPECT_EQ(plant.leaves, 3);
  EXPECT_EQ(plant.failed, 1);
  EXPECT_DOUBLE_EQ(plant.totalArea, 60.0);
  EXPECT_DOUBLE_EQ(plant.meanArea, 20.0);
  EXPECT_NEAR(plant.meanInclination, 110.0 / 3.0, 1e-12);
  ASSERT_EQ(plant.inclinationFraction.size(), 9u);
  EXPECT_NEAR(plant.inclinationFraction[0], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(plant.inclinationFraction[1], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(plant.inclinationFraction[8], 1.0 / 3.0, 1e-12); // 90 degrees in the last class
  EXPECT_EQ(PlantColumnNames().size(), PlantColumnValues(plant).size());
}

TEST(LeafPlant, EveryColumnHasAUnit)
{
  for (const std::string& name : TraitNames())
    EXPECT_NE(ColumnUnit(name, "mm"), "") << name;
  for (const std::string& name : PlantColumnNames())
    EXPECT_NE(ColumnUnit(name, "mm"), "") << name;
  EXPECT_EQ(ColumnUnit("Area", "mm"), "mm^2");
  EXPECT_EQ(ColumnUnit("RollingCurvature", "cm"), "1/cm");
  EXPECT_EQ(ColumnUnit("Bending", "mm"), "degrees");
  EXPECT_EQ(ScaledUnit("mm", 1.0), "mm");
  EXPECT_EQ(ScaledUnit("mm", 0.1), "cm");
  EXPECT_EQ(ScaledUnit("mm", 0.001), "m");
  EXPECT_EQ(ScaledUnit("cm", 10.0), "mm");
  EXPECT_EQ(ScaledUnit("mm", 0.5), "(2 mm)");
  EXPECT_EQ(ScaledUnit("", 0.1), "");
}

TEST(LeafPlant, AGoodFitPassesItsChecksAndAFlapDoesNot)
{
  // An ellipse is the same at both ends: without a hint its base is a guess, with the only warning saying so.
  const std::vector<Eigen::Vector3d> points = Ellipse({ 0.0, 0.0, 0.0 }, 2.0, 5.0, 0.1, 0.005, 4);
  const LeafFitResult guess = FitLeaf(points, LeafFitParameters());
  ASSERT_EQ(guess.error, "");
  EXPECT_EQ(guess.traits.baseFrom, 3);
  const std::vector<std::string> said = CheckFittedLeaf(guess, 60);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_NE(said[0].find("same at both ends"), std::string::npos);
  // With its base given, the fit passes its checks.
  LeafFitParameters hinted;
  hinted.basePoint = Eigen::Vector3d(0.0, -5.0, 0.0);
  const LeafFitResult fit = FitLeaf(points, hinted);
  ASSERT_EQ(fit.error, "");
  EXPECT_EQ(fit.traits.baseFrom, 1);
  EXPECT_GT(fit.traits.coverage, MinCoverage);
  EXPECT_NEAR(FlatModelArea(fit, 60) / fit.traits.area, 1.0, MaxModelAreaError);
  EXPECT_NEAR(FlatBladeArea(fit) / fit.traits.area, 1.0, 1e-3); // flat: laid flat, the same area
  EXPECT_TRUE(CheckFittedLeaf(fit, 60).empty());
  // The same fit with its Support made large over most of the blade: Coverage below the limit gives a warning.
  LeafFitResult flap = fit;
  flap.traits.coverage = 0.5;
  const std::vector<std::string> warnings = CheckFittedLeaf(flap, 60);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("Coverage"), std::string::npos);
  // A flat model shrunk by 10 % in width: its area is off by 10 %, and the warning gives both areas.
  LeafFitResult narrow = fit;
  for (auto* curve : { &narrow.flatLeftMargin, &narrow.flatRightMargin })
    for (auto& p : *curve)
      p.x() *= 0.9;
  const std::vector<std::string> model = CheckFittedLeaf(narrow, 60);
  ASSERT_EQ(model.size(), 1u);
  EXPECT_NE(model[0].find("area"), std::string::npos);
}

} // namespace
} // namespace plantmorph
