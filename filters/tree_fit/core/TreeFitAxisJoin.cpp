// SPDX-License-Identifier: GPL-3.0-or-later
// Step 2 of the tree fit (TreeFit.h): a part of a branch left apart from the tree by a hidden stretch longer than the
// gaps the neighbour graph bridges, joined where its own axis points back at the tree.
#include "PointGrid.h"
#include "TreeFitInternal.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <tuple>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr double ThinSpacings = 4.0;  // the nearest searches run on one point per cube this many spacings wide
constexpr double AxisGapReach = 60.0; // spacings: the longest hidden stretch crossed (the reach of step 7's growth)
constexpr double AxisCosine = 0.7071; // the tree point reached lies within 45 degrees of the part's axis
constexpr double AxisSpread = 0.5;    // the part's end: its spread across its axis at most this share of the spread
                                      // along it (a tube, not a sheet or a brush)...
constexpr double AxisLength = 12.0;   // ...over at least this many spacings, and at least as long as the gap
constexpr double EndShare = 0.25;     // the point nearest the tree lies in this outer share of the tube's length

/// One point per occupied cube of side `side` (the lowest id in it): ids into `points`, of the points `ids`.
std::vector<int> Thin(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, double side)
{
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, int> cubes;
  for (int i : ids)
  {
    const Eigen::Vector3d& p = points[i];
    const auto key = std::make_tuple(static_cast<std::int64_t>(std::floor(p.x() / side)),
      static_cast<std::int64_t>(std::floor(p.y() / side)), static_cast<std::int64_t>(std::floor(p.z() / side)));
    auto [it, inserted] = cubes.try_emplace(key, i);
    if (!inserted)
      it->second = std::min(it->second, i);
  }
  std::vector<int> out;
  for (const auto& [key, i] : cubes)
    out.push_back(i);
  std::sort(out.begin(), out.end());
  return out;
}

/// The bridge from part `members` to the tree points `treeIds` (thinned, indexed by `treeGrid` over `treePoints`),
/// or none (distance infinite): the part's point nearest the tree within AxisGapReach spacings; the part's points
/// within twice that gap of it (at least AxisLength spacings) make a tube whose axis, out of the part through that
/// point, reaches a tree point within 45 degrees no farther than the tube is long.
std::tuple<double, int, int> AxisBridge(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& members,
  const std::vector<int>& treeIds, const std::vector<Eigen::Vector3d>& treePoints, const PointGrid& treeGrid,
  double spacing)
{
  const std::tuple<double, int, int> none{ std::numeric_limits<double>::infinity(), -1, -1 };
  const double reach = AxisGapReach * spacing;
  int from = -1;
  double gap = reach;
  for (int i : Thin(points, members, ThinSpacings * spacing))
  {
    const auto nearest = treeGrid.Nearest(points[i], 1, -1, gap);
    if (!nearest.empty() && std::sqrt(nearest[0].first) < gap)
      gap = std::sqrt(nearest[0].first), from = i;
  }
  if (from < 0)
    return none;
  const Eigen::Vector3d& p = points[from];
  const double radius = std::max(2.0 * gap, AxisLength * spacing);
  std::vector<int> stretch;
  for (int i : members)
    if ((points[i] - p).norm() <= radius)
      stretch.push_back(i);
  if (stretch.size() < 3)
    return none;
  const PointAxes axes = AxesOf(points, stretch);
  const Eigen::Vector3d& mean = axes.mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& solver = axes.solver;
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
  if (std::sqrt(l[1]) > AxisSpread * std::sqrt(l[2]))
    return none;
  Eigen::Vector3d axis = solver.eigenvectors().col(2);
  if ((p - mean).dot(axis) < 0.0)
    axis = -axis;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i : stretch)
  {
    lo = std::min(lo, (points[i] - mean).dot(axis));
    hi = std::max(hi, (points[i] - mean).dot(axis));
  }
  // The point nearest the tree is where the part ends (in the outer quarter of the tube along its axis, or within the
  // tube's width of its end: a thick branch's end seen from one side is cut across it), not a point on its side: a
  // part parallel to the tree lies beside it, its axis reaching past it.
  const double length = hi - lo, width = 4.0 * std::sqrt(l[1] / static_cast<double>(stretch.size()));
  if (length < AxisLength * spacing || hi - (p - mean).dot(axis) > EndShare * length + width)
    return none;
  std::vector<int> near;
  treeGrid.Within(p, std::min(reach, length), near);
  std::tuple<double, int, int> best = none;
  for (int k : near)
  {
    const Eigen::Vector3d d = treePoints[k] - p;
    const double dn = d.norm();
    if (d.dot(axis) >= AxisCosine * dn && dn < std::get<0>(best))
      best = { dn, std::min(from, treeIds[k]), std::max(from, treeIds[k]) };
  }
  return best;
}
} // namespace

std::vector<std::tuple<double, int, int>> BridgesAlongAxes(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& group, int base, double spacing)
{
  std::vector<std::tuple<double, int, int>> bridges;
  std::map<int, std::vector<int>> parts;
  std::vector<unsigned char> tree(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (group[i] == base)
      tree[i] = 1;
    else if (group[i] >= 0)
      parts[group[i]].push_back(static_cast<int>(i));
  // Parts too short to make a tube of AxisLength spacings are left out at once (stray returns, small clumps).
  for (auto it = parts.begin(); it != parts.end();)
  {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int i : it->second)
      lo = lo.cwiseMin(points[i]), hi = hi.cwiseMax(points[i]);
    it = (hi - lo).norm() < AxisLength * spacing ? parts.erase(it) : std::next(it);
  }
  // Shortest bridges first, each pass against the tree as it stands (a part joined can carry the next).
  while (!parts.empty())
  {
    std::vector<int> treeAll;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (tree[i])
        treeAll.push_back(static_cast<int>(i));
    const std::vector<int> treeIds = Thin(points, treeAll, ThinSpacings * spacing);
    std::vector<Eigen::Vector3d> treePoints;
    for (int i : treeIds)
      treePoints.push_back(points[i]);
    if (treePoints.empty())
      break;
    const PointGrid treeGrid(treePoints, ThinSpacings * spacing);
    std::vector<std::pair<std::tuple<double, int, int>, int>> found;
    for (const auto& [id, members] : parts)
    {
      const auto bridge = AxisBridge(points, members, treeIds, treePoints, treeGrid, spacing);
      if (std::isfinite(std::get<0>(bridge)))
        found.emplace_back(bridge, id);
    }
    if (found.empty())
      break;
    std::sort(found.begin(), found.end());
    for (const auto& [bridge, id] : found)
    {
      bridges.push_back(bridge);
      for (int i : parts[id])
        tree[i] = 1;
      parts.erase(id);
    }
  }
  return bridges;
}

} // namespace treefit
} // namespace plantmorph
