// SPDX-License-Identifier: GPL-3.0-or-later
// Palmate leaves (paper 002 sec. 4, Fig. 8): the lobes' union is one manifold blade that tiles its outline exactly
// (no overlapping triangles where the lobes overlap), every lobe's midvein is a feature line from the base to its
// tip, the leaf is mirror-symmetric, grows as an exact similarity, and bad lobe parameters are refused.
#include "MeshInvariants.h"
#include "PalmateLeaf.h"
#include "SpaceCurvePresets.h"

#include <plantmorph/DataContract.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace plantmorph
{
namespace
{
using testing::BoundaryLoops;
using testing::EdgeUse;
using testing::InsideOrOn;
using testing::SignedArea;

LeafGeometry Build(const SpaceCurveParameters& p, bool quality, int resolution = 40)
{
  SpaceCurveMeshParameters settings;
  settings.resolution = resolution;
  settings.quality = quality;
  LeafGeometry leaf;
  EXPECT_EQ(BuildSpaceCurveLeaf(p, settings, leaf), "");
  return leaf;
}

/// The outline as a closed polygon: right margin from the base to lobe 1's tip, then the left margin back down.
std::vector<Eigen::Vector2d> OutlinePolygon(const LeafGeometry& leaf)
{
  std::vector<Eigen::Vector2d> polygon;
  for (int id : leaf.rightMargin)
    polygon.push_back(leaf.blade.points[id]);
  for (std::size_t i = leaf.leftMargin.size() - 2; i >= 1; --i)
    polygon.push_back(leaf.blade.points[leaf.leftMargin[i]]);
  return polygon;
}

double Area(const std::vector<Eigen::Vector2d>& polygon)
{
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

struct Case
{
  SpaceCurvePreset preset;
  bool quality;
};

class EveryPalmatePreset : public ::testing::TestWithParam<Case>
{
};

TEST_P(EveryPalmatePreset, BladeIsOneManifoldDiskThatTilesTheLobesUnion)
{
  const SpaceCurveParameters p = MakeSpaceCurvePreset(GetParam().preset, 5.0);
  const LeafGeometry leaf = Build(p, GetParam().quality);
  ASSERT_FALSE(leaf.blade.triangles.empty());
  ASSERT_EQ(leaf.lobeMidveins.size(), static_cast<std::size_t>(p.lobes - 1));

  // Manifold disk: every edge in one or two triangles, one boundary loop, Euler characteristic 1.
  const auto use = EdgeUse(leaf.blade.triangles);
  for (const auto& [edge, count] : use)
    ASSERT_LE(count, 2);
  const auto loops = BoundaryLoops(leaf.blade.triangles);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(static_cast<long>(leaf.blade.points.size()) - static_cast<long>(use.size()) +
      static_cast<long>(leaf.blade.triangles.size()),
    1L);

  // The boundary loop is exactly the two margins (which meet at the base and lobe 1's tip).
  const std::set<int> boundary(loops[0].begin(), loops[0].end());
  std::set<int> margins(leaf.leftMargin.begin(), leaf.leftMargin.end());
  margins.insert(leaf.rightMargin.begin(), leaf.rightMargin.end());
  EXPECT_EQ(boundary, margins);

  // No overlapping triangles: all counter-clockwise, inside the outline, and their areas add up to its area.
  const std::vector<Eigen::Vector2d> polygon = OutlinePolygon(leaf);
  std::vector<Eigen::Vector2d> closed = polygon;
  closed.push_back(polygon.front());
  double total = 0.0;
  for (const auto& t : leaf.blade.triangles)
  {
    const double area = SignedArea(leaf.blade.points, t);
    ASSERT_GT(area, 0.0);
    total += area;
    const Eigen::Vector2d centroid =
      (leaf.blade.points[t[0]] + leaf.blade.points[t[1]] + leaf.blade.points[t[2]]) / 3.0;
    ASSERT_TRUE(InsideOrOn(centroid, closed, 1e-12));
  }
  EXPECT_NEAR(total, Area(polygon), 1e-9 * Area(polygon));

  // The lobes add to lobe 1: the palmate blade is much larger than the simple leaf with the same curvature.
  SpaceCurveParameters simple = p;
  simple.lobes = 1;
  const LeafGeometry single = Build(simple, GetParam().quality);
  EXPECT_GT(Area(polygon), 1.5 * Area(OutlinePolygon(single)));
}

TEST_P(EveryPalmatePreset, EveryLobeMidveinIsAFeatureLineFromTheBaseToItsTip)
{
  const SpaceCurveParameters p = MakeSpaceCurvePreset(GetParam().preset, 5.0);
  const LeafGeometry leaf = Build(p, GetParam().quality);
  ASSERT_FALSE(leaf.blade.triangles.empty());
  const auto use = EdgeUse(leaf.blade.triangles);
  const auto loops = BoundaryLoops(leaf.blade.triangles);
  ASSERT_EQ(loops.size(), 1u);
  const std::set<int> boundary(loops[0].begin(), loops[0].end());
  std::vector<std::vector<int>> midveins = leaf.lobeMidveins;
  midveins.insert(midveins.begin(), leaf.midvein);
  std::set<int> tips;
  for (const std::vector<int>& midvein : midveins)
  {
    ASSERT_GE(midvein.size(), 3u);
    EXPECT_EQ(midvein.front(), leaf.midvein.front()); // all from the base
    EXPECT_EQ(leaf.blade.points[midvein.front()], Eigen::Vector2d::Zero());
    EXPECT_TRUE(boundary.count(midvein.back())); // to a tip on the outline
    tips.insert(midvein.back());
    const double u = leaf.blade.uv[midvein[midvein.size() - 2]].x(); // its own stretch (the first may be shared)
    for (std::size_t i = 0; i + 1 < midvein.size(); ++i)
    {
      // Each piece is a mesh edge between two triangles: the midvein is interior and no triangle crosses it.
      const auto edge = std::minmax(midvein[i], midvein[i + 1]);
      ASSERT_TRUE(use.count(edge));
      EXPECT_EQ(use.at(edge), 2);
      if (i > 0)
      {
        EXPECT_FALSE(boundary.count(midvein[i]));
        EXPECT_EQ(leaf.blade.region[midvein[i]], RegionMidvein);
      }
      EXPECT_LE(leaf.blade.uv[midvein[i]].y(), leaf.blade.uv[midvein[i + 1]].y());
    }
    // Lobe 1's midvein is u = 0, straight up +Y; the others are lines u = constant (shared bends excepted).
    if (&midvein == &midveins.front())
    {
      for (int id : midvein)
      {
        EXPECT_EQ(leaf.blade.points[id].x(), 0.0);
        EXPECT_EQ(leaf.blade.uv[id].x(), 0.0);
      }
    }
    else
      EXPECT_EQ(leaf.blade.uv[midvein.back()].x(), u);
    EXPECT_EQ(leaf.blade.uv[midvein.back()].y(), 1.0);
  }
  EXPECT_EQ(tips.size(), midveins.size());

  // LeafUV in range everywhere; Region 4 exactly on the outline except the base and the tips.
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
  {
    const Eigen::Vector2d& uv = leaf.blade.uv[i];
    ASSERT_TRUE(uv.x() >= -0.5 && uv.x() <= 0.5 && uv.y() >= 0.0 && uv.y() <= 1.0) << "point " << i;
    const bool onOutline = boundary.count(static_cast<int>(i)) > 0;
    const bool special = static_cast<int>(i) == leaf.midvein.front() || tips.count(static_cast<int>(i)) > 0;
    EXPECT_EQ(leaf.blade.region[i] == RegionMargin, onOutline && !special) << "point " << i;
  }
}

TEST_P(EveryPalmatePreset, LeafIsMirrorSymmetricAndBitIdenticalOnRerun)
{
  const SpaceCurveParameters p = MakeSpaceCurvePreset(GetParam().preset, 5.0);
  const LeafGeometry leaf = Build(p, GetParam().quality);
  const LeafGeometry again = Build(p, GetParam().quality);
  ASSERT_EQ(leaf.blade.points, again.blade.points);
  ASSERT_EQ(leaf.blade.uv, again.blade.uv);
  ASSERT_EQ(leaf.blade.triangles, again.blade.triangles);
  // The outline (margins and midveins) is exactly symmetric in the Y axis, with mirrored LeafUV u.
  ASSERT_EQ(leaf.leftMargin.size(), leaf.rightMargin.size());
  for (std::size_t i = 0; i < leaf.leftMargin.size(); ++i)
  {
    const Eigen::Vector2d& l = leaf.blade.points[leaf.leftMargin[i]];
    const Eigen::Vector2d& r = leaf.blade.points[leaf.rightMargin[i]];
    EXPECT_EQ(l.x(), -r.x());
    EXPECT_EQ(l.y(), r.y());
    EXPECT_NEAR(leaf.blade.uv[leaf.leftMargin[i]].x(), -leaf.blade.uv[leaf.rightMargin[i]].x(), 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(PalmateLeaf, EveryPalmatePreset,
  ::testing::Values(Case{ SpaceCurvePreset::Figure8ThreeLobes, true },
    Case{ SpaceCurvePreset::Figure8ThreeLobes, false }, Case{ SpaceCurvePreset::Figure8FiveLobes, true },
    Case{ SpaceCurvePreset::Figure8FiveLobes, false }, Case{ SpaceCurvePreset::Watermelon, true },
    Case{ SpaceCurvePreset::Watermelon, false }, Case{ SpaceCurvePreset::WatermelonPinnatifid, true },
    Case{ SpaceCurvePreset::WatermelonPinnatifid, false }),
  [](const ::testing::TestParamInfo<Case>& info) {
    return SpaceCurvePresetName(info.param.preset) + (info.param.quality ? "Quality" : "Paper");
  });

TEST(PalmateLeaf, GrowingAtFixedMuIsAnExactSimilarity)
{
  // Paper 002's similarity holds lobe by lobe: doubling S doubles every outline sample (to rounding).
  for (const SpaceCurvePreset preset : { SpaceCurvePreset::Figure8ThreeLobes, SpaceCurvePreset::Figure8FiveLobes })
  {
    const LeafGeometry small = Build(MakeSpaceCurvePreset(preset, 2.5), false);
    const LeafGeometry large = Build(MakeSpaceCurvePreset(preset, 5.0), false);
    ASSERT_EQ(small.rightMargin.size(), large.rightMargin.size());
    for (std::size_t i = 0; i < small.rightMargin.size(); ++i)
    {
      const Eigen::Vector2d a = 2.0 * small.blade.points[small.rightMargin[i]];
      const Eigen::Vector2d b = large.blade.points[large.rightMargin[i]];
      EXPECT_LT((a - b).norm(), 1e-9 * 5.0);
    }
  }
}

TEST(PalmateLeaf, MoreLobesCoverMore)
{
  const double three =
    Area(OutlinePolygon(Build(MakeSpaceCurvePreset(SpaceCurvePreset::Figure8ThreeLobes, 5.0), false)));
  SpaceCurveParameters p = MakeSpaceCurvePreset(SpaceCurvePreset::Figure8ThreeLobes, 5.0);
  p.lobes = 5;
  const double five = Area(OutlinePolygon(Build(p, false)));
  EXPECT_GT(five, three * 1.1);
}

/// The distance from x to the polygon's boundary.
double DistanceToOutline(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& x)
{
  double best = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const Eigen::Vector2d a = polygon[i], d = polygon[(i + 1) % polygon.size()] - a;
    const double t = std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * d - x).norm());
  }
  return best;
}

TEST(PalmateLeaf, SubLobesCutSinusesBetweenTipsThatStayOnTheEntireLobes)
{
  // The Watermelon preset is Fig. 8's five lobes with two sub-lobes a side. Its sub-lobe tips are margin vertices,
  // mirror-symmetric, kept (to 1e-3 L) on the entire lobes' outline, while the sinuses between them cut into the
  // blade: its area is smaller by more than 5 %. Off by default: SubLobes 0 is Fig. 8's leaf exactly.
  const double length = 5.0;
  const SpaceCurveParameters entire = MakeSpaceCurvePreset(SpaceCurvePreset::Figure8FiveLobes, length);
  SpaceCurveParameters zero = entire;
  zero.subLobeDepth = 0.8; // unused without sub-lobes
  const LeafGeometry a = Build(entire, false, 60), b = Build(zero, false, 60);
  EXPECT_EQ(a.blade.points, b.blade.points);
  EXPECT_TRUE(a.subLobeTips.empty());

  const LeafGeometry lobed = Build(MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, length), false, 60);
  const std::vector<Eigen::Vector2d> outline = OutlinePolygon(a);
  ASSERT_GE(lobed.subLobeTips.size(), 12u);
  EXPECT_LE(lobed.subLobeTips.size(), 20u); // 5 lobes x 2 sides x 2, less those inside a neighbouring lobe
  std::set<int> margin(lobed.rightMargin.begin(), lobed.rightMargin.end());
  margin.insert(lobed.leftMargin.begin(), lobed.leftMargin.end());
  for (int id : lobed.subLobeTips)
  {
    const Eigen::Vector2d x = lobed.blade.points[id];
    EXPECT_EQ(margin.count(id), 1u);
    EXPECT_LT(DistanceToOutline(outline, x), 1e-3 * length) << x.transpose();
    bool mirrored = false;
    for (int other : lobed.subLobeTips)
      mirrored = mirrored || (lobed.blade.points[other] - Eigen::Vector2d(-x.x(), x.y())).norm() < 1e-12 * length;
    EXPECT_TRUE(mirrored) << x.transpose();
  }
  EXPECT_LT(Area(OutlinePolygon(lobed)), 0.95 * Area(outline));

  // Resolution-independent: at twice the resolution the same tips, each within one coarse spacing.
  const LeafGeometry fine = Build(MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, length), false, 120);
  ASSERT_EQ(fine.subLobeTips.size(), lobed.subLobeTips.size());
  for (int id : fine.subLobeTips)
  {
    double nearest = std::numeric_limits<double>::max();
    for (int other : lobed.subLobeTips)
      nearest = std::min(nearest, (fine.blade.points[id] - lobed.blade.points[other]).norm());
    EXPECT_LT(nearest, length / 60.0);
  }
}

/// Each lobe's length (its tip's distance from the base), lobe 1 first, and each sinus's depth: the distance from
/// the base of the outline point nearest it between two tips that follow each other along the outline, over the
/// shorter of the two lobes' lengths.
void LobesAndSinuses(const LeafGeometry& leaf, std::vector<double>& lengths, std::vector<double>& sinuses)
{
  const Eigen::Vector2d base = leaf.blade.points[leaf.midvein.front()];
  std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
  for (const std::vector<int>& lobe : leaf.lobeMidveins)
    tips.push_back(leaf.blade.points[lobe.back()]);
  for (const Eigen::Vector2d& tip : tips)
    lengths.push_back((tip - base).norm());
  const std::vector<Eigen::Vector2d> outline = OutlinePolygon(leaf); // from the base round the outline
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i < outline.size(); ++i)
  {
    for (const Eigen::Vector2d& tip : tips)
    {
      if (outline[i] == tip)
        at.push_back(i);
    }
  }
  ASSERT_EQ(at.size(), tips.size());
  for (std::size_t k = 0; k + 1 < at.size(); ++k)
  {
    double nearest = std::numeric_limits<double>::max();
    for (std::size_t i = at[k] + 1; i < at[k + 1]; ++i)
      nearest = std::min(nearest, (outline[i] - base).norm());
    sinuses.push_back(nearest / std::min((outline[at[k]] - base).norm(), (outline[at[k + 1]] - base).norm()));
  }
}

