// SPDX-License-Identifier: GPL-3.0-or-later
// Step 4 of the tree fit (TreeFit.h), checked on its cylinders: a chain of the skeleton whose points lie in another
// branch's cylinders is that branch's wood (strips of one stem's surface that leaves or a segmentation left apart),
// and its points join that branch. After step 7, the same for the points labelled leaf: no point lies inside wood, so a
// modelled cylinder whose solid is full of leaf points is narrower than the model made it.
#include "TreeFitInternal.h"

#include "PointGrid.h"

#include <plantmorph/statistics/Median.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr double InsideRadii = 0.5; // a point this share of a cylinder's radius outside its surface is still on it...
constexpr double InsideSpacings = 2.0; // ...or this many point spacings (thin cylinders, noise)
constexpr double InsideShare = 0.8;    // share of a chain's points on or in other branches' cylinders: it is theirs
constexpr double AlongAngle = 20.0;    // degrees: a chain's cylinder inside another runs along it, either way

constexpr double GridSpacings = 16.0; // cells of the grid the points are looked up in
constexpr double InsideNoise = 3.0;   // noise deviations: a point this far inside a cylinder's surface is in its solid
constexpr std::size_t MinLeafInside = 3; // leaf points in a solid, outnumbering its (and its surface's) wood points...
// ...this many times over (a twig's own points lie in a solid the model made too wide). Chosen on the tree fit
// benchmark's `--physical` scans: at 1 the exact-label fits lost 0.2 points of branch volume (benchmarks/README.md,
// "where mono-small's excess lies").
constexpr double LeafOverWood = 4.0;

constexpr int MinCirclePoints = 12;     // a circle fitted through this many points...
constexpr double MaxCircleScale = 0.35; // ...within this share of its radius (residual scale) is the wood's extent

/// The radius of the wood a cylinder stands for: its fitted circle's where that circle fits its points (MinCirclePoints,
/// MaxCircleScale), measured or not (a strip of a stem is fitted on too narrow an arc to be measured, but its circle
/// is the stem's, and the model's radius there can be a fraction of it), else its radius.
double Extent(const TreeCylinder& c)
{
  const bool circle = std::isfinite(c.fittedRadius) && c.points >= MinCirclePoints && std::isfinite(c.fitRMS) &&
    c.fitRMS <= MaxCircleScale * c.fittedRadius;
  return circle ? std::max(c.radius, c.fittedRadius) : c.radius;
}

/// How far `x` lies outside cylinder c (of radius Extent), in units of the tolerance (InsideRadii of that radius,
/// InsideSpacings): at most 1 on or in it.
double Outside(const Eigen::Vector3d& x, const TreeCylinder& c, double spacing)
{
  const double radius = Extent(c), tolerance = std::max(InsideRadii * radius, InsideSpacings * spacing);
  return (SegmentDistance(x, c.start, c.end) - radius) / tolerance;
}

/// The cylinder of `candidates` that `x` lies least outside of, and how far (Outside).
std::pair<int, double> Nearest(
  const Eigen::Vector3d& x, const std::vector<int>& candidates, const std::vector<TreeCylinder>& cylinders, double s)
{
  std::pair<int, double> best{ -1, std::numeric_limits<double>::infinity() };
  for (int k : candidates)
  {
    const double outside = Outside(x, cylinders[k], s);
    if (outside < best.second)
      best = { k, outside };
  }
  return best;
}

/// Whether node `node` hangs (now) from node `top`: the node tree's parents walked up from it.
bool HangsFrom(const std::vector<Node>& nodes, int node, int top)
{
  for (; node >= 0; node = nodes[node].parent)
    if (node == top)
      return true;
  return false;
}

/// The node of cylinder k (`cylinderNodes`) whose centroid is nearest to x.
int NearestNode(const Skeleton& s, const std::vector<int>& nodes, const Eigen::Vector3d& x)
{
  int best = nodes.front();
  for (int m : nodes)
    if ((s.nodes[m].centroid - x).squaredNorm() < (s.nodes[best].centroid - x).squaredNorm())
      best = m;
  return best;
}

