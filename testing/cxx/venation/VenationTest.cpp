// SPDX-License-Identifier: GPL-3.0-or-later
// Venation (paper 000 sec. 3, docs/methods/venation.md) on real blades from LeafOutlineSource's models: veins stay on
// the blade and inside its outline, the network is connected through veins of equal or lower order, growth junctions
// keep their angles, areoles are closed and scale with AreoleSize, every pattern builds, palmate growth forks
// dichotomously, the statistics are what the network measures, and the same seed gives the same network bit for bit.
#include "MeshInvariants.h"
#include "VenationGrowth.h"

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "PalmateLeaf.h"
#include "SpaceCurvePresets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>

namespace plantmorph
{
namespace
{
using testing::InsideOrOn;

VenationBlade BladeOf(const LeafGeometry& leaf)
{
  return { leaf.blade.points, leaf.blade.uv, leaf.blade.triangles };
}

LeafGeometry EntireLeaf(int resolution = 60)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  LeafGeometry leaf;
  EXPECT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, 5.0), settings, leaf), "");
  return leaf;
}

VenationResult Grow(const LeafGeometry& leaf, const VenationParameters& p)
{
  VenationResult result;
  EXPECT_EQ(GrowVenation(BladeOf(leaf), p, result), "");
  return result;
}

std::vector<Eigen::Vector2d> Outline(const LeafGeometry& leaf)
{
  // The blade's boundary loop (left margin reversed after the right one), closed.
  std::vector<Eigen::Vector2d> polygon;
  for (int id : leaf.rightMargin)
    polygon.push_back(leaf.blade.points[id]);
  for (std::size_t i = leaf.leftMargin.size() - 1; i-- > 0;)
    polygon.push_back(leaf.blade.points[leaf.leftMargin[i]]);
  return polygon;
}

/// Nodes of veins of order <= `order` connected to a primary vein through such veins.
std::vector<char> ReachableFromPrimaries(const VenationResult& r, int order)
{
  std::vector<std::vector<int>> next(r.nodes.size());
  std::queue<int> queue;
  std::vector<char> reached(r.nodes.size(), 0);
  for (const auto& vein : r.veins)
  {
    if (vein.order > order)
      continue;
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      next[vein.nodes[i]].push_back(vein.nodes[i + 1]);
      next[vein.nodes[i + 1]].push_back(vein.nodes[i]);
    }
    if (vein.order == VeinOrderPrimary)
    {
      for (int n : vein.nodes)
      {
        if (!reached[n])
        {
          reached[n] = 1;
          queue.push(n);
        }
      }
    }
  }
  while (!queue.empty())
  {
    const int n = queue.front();
    queue.pop();
    for (int m : next[n])
    {
      if (!reached[m])
      {
        reached[m] = 1;
        queue.push(m);
      }
    }
  }
  return reached;
}

class EveryPattern : public ::testing::TestWithParam<int>
{
};

