// SPDX-License-Identifier: GPL-3.0-or-later
// Palmate (actinodromous) venation follows the blade (docs/methods/venation.md "Palmate veins by leaf growth"), on
// the project's own blades: on entire blades the primaries fan over at least 80 degrees seen from the base; on
// paper 002's lobed leaves one primary runs into each lobe and reaches within 3 % of the leaf length of its tip
// (the tips are the Outline's lobe midveins' ends, which the venation never sees); on cordate blades (the cucumber,
// paper 000 Fig. 2c) the outermost primaries run into the basal lobes; ginkgo's dichotomies fill the fan; the
// wilting species' presets (cucumber, watermelon, a tomato leaflet) follow their blades.
#include "VenationGrowth.h"

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "SpaceCurvePresets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>

namespace plantmorph
{
namespace
{
constexpr double Degrees = 180.0 / 3.14159265358979323846;

VenationBlade BladeOf(const LeafGeometry& leaf)
{
  return { leaf.blade.points, leaf.blade.uv, leaf.blade.triangles };
}

VenationResult Grow(const LeafGeometry& leaf, const VenationParameters& p)
{
  VenationResult result;
  EXPECT_EQ(GrowVenation(BladeOf(leaf), p, result), "");
  return result;
}

VenationParameters Palmate(int veins)
{
  VenationParameters p;
  p.pattern = VenationPattern::Palmate;
  p.palmateVeins = veins;
  p.forkLevels = 0;
  p.tertiary = false;
  return p;
}

LeafGeometry DeformedRectangle(DeformedRectanglePreset preset)
{
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  EXPECT_EQ(BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(preset, 5.0), settings, leaf), "");
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

LeafGeometry Lobed(SpaceCurvePreset preset)
{
  SpaceCurveMeshParameters settings;
  settings.resolution = 40;
  LeafGeometry leaf;
  EXPECT_EQ(BuildSpaceCurveLeaf(MakeSpaceCurvePreset(preset, 5.0), settings, leaf), "");
  return leaf;
}

/// The leaf's base (the first midvein point) and unit axis (base to the apex).
struct Frame
{
  Eigen::Vector2d base, axis;
  double Angle(const Eigen::Vector2d& x) const
  {
    const Eigen::Vector2d r = x - this->base;
    return std::atan2(this->axis.x() * r.y() - this->axis.y() * r.x(), r.dot(this->axis)) * Degrees;
  }
};

Frame FrameOf(const LeafGeometry& leaf)
{
  const Eigen::Vector2d base = leaf.blade.points[leaf.midvein.front()];
  return { base, (leaf.blade.points[leaf.midvein.back()] - base).normalized() };
}

std::vector<Eigen::Vector2d> Ends(const VenationResult& r, int order)
{
  std::vector<Eigen::Vector2d> ends;
  for (const auto& vein : r.veins)
  {
    if (vein.order == order)
      ends.push_back(r.nodes[vein.nodes.back()]);
  }
  return ends;
}

/// Angular span (degrees) of the points seen from the base.
double Span(const Frame& frame, const std::vector<Eigen::Vector2d>& points)
{
  double low = 180.0, high = -180.0;
  for (const Eigen::Vector2d& x : points)
  {
    low = std::min(low, frame.Angle(x));
    high = std::max(high, frame.Angle(x));
  }
  return high - low;
}

/// Distance from x to the nearest vein of `order` (of order `order` or lower when `orLower`).
double DistanceToVeins(const VenationResult& r, int order, const Eigen::Vector2d& x, bool orLower = false)
{
  double best = std::numeric_limits<double>::max();
  for (const auto& vein : r.veins)
  {
    if (orLower ? vein.order > order : vein.order != order)
      continue;
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      const Eigen::Vector2d a = r.nodes[vein.nodes[i]], d = r.nodes[vein.nodes[i + 1]] - a;
      const double t = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      best = std::min(best, (a + t * d - x).norm());
    }
  }
  return best;
}

/// Each basal lobe's tip: the margin point farthest behind the base (the lowest along the axis), on each side, if
/// it lies more than 0.05 of the base-apex distance behind the base.
std::vector<Eigen::Vector2d> BasalLobeTips(const LeafGeometry& leaf, const Frame& frame)
{
  std::vector<Eigen::Vector2d> lobes;
  for (const std::vector<int>* margin : { &leaf.rightMargin, &leaf.leftMargin })
  {
    Eigen::Vector2d tip = frame.base;
    for (int id : *margin)
    {
      const Eigen::Vector2d x = leaf.blade.points[id];
      if ((x - frame.base).dot(frame.axis) < (tip - frame.base).dot(frame.axis))
        tip = x;
    }
    if ((tip - frame.base).dot(frame.axis) < -0.05 * (leaf.blade.points[leaf.midvein.back()] - frame.base).norm())
      lobes.push_back(tip);
  }
  return lobes;
}

/// Every primary ends on the margin: no free end (tertiaries off, so every vein end is on the margin or a vein).
void ExpectPrimariesEndOnTheMargin(const VenationResult& r)
{
  EXPECT_EQ(r.statistics.freeEnds, 0u);
}

/// Where each primary is a `fraction` of its own length (along it) from its start at the base: the directions in
/// which the primaries leave the base (their ends say where they arrive, which a curved vein's do not).
std::vector<Eigen::Vector2d> LeavingPoints(const VenationResult& r, double fraction)
{
  std::vector<Eigen::Vector2d> points;
  for (const auto& vein : r.veins)
  {
    if (vein.order != VeinOrderPrimary)
      continue;
    double length = 0.0;
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      length += (r.nodes[vein.nodes[i + 1]] - r.nodes[vein.nodes[i]]).norm();
    double walked = 0.0;
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      const Eigen::Vector2d a = r.nodes[vein.nodes[i]], b = r.nodes[vein.nodes[i + 1]];
      const double piece = (b - a).norm();
      if (walked + piece >= fraction * length)
      {
        points.push_back(a + (fraction * length - walked) / std::max(piece, 1e-300) * (b - a));
        break;
      }
      walked += piece;
    }
  }
  return points;
}

