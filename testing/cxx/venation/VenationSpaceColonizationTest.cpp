// SPDX-License-Identifier: GPL-3.0-or-later
// Space colonization venation (Runions et al. 2005, open venation; SpaceColonization.h) on the
// project's own blades: the veins cover the blade (95 % of its points within 3 % of the leaf length of a vein), the
// network is a tree, widths obey the pipe model with the chosen Murray exponent, the same seed gives the same
// network bit for bit, and bad distances are refused with a message naming the property.
#include "VenationGrowth.h"
#include "VeinNetworkMeasures.h"

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "SpaceCurvePresets.h"

#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numeric>

namespace plantmorph
{
namespace
{
VenationBlade BladeOf(const LeafGeometry& leaf)
{
  return { leaf.blade.points, leaf.blade.uv, leaf.blade.triangles };
}

LeafGeometry Entire()
{
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  EXPECT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, 5.0), settings, leaf), "");
  return leaf;
}

LeafGeometry Cucumber()
{
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  EXPECT_EQ(BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Cucumber, 8.0, 7.0, 9), settings, leaf), "");
  return leaf;
}

LeafGeometry Lobed()
{
  SpaceCurveMeshParameters settings;
  settings.resolution = 40;
  LeafGeometry leaf;
  EXPECT_EQ(BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Figure8FiveLobes, 5.0), settings, leaf), "");
  return leaf;
}

VenationParameters Colonization(std::uint64_t seed = 1)
{
  VenationParameters p;
  p.pattern = VenationPattern::SpaceColonization;
  p.seed = seed;
  return p;
}

VenationResult Grow(const LeafGeometry& leaf, const VenationParameters& p)
{
  VenationResult result;
  EXPECT_EQ(GrowVenation(BladeOf(leaf), p, result), "");
  return result;
}

double SegmentDistance(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * d - x).norm();
}

/// Distances from uniformly random blade points (area-weighted triangles) to the nearest vein segment, sorted.
std::vector<double> DistancesToVeins(const LeafGeometry& leaf, const VenationResult& r, int samples)
{
  const auto& points = leaf.blade.points;
  std::vector<double> cumulative;
  double total = 0.0;
  for (const auto& t : leaf.blade.triangles)
  {
    const Eigen::Vector2d a = points[t[1]] - points[t[0]], b = points[t[2]] - points[t[0]];
    total += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    cumulative.push_back(total);
  }
  RandomStream random(99);
  std::vector<double> distances;
  for (int k = 0; k < samples; ++k)
  {
    const auto at = std::lower_bound(cumulative.begin(), cumulative.end(), random.Uniform() * total);
    const auto& t = leaf.blade.triangles[std::min<std::size_t>(at - cumulative.begin(), cumulative.size() - 1)];
    double s = random.Uniform(), q = random.Uniform();
    if (s + q > 1.0)
    {
      s = 1.0 - s;
      q = 1.0 - q;
    }
    const Eigen::Vector2d x = points[t[0]] + s * (points[t[1]] - points[t[0]]) + q * (points[t[2]] - points[t[0]]);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& vein : r.veins)
      for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
        best = std::min(best, SegmentDistance(x, r.nodes[vein.nodes[i]], r.nodes[vein.nodes[i + 1]]));
    distances.push_back(best);
  }
  std::sort(distances.begin(), distances.end());
  return distances;
}

/// Every node's parent (from the veins: each polyline runs away from the base), -1 at the base.
std::vector<int> Parents(const VenationResult& r)
{
  std::vector<int> parent(r.nodes.size(), -2);
  parent[r.veins.front().nodes.front()] = -1;
  for (const auto& vein : r.veins)
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      EXPECT_EQ(parent[vein.nodes[i + 1]], -2) << "node " << vein.nodes[i + 1] << " has two parents (a loop)";
      parent[vein.nodes[i + 1]] = vein.nodes[i];
    }
  return parent;
}

class Coverage : public ::testing::TestWithParam<int>
{
};

