// SPDX-License-Identifier: GPL-3.0-or-later
// Step 3 of the tree fit (TreeFit.h): level sets of the geodesic distance, their connected components as nodes, the
// node tree, pruning of short side chains, segments.
#include "TreeFitInternal.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr double BinSpacings = 6.0;
constexpr int MinSideBins = 3;

int FindRoot(std::vector<int>& up, int a)
{
  while (up[a] != a)
    a = up[a] = up[up[a]];
  return a;
}

/// The nodes: connected components (graph edges inside a bin) of every bin, numbered by (bin, lowest point id); all
/// of bin 0 is one node, the base.
std::vector<Node> BinComponents(const Wood& wood, double width, std::vector<int>& nodeOf)
{
  const std::size_t n = wood.points.size();
  std::vector<int> bin(n);
  for (std::size_t i = 0; i < n; ++i)
    bin[i] = static_cast<int>(std::floor(wood.geodesic[i] / width));
  std::vector<int> up(n);
  std::iota(up.begin(), up.end(), 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int e = wood.graph.offset[i]; e < wood.graph.offset[i + 1]; ++e)
    {
      const int j = wood.graph.target[e];
      if (bin[j] == bin[i] || (bin[i] == 0 && bin[j] == 0))
      {
        const int a = FindRoot(up, static_cast<int>(i)), b = FindRoot(up, j);
        if (a != b)
          up[std::max(a, b)] = std::min(a, b);
      }
    }
  int base = -1;
  for (std::size_t i = 0; i < n; ++i)
    if (bin[i] == 0)
    {
      const int r = FindRoot(up, static_cast<int>(i));
      if (base < 0)
        base = r;
      else
        up[std::max(r, base)] = std::min(r, base), base = std::min(r, base);
    }
  std::map<std::pair<int, int>, int> key; // (bin, root) -> node; roots are lowest ids, so the order is (bin, id)
  for (std::size_t i = 0; i < n; ++i)
    key.emplace(std::make_pair(bin[i], FindRoot(up, static_cast<int>(i))), 0);
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
    nodeOf[i] = key[{ bin[i], FindRoot(up, static_cast<int>(i)) }];
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

/// Side chains shorter than MinSideBins bins are cut off at their fork: their points go to the fork node, unfitted.
void Prune(std::vector<Node>& nodes, std::vector<int>& nodeOf, std::vector<unsigned char>& fitted)
{
  std::vector<int> reach(nodes.size(), 1);
  for (std::size_t k = nodes.size(); k-- > 1;) // children have higher bins, hence higher ids
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
      std::vector<int> cut;
      Subtree(nodes, c, cut);
      for (int m : cut)
      {
        for (int i : nodes[m].points)
        {
          nodeOf[i] = static_cast<int>(k);
          fitted[i] = 0;
          node.points.push_back(i);
        }
        nodes[m].points.clear();
        nodes[m].children.clear();
        nodes[m].parent = -2; // removed
      }
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
  s.fitted.assign(wood.points.size(), 1);
  Prune(s.nodes, s.nodeOf, s.fitted);
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
  return s;
}

} // namespace treefit
} // namespace plantmorph
