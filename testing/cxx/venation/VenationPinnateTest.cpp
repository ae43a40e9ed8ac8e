// SPDX-License-Identifier: GPL-3.0-or-later
// Pinnate venation reaches out (docs/methods/venation.md "Secondary veins"): on the entire blade the paper
// mulberry preset's secondaries leave the midvein at the preset's divergence angle (45 deg at the base to 70 at the
// apex), run out into the outer part of the half-blade before they loop (brochidodromous), and craspedodromous
// secondaries end on the margin. The blade is symmetric about x = 0 with its midvein on it, so the half-width at a
// height is read off its outline.
#include "VenationGrowth.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace plantmorph
{
namespace
{
constexpr double Degrees = 180.0 / 3.14159265358979323846;

struct Blade
{
  LeafGeometry leaf;
  std::vector<Eigen::Vector2d> outline; ///< closed
  /// The blade's half-width at height y: the largest |x| where the outline crosses the line at y.
  double HalfWidth(double y) const
  {
    double best = 0.0;
    for (std::size_t i = 0; i + 1 < this->outline.size(); ++i)
    {
      const Eigen::Vector2d a = this->outline[i], b = this->outline[i + 1];
      if ((a.y() - y) * (b.y() - y) > 0.0 || a.y() == b.y())
        continue;
      const double t = (y - a.y()) / (b.y() - a.y());
      best = std::max(best, std::abs(a.x() + t * (b.x() - a.x())));
    }
    return best;
  }
  double DistanceToOutline(const Eigen::Vector2d& x) const
  {
    double best = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i + 1 < this->outline.size(); ++i)
    {
      const Eigen::Vector2d a = this->outline[i], d = this->outline[i + 1] - a;
      const double t = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      best = std::min(best, (a + t * d - x).norm());
    }
    return best;
  }
};

Blade Entire(DeformedRectanglePreset preset = DeformedRectanglePreset::Entire)
{
  Blade blade;
  LeafMeshParameters settings;
  settings.resolution = 80;
  EXPECT_EQ(BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(preset, 5.0), settings, blade.leaf), "");
  for (int id : blade.leaf.rightMargin)
    blade.outline.push_back(blade.leaf.blade.points[id]);
  for (std::size_t i = blade.leaf.leftMargin.size(); i-- > 0;)
    blade.outline.push_back(blade.leaf.blade.points[blade.leaf.leftMargin[i]]);
  return blade;
}

VenationResult Grow(const Blade& blade, const VenationParameters& p)
{
  VenationResult result;
  EXPECT_EQ(GrowVenation({ blade.leaf.blade.points, blade.leaf.blade.uv, blade.leaf.blade.triangles }, p, result), "");
  return result;
}

TEST(PinnateVenation, PaperMulberrySecondariesLeaveAtTheDivergenceAngleAndLoopInTheOuterPart)
{
  const Blade blade = Entire();
  VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
  p.tertiary = false;
  const VenationResult r = Grow(blade, p);
  int secondaries = 0;
  double lowest = 1.0;
  std::vector<double> outs;
  for (const auto& vein : r.veins)
  {
    const Eigen::Vector2d start = r.nodes[vein.nodes.front()];
    if (vein.order != VeinOrderSecondary || start.x() != 0.0)
      continue; // a loop, not a secondary leaving the midvein
    ++secondaries;
    // The divergence angle interpolates from the base to the apex along the midvein (here v = y / L).
    const double v = start.y() / r.leafLength;
    const double expected = p.divergenceAngle + (p.divergenceAngleApex - p.divergenceAngle) * v;
    const Eigen::Vector2d d = r.nodes[vein.nodes[1]] - start;
    EXPECT_NEAR(std::atan2(std::abs(d.x()), d.y()) * Degrees, expected, 1.0) << "secondary at v = " << v;
    // Where it forks into its loop: its last node, as a fraction of the half-width at that height.
    const Eigen::Vector2d fork = r.nodes[vein.nodes.back()];
    const double out = std::abs(fork.x()) / blade.HalfWidth(fork.y());
    lowest = std::min(lowest, out);
    outs.push_back(out);
    EXPECT_GE(out, 0.5) << "secondary at v = " << v;
  }
  std::sort(outs.begin(), outs.end());
  const double median = outs.empty() ? 0.0 : outs[outs.size() / 2];
  std::cout << secondaries << " secondaries; the forks lie at " << lowest << " (innermost), " << median
            << " (median) of the half-width\n";
  EXPECT_GE(median, 0.7); // most loops run in the outer 30 % of the half-blade
  EXPECT_GT(secondaries, 10);
}