/// The blade's own angular extent seen from the base (degrees) at the distance of `points` from it: the span of
/// its margin vertices within 0.03 of the leaf length of their mean distance.
double BladeExtentAt(const LeafGeometry& leaf, const Frame& frame, const std::vector<Eigen::Vector2d>& points)
{
  double distance = 0.0;
  for (const Eigen::Vector2d& x : points)
    distance += (x - frame.base).norm() / points.size();
  const double length = (leaf.blade.points[leaf.midvein.back()] - frame.base).norm();
  std::vector<Eigen::Vector2d> margin;
  for (const std::vector<int>* side : { &leaf.rightMargin, &leaf.leftMargin })
  {
    for (int id : *side)
    {
      if (std::abs((leaf.blade.points[id] - frame.base).norm() - distance) <= 0.03 * length)
        margin.push_back(leaf.blade.points[id]);
    }
  }
  return Span(frame, margin);
}

/// The spread and evenness of the primaries' ends on the margin.
void ExpectEndsFanned(const std::string& name, const Frame& frame, const VenationResult& r, int veins)
{
  const std::vector<Eigen::Vector2d> ends = Ends(r, VeinOrderPrimary);
  ASSERT_EQ(ends.size(), static_cast<std::size_t>(veins));
  const double span = Span(frame, ends);
  std::cout << name << " " << veins << " palmate veins: ends span " << span << " deg\n";
  EXPECT_GE(span, 80.0);
  ExpectPrimariesEndOnTheMargin(r);
  // Spread evenly: no two neighbouring ends closer in angle than half the mean gap.
  std::vector<double> angles;
  for (const Eigen::Vector2d& x : ends)
    angles.push_back(frame.Angle(x));
  std::sort(angles.begin(), angles.end());
  for (std::size_t i = 1; i < angles.size(); ++i)
    EXPECT_GT(angles[i] - angles[i - 1], 0.5 * span / (veins - 1));
}

/// The fan as a botanist reads it: the spread of the primaries' directions as they leave the base, measured a fifth
/// of each primary's length from the base (and a tenth, nearer still), not where they end. On the serrate blade
/// they left over 45-58 degrees with 4 and 5 veins: a ray ending beyond a tooth left the blade at the notch, so
/// every primary grew curved in LeafUV; now a primary ends at the notch's margin and stays straight.
void ExpectFannedLeavingTheBase(
  const std::string& name, const LeafGeometry& leaf, const Frame& frame, const VenationResult& r, int veins)
{
  for (const double fraction : { 0.1, 0.2 })
  {
    const std::vector<Eigen::Vector2d> leaving = LeavingPoints(r, fraction);
    ASSERT_EQ(leaving.size(), static_cast<std::size_t>(veins));
    const double span = Span(frame, leaving);
    const double room = BladeExtentAt(leaf, frame, leaving);
    std::cout << name << " " << veins << " palmate veins: leaving the base (at " << fraction
              << " of their length) over " << span << " deg, the blade there over " << room << " deg\n";
    // The ginkgo's cuneate base is narrower than 80 degrees seen from the base (51 at a tenth of the length, 71
    // at a fifth): its veins leave bunched (7 and 20 degrees) and fan out higher up; the goal holds where the
    // blade leaves room for it.
    if (room >= 80.0)
    {
      EXPECT_GE(span, 80.0) << "at " << fraction << " of their length";
    }
  }
}

