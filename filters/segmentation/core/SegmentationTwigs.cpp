// SPDX-License-Identifier: GPL-3.0-or-later
// A twig lying along a leaf's edge in the leaf's plane, taken into the leaf's instance (step 5 of
// PlantSegmentation.h; docs/methods/segmentation.md gives the numbers): its points go back to the wood.
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <plantmorph/PlaneFit.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

namespace plantmorph
{
namespace segmentation
{
namespace
{

/// A thin wood's axis near a point and the band around it that holds its surface.
struct TwigLine
{
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double band = 0.0;
};

double DistanceToLine(const TwigLine& line, const Eigen::Vector3d& q)
{
  return (q - line.point).cross(line.axis).norm();
}

/// The line of the thin wood at wood point c: the main axis of the wood points within 2r of it, or 4r or 8r when the
/// smaller ball is no line (a twig as thick as the ball is round in it). The first ball whose points spread across
/// that axis by under TwigLineSpread of their spread along it gives the line; wood thicker than r around it (a
/// branch: ThickWoodKeepsItsSurface looks at those) gives none. The band is the distance from the axis that holds
/// nine in ten of the ball's points (the twig's radius and the noise), and half a spacing more.
bool TwigLineAt(const std::vector<Eigen::Vector3d>& wood, const PointGrid& woodGrid, const Eigen::Vector3d& c,
  double radius, double spacing, TwigLine& line)
{
  std::vector<int> ball;
  std::vector<Eigen::Vector3d> near;
  for (int step = 0; step < TwigLineBalls; ++step)
  {
    woodGrid.Within(c, 2.0 * radius * static_cast<double>(1 << step), ball);
    if (ball.size() < TwigLinePoints)
      continue;
    near.clear();
    for (int j : ball)
      near.push_back(wood[static_cast<std::size_t>(j)]);
    const FittedPlane fit = FitPlane(near);
    if (fit.moments[1] > TwigLineSpread * fit.moments[2])
      continue;
    line.point = fit.centroid;
    line.axis = fit.major;
    std::vector<double> distance;
    double squares = 0.0;
    for (const Eigen::Vector3d& q : near)
    {
      distance.push_back(DistanceToLine(line, q));
      squares += distance.back() * distance.back();
    }
    if (squares > radius * radius * static_cast<double>(near.size()))
      return false;
    const auto at = distance.begin() + static_cast<std::ptrdiff_t>(0.9 * static_cast<double>(distance.size() - 1));
    std::nth_element(distance.begin(), at, distance.end());
    line.band = *at + 0.5 * spacing;
    return true;
  }
  return false;
}

/// The part's points near one twig line: those within its band (by their place t along the axis) and those beyond
/// 1.5 bands (the blade beside it), as indices into the part.
struct BandSplit
{
  std::vector<std::pair<double, int>> band; ///< (t, index), ascending
  std::vector<int> blade;
};

BandSplit SplitAtBand(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const TwigLine& line)
{
  BandSplit split;
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    const Eigen::Vector3d& q = points[static_cast<std::size_t>(ids[k])];
    const double d = DistanceToLine(line, q);
    if (d <= line.band)
      split.band.emplace_back((q - line.point).dot(line.axis), static_cast<int>(k));
    else if (d > 1.5 * line.band)
      split.blade.push_back(static_cast<int>(k));
  }
  std::sort(split.band.begin(), split.band.end());
  return split;
}

/// Whether the band's points [first, last), the window t in [lo, hi), are a twig's surface beside the blade: they
/// stand off the plane of the blade's points around them (within 2r and 1.5 bands of their centre, at least
/// TwigPlanePoints) by more (root mean square) than TwigOffPlane times the blade's own points do, and by more than
/// TwigBump of the band's width (the twig's radius: a twig's surface rises off the plane through its axis); the blade
/// lies on one side of the line there (fewer than TwigOtherSide as many of its points on the other: a twig along the
/// edge, not a leaf lying across a twig); and the window's points lie around the line, not on one side of it (a row
/// of the blade's own edge within the band).
bool TwigWindow(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const TwigLine& line,
  const BandSplit& split, std::size_t first, std::size_t last, double lo, double hi, double radius, double spacing)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t w = first; w < last; ++w)
    centre += points[static_cast<std::size_t>(ids[static_cast<std::size_t>(split.band[w].second)])];
  centre /= static_cast<double>(last - first);
  const double reach = 2.0 * radius + 1.5 * line.band;
  std::vector<Eigen::Vector3d> blade;
  for (int k : split.blade)
  {
    const Eigen::Vector3d& q = points[static_cast<std::size_t>(ids[static_cast<std::size_t>(k)])];
    if ((q - centre).squaredNorm() < reach * reach)
      blade.push_back(q);
  }
  if (blade.size() < TwigPlanePoints)
    return false;
  const FittedPlane plane = FitPlane(blade);
  Eigen::Vector3d across = line.axis.cross(plane.normal);
  if (across.norm() < 1e-6)
    return false; // the twig runs across the blade's plane
  across.normalize();
  std::size_t sideA = 0, sideB = 0;
  for (const Eigen::Vector3d& q : blade)
  {
    const double t = (q - line.point).dot(line.axis);
    if (t >= lo && t < hi)
      ((q - line.point).dot(across) > 0.0 ? sideA : sideB) += 1;
  }
  if (static_cast<double>(std::min(sideA, sideB)) > TwigOtherSide * static_cast<double>(std::max(sideA, sideB)))
    return false;
  double off = 0.0, side = 0.0;
  for (std::size_t w = first; w < last; ++w)
  {
    const Eigen::Vector3d& q = points[static_cast<std::size_t>(ids[static_cast<std::size_t>(split.band[w].second)])];
    off += std::pow((q - plane.centroid).dot(plane.normal), 2);
    side += (q - line.point).dot(across);
  }
  const double count = static_cast<double>(last - first);
  const double bladeOff = std::sqrt(plane.moments[0] / static_cast<double>(blade.size()));
  return std::abs(side / count) < TwigCentred * line.band &&
    std::sqrt(off / count) > std::max(TwigOffPlane * bladeOff, TwigBump * (line.band - 0.5 * spacing));
}

