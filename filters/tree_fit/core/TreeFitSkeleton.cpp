// SPDX-License-Identifier: GPL-3.0-or-later
// Step 3 of the tree fit (TreeFit.h): level sets of the geodesic distance, their connected components as nodes, the
// node tree, pruning of short side chains, segments.
#include "TreeFitInternal.h"

#include <plantmorph/graph/DisjointSets.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr double BinSpacings = 6.0;
constexpr int MinSideBins = 3;
constexpr double OneStemTolerance = 0.3; // of the joint circle's radius (at least 1.5 spacings): a point on it
constexpr double OneStemShare = 0.85;    // share of each of the two nodes' points that must lie on the joint circle
constexpr double OneStemWidth = 1.5;     // the joint circle's radius within this factor of the stem's below
constexpr double OneStemArc = 150.0;     // degrees of the joint circle the two nodes' points cover together
constexpr int ParallelBins = 4;          // bins two chains that both go on must run side by side to be one stem
constexpr double SheetFlatness = 0.2;    // a node's smallest principal deviation under this share of its middle one...
constexpr double SheetWidth = 1.0;       // ...which is at least this many spacings: a flat sheet (a leaf's strip)
constexpr int SheetMinPoints = 10;       // points a node needs to be called a sheet
constexpr double SheetShare = 0.5;       // share of a side chain's points in sheets that makes it leaves, not wood...
constexpr int TubeBins = 12;             // ...unless it holds a run of this many bins of tube (no sheet) nodes: wood

/// The nodes: connected components (graph edges inside a bin) of every bin, numbered by (bin, lowest point id); all
/// of bin 0 is one node, the base.
std::vector<Node> BinComponents(const Wood& wood, double width, std::vector<int>& nodeOf)
{
  const std::size_t n = wood.points.size();
  std::vector<int> bin(n);
  for (std::size_t i = 0; i < n; ++i)
    bin[i] = static_cast<int>(std::floor(wood.geodesic[i] / width));
  DisjointSets<int> sets(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int e = wood.graph.offset[i]; e < wood.graph.offset[i + 1]; ++e)
    {
      const int j = wood.graph.target[e];
      if (bin[j] == bin[i] || (bin[i] == 0 && bin[j] == 0))
        sets.Join(static_cast<int>(i), j);
    }
  int base = -1;
  for (std::size_t i = 0; i < n; ++i)
    if (bin[i] == 0)
    {
      const int r = sets.Find(static_cast<int>(i));
      if (base < 0)
        base = r;
      else
        sets.JoinRoots(r, base), base = std::min(r, base);
    }
  std::map<std::pair<int, int>, int> key; // (bin, root) -> node; roots are lowest ids, so the order is (bin, id)
  for (std::size_t i = 0; i < n; ++i)
    key.emplace(std::make_pair(bin[i], sets.Find(static_cast<int>(i))), 0);
  std::vector<Node> nodes;
  for (auto& [k, id] : key)
  {
    id = static_cast<int>(nodes.size());
    nodes.emplace_back();
    nodes.back().bin = k.first;
  }
  nodeOf.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i)
  {
    nodeOf[i] = key[{ bin[i], sets.Find(static_cast<int>(i)) }];
    nodes[nodeOf[i]].points.push_back(static_cast<int>(i));
  }
  return nodes;
}

/// Each node's parent: the node its nearest-to-base point's shortest path comes from.
void LinkNodes(const Wood& wood, const std::vector<int>& nodeOf, std::vector<Node>& nodes)
{
  for (std::size_t k = 1; k < nodes.size(); ++k)
  {
    Node& node = nodes[k];
    int first = node.points.front();
    for (int i : node.points)
      if (wood.geodesic[i] < wood.geodesic[first])
        first = i;
    int at = first;
    while (at >= 0 && nodeOf[at] == static_cast<int>(k))
      at = wood.previous[at];
    node.parent = at >= 0 ? nodeOf[at] : 0;
    if (nodes[node.parent].bin >= node.bin) // cannot happen along decreasing distances; keep the tree a tree
      node.parent = 0;
  }
  for (std::size_t k = 1; k < nodes.size(); ++k)
    nodes[nodes[k].parent].children.push_back(static_cast<int>(k));
}

