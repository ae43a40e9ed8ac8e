// SPDX-License-Identifier: GPL-3.0-or-later
// Step 7 of the tree fit (TreeFit.h): twigs hidden in leaves, grown from the fitted wood towards the labelled wood
// the fit could not connect to it (space colonization, Runions et al. 2007; Xu et al. 2007 for laser-scanned trees).
#include "TreeFitInternal.h"

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
constexpr double ClusterSpacings = 8.0;    // a cluster: the points in a cube this many spacings wide...
constexpr int MinClusterPoints = 3;        // ...when it holds at least this many
constexpr double KillSpacings = 16.0;      // a cluster this near the wood's surface is carried by that wood
constexpr double InfluenceSpacings = 60.0; // a cluster draws the nearest twig end within this distance...
constexpr double StepSpacings = 6.0;       // ...which grows this far towards the clusters it draws
constexpr int MaxIterations = 400;
constexpr double SameDirection = 0.999; // cosine
constexpr int MinTwigSteps = 3; // a grown twig (from the wood or a grown fork to its tip) shorter than this is none

/// The clusters: per occupied cube of ClusterSpacings spacings holding MinClusterPoints points, their centroid
/// (cubes in the order of their integer coordinates: the result does not depend on the points' order beyond sums).
std::vector<Eigen::Vector3d> Clusters(const std::vector<Eigen::Vector3d>& points, double side)
{
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, std::pair<Eigen::Vector3d, int>> cubes;
  for (const Eigen::Vector3d& p : points)
  {
    const auto key = std::make_tuple(static_cast<std::int64_t>(std::floor(p.x() / side)),
      static_cast<std::int64_t>(std::floor(p.y() / side)), static_cast<std::int64_t>(std::floor(p.z() / side)));
    auto& cube = cubes.try_emplace(key, Eigen::Vector3d::Zero(), 0).first->second;
    cube.first += p;
    ++cube.second;
  }
  std::vector<Eigen::Vector3d> clusters;
  for (const auto& [key, cube] : cubes)
    if (cube.second >= MinClusterPoints)
      clusters.push_back(cube.first / cube.second);
  return clusters;
}
/// Grown twigs (cylinders from index `first` on) shorter than MinTwigSteps steps from where they leave the wood or a
/// grown fork to their farthest tip are dropped: a cluster drawing a twig end only a step or two lies by wood that
/// carries it, not at a hidden twig's end. Returns how many are kept.
int DropStubs(std::size_t first, double step, std::vector<TreeCylinder>& cylinders)
{
  const std::size_t n = cylinders.size();
  std::vector<double> reach(n, 0.0); // the longest path from a cylinder's start through its grown descendants
  std::vector<int> childCount(n, 0);
  for (std::size_t k = n; k-- > first;)
  {
    reach[k] += cylinders[k].length;
    const int p = cylinders[k].parent;
    ++childCount[p];
    if (static_cast<std::size_t>(p) >= first)
      reach[p] = std::max(reach[p], reach[k]);
  }
  std::vector<int> index(n, -1);
  std::size_t kept = first;
  for (std::size_t k = 0; k < n; ++k)
  {
    const int p = cylinders[k].parent;
    const bool grown = k >= first;
    const bool starts = grown && (static_cast<std::size_t>(p) < first || childCount[p] > 1);
    if (grown && (index[p] < 0 || (starts && reach[k] < (MinTwigSteps - 0.5) * step)))
      continue;
    index[k] = static_cast<int>(k < first ? k : kept);
    if (grown)
    {
      TreeCylinder c = cylinders[k];
      c.parent = index[p];
      cylinders[kept++] = c;
    }
  }
  cylinders.resize(kept);
  return static_cast<int>(kept - first);
}
} // namespace