TEST(PalmateVenation, PrimariesFanOverAtLeast80DegreesOnEntireBlades)
{
  // Each venation is grown once and read twice: where the primaries end, and where they leave the base.
  for (const DeformedRectanglePreset preset : { DeformedRectanglePreset::Entire, DeformedRectanglePreset::Ginkgo,
         DeformedRectanglePreset::Serrate, DeformedRectanglePreset::RoundedBaseAcuminateApex })
  {
    const LeafGeometry leaf = DeformedRectangle(preset);
    const Frame frame = FrameOf(leaf);
    for (int veins : { 3, 4, 5, 7 })
    {
      SCOPED_TRACE(PresetName(preset) + ", " + std::to_string(veins) + " veins");
      const VenationResult r = Grow(leaf, Palmate(veins));
      ExpectEndsFanned(PresetName(preset), frame, r, veins);
      ExpectFannedLeavingTheBase(PresetName(preset), leaf, frame, r, veins);
    }
  }
}

TEST(PalmateVenation, OnePrimaryRunsIntoEachLobeAndReachesItsTip)
{
  for (const SpaceCurvePreset preset : { SpaceCurvePreset::Figure8ThreeLobes, SpaceCurvePreset::Figure8FiveLobes })
  {
    SCOPED_TRACE(SpaceCurvePresetName(preset));
    const LeafGeometry leaf = Lobed(preset);
    // The lobe tips, from the Outline's lobe midveins (the venation sees only the blade and its LeafUV).
    std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
    for (const std::vector<int>& lobe : leaf.lobeMidveins)
      tips.push_back(leaf.blade.points[lobe.back()]);
    for (int veins : { 3, 4 }) // PalmateVeins does not matter on a lobed blade: one primary per lobe
    {
      const VenationResult r = Grow(leaf, Palmate(veins));
      EXPECT_EQ(Ends(r, VeinOrderPrimary).size(), tips.size());
      ExpectPrimariesEndOnTheMargin(r);
      for (const Eigen::Vector2d& tip : tips)
      {
        const double gap = DistanceToVeins(r, VeinOrderPrimary, tip) / r.leafLength;
        std::cout << SpaceCurvePresetName(preset) << ": lobe tip " << tip.transpose() << " is " << 100.0 * gap
                  << " % of the length from a primary\n";
        EXPECT_LE(gap, 0.03);
      }
    }
  }
}

TEST(PalmateVenation, LobedBladesPrimariesDoNotForkWhateverForkLevels)
{
  // ForkLevels makes the dichotomous fan of an entire blade; on a lobed blade each primary still runs undivided to
  // its lobe's tip (forked, its two branches ended on both sides of the tip and the farthest tip was 0.82 leaf
  // lengths from any primary).
  for (const SpaceCurvePreset preset : { SpaceCurvePreset::Figure8ThreeLobes, SpaceCurvePreset::Figure8FiveLobes })
  {
    SCOPED_TRACE(SpaceCurvePresetName(preset));
    const LeafGeometry leaf = Lobed(preset);
    std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
    for (const std::vector<int>& lobe : leaf.lobeMidveins)
      tips.push_back(leaf.blade.points[lobe.back()]);
    for (int levels : { 1, 2 })
    {
      VenationParameters p = Palmate(4);
      p.forkLevels = levels;
      const VenationResult r = Grow(leaf, p);
      EXPECT_EQ(Ends(r, VeinOrderPrimary).size(), tips.size()) << levels << " fork levels";
      for (const Eigen::Vector2d& tip : tips)
        EXPECT_LE(DistanceToVeins(r, VeinOrderPrimary, tip) / r.leafLength, 0.03) << levels << " fork levels";
    }
  }
  // The filter's default is undivided primaries.
  EXPECT_EQ(VenationParameters().forkLevels, 0);
}