Eigen::Vector3d Mean(const Wood& wood, const std::vector<int>& a, const std::vector<int>& b = {})
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i : a)
    sum += wood.points[i];
  for (int i : b)
    sum += wood.points[i];
  return sum / static_cast<double>(std::max<std::size_t>(1, a.size() + b.size()));
}

/// The circle about `axis` that fits the points (ids into the wood) best: its centre and radius; false if none.
bool CrossSection(
  const Wood& wood, const std::vector<int>& ids, const Eigen::Vector3d& axis, Eigen::Vector3d& centre, double& radius)
{
  std::vector<Eigen::Vector3d> q;
  for (int i : ids)
    q.push_back(wood.points[i]);
  const Eigen::Vector3d c = Mean(wood, ids);
  Eigen::Vector3d u, v, circle;
  Frame(axis, u, v);
  if (q.size() < 6 || !CircleFit(q, c, u, v, circle))
    return false;
  centre = c + circle[0] * u + circle[1] * v;
  radius = circle[2];
  return true;
}

/// Whether the points of two nodes of one bin lie on one circle about `axis`, as the two sides of one stem do, and
/// not two branches side by side: the circle is about as wide as the stem below (`stemRadius`, within OneStemWidth),
/// OneStemShare of each node's points lie within OneStemTolerance of it, and together they cover OneStemArc of it.
bool OnOneCircle(const Wood& wood, const Node& a, const Node& b, const Eigen::Vector3d& axis, double stemRadius)
{
  std::vector<int> both = a.points;
  both.insert(both.end(), b.points.begin(), b.points.end());
  Eigen::Vector3d centre;
  double radius = 0;
  if (!CrossSection(wood, both, axis, centre, radius) || radius > OneStemWidth * stemRadius ||
    radius < stemRadius / OneStemWidth)
    return false;
  const double tolerance = std::max(OneStemTolerance * radius, 1.5 * wood.spacing);
  Eigen::Vector3d u, v;
  Frame(axis, u, v);
  std::array<bool, 36> seen{};
  const auto share = [&](const Node& node) {
    std::size_t on = 0;
    for (int i : node.points)
    {
      const Eigen::Vector3d r = wood.points[i] - centre;
      if (std::abs(r.cross(axis).norm() - radius) > tolerance)
        continue;
      ++on;
      const double angle = std::atan2(r.dot(v), r.dot(u)) + M_PI;
      seen[static_cast<std::size_t>(std::min(35.0, std::floor(angle / (2 * M_PI) * 36.0)))] = true;
    }
    return static_cast<double>(on) / static_cast<double>(node.points.size());
  };
  const bool on = share(a) >= OneStemShare && share(b) >= OneStemShare;
  return on && 10.0 * static_cast<double>(std::count(seen.begin(), seen.end(), true)) >= OneStemArc;
}