TEST(PalmateLeaf, PinnatifidWatermelonHasSinusesNearlyToTheBaseAndTheLongestMiddleLobe)
{
  // A watermelon leaf is pinnatifid: the sinuses between its lobes reach nearly to the midrib and the middle lobe is
  // the longest. The union of Fig. 8's lobes (the Watermelon preset) has its inner sinuses at 0.69 of the shorter
  // lobe's length from the base and the side lobes longer than the middle one; the pinnatifid preset (SinusDepth
  // 0.8) cuts every sinus to at most 0.2 of it, and its middle lobe is at least 15 % longer than any other.
  for (const bool quality : { true, false })
  {
    std::vector<double> lengths, sinuses;
    LobesAndSinuses(
      Build(MakeSpaceCurvePreset(SpaceCurvePreset::WatermelonPinnatifid, 5.0), quality), lengths, sinuses);
    ASSERT_EQ(lengths.size(), 5u);
    ASSERT_EQ(sinuses.size(), 4u);
    for (std::size_t k = 1; k < lengths.size(); ++k)
      EXPECT_GT(lengths[0], 1.15 * lengths[k]) << "lobe " << k + 1;
    for (const double sinus : sinuses)
      EXPECT_LE(sinus, 0.2 + 1e-9);
    std::vector<double> shallowLengths, shallow;
    LobesAndSinuses(Build(MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, 5.0), quality), shallowLengths, shallow);
    EXPECT_GT(*std::max_element(shallow.begin(), shallow.end()), 0.6);
    EXPECT_LT(shallowLengths[0], shallowLengths[1]);
  }
  // SinusDepth out of range is refused by name, with no leaf.
  SpaceCurveParameters p = MakeSpaceCurvePreset(SpaceCurvePreset::WatermelonPinnatifid, 5.0);
  p.sinusDepth = 0.96;
  SpaceCurveMeshParameters settings;
  LeafGeometry leaf;
  EXPECT_NE(BuildSpaceCurveLeaf(p, settings, leaf).find("SinusDepth"), std::string::npos);
  EXPECT_TRUE(leaf.blade.points.empty());
}