TEST(PalmateVenation, BasalPrimariesRunIntoTheBasalLobesOfCordateBlades)
{
  const LeafGeometry cucumber = Cucumber(),
                     cordate = DeformedRectangle(DeformedRectanglePreset::CordateBaseRoundedApex);
  for (const LeafGeometry* leaf : { &cucumber, &cordate })
  {
    SCOPED_TRACE(leaf == &cucumber ? "cucumber" : "cordate base");
    const Frame frame = FrameOf(*leaf);
    const std::vector<Eigen::Vector2d> lobes = BasalLobeTips(*leaf, frame);
    ASSERT_EQ(lobes.size(), 2u);
    for (int veins : { 3, 5 })
    {
      const VenationResult r = Grow(*leaf, Palmate(veins));
      const std::vector<Eigen::Vector2d> ends = Ends(r, VeinOrderPrimary);
      ExpectPrimariesEndOnTheMargin(r);
      std::cout << (leaf == &cucumber ? "cucumber" : "cordate") << " " << veins << " veins: " << ends.size()
                << " primaries, span " << Span(frame, ends) << " deg\n";
      EXPECT_GE(Span(frame, ends), 80.0);
      for (const Eigen::Vector2d& lobe : lobes)
      {
        const double gap = DistanceToVeins(r, VeinOrderPrimary, lobe) / r.leafLength;
        std::cout << "  basal lobe tip " << lobe.transpose() << ": " << 100.0 * gap << " % of the length\n";
        EXPECT_LE(gap, 0.03);
      }
      // The basal primaries end behind the base, one on each side.
      int behind[2] = { 0, 0 };
      for (const Eigen::Vector2d& x : ends)
      {
        if ((x - frame.base).dot(frame.axis) < 0.0)
          ++behind[frame.Angle(x) < 0.0 ? 0 : 1];
      }
      EXPECT_EQ(behind[0], 1);
      EXPECT_EQ(behind[1], 1);
    }
  }
}

TEST(PalmateVenation, GinkgoDichotomiesFillTheFan)
{
  // The preset: two veins from the petiole forking five times, 64 nearly parallel veins at the margin.
  const LeafGeometry leaf = DeformedRectangle(DeformedRectanglePreset::Ginkgo);
  const Frame frame = FrameOf(leaf);
  const VenationParameters p = MakeVenationPreset(VenationPreset::Ginkgo);
  const VenationResult r = Grow(leaf, p);
  const std::size_t tipCount = static_cast<std::size_t>(p.palmateVeins) << p.forkLevels;
  ASSERT_GE(tipCount, 40u); // dozens, as a real ginkgo leaf has
  // The fan's angular extent: its margin points at least a fifth of the length from the base.
  double low = 180.0, high = -180.0;
  for (const std::vector<int>* margin : { &leaf.rightMargin, &leaf.leftMargin })
  {
    for (int id : *margin)
    {
      const Eigen::Vector2d x = leaf.blade.points[id];
      if ((x - frame.base).norm() >= 0.2 * r.leafLength)
      {
        low = std::min(low, frame.Angle(x));
        high = std::max(high, frame.Angle(x));
      }
    }
  }
  // Every fork makes two branches (order 2): 2 + 4 + ... + 2^levels per primary.
  ASSERT_EQ(Ends(r, VeinOrderSecondary).size(), static_cast<std::size_t>(p.palmateVeins) * ((2u << p.forkLevels) - 2));
  // The branch tips on the margin: branch ends where no later branch starts.
  std::vector<double> tips;
  for (const auto& vein : r.veins)
  {
    if (vein.order != VeinOrderSecondary)
      continue;
    const Eigen::Vector2d x = r.nodes[vein.nodes.back()];
    bool onMargin = true;
    for (const auto& other : r.veins)
    {
      if (&other != &vein && other.nodes.front() == vein.nodes.back())
        onMargin = false; // a fork: a later branch starts here
    }
    if (onMargin)
      tips.push_back(frame.Angle(x));
  }
  ASSERT_EQ(tips.size(), tipCount);
  std::sort(tips.begin(), tips.end());
  const double extent = high - low, even = extent / static_cast<double>(tipCount);
  std::cout << "ginkgo fan " << low << ".." << high << " deg; " << tipCount << " branch tips " << tips.front() << ".."
            << tips.back() << " deg\n";
  EXPECT_LE(tips.front() - low, 2.0 * even);
  EXPECT_LE(high - tips.back(), 2.0 * even);
  for (std::size_t i = 1; i < tips.size(); ++i)
    EXPECT_LE(tips[i] - tips[i - 1], 2.0 * even) << "gap " << i;
  // Every part of the fan is near a vein: the blade's triangle centroids (every 3rd), their distance to the veins.
  std::vector<double> distances;
  for (std::size_t t = 0; t < leaf.blade.triangles.size(); t += 3)
  {
    const auto& tri = leaf.blade.triangles[t];
    const Eigen::Vector2d c = (leaf.blade.points[tri[0]] + leaf.blade.points[tri[1]] + leaf.blade.points[tri[2]]) / 3.0;
    distances.push_back(DistanceToVeins(r, VeinOrderSecondary, c, true) / r.leafLength);
  }
  std::sort(distances.begin(), distances.end());
  const double p95 = distances[distances.size() * 95 / 100];
  std::cout << "ginkgo: 95th percentile distance to a vein " << p95 << " L, largest " << distances.back() << " L\n";
  // The required space-colonization bound: 95 % of the fan within 0.03 L of a vein (with the ends spread in angle:
  // 0.077 L, and 0.135 L at most, on the bare lower flanks below the outermost veins).
  EXPECT_LE(p95, 0.03);
  EXPECT_LE(distances.back(), 0.08);
}