TEST_P(Coverage, NinetyFivePercentOfTheBladeLiesWithinThreePercentOfTheLengthFromAVein)
{
  const LeafGeometry leaf = GetParam() == 0 ? Entire() : GetParam() == 1 ? Cucumber() : Lobed();
  const VenationResult r = Grow(leaf, Colonization(3));
  ASSERT_GT(r.veins.size(), 20u);
  const std::vector<double> d = DistancesToVeins(leaf, r, 4000);
  const double p95 = d[d.size() * 95 / 100] / r.leafLength;
  std::cout << "blade " << GetParam() << ": " << r.statistics.segments << " segments, 95th percentile distance " << p95
            << " L, largest " << d.back() / r.leafLength << " L\n";
  EXPECT_LT(p95, 0.03);
  // Inside the blade along every segment, not only at its nodes (the lobed blade's sinuses are narrow).
  BladeLocator locator;
  const VenationBlade blade = BladeOf(leaf);
  ASSERT_EQ(locator.Build(blade), "");
  int outside = 0;
  for (const auto& vein : r.veins)
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      for (int k = 1; k < 16; ++k)
      {
        const Eigen::Vector2d x =
          r.nodes[vein.nodes[i]] + k / 16.0 * (r.nodes[vein.nodes[i + 1]] - r.nodes[vein.nodes[i]]);
        outside += locator.Locate(x, 1e-9 * r.leafLength).triangle < 0;
      }
  EXPECT_EQ(outside, 0);
}

INSTANTIATE_TEST_SUITE_P(
  SpaceColonization, Coverage, ::testing::Values(0, 1, 2), [](const ::testing::TestParamInfo<int>& info) {
    return std::string(info.param == 0 ? "Entire" : info.param == 1 ? "Cucumber" : "FiveLobes");
  });

TEST(SpaceColonization, OpenVenationIsATreeFromTheBase)
{
  const LeafGeometry leaf = Entire();
  const VenationResult r = Grow(leaf, Colonization(4));
  ASSERT_GT(r.nodes.size(), 100u);
  // Every node has exactly one parent and the parents lead to the base: nodes = segments + 1, no loop.
  const std::vector<int> parent = Parents(r);
  EXPECT_EQ(r.statistics.segments + 1, r.nodes.size());
  EXPECT_EQ(r.statistics.areoles, 0u);
  const Eigen::Vector2d base = r.nodes[r.veins.front().nodes.front()];
  for (std::size_t i = 0; i < r.nodes.size(); ++i)
  {
    ASSERT_NE(parent[i], -2) << "node " << i << " is on no vein";
    int at = static_cast<int>(i);
    std::size_t hops = 0;
    while (parent[at] >= 0 && hops <= r.nodes.size())
    {
      at = parent[at];
      ++hops;
    }
    ASSERT_EQ(parent[at], -1) << "node " << i << " does not reach the base";
  }
  // The measures see a tree: loopiness 1, no areole, every free end plus the base has one segment.
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, r.statistics.bladeArea, {}, 0.0, m), "");
  EXPECT_NEAR(m.loopiness, 1.0, 1e-12);
  EXPECT_EQ(m.areoles, 0u) << (m.areoles ? m.areoleAreas.back() : 0.0);
  EXPECT_EQ(m.freeEnds, r.statistics.freeEnds + 1);
  EXPECT_EQ(m.branchPoints, r.statistics.branchPoints);
  EXPECT_EQ(r.veins.front().order, VeinOrderPrimary);
  EXPECT_LT(base.y(), r.nodes[r.veins.front().nodes.back()].y()); // the midvein runs from the base upwards
}