/// Two chains leaving one node that are one stem whose level sets split side by side (a side occluded, a gap in the
/// scan, a junction): bin by bin, while each goes on one node a bin, both nodes lie on one circle about the stem's
/// axis. One stem when one chain ends within that walk (the two reunite, or one side's points stop) or when both run
/// so for ParallelBins bins; then the node pairs, else nothing (a fork: the chains part within a few bins).
std::vector<std::pair<int, int>> SideBySide(const Wood& wood, const std::vector<Node>& nodes, int fork, int a, int b)
{
  std::vector<Eigen::Vector3d> centres; // the stem's centre line below the fork (up to three nodes), then the pairs'
  for (int k = fork, n = 0; k >= 0 && n < 3; k = nodes[k].parent, ++n)
    centres.insert(centres.begin(), Mean(wood, nodes[k].points));
  Eigen::Vector3d stemCentre;
  double stemRadius = 0;
  const Eigen::Vector3d stemAxis = Mean(wood, nodes[a].points, nodes[b].points) - centres.front();
  if (!(stemAxis.norm() > 0.0) ||
    !CrossSection(wood, nodes[fork].points, stemAxis.normalized(), stemCentre, stemRadius))
    return {};
  std::vector<std::pair<int, int>> pairs;
  while (true)
  {
    if (nodes[a].bin != nodes[b].bin)
      return {};
    const Eigen::Vector3d centre = Mean(wood, nodes[a].points, nodes[b].points);
    const Eigen::Vector3d axis = centre - centres[centres.size() >= 3 ? centres.size() - 3 : 0];
    if (!(axis.norm() > 0.0) || !OnOneCircle(wood, nodes[a], nodes[b], axis.normalized(), stemRadius))
      return {};
    centres.push_back(centre);
    pairs.emplace_back(a, b);
    if (nodes[a].children.size() != 1 || nodes[b].children.size() != 1)
    {
      const bool ends = nodes[a].children.empty() || nodes[b].children.empty();
      return ends || pairs.size() >= static_cast<std::size_t>(ParallelBins) ? pairs : decltype(pairs){};
    }
    a = nodes[a].children.front();
    b = nodes[b].children.front();
  }
}

/// Chains that are one stem split side by side (SideBySide) become one chain: each pair's second node's points join
/// the first, and what hung from the last second node hangs from the last first one. Without this, the lighter of
/// the two becomes a short child branch at a few degrees, one order up, and both sides are fitted as half cylinders.
void MergeSideBySide(const Wood& wood, std::vector<Node>& nodes, std::vector<int>& nodeOf)
{
  for (std::size_t k = 0; k < nodes.size(); ++k) // parents before children: ids go by bin
    for (std::size_t x = 0; x < nodes[k].children.size(); ++x)
      for (std::size_t y = x + 1; y < nodes[k].children.size();)
      {
        const auto pairs = SideBySide(wood, nodes, static_cast<int>(k), nodes[k].children[x], nodes[k].children[y]);
        if (pairs.empty())
        {
          ++y;
          continue;
        }
        for (auto [keep, gone] : pairs)
        {
          for (int i : nodes[gone].points)
            nodeOf[i] = keep;
          nodes[keep].points.insert(nodes[keep].points.end(), nodes[gone].points.begin(), nodes[gone].points.end());
          nodes[gone].points.clear();
          nodes[gone].parent = -2; // removed
        }
        const auto [last, lastGone] = pairs.back();
        for (int c : nodes[lastGone].children)
        {
          nodes[c].parent = last;
          nodes[last].children.push_back(c);
        }
        for (auto [keep, gone] : pairs)
          nodes[gone].children.clear();
        std::sort(nodes[last].children.begin(), nodes[last].children.end());
        nodes[k].children.erase(nodes[k].children.begin() + static_cast<std::ptrdiff_t>(y));
      }
}

/// Collects the nodes of the subtree under `node` (itself included).
void Subtree(const std::vector<Node>& nodes, int node, std::vector<int>& out)
{
  std::vector<int> stack{ node };
  while (!stack.empty())
  {
    const int k = stack.back();
    stack.pop_back();
    out.push_back(k);
    for (int c : nodes[k].children)
      stack.push_back(c);
  }
}

} // namespace

/// Removes the subtree under `node` (itself included): each of its points goes to node `to` (-1: none) unfitted, and
/// its nodes are marked removed. The caller drops `node` from its parent's children.
void CutSubtree(
  std::vector<Node>& nodes, int node, int to, std::vector<int>& nodeOf, std::vector<unsigned char>& fitted)
{
  std::vector<int> cut;
  Subtree(nodes, node, cut);
  for (int m : cut)
  {
    for (int i : nodes[m].points)
    {
      nodeOf[i] = to;
      fitted[i] = 0;
      if (to >= 0)
        nodes[to].points.push_back(i);
    }
    nodes[m].points.clear();
    nodes[m].children.clear();
    nodes[m].parent = -2; // removed
  }
}