TEST_P(EveryPattern, VeinsLieOnTheBladeInsideItsOutlineAndReachTheMidvein)
{
  const LeafGeometry leaf = EntireLeaf();
  VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
  p.pattern = static_cast<VenationPattern>(GetParam());
  p.veinlets = true;
  p.seed = 11;
  const VenationResult r = Grow(leaf, p);
  ASSERT_GT(r.veins.size(), 10u);
  ASSERT_EQ(r.nodes.size(), r.location.size());
  std::vector<Eigen::Vector2d> outline = Outline(leaf);
  outline.push_back(outline.front());
  const double size = r.leafLength;
  for (std::size_t i = 0; i < r.nodes.size(); ++i)
  {
    // On the surface: inside a blade triangle, the point its weights give.
    const BladeLocation& at = r.location[i];
    ASSERT_GE(at.triangle, 0) << "node " << i;
    const auto& t = leaf.blade.triangles[at.triangle];
    const Eigen::Vector2d x = at.weights[0] * leaf.blade.points[t[0]] + at.weights[1] * leaf.blade.points[t[1]] +
      at.weights[2] * leaf.blade.points[t[2]];
    EXPECT_LT((x - r.nodes[i]).norm(), 1e-6 * size) << "node " << i;
    EXPECT_GE(at.weights.minCoeff(), 0.0);
    EXPECT_TRUE(InsideOrOn(r.nodes[i], outline, 1e-9 * size)) << "node " << i;
  }
  for (const auto& vein : r.veins)
  {
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      EXPECT_TRUE(InsideOrOn(0.5 * (r.nodes[vein.nodes[i]] + r.nodes[vein.nodes[i + 1]]), outline, 1e-9 * size));
  }
  // Connected: every vein of order k reaches a primary through veins of order <= k.
  for (int order = VeinOrderSecondary; order <= VeinOrderVeinlet; ++order)
  {
    const std::vector<char> reached = ReachableFromPrimaries(r, order);
    for (const auto& vein : r.veins)
    {
      if (vein.order == order)
      {
        EXPECT_TRUE(reached[vein.nodes.front()] || reached[vein.nodes.back()]) << "a vein of order " << order;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
  Venation, EveryPattern, ::testing::Range(0, VenationPatternCount), [](const ::testing::TestParamInfo<int>& info) {
    return VenationPatternName(static_cast<VenationPattern>(info.param));
  });

TEST(Venation, GrowthJunctionsKeepTheirAnglesAndAverage120Degrees)
{
  const LeafGeometry leaf = EntireLeaf();
  VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
  p.areoleSize = 0.025;
  const VenationResult r = Grow(leaf, p);
  ASSERT_GT(r.junctionAngles.size(), 300u);
  double sum = 0.0;
  for (double angle : r.junctionAngles)
  {
    EXPECT_GE(angle, p.minJunctionAngle);
    sum += angle;
  }
  EXPECT_NEAR(sum / r.junctionAngles.size(), 120.0, 10.0);
  // The recorded angles are the geometry's: at a growth node of degree 3 made of tertiaries, the three angles
  // between its edges add to 360 and none is below the minimum.
  std::vector<std::vector<int>> next(r.nodes.size());
  std::vector<int> order(r.nodes.size(), 9);
  for (const auto& vein : r.veins)
  {
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      next[vein.nodes[i]].push_back(vein.nodes[i + 1]);
      next[vein.nodes[i + 1]].push_back(vein.nodes[i]);
    }
  }
  int checked = 0;
  for (std::size_t n = 0; n < r.nodes.size(); ++n)
  {
    // Reticulum nodes (tertiary or quaternary: grown alike, only classified after growth).
    if (next[n].size() != 3 || (r.order[n] != VeinOrderTertiary && r.order[n] != VeinOrderQuaternary))
      continue;
    std::vector<double> angles;
    for (int m : next[n])
    {
      const Eigen::Vector2d d = r.nodes[m] - r.nodes[n];
      angles.push_back(std::atan2(d.y(), d.x()) * 180.0 / 3.14159265358979323846);
    }
    std::sort(angles.begin(), angles.end());
    const double gaps[3] = { angles[1] - angles[0], angles[2] - angles[1], 360.0 - angles[2] + angles[0] };
    // Growth nodes (not T-junctions on a vein, where a straight vein makes a 180 degree gap).
    if (*std::max_element(gaps, gaps + 3) > 179.0)
      continue;
    ++checked;
    for (double g : gaps)
      EXPECT_GE(g, p.minJunctionAngle - 1e-6);
  }
  EXPECT_GT(checked, 100);
}

TEST(Venation, AreolesAreClosedAndScaleWithAreoleSize)
{
  const LeafGeometry leaf = EntireLeaf(100);
  VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
  double previous = 0.0;
  for (double size : { 0.04, 0.02, 0.01 })
  {
    p.areoleSize = size;
    const VenationResult r = Grow(leaf, p);
    // Closed: no vein ends free (veinlets off), so every vein edge borders two areoles or the margin.
    EXPECT_EQ(r.statistics.freeEnds, 0u) << "AreoleSize " << size;
    ASSERT_GT(r.statistics.areoles, 20u);
    const double unit = size * r.leafLength;
    const double relative = r.statistics.areoleAreaMean / (unit * unit);
    EXPECT_GT(relative, 0.3);
    EXPECT_LT(relative, 2.0);
    if (previous > 0.0)
    {
      EXPECT_NEAR(previous / r.statistics.areoleAreaMean, 4.0, 1.2); // halving the size quarters the areoles
    }
    previous = r.statistics.areoleAreaMean;
  }
}

TEST(Venation, VeinletsEndFreeInsideAreoles)
{
  const LeafGeometry leaf = EntireLeaf();
  const VenationParameters p = MakeVenationPreset(VenationPreset::Poplar);
  const VenationResult r = Grow(leaf, p);
  std::size_t veinlets = 0;
  std::map<int, int> degree;
  for (const auto& vein : r.veins)
  {
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      ++degree[vein.nodes[i]];
      ++degree[vein.nodes[i + 1]];
    }
  }
  for (const auto& vein : r.veins)
  {
    if (vein.order != VeinOrderVeinlet)
      continue;
    ++veinlets;
    EXPECT_EQ(degree[vein.nodes.back()], 1);  // its tip meets nothing
    EXPECT_GE(degree[vein.nodes.front()], 3); // its start is on an areole's vein
  }
  EXPECT_GT(veinlets, 20u);
  EXPECT_GE(r.statistics.freeEnds, veinlets);
  EXPECT_GT(r.statistics.length[VeinOrderVeinlet], 0.0);
}

TEST(Venation, SecondariesLeaveTheMidveinAtTheDivergenceAngle)
{
  const LeafGeometry leaf = EntireLeaf();
  VenationParameters p;
  p.pattern = VenationPattern::Craspedodromous;
  p.tertiary = false;
  for (double angle : { 40.0, 70.0 })
  {
    p.divergenceAngle = p.divergenceAngleApex = angle;
    const VenationResult r = Grow(leaf, p);
    int checked = 0;
    for (const auto& vein : r.veins)
    {
      if (vein.order != VeinOrderSecondary)
        continue;
      // The midvein is the Y axis of this blade: the first piece's angle to +Y.
      const Eigen::Vector2d d = r.nodes[vein.nodes[1]] - r.nodes[vein.nodes[0]];
      EXPECT_EQ(r.nodes[vein.nodes[0]].x(), 0.0);
      const double measured = std::atan2(std::abs(d.x()), d.y()) * 180.0 / 3.14159265358979323846;
      EXPECT_NEAR(measured, angle, 1.0);
      ++checked;
    }
    EXPECT_GT(checked, 10);
  }
}

TEST(Venation, StatisticsAreWhatTheNetworkMeasures)
{
  const LeafGeometry leaf = EntireLeaf();
  const VenationResult r = Grow(leaf, MakeVenationPreset(VenationPreset::Poplar));
  double length[VeinOrderCount] = {};
  std::size_t segments = 0;
  for (const auto& vein : r.veins)
  {
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      length[vein.order] += (r.nodes[vein.nodes[i + 1]] - r.nodes[vein.nodes[i]]).norm();
    segments += vein.nodes.size() - 1;
  }
  double total = 0.0;
  for (int o = 1; o < VeinOrderCount; ++o)
  {
    EXPECT_NEAR(r.statistics.length[o], length[o], 1e-9 * (1.0 + length[o]));
    total += length[o];
  }
  EXPECT_EQ(r.statistics.segments, segments);
  double area = 0.0;
  for (const auto& t : leaf.blade.triangles)
    area += testing::SignedArea(leaf.blade.points, t);
  EXPECT_NEAR(r.statistics.bladeArea, area, 1e-9 * area);
  EXPECT_NEAR(r.statistics.density, total / area, 1e-9 * total / area);
  EXPECT_NEAR(r.statistics.length[VeinOrderPrimary], r.leafLength, 1e-6 * r.leafLength); // the midvein
}

TEST(Venation, SameSeedSameNetworkOtherSeedOtherNetwork)
{
  const LeafGeometry leaf = EntireLeaf();
  VenationParameters p = MakeVenationPreset(VenationPreset::Poplar);
  p.seed = 5;
  const VenationResult a = Grow(leaf, p), b = Grow(leaf, p);
  ASSERT_EQ(a.nodes, b.nodes);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.veins.size(), b.veins.size());
  for (std::size_t i = 0; i < a.veins.size(); ++i)
    ASSERT_EQ(a.veins[i].nodes, b.veins[i].nodes);
  p.seed = 6;
  const VenationResult c = Grow(leaf, p);
  EXPECT_NE(a.nodes, c.nodes);
}