/// Chain `g`'s nodes go: every point to the node of the candidate cylinder it lies least outside of, the chains
/// hanging from its last node to the nearest such node, and its first node leaves its parent's children.
void MergeChain(const Wood& wood, const std::vector<TreeCylinder>& cylinders,
  const std::vector<std::vector<int>>& cylinderNodes, const std::vector<int>& candidates, int g, Skeleton& s)
{
  const std::vector<int>& chain = s.segments[g];
  const auto hostNode = [&](const Eigen::Vector3d& x) {
    return NearestNode(s, cylinderNodes[Nearest(x, candidates, cylinders, wood.spacing).first], x);
  };
  for (int c : s.nodes[chain.back()].children)
  {
    const int host = hostNode(s.nodes[c].centroid);
    s.nodes[c].parent = host;
    s.nodes[host].children.push_back(c);
  }
  for (int m : chain)
  {
    for (int i : s.nodes[m].points)
    {
      const int host = hostNode(wood.points[i]);
      s.nodeOf[i] = host;
      s.nodes[host].points.push_back(i);
    }
    s.nodes[m].points.clear();
    s.nodes[m].children.clear();
  }
  auto& siblings = s.nodes[s.nodes[chain.front()].parent].children;
  siblings.erase(std::remove(siblings.begin(), siblings.end(), chain.front()), siblings.end());
  for (int m : chain)
    s.nodes[m].parent = -2; // removed
}
} // namespace