namespace
{
/// Whether a node's points lie in a flat sheet wider than a twig's section (a leaf, or a strip of one): the smallest
/// principal deviation under SheetFlatness of the middle one, which is at least SheetWidth spacings. A twig's level
/// set is a short tube (its two smaller deviations about equal, or an arc's when one side is scanned, at least 0.3
/// of the larger), a thick stem's a ring; a blade's is a strip across the blade, flat within the scan's noise.
bool IsSheet(const Wood& wood, const Node& node, const std::vector<unsigned char>& fitted)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int count = 0;
  for (int i : node.points)
    if (fitted[i])
      mean += wood.points[i], ++count;
  if (count < SheetMinPoints)
    return false;
  mean /= count;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int i : node.points)
    if (fitted[i])
      covariance += (wood.points[i] - mean) * (wood.points[i] - mean).transpose();
  const Eigen::Vector3d ev =
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance / count, Eigen::EigenvaluesOnly).eigenvalues();
  const double thin = std::sqrt(std::max(ev[0], 0.0)), middle = std::sqrt(std::max(ev[1], 0.0));
  return middle >= SheetWidth * wood.spacing && thin <= SheetFlatness * middle;
}

/// Side chains that are leaves, not wood (a segmentation labels some leaf points wood: blade margins and petioles
/// beside the twigs): at every fork, a child that leaves it as a flat sheet (IsSheet) and whose subtree has at least
/// SheetShare of its points in sheets is returned to the leaves with everything it carries: its points get no node and are no wood. Without
/// this each such sheet becomes a twig of its own, whose pipe-model radius adds volume and whose growth length
/// widens the model radii of the branches carrying it. A side chain that holds a run of TubeBins bins of nodes that
/// are no sheets (72 spacings of a tube, longer than a leaf's strips run) is wood however many sheets hang from it:
/// a branch reached across its hidden stretch through a leaf labelled wood leaves its fork as a sheet, and the
/// leaves on it can outweigh it (mono-58 behind the segmentation: a lateral's outer 2.7 m with its twigs, 48 % of
/// its subtree's points, went back with the 30,000 points of the leaf sheets on it, or stayed, on a few dozen labels elsewhere). The sheets
/// hanging from it are judged at their own forks.
void ReturnLeafSheets(
  const Wood& wood, std::vector<Node>& nodes, std::vector<int>& nodeOf, std::vector<unsigned char>& fitted)
{
  std::vector<double> sheet(nodes.size(), 0.0), all(nodes.size(), 0.0);
  std::vector<unsigned char> flat(nodes.size(), 0);
  for (std::size_t k = 0; k < nodes.size(); ++k)
  {
    all[k] = static_cast<double>(nodes[k].points.size());
    flat[k] = IsSheet(wood, nodes[k], fitted) ? 1 : 0;
    sheet[k] = flat[k] ? all[k] : 0.0;
  }
  // Where a side chain leaves its fork: its first node with points enough to tell a sheet from a tube. A twig leaves
  // as a tube, whatever leaves (labelled wood) it carries further on; a blade strip hangs from its margin.
  const auto leavesAsSheet = [&](int c) {
    while (nodes[c].points.size() < static_cast<std::size_t>(SheetMinPoints) && nodes[c].children.size() == 1)
      c = nodes[c].children.front();
    return flat[c] != 0;
  };
  // Per node the run of tube nodes ending at it (bins; nodes too small to tell go on a run without adding to it),
  // then per subtree the longest run in it.
  std::vector<int> run(nodes.size(), 0);
  for (std::size_t k = 0; k < nodes.size(); ++k) // parents first: lower bins, lower ids
  {
    const int up = nodes[k].parent >= 0 ? run[nodes[k].parent] : 0;
    const bool small = nodes[k].points.size() < static_cast<std::size_t>(SheetMinPoints);
    run[k] = flat[k] ? 0 : (small ? up : up + 1);
  }
  for (std::size_t k = nodes.size(); k-- > 1;) // children have higher bins, hence higher ids
    if (nodes[k].parent >= 0)
    {
      sheet[nodes[k].parent] += sheet[k];
      all[nodes[k].parent] += all[k];
      run[nodes[k].parent] = std::max(run[nodes[k].parent], run[k]);
    }
  for (std::size_t k = 0; k < nodes.size(); ++k) // parents first; removed nodes have no children left
  {
    if (nodes[k].children.size() < 2)
      continue;
    std::vector<int> keep;
    for (int c : nodes[k].children)
    {
      if (!(sheet[c] >= SheetShare * all[c]) || run[c] >= TubeBins || !leavesAsSheet(c))
      {
        keep.push_back(c);
        continue;
      }
      CutSubtree(nodes, c, -1, nodeOf, fitted);
    }
    nodes[k].children = keep;
  }
}