TEST(PinnateVenation, PaperMulberryLoopsBulgeTowardsTheMargin)
{
  // Brochidodromous loops lie in the outer part of the half-blade, nearer the margin than the midvein: each loop's
  // outermost point (its apex) and the mean of its points, as fractions of the half-width at their height. On the
  // entire blade and on LeafOutlineSource's default blade (the ginkgo fan, widest near its apex, where the loops
  // used to hug the midvein).
  for (const DeformedRectanglePreset preset : { DeformedRectanglePreset::Entire, DeformedRectanglePreset::Ginkgo })
  {
    SCOPED_TRACE(PresetName(preset));
    const Blade blade = Entire(preset);
    VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
    p.tertiary = false;
    const VenationResult r = Grow(blade, p);
    std::vector<double> apexes, means;
    for (const auto& vein : r.veins)
    {
      const Eigen::Vector2d start = r.nodes[vein.nodes.front()], end = r.nodes[vein.nodes.back()];
      if (vein.order != VeinOrderSecondary || start.x() == 0.0 || blade.DistanceToOutline(end) < 1e-6 * r.leafLength)
        continue; // a secondary leaving the midvein, or the topmost one's run on to the margin
      double apex = 0.0, sum = 0.0;
      Eigen::Vector2d outermost = start;
      for (int n : vein.nodes)
      {
        const Eigen::Vector2d x = r.nodes[n];
        const double fraction = std::abs(x.x()) / blade.HalfWidth(x.y());
        sum += fraction;
        if (fraction > apex)
        {
          apex = fraction;
          outermost = x;
        }
      }
      apexes.push_back(apex);
      means.push_back(sum / static_cast<double>(vein.nodes.size()));
      // Its apex is nearer the margin than the midvein.
      EXPECT_LT(blade.DistanceToOutline(outermost), std::abs(outermost.x())) << "loop from " << start.transpose();
      EXPECT_GE(means.back(), 0.6) << "loop from " << start.transpose();
    }
    ASSERT_GE(apexes.size(), 8u);
    std::sort(apexes.begin(), apexes.end());
    std::sort(means.begin(), means.end());
    std::cout << PresetName(preset) << ": " << apexes.size() << " loops; apexes at " << apexes.front()
              << " (innermost), " << apexes[apexes.size() / 2] << " (median) of the half-width; mean positions "
              << means.front() << ".." << means.back() << "\n";
    EXPECT_GE(apexes.front(), 2.0 / 3.0);      // every loop reaches the outer third
    EXPECT_GE(apexes[apexes.size() / 2], 0.8); // most run close to the margin
  }
}

/// Distances (in leaf lengths) from blade points (triangle centroids) to the nearest primary or secondary, sorted;
/// only points below `below` (a height) and farther than `side` from the midvein.
std::vector<double> MajorVeinDistances(const Blade& blade, const VenationResult& r, double below, double side)
{
  std::vector<double> distances;
  for (const auto& t : blade.leaf.blade.triangles)
  {
    const Eigen::Vector2d c =
      (blade.leaf.blade.points[t[0]] + blade.leaf.blade.points[t[1]] + blade.leaf.blade.points[t[2]]) / 3.0;
    if (c.y() > below || std::abs(c.x()) < side)
      continue;
    double best = std::numeric_limits<double>::max();
    for (const auto& vein : r.veins)
    {
      if (vein.order > VeinOrderSecondary)
        continue;
      for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
      {
        const Eigen::Vector2d a = r.nodes[vein.nodes[i]], d = r.nodes[vein.nodes[i + 1]] - a;
        const double u = std::clamp((c - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
        best = std::min(best, (a + u * d - c).norm());
      }
    }
    distances.push_back(best / r.leafLength);
  }
  std::sort(distances.begin(), distances.end());
  return distances;
}

TEST(PinnateVenation, PaperMulberryFlanksOfTheFanGetSecondaries)
{
  // On the default ginkgo fan the lowest secondaries run parallel to its straight lower flanks; the paper mulberry
  // preset's flank secondaries (flankSecondaries) reach into them. The measure: in the lower flanks (below the
  // lateral corners, outside the middle half), the largest distance from a blade point to a primary or secondary,
  // at most SecondarySpacing (0.11 L, sampling tolerance 0.01 L) with them and more than 0.15 L without, seeds 1-4.
  const Blade fan = Entire(DeformedRectanglePreset::Ginkgo);
  double lowY = std::numeric_limits<double>::max(), highY = -lowY, halfWidth = 0.0;
  for (const Eigen::Vector2d& x : fan.outline)
  {
    lowY = std::min(lowY, x.y());
    highY = std::max(highY, x.y());
    halfWidth = std::max(halfWidth, std::abs(x.x()));
  }
  // The lateral corners: the outline's widest points.
  double cornerY = 0.0;
  for (const Eigen::Vector2d& x : fan.outline)
  {
    if (std::abs(x.x()) == halfWidth)
      cornerY = x.y();
  }
  for (std::uint64_t seed = 1; seed <= 4; ++seed)
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    VenationParameters p = MakeVenationPreset(VenationPreset::PaperMulberry);
    p.seed = seed;
    const std::vector<double> with = MajorVeinDistances(fan, Grow(fan, p), cornerY, 0.25 * halfWidth);
    p.flankSecondaries = false;
    const std::vector<double> without = MajorVeinDistances(fan, Grow(fan, p), cornerY, 0.25 * halfWidth);
    ASSERT_GT(with.size(), 50u);
    std::cout << "fan flanks, seed " << seed << ": farthest from a primary or secondary " << with.back()
              << " L with flank secondaries, " << without.back() << " L without (95th percentile "
              << with[with.size() * 95 / 100] << ", " << without[without.size() * 95 / 100] << ")\n";
    EXPECT_LE(with.back(), p.secondarySpacing + 0.01);
    EXPECT_GT(without.back(), 0.15);
  }
}

TEST(PinnateVenation, CraspedodromousSecondariesEndOnTheMargin)
{
  const Blade blade = Entire();
  for (const double angle : { 45.0, 55.0, 70.0 })
  {
    VenationParameters p;
    p.pattern = VenationPattern::Craspedodromous;
    p.tertiary = false;
    p.divergenceAngle = p.divergenceAngleApex = angle;
    const VenationResult r = Grow(blade, p);
    int secondaries = 0;
    for (const auto& vein : r.veins)
    {
      if (vein.order != VeinOrderSecondary)
        continue;
      ++secondaries;
      const Eigen::Vector2d end = r.nodes[vein.nodes.back()];
      EXPECT_LT(blade.DistanceToOutline(end), 1e-6 * r.leafLength) << "angle " << angle << ", end " << end.transpose();
    }
    EXPECT_GT(secondaries, 10);
    EXPECT_EQ(r.statistics.freeEnds, 0u);
  }
}

} // namespace
} // namespace plantmorph