/// Walks the band from the wood point's place along the line, both ways, a window (r / 2, at least 10 spacings) at
/// a time, marking each window TwigWindow takes, until one has too few points or is not a twig's.
void WalkTwigLine(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const TwigLine& line,
  const Eigen::Vector3d& start, double radius, double spacing, std::vector<char>& taken)
{
  const BandSplit split = SplitAtBand(points, ids, line);
  const double window = std::max(0.5 * radius, TwigWindowSpacings * spacing);
  const double from = (start - line.point).dot(line.axis);
  if (split.band.size() < TwigWindowPoints || !(window > 0.0) || !std::isfinite(from))
    return;
  for (const double direction : { 1.0, -1.0 })
    for (double edge = from;; edge += direction * window)
    {
      const double lo = direction > 0.0 ? edge : edge - window;
      const auto first = std::lower_bound(split.band.begin(), split.band.end(), std::make_pair(lo, -1));
      const auto last = std::lower_bound(first, split.band.end(), std::make_pair(lo + window, -1));
      if (last - first < static_cast<std::ptrdiff_t>(TwigWindowPoints) ||
        !TwigWindow(points, ids, line, split, static_cast<std::size_t>(first - split.band.begin()),
          static_cast<std::size_t>(last - split.band.begin()), lo, lo + window, radius, spacing))
        break;
      for (auto w = first; w != last; ++w)
        taken[static_cast<std::size_t>(w->second)] = 1;
    }
}

/// The points of one leaf part (indices into the points) that a twig beside its edge put there: from each wood
/// point within r of the part (one in every r along the wood, in ascending order), the twig's line walked through
/// the part. None when they would be more than TwigPartShare of the part.
std::vector<int> TwigPointsOfPart(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
  const std::vector<Eigen::Vector3d>& wood, const PointGrid& woodGrid, double radius, double spacing)
{
  std::vector<int> contacts;
  for (int j : ids)
  {
    const int w = woodGrid.Near(points[static_cast<std::size_t>(j)], radius);
    if (w >= 0)
      contacts.push_back(w);
  }
  std::sort(contacts.begin(), contacts.end());
  contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
  std::vector<char> taken(ids.size(), 0);
  std::vector<Eigen::Vector3d> seeds;
  for (int w : contacts)
  {
    const Eigen::Vector3d& c = wood[static_cast<std::size_t>(w)];
    if (std::any_of(seeds.begin(), seeds.end(), [&](const Eigen::Vector3d& s) { return (s - c).norm() < radius; }))
      continue;
    seeds.push_back(c);
    TwigLine line;
    if (TwigLineAt(wood, woodGrid, c, radius, spacing, line))
      WalkTwigLine(points, ids, line, c, radius, spacing, taken);
  }
  std::vector<int> twig;
  for (std::size_t k = 0; k < ids.size(); ++k)
    if (taken[k])
      twig.push_back(ids[k]);
  if (static_cast<double>(twig.size()) > TwigPartShare * static_cast<double>(ids.size()))
    twig.clear();
  return twig;
}

} // namespace

std::size_t TwigsAlongLeafEdges(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& wood,
  const PointGrid& woodGrid, const std::vector<char>& kept, double radius, double spacing, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts, std::vector<int>& organ, std::vector<double>& confidence)
{
  if (wood.empty())
    return 0;
  std::vector<std::vector<int>> twig(parts.size());
  parallel(parts.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      if (kept[k] && parts[k].size() >= TwigPlanePoints)
        twig[k] = TwigPointsOfPart(points, parts[k], wood, woodGrid, radius, spacing);
  });
  std::size_t moved = 0;
  std::vector<char> out(points.size(), 0);
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    if (twig[k].empty())
      continue;
    for (int j : twig[k])
    {
      out[static_cast<std::size_t>(j)] = 1;
      organ[static_cast<std::size_t>(j)] = OrganWood;
      confidence[static_cast<std::size_t>(j)] = 0.5; // judged leaf, made wood by the twig's line
    }
    std::vector<int>& ids = parts[k];
    ids.erase(
      std::remove_if(ids.begin(), ids.end(), [&](int j) { return out[static_cast<std::size_t>(j)] != 0; }), ids.end());
    moved += twig[k].size();
  }
  return moved;
}

} // namespace segmentation
} // namespace plantmorph