TEST(Venation, GinkgoForksDichotomouslyIntoVeinsThatReachTheMargin)
{
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  ASSERT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf), "");
  const VenationParameters p = MakeVenationPreset(VenationPreset::Ginkgo);
  const VenationResult r = Grow(leaf, p);
  // p.palmateVeins veins from the base, each forking p.forkLevels times: with 2 and 5, 2 + (4 + 8 + ... + 64) veins,
  // all 64 tips on the margin, 2 + 4 + ... + 32 = 62 forks.
  int primaries = 0, branches = 0;
  std::set<int> tips;
  std::vector<std::vector<int>> next(r.nodes.size());
  for (const auto& vein : r.veins)
  {
    (vein.order == VeinOrderPrimary ? primaries : branches) += 1;
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      next[vein.nodes[i]].push_back(vein.nodes[i + 1]);
      next[vein.nodes[i + 1]].push_back(vein.nodes[i]);
    }
  }
  EXPECT_EQ(primaries, p.palmateVeins);
  EXPECT_EQ(branches, p.palmateVeins * ((2 << p.forkLevels) - 2));
  EXPECT_EQ(r.statistics.freeEnds, 0u);
  std::size_t forks = 0;
  for (const auto& n : next)
    forks += n.size() == 3;
  EXPECT_EQ(forks, static_cast<std::size_t>(p.palmateVeins * ((1 << p.forkLevels) - 1)));
  // Every vein starts at the base (0, 0) or at a fork, never on another vein's side.
  for (const auto& vein : r.veins)
  {
    const int start = vein.nodes.front();
    EXPECT_TRUE(r.nodes[start].norm() < 1e-12 || next[start].size() == 3);
  }
}