TEST(PalmateVenation, WiltingSpeciesPresetsFollowTheirBlades)
{
  // Cucumber: its primaries and their branches reach both basal lobes and fan over more than 80 degrees.
  {
    const LeafGeometry leaf = Cucumber();
    const Frame frame = FrameOf(leaf);
    const VenationResult r = Grow(leaf, MakeVenationPreset(VenationPreset::Cucumber));
    const std::vector<Eigen::Vector2d> lobes = BasalLobeTips(leaf, frame);
    ASSERT_EQ(lobes.size(), 2u);
    for (const Eigen::Vector2d& lobe : lobes)
      EXPECT_LE(DistanceToVeins(r, VeinOrderSecondary, lobe, true) / r.leafLength, 0.03);
    EXPECT_GE(Span(frame, Ends(r, VeinOrderPrimary)), 80.0);
    EXPECT_GT(r.statistics.areoles, 100u); // the reticulum
  }
  // Watermelon: a vein into every lobe of a five-lobed blade, ending within 3 % of the length of its tip.
  {
    const LeafGeometry leaf = Lobed(SpaceCurvePreset::Figure8FiveLobes);
    std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
    for (const std::vector<int>& lobe : leaf.lobeMidveins)
      tips.push_back(leaf.blade.points[lobe.back()]);
    const VenationResult r = Grow(leaf, MakeVenationPreset(VenationPreset::Watermelon));
    EXPECT_EQ(Ends(r, VeinOrderPrimary).size(), tips.size());
    for (const Eigen::Vector2d& tip : tips)
      EXPECT_LE(DistanceToVeins(r, VeinOrderSecondary, tip, true) / r.leafLength, 0.03);
  }
  // Tomato (a leaflet): pinnate, the midvein and secondaries, with free-ending veinlets.
  {
    const LeafGeometry leaf = DeformedRectangle(DeformedRectanglePreset::Serrate);
    const VenationResult r = Grow(leaf, MakeVenationPreset(VenationPreset::Tomato));
    EXPECT_EQ(Ends(r, VeinOrderPrimary).size(), 1u);
    EXPECT_GT(Ends(r, VeinOrderSecondary).size(), 8u);
    EXPECT_FALSE(Ends(r, VeinOrderVeinlet).empty());
  }
}

/// How many secondaries leave each primary (order-2 veins whose first node lies on it), primaries in output order.
std::vector<int> SecondariesPerPrimary(const VenationResult& r)
{
  std::vector<const VenationResult::Polyline*> primaries;
  for (const auto& vein : r.veins)
  {
    if (vein.order == VeinOrderPrimary)
      primaries.push_back(&vein);
  }
  std::vector<int> counts(primaries.size(), 0);
  for (const auto& vein : r.veins)
  {
    if (vein.order != VeinOrderSecondary)
      continue;
    for (std::size_t i = 0; i < primaries.size(); ++i)
    {
      const std::vector<int>& nodes = primaries[i]->nodes;
      if (std::find(nodes.begin() + 1, nodes.end(), vein.nodes.front()) != nodes.end())
      {
        ++counts[i];
        break;
      }
    }
  }
  return counts;
}

/// Distance from x to the blade's margin (its right and left margin polylines).
double DistanceToMargin(const LeafGeometry& leaf, const Eigen::Vector2d& x)
{
  double best = std::numeric_limits<double>::max();
  for (const std::vector<int>* margin : { &leaf.rightMargin, &leaf.leftMargin })
  {
    for (std::size_t i = 0; i + 1 < margin->size(); ++i)
    {
      const Eigen::Vector2d a = leaf.blade.points[(*margin)[i]], d = leaf.blade.points[(*margin)[i + 1]] - a;
      const double t = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      best = std::min(best, (a + t * d - x).norm());
    }
  }
  return best;
}