bool MergeInsideChains(const Wood& wood, const TreeFitResult& fit, Skeleton& s)
{
  const auto& cylinders = fit.cylinders;
  const std::size_t segments = s.segments.size();
  std::vector<int> nodeSegment(s.nodes.size(), -1);
  for (std::size_t g = 0; g < segments; ++g)
    for (int m : s.segments[g])
      nodeSegment[m] = static_cast<int>(g);
  std::vector<std::vector<int>> cylinderNodes(cylinders.size()), segmentCylinders(segments);
  for (std::size_t k = 0; k < cylinders.size(); ++k)
    segmentCylinders[cylinders[k].segment].push_back(static_cast<int>(k));
  // A cylinder's nodes: its segment's nodes in order, shared out as the pieces were (consecutive runs).
  for (std::size_t g = 0; g < segments; ++g)
  {
    const auto& chain = s.segments[g];
    const auto& ks = segmentCylinders[g];
    for (std::size_t j = 0; j < ks.size(); ++j)
      for (std::size_t m = chain.size() * j / ks.size(); m < chain.size() * (j + 1) / ks.size(); ++m)
        cylinderNodes[ks[j]].push_back(chain[m]);
  }
  // Each chain's fitted points, and what its subtree carries: the lighter of two chains inside each other goes.
  std::vector<std::vector<int>> ownPoints(segments);
  for (std::size_t i = 0; i < wood.points.size(); ++i)
    if (s.nodeOf[i] >= 0 && s.fitted[i] && nodeSegment[s.nodeOf[i]] >= 0)
      ownPoints[nodeSegment[s.nodeOf[i]]].push_back(static_cast<int>(i));
  std::vector<double> weight(segments, 0.0);
  for (std::size_t g = segments; g-- > 0;) // children come after their parent (depth first)
  {
    weight[g] += static_cast<double>(ownPoints[g].size());
    if (s.segmentParent[g] >= 0)
      weight[s.segmentParent[g]] += weight[g];
  }
  std::vector<int> order(segments);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return weight[a] < weight[b]; });
  std::vector<unsigned char> removed(segments, 0);
  bool merged = false;
  for (int g : order)
  {
    if (g == 0 || ownPoints[g].empty())
      continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int i : ownPoints[g])
      lo = lo.cwiseMin(wood.points[i]), hi = hi.cwiseMax(wood.points[i]);
    std::vector<int> candidates;
    for (std::size_t k = 0; k < cylinders.size(); ++k)
    {
      const TreeCylinder& c = cylinders[k];
      const double reach = Extent(c) + std::max(InsideRadii * Extent(c), InsideSpacings * wood.spacing);
      const Eigen::Vector3d clo = c.start.cwiseMin(c.end).array() - reach,
                            chi = c.start.cwiseMax(c.end).array() + reach;
      if (c.segment == g || removed[c.segment] || (clo.array() > hi.array()).any() || (chi.array() < lo.array()).any())
        continue;
      if (!HangsFrom(s.nodes, cylinderNodes[k].front(), s.segments[g].front()))
        candidates.push_back(static_cast<int>(k));
    }
    if (candidates.empty())
      continue;
    // Most of the chain's cylinders (the middles of their axes) lie in candidates and run along them (a strip of
    // a stem runs along it; a lateral's base in its parent's junction does not), and most of its points.
    const auto& ks = segmentCylinders[g];
    std::size_t along = 0;
    for (int k : ks)
    {
      const Eigen::Vector3d axis = (cylinders[k].end - cylinders[k].start).normalized();
      const auto [host, outside] =
        Nearest(0.5 * (cylinders[k].start + cylinders[k].end), candidates, cylinders, wood.spacing);
      const Eigen::Vector3d hostAxis = (cylinders[host].end - cylinders[host].start).normalized();
      along += outside <= 1.0 && std::abs(axis.dot(hostAxis)) >= std::cos(AlongAngle * M_PI / 180.0) ? 1 : 0;
    }
    if (static_cast<double>(along) < InsideShare * static_cast<double>(ks.size()))
      continue;
    const auto& own = ownPoints[g];
    const auto allowed = static_cast<std::size_t>((1.0 - InsideShare) * static_cast<double>(own.size()));
    std::size_t outside = 0; // stops once the chain cannot be inside
    for (std::size_t j = 0; j < own.size() && outside <= allowed; ++j)
      outside += Nearest(wood.points[own[j]], candidates, cylinders, wood.spacing).second > 1.0 ? 1 : 0;
    if (outside > allowed)
      continue;
    MergeChain(wood, cylinders, cylinderNodes, candidates, g, s);
    removed[g] = 1;
    merged = true;
  }
  if (merged)
    Segments(wood, s);
  return merged;
}

void NarrowLeafFilledCylinders(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel, double spacing, TreeFitResult& result)
{
  const double noise = result.traits.noise;
  if (woodLabel.size() != points.size() || !(noise > 0.0))
    return;
  const PointGrid grid(points, std::max(GridSpacings * spacing, 1e-9));
  std::vector<int> near;
  for (TreeCylinder& c : result.cylinders)
  {
    if (c.measured || c.segment < 0 || c.length <= 0.0 || c.radius <= InsideNoise * noise)
      continue;
    const Eigen::Vector3d axis = (c.end - c.start) / c.length;
    const double reach = c.radius + InsideNoise * noise;
    // Every point of the solid and its surface lies within half the length and the reach of the axis' middle.
    grid.Within(c.start + 0.5 * c.length * axis, 0.5 * c.length + reach, near);
    std::vector<double> leaf;
    std::size_t wood = 0;
    for (int i : near)
    {
      const Eigen::Vector3d d = points[i] - c.start;
      const double t = d.dot(axis), r = (d - t * axis).norm();
      if (t <= 0.0 || t >= c.length || r >= reach)
        continue;
      if (woodLabel[i] != 0)
        ++wood;
      else if (r < c.radius - InsideNoise * noise)
        leaf.push_back(r);
    }
    if (leaf.size() < MinLeafInside || static_cast<double>(leaf.size()) <= LeafOverWood * static_cast<double>(wood))
      continue;
    c.radius = std::max(Median(leaf), InsideNoise * noise);
  }
}

} // namespace treefit
} // namespace plantmorph