TEST(Venation, PalmateVeinsFollowThePalmateBladesLobes)
{
  // On paper 002's 5-lobed leaf, one palmate primary runs to each lobe tip (VenationPalmateTest.cpp measures them).
  SpaceCurveMeshParameters settings;
  settings.resolution = 40;
  LeafGeometry leaf;
  ASSERT_EQ(BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Figure8FiveLobes, 5.0), settings, leaf), "");
  VenationParameters p = MakeVenationPreset(VenationPreset::Ginkgo);
  p.palmateVeins = 5;
  p.forkLevels = 0;
  const VenationResult r = Grow(leaf, p);
  ASSERT_EQ(r.veins.size(), 5u);
  // The 5 vein ends spread over the blade's width.
  double low = 0.0, high = 0.0;
  for (const auto& vein : r.veins)
  {
    low = std::min(low, r.nodes[vein.nodes.back()].x());
    high = std::max(high, r.nodes[vein.nodes.back()].x());
  }
  double left = 0.0, right = 0.0;
  for (const Eigen::Vector2d& x : leaf.blade.points)
  {
    left = std::min(left, x.x());
    right = std::max(right, x.x());
  }
  EXPECT_GT(high - low, 0.5 * (right - left));
}

TEST(Venation, BadInputGivesAMessageNamingThePropertyAndNoNetwork)
{
  const LeafGeometry leaf = EntireLeaf(20);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Bad
  {
    const char* property;
    void (*change)(VenationParameters&, double);
    double value;
  };
  const Bad cases[] = {
    { "Pattern", [](VenationParameters& p, double v) { p.pattern = static_cast<VenationPattern>(static_cast<int>(v)); },
      VenationPatternCount },
    { "SecondarySpacing", [](VenationParameters& p, double v) { p.secondarySpacing = v; }, nan },
    { "DivergenceAngle", [](VenationParameters& p, double v) { p.divergenceAngle = v; }, 95 },
    { "AreoleSize", [](VenationParameters& p, double v) { p.areoleSize = v; }, 0.0 },
    { "MinJunctionAngle", [](VenationParameters& p, double v) { p.minJunctionAngle = v; }, 130 },
    { "ForkLevels", [](VenationParameters& p, double v) { p.forkLevels = static_cast<int>(v); }, 9 },
    { "AreoleSize",
      [](VenationParameters& p, double v) {
        p.areoleSize = v;
        p.maxSegments = 1000;
      },
      0.002 },
  };
  for (const Bad& bad : cases)
  {
    SCOPED_TRACE(bad.property);
    VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
    bad.change(p, bad.value);
    VenationResult r;
    const std::string error = GrowVenation(BladeOf(leaf), p, r);
    EXPECT_NE(error.find(bad.property), std::string::npos) << error;
    EXPECT_TRUE(r.nodes.empty() && r.veins.empty());
  }
  // A blade without LeafUV, or with NaN points, or without triangles.
  VenationBlade blade = BladeOf(leaf);
  blade.uv.pop_back();
  VenationResult r;
  EXPECT_NE(GrowVenation(blade, VenationParameters(), r).find("LeafUV"), std::string::npos);
  blade = BladeOf(leaf);
  blade.points[3].x() = nan;
  EXPECT_NE(GrowVenation(blade, VenationParameters(), r).find("non-finite"), std::string::npos);
  blade.triangles.clear();
  EXPECT_NE(GrowVenation(blade, VenationParameters(), r).find("no triangles"), std::string::npos);
  EXPECT_TRUE(r.nodes.empty());
}