TEST(SpaceColonization, WidthsFollowThePipeModel)
{
  const LeafGeometry leaf = Entire();
  for (const double n : { 2.0, 3.0 })
  {
    VenationParameters p = Colonization(5);
    p.murrayExponent = n;
    const VenationResult r = Grow(leaf, p);
    const std::vector<int> parent = Parents(r);
    std::vector<double> sum(r.nodes.size(), 0.0);
    std::vector<int> children(r.nodes.size(), 0);
    for (std::size_t i = 0; i < r.nodes.size(); ++i)
    {
      if (parent[i] >= 0)
      {
        sum[parent[i]] += std::pow(r.width[i], n);
        ++children[parent[i]];
      }
    }
    const double tip = *std::min_element(r.width.begin(), r.width.end());
    const int base = r.veins.front().nodes.front();
    EXPECT_NEAR(r.width[base], p.primaryWidth * r.leafLength, 1e-12 * r.leafLength);
    for (std::size_t i = 0; i < r.nodes.size(); ++i)
    {
      if (children[i] == 0)
        EXPECT_NEAR(r.width[i], tip, 1e-12 * tip) << "free end " << i;
      else
        EXPECT_NEAR(std::pow(r.width[i], n), sum[i], 1e-9 * sum[i]) << "node " << i;
    }
  }
}

TEST(SpaceColonization, SameSeedSameNetworkOtherSeedOtherNetwork)
{
  const LeafGeometry leaf = Cucumber();
  const VenationResult a = Grow(leaf, Colonization(8)), b = Grow(leaf, Colonization(8));
  ASSERT_EQ(a.nodes, b.nodes);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.veins.size(), b.veins.size());
  for (std::size_t i = 0; i < a.veins.size(); ++i)
    ASSERT_EQ(a.veins[i].nodes, b.veins[i].nodes);
  const VenationResult c = Grow(leaf, Colonization(9));
  EXPECT_NE(a.nodes, c.nodes);
}

TEST(SpaceColonization, ClosedVenationMakesLoopsAndCoversTheBlade)
{
  // Closed venation (Runions 2005 sec. 4): veins approaching one source from different sides meet there, so the
  // network has areoles and loopiness below 1, and it still covers the blade.
  const LeafGeometry leaf = Entire();
  VenationParameters p = Colonization(6);
  p.closedVenation = true;
  const VenationResult r = Grow(leaf, p);
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, r.statistics.bladeArea, {}, 0.0, m), "");
  std::cout << "closed: " << r.statistics.segments << " segments, " << m.areoles << " areoles, loopiness "
            << m.loopiness << "\n";
  EXPECT_GE(m.areoles, 20u);
  EXPECT_LT(m.loopiness, 0.97);
  const std::vector<double> d = DistancesToVeins(leaf, r, 2000);
  EXPECT_LT(d[d.size() * 95 / 100] / r.leafLength, 0.03);
  const VenationResult again = Grow(leaf, p);
  EXPECT_EQ(r.nodes, again.nodes);
}

TEST(VeinNetworkMeasures, AgreeWithTheGrowthsOwnCountsOnAPaperMulberryNetwork)
{
  // The growth counts areoles as faces of its vein graph with the margin that no margin edge bounds, and free ends
  // off the margin; the measures see only the veins and the margin polygon, and must count the same.
  const LeafGeometry leaf = Entire();
  VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
  p.seed = 12;
  const VenationResult r = Grow(leaf, p);
  std::vector<Eigen::Vector2d> margin;
  for (int id : leaf.rightMargin)
    margin.push_back(leaf.blade.points[id]);
  for (std::size_t i = leaf.leftMargin.size() - 1; i-- > 1;)
    margin.push_back(leaf.blade.points[leaf.leftMargin[i]]);
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, r.statistics.bladeArea, margin, 1e-9 * r.leafLength, m), "");
  ASSERT_GT(r.statistics.areoles, 50u);
  EXPECT_EQ(m.areoles, r.statistics.areoles);
  EXPECT_NEAR(m.areoleMean, r.statistics.areoleAreaMean, 1e-9 * r.statistics.areoleAreaMean);
  EXPECT_EQ(m.branchPoints, r.statistics.branchPoints);
  EXPECT_EQ(m.freeEnds, r.statistics.freeEnds);
  EXPECT_NEAR(m.vla, r.statistics.density, 1e-9 * r.statistics.density);
  EXPECT_LT(m.loopiness, 0.9);
}