/// Side chains shorter than MinSideBins bins are cut off at their fork: their points go to the fork node, unfitted.
void Prune(std::vector<Node>& nodes, std::vector<int>& nodeOf, std::vector<unsigned char>& fitted)
{
  std::vector<int> reach(nodes.size(), 1);
  for (std::size_t k = nodes.size(); k-- > 1;) // children have higher bins, hence higher ids
    if (nodes[k].parent >= 0)
      reach[nodes[k].parent] = std::max(reach[nodes[k].parent], reach[k] + nodes[k].bin - nodes[nodes[k].parent].bin);
  for (std::size_t k = 0; k < nodes.size(); ++k)
  {
    Node& node = nodes[k];
    if (node.children.size() < 2)
      continue;
    int longest = node.children.front();
    for (int c : node.children)
      if (reach[c] > reach[longest])
        longest = c;
    std::vector<int> keep;
    for (int c : node.children)
    {
      if (c == longest || reach[c] >= MinSideBins)
      {
        keep.push_back(c);
        continue;
      }
      CutSubtree(nodes, c, static_cast<int>(k), nodeOf, fitted);
    }
    node.children = keep;
  }
}
} // namespace

Skeleton BuildSkeleton(const Wood& wood)
{
  Skeleton s;
  s.binWidth = BinSpacings * wood.spacing;
  s.nodes = BinComponents(wood, s.binWidth, s.nodeOf);
  LinkNodes(wood, s.nodeOf, s.nodes);
  MergeSideBySide(wood, s.nodes, s.nodeOf);
  s.fitted.assign(wood.points.size(), 1);
  ReturnLeafSheets(wood, s.nodes, s.nodeOf, s.fitted);
  Prune(s.nodes, s.nodeOf, s.fitted);
  Segments(wood, s);
  return s;
}

void Segments(const Wood& wood, Skeleton& s)
{
  for (Node& node : s.nodes)
  {
    node.centroid.setZero();
    int count = 0;
    for (int i : node.points)
      if (s.fitted[i])
      {
        node.centroid += wood.points[i];
        ++count;
      }
    if (count > 0)
      node.centroid /= count;
  }
  // Segments: chains between forks, depth first from the base.
  s.segments.clear();
  s.segmentParent.clear();
  std::vector<std::pair<int, int>> stack{ { 0, -1 } }; // (first node, parent segment)
  while (!stack.empty())
  {
    auto [first, parent] = stack.back();
    stack.pop_back();
    std::vector<int> chain{ first };
    while (s.nodes[chain.back()].children.size() == 1)
      chain.push_back(s.nodes[chain.back()].children.front());
    const int id = static_cast<int>(s.segments.size());
    s.segments.push_back(chain);
    s.segmentParent.push_back(parent);
    const auto& children = s.nodes[chain.back()].children;
    for (auto c = children.rbegin(); c != children.rend(); ++c)
      stack.emplace_back(*c, id);
  }
}

} // namespace treefit
} // namespace plantmorph