int GrowHiddenTwigs(const std::vector<Eigen::Vector3d>& apart, double spacing,
  const std::vector<TreeCylinder>& modelled, std::vector<TreeCylinder>& cylinders)
{
  if (apart.empty() || modelled.empty() || !(spacing > 0))
    return 0;
  const double kill = KillSpacings * spacing, influence = InfluenceSpacings * spacing, step = StepSpacings * spacing;
  // Attraction points: the clusters no fitted wood carries already (further than `kill` from every surface).
  std::vector<Eigen::Vector3d> attractors;
  for (const Eigen::Vector3d& a : Clusters(apart, ClusterSpacings * spacing))
  {
    const bool carried = std::any_of(modelled.begin(), modelled.end(),
      [&](const TreeCylinder& c) { return SegmentDistance(a, c.start, c.end) - c.radius <= kill; });
    if (!carried)
      attractors.push_back(a);
  }
  // Twig ends that may grow: the fitted chains' tips, drawn only by clusters ahead of them (beyond the plane through
  // the tip normal to its axis), then every grown cylinder's end, drawn from every side; each the cylinder ending there.
  std::vector<Eigen::Vector3d> node, ahead;
  std::vector<int> nodeCylinder;
  std::vector<unsigned char> tip(modelled.size(), 1);
  for (const TreeCylinder& c : modelled)
    if (c.parent >= 0)
      tip[c.parent] = 0;
  for (std::size_t k = 0; k < modelled.size(); ++k)
    if (tip[k])
    {
      node.push_back(modelled[k].end);
      ahead.push_back((modelled[k].end - modelled[k].start).normalized());
      nodeCylinder.push_back(static_cast<int>(k));
    }
  std::vector<int> nearest(attractors.size(), -1);
  std::vector<double> distance(attractors.size(), influence);
  std::vector<unsigned char> alive(attractors.size(), 1);
  // per node, the direction it grew in last (a node drawn the same way twice by attractors no step brings nearer grows
  // no second twig there)
  std::vector<Eigen::Vector3d> grewTowards(node.size(), Eigen::Vector3d::Zero());
  const auto offer = [&](std::size_t from) { // nodes from `from` on: the attractors' nearest within reach
    for (std::size_t a = 0; a < attractors.size(); ++a)
      for (std::size_t n = from; alive[a] && n < node.size(); ++n)
      {
        const double d = (attractors[a] - node[n]).norm();
        if (d <= kill)
          alive[a] = 0;
        else if (d < distance[a] && (ahead[n].isZero() || (attractors[a] - node[n]).dot(ahead[n]) > 0.0))
          distance[a] = d, nearest[a] = static_cast<int>(n);
      }
  };
  offer(0);
  const std::size_t first = cylinders.size();
  for (int iteration = 0; iteration < MaxIterations; ++iteration)
  {
    std::vector<Eigen::Vector3d> pull(node.size(), Eigen::Vector3d::Zero());
    for (std::size_t a = 0; a < attractors.size(); ++a)
      if (alive[a] && nearest[a] >= 0)
        pull[nearest[a]] += (attractors[a] - node[nearest[a]]).normalized();
    const std::size_t before = node.size();
    for (std::size_t n = 0; n < before; ++n)
    {
      if (pull[n].norm() < 1e-6)
        continue;
      const Eigen::Vector3d towards = pull[n].normalized();
      if (towards.dot(grewTowards[n]) > SameDirection)
        continue;
      grewTowards[n] = towards;
      TreeCylinder c;
      c.start = node[n];
      c.end = node[n] + step * towards;
      c.length = step;
      c.parent = nodeCylinder[n];
      c.fittedRadius = std::numeric_limits<double>::quiet_NaN();
      c.fitRMS = std::numeric_limits<double>::quiet_NaN();
      c.path = towards;
      cylinders.push_back(c);
      node.push_back(c.end);
      ahead.push_back(Eigen::Vector3d::Zero());
      grewTowards.push_back(Eigen::Vector3d::Zero());
      nodeCylinder.push_back(static_cast<int>(cylinders.size()) - 1);
    }
    if (node.size() == before)
      break;
    offer(before);
  }
  return DropStubs(first, step, cylinders);
}

} // namespace treefit
} // namespace plantmorph