TEST(Venation, ReliefRisesOnVeinsAndNowhereElse)
{
  const LeafGeometry leaf = EntireLeaf(120);
  VenationParameters p;
  p.pattern = VenationPattern::Craspedodromous;
  p.tertiary = false;
  const VenationResult r = Grow(leaf, p);
  const std::vector<double> heights = VeinReliefHeights(BladeOf(leaf), r, 0.1);
  ASSERT_EQ(heights.size(), leaf.blade.points.size());
  double highest = 0.0;
  int raised = 0;
  for (std::size_t i = 0; i < heights.size(); ++i)
  {
    highest = std::max(highest, heights[i]);
    raised += heights[i] > 0.0;
    if (heights[i] > 0.0)
    {
      EXPECT_LE(heights[i], 0.1 + 1e-12);
    }
  }
  EXPECT_GT(highest, 0.05); // on the midvein
  EXPECT_GT(raised, 20);
  EXPECT_LT(raised, static_cast<int>(heights.size()) / 2);
  // The midvein's own points (x = 0 on this blade) are raised.
  for (std::size_t i = 0; i < heights.size(); ++i)
  {
    if (leaf.blade.points[i].x() == 0.0 && leaf.blade.points[i].y() > 0.1 && leaf.blade.points[i].y() < 4.0)
    {
      EXPECT_GT(heights[i], 0.0) << "midvein point " << i;
    }
  }
  EXPECT_EQ(VeinReliefHeights(BladeOf(leaf), r, 0.0), std::vector<double>(heights.size(), 0.0));
}

} // namespace
} // namespace plantmorph