TEST(PalmateLeaf, BadLobeParametersGiveAMessageNamingThePropertyAndNoLeaf)
{
  const SpaceCurveParameters good = MakeSpaceCurvePreset(SpaceCurvePreset::Figure8ThreeLobes, 5.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Bad
  {
    const char* property;
    void (*change)(SpaceCurveParameters&, double);
    double value;
  };
  const Bad cases[] = {
    { "Lobes", [](SpaceCurveParameters& p, double v) { p.lobes = static_cast<int>(v); }, 2 },
    { "Lobes", [](SpaceCurveParameters& p, double v) { p.lobes = static_cast<int>(v); }, 7 },
    { "LobeStart", [](SpaceCurveParameters& p, double v) { p.lobeStart = v; }, 0.0 },
    { "LobeStart", [](SpaceCurveParameters& p, double v) { p.lobeStart = v; }, 1.0 },
    { "LobeStart", [](SpaceCurveParameters& p, double v) { p.lobeStart = v; }, nan },
    { "LobeAngle", [](SpaceCurveParameters& p, double v) { p.lobeAngle = v; }, 0.0 },
    { "LobeAngle", [](SpaceCurveParameters& p, double v) { p.lobeAngle = v; }, 120.0 },
    { "LobeScale", [](SpaceCurveParameters& p, double v) { p.lobeScale = v; }, 0.0 },
    { "LobeScale", [](SpaceCurveParameters& p, double v) { p.lobeScale = v; }, nan },
    { "SubLobes", [](SpaceCurveParameters& p, double v) { p.subLobes = static_cast<int>(v); }, -1 },
    { "SubLobes", [](SpaceCurveParameters& p, double v) { p.subLobes = static_cast<int>(v); }, 9 },
    { "SubLobeDepth", [](SpaceCurveParameters& p, double v) { p.subLobeDepth = v; }, 0.0 },
    { "SubLobeDepth", [](SpaceCurveParameters& p, double v) { p.subLobeDepth = v; }, 0.95 },
    { "SubLobeDepth", [](SpaceCurveParameters& p, double v) { p.subLobeDepth = v; }, nan },
    { "Lobes", [](SpaceCurveParameters& p, double v) { p.torsion.mu = v; }, 4.0 }, // palmate leaves are flat
    { "Lobes", [](SpaceCurveParameters& p, double v) { p.opening = v; }, 0.5 },
    // Lobes turned so far out that they hang from lobe 1 by their start point only.
    { "LobeAngle",
      [](SpaceCurveParameters& p, double v) {
        p.lobeAngle = v;
        p.curvature.mu = 2.0;
      },
      60.0 },
  };
  for (const Bad& bad : cases)
  {
    SCOPED_TRACE(std::string(bad.property) + " " + std::to_string(bad.value));
    SpaceCurveParameters p = good;
    bad.change(p, bad.value);
    SpaceCurveMeshParameters settings;
    settings.resolution = 30;
    LeafGeometry leaf;
    const std::string error = BuildSpaceCurveLeaf(p, settings, leaf);
    EXPECT_NE(error.find(bad.property), std::string::npos) << error;
    EXPECT_TRUE(
      leaf.blade.points.empty() && leaf.blade.triangles.empty() && leaf.midvein.empty() && leaf.lobeMidveins.empty());
  }
}

} // namespace
} // namespace plantmorph
