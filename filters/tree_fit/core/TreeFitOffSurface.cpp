// SPDX-License-Identifier: GPL-3.0-or-later
// Step 5 of the tree fit (TreeFit.h), checked on its cylinders: a chain whose radius could be measured nowhere and
// whose points lie on no surface about its axis is leaves labelled wood, not a twig, and goes back to the leaves.
#include "TreeFitInternal.h"

#include <plantmorph/statistics/Median.h>

#include <algorithm>
#include <cmath>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr double OffNoise = 3.0; // noise deviations: a point further than this from a surface is off it
constexpr double OnShare = 0.5;  // share of a cylinder's fitted points a surface of wood holds

/// Per cylinder whether it is leaves: not measured, and under OnShare of its fitted points lie within OffNoise noise
/// deviations of its surface (its radius as modelled) and under OnShare within as much of the ring its own points
/// make about its axis (the median of their distances to it, whatever the model says). A twig too thin to measure
/// has its points within the noise of that ring, and so has a strip of a wider branch whose radius was not measured
/// (on the bare benchmark scans such chains lie up to 30 noise deviations off their modelled surfaces, but on their
/// rings); leaves hanging round a twig, or one flat leaf across its axis, spread their points over centimetres on
/// either side of any ring.
std::vector<unsigned char> LeafCylinders(
  const Wood& wood, const TreeFitResult& fit, const std::vector<int>& woodCylinder, const Skeleton& s)
{
  const auto& cylinders = fit.cylinders;
  const double tolerance = OffNoise * fit.traits.noise;
  std::vector<std::vector<double>> distance(cylinders.size());
  for (std::size_t i = 0; i < wood.points.size(); ++i)
  {
    const int c = woodCylinder[i];
    if (s.nodeOf[i] < 0 || !s.fitted[i] || c < 0 || cylinders[c].measured)
      continue;
    const Eigen::Vector3d axis = (cylinders[c].end - cylinders[c].start).normalized();
    distance[c].push_back((wood.points[i] - cylinders[c].start).cross(axis).norm());
  }
  std::vector<unsigned char> leaves(cylinders.size(), 0);
  for (std::size_t c = 0; c < cylinders.size(); ++c)
  {
    if (distance[c].empty())
      continue;
    std::vector<double> sorted = distance[c];
    const double ring = Median(sorted);
    std::size_t onSurface = 0, onRing = 0;
    for (double d : distance[c])
    {
      onSurface += std::abs(d - cylinders[c].radius) <= tolerance ? 1 : 0;
      onRing += std::abs(d - ring) <= tolerance ? 1 : 0;
    }
    const double most = OnShare * static_cast<double>(distance[c].size());
    leaves[c] = static_cast<double>(onSurface) < most && static_cast<double>(onRing) < most ? 1 : 0;
  }
  return leaves;
}
} // namespace

bool ReturnOffSurfaceChains(
  const Wood& wood, const TreeFitResult& fit, const std::vector<int>& woodCylinder, Skeleton& s)
{
  const std::vector<unsigned char> leafCylinder = LeafCylinders(wood, fit, woodCylinder, s);
  std::vector<int> nodeCylinder(s.nodes.size(), -1);
  for (std::size_t i = 0; i < wood.points.size(); ++i)
    if (s.nodeOf[i] >= 0)
      nodeCylinder[s.nodeOf[i]] = woodCylinder[i];
  // Per chain where its run of leaf cylinders up to its tip starts (its length: none; nodes without points go with
  // the run), and whether it is leaves from its first node on with every chain hanging from it (children come after
  // their parent: depth first).
  const std::size_t segments = s.segments.size();
  std::vector<std::size_t> tail(segments);
  std::vector<unsigned char> leaves(segments, 0);
  for (std::size_t g = 0; g < segments; ++g)
  {
    const auto& chain = s.segments[g];
    std::size_t t = chain.size();
    while (t > 0 && (nodeCylinder[chain[t - 1]] < 0 || leafCylinder[nodeCylinder[chain[t - 1]]]))
      --t;
    tail[g] = t;
    leaves[g] = g > 0 && t == 0 ? 1 : 0;
  }
  std::vector<unsigned char> childrenLeaves(segments, 1);
  for (std::size_t g = segments; g-- > 1;)
    if (s.segmentParent[g] >= 0)
    {
      leaves[g] = leaves[g] && childrenLeaves[g];
      childrenLeaves[s.segmentParent[g]] = childrenLeaves[s.segmentParent[g]] && leaves[g];
    }
  bool returned = false;
  for (std::size_t g = 0; g < segments; ++g)
  {
    const auto& chain = s.segments[g];
    const int parent = s.segmentParent[g]; // -1 for a chain that starts a skeleton of its own
    const bool whole = leaves[g] && parent >= 0 && !leaves[parent];
    const bool end = !leaves[g] && tail[g] < chain.size() && childrenLeaves[g];
    const int first = whole ? chain.front() : end ? chain[tail[g]] : -1;
    if (first < 0 || s.nodes[first].parent < 0) // nothing to return, or already returned with its parent's tip
      continue;
    auto& children = s.nodes[s.nodes[first].parent].children;
    children.erase(std::remove(children.begin(), children.end(), first), children.end());
    CutSubtree(s.nodes, first, -1, s.nodeOf, s.fitted);
    returned = true;
  }
  if (returned)
    Segments(wood, s);
  return returned;
}

} // namespace treefit
} // namespace plantmorph