/// The areoles of a grown network (the bounded faces of its veins' planar graph, the margin left out): centroid
/// and area of each.
struct Areole
{
  Eigen::Vector2d centroid;
  double area = 0.0;
};
std::vector<Areole> Areoles(const VenationResult& r)
{
  Eigen::Vector2d low = r.nodes.front(), high = low;
  for (const Eigen::Vector2d& x : r.nodes)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const Eigen::Vector2d pad = Eigen::Vector2d::Constant(0.01 * r.leafLength);
  VeinGraph graph(low - pad, high + pad, 0.05 * r.leafLength);
  for (const Eigen::Vector2d& x : r.nodes)
    graph.AddNode(x);
  const int vein = graph.AddVein(VeinOrderTertiary);
  for (const auto& line : r.veins)
  {
    for (std::size_t i = 0; i + 1 < line.nodes.size(); ++i)
    {
      if (line.nodes[i] != line.nodes[i + 1] && graph.FindEdge(line.nodes[i], line.nodes[i + 1]) < 0)
        graph.AddEdge(line.nodes[i], line.nodes[i + 1], vein);
    }
  }
  std::vector<Areole> areoles;
  for (const VeinGraph::Face& face : graph.Faces())
  {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    double twice = 0.0;
    for (std::size_t i = 0; i < face.nodes.size(); ++i)
    {
      const Eigen::Vector2d a = r.nodes[face.nodes[i]], b = r.nodes[face.nodes[(i + 1) % face.nodes.size()]];
      const double cross = a.x() * b.y() - a.y() * b.x();
      twice += cross;
      sum += cross * (a + b);
    }
    if (twice > 0.0)
      areoles.push_back({ sum / (3.0 * twice), 0.5 * twice });
  }
  return areoles;
}