TEST(SpaceColonization, MarginalGrowthPutsTheFinerVeinsNearTheMargin)
{
  // Marginal growth (Runions 2005): sources appear only within one attraction distance of the growing margin, so
  // the interior is colonized early and sparsely and the margin's band late and densely: the share of the vein
  // length lying in the band (within 0.1 L of the margin) is larger than with sources added uniformly.
  const LeafGeometry leaf = Entire();
  std::vector<Eigen::Vector2d> margin;
  for (int id : leaf.rightMargin)
    margin.push_back(leaf.blade.points[id]);
  for (std::size_t i = leaf.leftMargin.size() - 1; i-- > 1;)
    margin.push_back(leaf.blade.points[leaf.leftMargin[i]]);
  const auto bandShare = [&](const VenationResult& r) {
    double band = 0.0, total = 0.0;
    for (const auto& vein : r.veins)
    {
      for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      {
        const Eigen::Vector2d a = r.nodes[vein.nodes[i]], b = r.nodes[vein.nodes[i + 1]], m = 0.5 * (a + b);
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < margin.size(); ++k)
        {
          const Eigen::Vector2d p = margin[k], e = margin[(k + 1) % margin.size()] - p;
          const double t = std::clamp((m - p).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
          d = std::min(d, (p + t * e - m).norm());
        }
        total += (b - a).norm();
        band += d <= 0.1 * r.leafLength ? (b - a).norm() : 0.0;
      }
    }
    return band / total;
  };
  VenationParameters p = Colonization(5);
  const VenationResult uniform = Grow(leaf, p);
  p.marginalGrowth = true;
  const VenationResult marginal = Grow(leaf, p);
  const double u = bandShare(uniform), m = bandShare(marginal);
  std::cout << "vein length within 0.1 L of the margin: uniform " << u << ", marginal " << m << " ("
            << uniform.nodes.size() << " and " << marginal.nodes.size() << " nodes)\n";
  EXPECT_GT(m, u + 0.05);
  EXPECT_EQ(marginal.nodes, Grow(leaf, p).nodes); // seeded: bit-identical
}

TEST(SpaceColonization, AStaticBladeGrowsToo)
{
  // growthStart = 1: every source is there from the start, most far beyond the attraction distance of the base.
  const LeafGeometry leaf = Entire();
  VenationParameters p = Colonization(2);
  p.growthStart = 1.0;
  const VenationResult r = Grow(leaf, p);
  const std::vector<double> d = DistancesToVeins(leaf, r, 2000);
  EXPECT_LT(d[d.size() * 95 / 100] / r.leafLength, 0.03);
}

TEST(SpaceColonization, BadDistancesGiveAMessageNamingThePropertyAndNoNetwork)
{
  const LeafGeometry leaf = Entire();
  struct Case
  {
    const char* property;
    VenationParameters p;
  };
  std::vector<Case> cases;
  cases.push_back({ "KillDistance", Colonization() });
  cases.back().p.killDistance = 0.0;
  cases.push_back({ "AttractionDistance", Colonization() });
  cases.back().p.attractionDistance = 0.5 * cases.back().p.killDistance;
  cases.push_back({ "SourceDensity", Colonization() });
  cases.back().p.sourceDensity = std::numeric_limits<double>::quiet_NaN();
  cases.push_back({ "MurrayExponent", Colonization() });
  cases.back().p.murrayExponent = 0.5;
  cases.push_back({ "GrowthStart", Colonization() });
  cases.back().p.growthStart = 0.0;
  cases.push_back({ "MaxSegments", Colonization() });
  cases.back().p.maxSegments = 100;
  for (const Case& c : cases)
  {
    VenationResult r;
    const std::string message = GrowVenation(BladeOf(leaf), c.p, r);
    EXPECT_NE(message.find(c.property), std::string::npos) << message;
    EXPECT_TRUE(r.nodes.empty() && r.veins.empty()) << c.property;
  }
}

} // namespace
} // namespace plantmorph