double Median(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// Blade coverage: the distances (in leaf lengths) from every 2nd triangle centroid to the nearest vein, sorted.
std::vector<double> CoverageDistances(const LeafGeometry& leaf, const VenationResult& r)
{
  std::vector<double> distances;
  for (std::size_t t = 0; t < leaf.blade.triangles.size(); t += 2)
  {
    const auto& tri = leaf.blade.triangles[t];
    const Eigen::Vector2d c = (leaf.blade.points[tri[0]] + leaf.blade.points[tri[1]] + leaf.blade.points[tri[2]]) / 3.0;
    distances.push_back(DistanceToVeins(r, VeinOrderVeinlet, c, true) / r.leafLength);
  }
  std::sort(distances.begin(), distances.end());
  return distances;
}

TEST(PalmateVenation, CucumberPrimariesSendSecondariesToTheMargin)
{
  const LeafGeometry leaf = Cucumber();
  for (const PalmateSecondaries kind : { PalmateSecondaries::Craspedodromous, PalmateSecondaries::Brochidodromous })
  {
    SCOPED_TRACE(static_cast<int>(kind));
    VenationParameters p = MakeVenationPreset(VenationPreset::Cucumber);
    p.palmateSecondaries = kind;
    p.tertiary = false;
    const VenationResult r = Grow(leaf, p);
    const std::vector<int> counts = SecondariesPerPrimary(r);
    ASSERT_EQ(counts.size(), 5u);
    std::cout << "cucumber secondaries per primary:";
    for (int c : counts)
      std::cout << " " << c;
    std::cout << "\n";
    // The midvein and the two lateral primaries carry several on both sides; the short basal ones, which end in
    // the basal lobes, have room for one or two on their outer side.
    for (int i : { 1, 2, 3 })
      EXPECT_GE(counts[i], 5);
    for (int c : counts)
      EXPECT_GE(c, 1);
    // Craspedodromous: most secondaries end on the margin (the rest on a neighbouring vein); brochidodromous: they
    // fork and loop, the loops joining the next secondary out along the same primary.
    int secondaries = 0, onMargin = 0;
    for (const auto& vein : r.veins)
    {
      if (vein.order != VeinOrderSecondary)
        continue;
      ++secondaries;
      onMargin += DistanceToMargin(leaf, r.nodes[vein.nodes.back()]) < 1e-6 * r.leafLength;
    }
    std::cout << "  " << onMargin << " of " << secondaries << " secondary veins end on the margin\n";
    if (kind == PalmateSecondaries::Craspedodromous)
      EXPECT_GE(onMargin, secondaries / 2);
    else
      EXPECT_GT(r.statistics.areoles, 5u); // the loops close regions between secondaries
  }
  // The preset is unchanged for other blades: bare primaries when PalmateSecondaries is None.
  VenationParameters bare = MakeVenationPreset(VenationPreset::Cucumber);
  bare.palmateSecondaries = PalmateSecondaries::None;
  bare.tertiary = false;
  for (int c : SecondariesPerPrimary(Grow(leaf, bare)))
    EXPECT_EQ(c, 0);
}

TEST(PalmateVenation, CucumberReticulumIsHierarchical)
{
  // Larger areoles beside the primaries, smaller ones farther out ("cracked mud" is near-equal polygons).
  const LeafGeometry leaf = Cucumber();
  for (const double gradient : { 0.0, MakeVenationPreset(VenationPreset::Cucumber).areoleGradient })
  {
    VenationParameters p = MakeVenationPreset(VenationPreset::Cucumber);
    p.areoleGradient = gradient;
    const VenationResult r = Grow(leaf, p);
    std::vector<double> nearAreas, farAreas;
    double farthest = 0.0;
    const std::vector<Areole> areoles = Areoles(r);
    std::vector<double> distance;
    for (const Areole& a : areoles)
    {
      distance.push_back(DistanceToVeins(r, VeinOrderPrimary, a.centroid) / r.leafLength);
      farthest = std::max(farthest, distance.back());
    }
    for (std::size_t i = 0; i < areoles.size(); ++i)
    {
      if (distance[i] < farthest / 4.0)
        nearAreas.push_back(areoles[i].area);
      else if (distance[i] > farthest / 2.0)
        farAreas.push_back(areoles[i].area);
    }
    const double ratio = Median(nearAreas) / Median(farAreas);
    std::cout << "cucumber, AreoleGradient " << gradient << ": " << areoles.size() << " areoles, median area "
              << Median(nearAreas) << " within " << farthest / 4.0 << " L of a primary (" << nearAreas.size() << "), "
              << Median(farAreas) << " beyond " << farthest / 2.0 << " L (" << farAreas.size() << "): ratio " << ratio
              << "\n";
    ASSERT_GT(nearAreas.size(), 20u);
    ASSERT_GT(farAreas.size(), 20u);
    if (gradient == 0.0)
      EXPECT_LT(ratio, 1.5); // even: the control
    else
      EXPECT_GE(ratio, 1.8);
  }
}

TEST(PalmateVenation, WatermelonVeinsReachEveryLobeAtEverySeed)
{
  const LeafGeometry leaf = Lobed(SpaceCurvePreset::Figure8FiveLobes);
  std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
  for (const std::vector<int>& lobe : leaf.lobeMidveins)
    tips.push_back(leaf.blade.points[lobe.back()]);
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    VenationParameters p = MakeVenationPreset(VenationPreset::Watermelon);
    p.seed = seed;
    const VenationResult r = Grow(leaf, p);
    for (const Eigen::Vector2d& tip : tips)
      EXPECT_LE(DistanceToVeins(r, VeinOrderSecondary, tip, true) / r.leafLength, 0.03);
    // Veins into each lobe's flanks: every primary sends secondaries out.
    for (int c : SecondariesPerPrimary(r))
      EXPECT_GE(c, 2);
    // No bare lobe: every part of the blade lies near a vein (a bare lobe leaves 0.1 L and more).
    const std::vector<double> d = CoverageDistances(leaf, r);
    std::cout << "watermelon seed " << seed << ": 99th percentile distance to a vein " << d[d.size() * 99 / 100]
              << " L, largest " << d.back() << " L\n";
    EXPECT_LE(d[d.size() * 99 / 100], 0.03);
    EXPECT_LE(d.back(), 0.05);
  }
}

TEST(PalmateVenation, PrimariesReachEveryLobeOfThePinnatifidWatermelon)
{
  // LeafOutlineSource's pinnatifid watermelon (sinuses cut to 0.2 of the shorter lobe from the base): with the
  // Watermelon preset and with Custom palmate veins (any ForkLevels), one primary to each of the five lobe tips.
  const LeafGeometry leaf = Lobed(SpaceCurvePreset::WatermelonPinnatifid);
  ASSERT_FALSE(leaf.blade.points.empty());
  std::vector<Eigen::Vector2d> tips = { leaf.blade.points[leaf.midvein.back()] };
  for (const std::vector<int>& lobe : leaf.lobeMidveins)
    tips.push_back(leaf.blade.points[lobe.back()]);
  ASSERT_EQ(tips.size(), 5u);
  VenationParameters custom = Palmate(4);
  custom.forkLevels = 1;
  for (const VenationParameters& p : { MakeVenationPreset(VenationPreset::Watermelon), custom })
  {
    const VenationResult r = Grow(leaf, p);
    for (const Eigen::Vector2d& tip : tips)
      EXPECT_LE(DistanceToVeins(r, VeinOrderPrimary, tip) / r.leafLength, 0.03);
  }
}

/// A sub-lobed watermelon blade (LeafOutlineSource's Watermelon preset) at Resolution 60.
LeafGeometry SubLobedWatermelon()
{
  SpaceCurveMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  EXPECT_EQ(BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, 5.0), settings, leaf), "");
  return leaf;
}

TEST(PalmateVenation, WatermelonVeinsReachEverySubLobeTip)
{
  // Every lobe and sub-lobe tip (the outline's own list, which the venation never sees) lies within 0.03 L of a
  // primary or secondary, at seeds 1-6; a vein of order 2 or lower ends within 0.03 L of each sub-lobe tip.
  const LeafGeometry leaf = SubLobedWatermelon();
  ASSERT_GE(leaf.subLobeTips.size(), 12u);
  std::vector<Eigen::Vector2d> lobeTips = { leaf.blade.points[leaf.midvein.back()] };
  for (const std::vector<int>& lobe : leaf.lobeMidveins)
    lobeTips.push_back(leaf.blade.points[lobe.back()]);
  std::vector<Eigen::Vector2d> subTips;
  for (int id : leaf.subLobeTips)
    subTips.push_back(leaf.blade.points[id]);
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    VenationParameters p = MakeVenationPreset(VenationPreset::Watermelon);
    p.seed = seed;
    const VenationResult r = Grow(leaf, p);
    for (const Eigen::Vector2d& tip : lobeTips)
      EXPECT_LE(DistanceToVeins(r, VeinOrderSecondary, tip, true) / r.leafLength, 0.03);
    double worst = 0.0;
    for (const Eigen::Vector2d& tip : subTips)
    {
      const double distance = DistanceToVeins(r, VeinOrderSecondary, tip, true) / r.leafLength;
      worst = std::max(worst, distance);
      EXPECT_LE(distance, 0.03) << "sub-lobe tip " << tip.transpose();
      bool ends = false;
      for (const auto& vein : r.veins)
      {
        ends = ends ||
          (vein.order <= VeinOrderSecondary &&
            ((r.nodes[vein.nodes.front()] - tip).norm() <= 0.03 * r.leafLength ||
              (r.nodes[vein.nodes.back()] - tip).norm() <= 0.03 * r.leafLength));
      }
      EXPECT_TRUE(ends) << "no vein ends at sub-lobe tip " << tip.transpose();
    }
    std::cout << "watermelon sub-lobes seed " << seed << ": " << subTips.size()
              << " sub-lobe tips, farthest from a vein " << worst << " L\n";
  }
}

TEST(PalmateVenation, SubLobeVeinsAreWhatReachTheSubLobes)
{
  // The control: without sub-lobe targeting the regular secondaries miss some sub-lobe tip by more than 0.03 L; on
  // Fig. 8's five-lobed blade (no sub-lobes) targeting finds none, so the network is the same as without it.
  const LeafGeometry leaf = SubLobedWatermelon();
  VenationParameters p = MakeVenationPreset(VenationPreset::Watermelon);
  p.seed = 1;
  p.subLobeVeins = false;
  const VenationResult off = Grow(leaf, p);
  double worst = 0.0;
  for (int id : leaf.subLobeTips)
    worst = std::max(worst, DistanceToVeins(off, VeinOrderSecondary, leaf.blade.points[id], true) / off.leafLength);
  std::cout << "without sub-lobe veins the farthest sub-lobe tip is " << worst << " L from a vein\n";
  EXPECT_GT(worst, 0.03);

  const LeafGeometry plain = Lobed(SpaceCurvePreset::Figure8FiveLobes);
  EXPECT_TRUE(plain.subLobeTips.empty());
  p.subLobeVeins = true;
  const VenationResult with = Grow(plain, p);
  p.subLobeVeins = false;
  const VenationResult without = Grow(plain, p);
  ASSERT_EQ(with.nodes.size(), without.nodes.size());
  EXPECT_EQ(with.veins.size(), without.veins.size());
  for (std::size_t i = 0; i < with.nodes.size(); ++i)
    EXPECT_EQ(with.nodes[i], without.nodes[i]);
}

} // namespace
} // namespace plantmorph
