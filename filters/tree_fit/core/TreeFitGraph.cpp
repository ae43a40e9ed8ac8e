// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 1-3 of the tree fit (TreeFit.h): spacing, outliers, the neighbour graph, joining its components across
// occlusion gaps, geodesic distances from the base.
#include "PointGrid.h"
#include "TreeFitInternal.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <sstream>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr int SpacingNeighbours = 6;
constexpr int GraphNeighbours = 10;
constexpr double GraphReach = 8.0; // spacings
constexpr double GapReach = 25.0;  // spacings
constexpr int MinComponent = 5;    // points

double Median(std::vector<double> values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

/// Mean distance of every point to its k nearest neighbours (infinite when it has none).
std::vector<double> MeanNeighbourDistance(
  const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, int k, const ParallelFor& parallel)
{
  std::vector<double> mean(points.size(), std::numeric_limits<double>::infinity());
  const std::vector<int>& order = grid.SortedIds();
  parallel(order.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j)
    {
      const int i = order[j];
      const auto near = grid.Nearest(points[i], k, i);
      if (near.empty())
        continue;
      double sum = 0;
      for (const auto& n : near)
        sum += std::sqrt(n.first);
      mean[i] = sum / static_cast<double>(near.size());
    }
  });
  return mean;
}

struct UnionFind
{
  std::vector<int> up;
  explicit UnionFind(std::size_t n)
    : up(n)
  {
    std::iota(up.begin(), up.end(), 0);
  }
  int Find(int a)
  {
    while (up[a] != a)
      a = up[a] = up[up[a]];
    return a;
  }
  void Join(int a, int b)
  {
    a = Find(a);
    b = Find(b);
    if (a != b)
      up[std::max(a, b)] = std::min(a, b);
  }
};

/// Not a line, not a plane: the smallest principal extent must be a fair share of the middle one.
std::string CheckShape(const std::vector<Eigen::Vector3d>& points, double spacing)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points)
    cov += (p - mean) * (p - mean).transpose();
  cov /= static_cast<double>(points.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d sd = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt(); // ascending
  if (!(sd[2] > 0.0))
    return "the points are all at one place";
  if (sd[1] < 1e-3 * sd[2] || sd[1] < 2.0 * spacing)
    return "the points lie on a line (no tree: a tree has a cross-section)";
  if (sd[0] < 1e-3 * sd[2] || sd[0] < 2.0 * spacing)
    return "the points lie in a plane (no tree: a tree has extent in three directions)";
  return {};
}

/// The graph: each point linked to its GraphNeighbours nearest within GraphReach spacings (symmetrised).
Graph NeighbourGraph(const std::vector<Eigen::Vector3d>& points, double spacing, const ParallelFor& parallel)
{
  PointGrid grid(points, 2.0 * spacing);
  std::vector<std::vector<std::pair<double, int>>> near(points.size());
  parallel(points.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      near[i] = grid.Nearest(points[i], GraphNeighbours, static_cast<int>(i), GraphReach * spacing);
  });
  std::vector<std::vector<std::pair<int, double>>> adjacency(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (const auto& n : near[i])
    {
      const double d = std::sqrt(n.first);
      adjacency[i].emplace_back(n.second, d);
      adjacency[static_cast<std::size_t>(n.second)].emplace_back(static_cast<int>(i), d);
    }
  Graph graph;
  graph.offset.assign(points.size() + 1, 0);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    auto& a = adjacency[i];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end(), [](const auto& x, const auto& y) { return x.first == y.first; }), a.end());
    graph.offset[i + 1] = graph.offset[i] + static_cast<int>(a.size());
    for (const auto& [j, d] : a)
    {
      graph.target.push_back(j);
      graph.weight.push_back(d);
    }
  }
  return graph;
}

/// Joins the graph's components to the one holding the lowest point across gaps up to GapReach spacings, nearest gaps
/// first (passes until none joins); returns, per point, whether it is in the joined tree. Bridges are added as edges.
std::vector<unsigned char> JoinComponents(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
  double spacing, const ParallelFor& parallel, Graph& graph)
{
  const std::size_t n = points.size();
  UnionFind sets(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int e = graph.offset[i]; e < graph.offset[i + 1]; ++e)
      sets.Join(static_cast<int>(i), graph.target[e]);
  std::vector<int> root(n);
  for (std::size_t i = 0; i < n; ++i)
    root[i] = sets.Find(static_cast<int>(i));
  // The base component: the largest among those reaching within a few spacings of the lowest point.
  std::vector<int> size(n, 0);
  for (int r : root)
    ++size[r];
  std::size_t lowest = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (points[i].dot(up) < points[lowest].dot(up))
      lowest = i;
  int base = root[lowest];
  const double low = points[lowest].dot(up);
  for (std::size_t i = 0; i < n; ++i)
    if (points[i].dot(up) < low + 10.0 * spacing && size[root[i]] > size[base])
      base = root[i];
  std::vector<unsigned char> in(n, 0);
  std::vector<std::pair<int, int>> bridges;
  for (int pass = 0; pass < 64; ++pass)
  {
    std::vector<Eigen::Vector3d> attached;
    std::vector<int> attachedId;
    for (std::size_t i = 0; i < n; ++i)
      if (root[i] == base || in[i])
      {
        in[i] = 1;
        attached.push_back(points[i]);
        attachedId.push_back(static_cast<int>(i));
      }
    std::vector<int> candidates;
    for (std::size_t i = 0; i < n; ++i)
      if (!in[i] && size[root[i]] >= MinComponent)
        candidates.push_back(static_cast<int>(i));
    if (candidates.empty())
      break;
    PointGrid grid(attached, 2.0 * spacing);
    std::vector<std::pair<double, int>> best(candidates.size(), { std::numeric_limits<double>::infinity(), -1 });
    parallel(candidates.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t c = b; c < e; ++c)
      {
        const auto near = grid.Nearest(points[candidates[c]], 1, -1, GapReach * spacing);
        if (!near.empty())
          best[c] = { near[0].first, attachedId[near[0].second] };
      }
    });
    // Per component, its shortest bridge.
    std::vector<std::pair<double, std::pair<int, int>>> link(
      n, { std::numeric_limits<double>::infinity(), { -1, -1 } });
    for (std::size_t c = 0; c < candidates.size(); ++c)
    {
      const int r = root[candidates[c]];
      if (best[c].second >= 0 && best[c].first < link[r].first)
        link[r] = { best[c].first, { candidates[c], best[c].second } };
    }
    bool joined = false;
    std::vector<unsigned char> joinRoot(n, 0);
    for (std::size_t r = 0; r < n; ++r)
      if (link[r].second.first >= 0)
      {
        bridges.push_back(link[r].second);
        joinRoot[r] = 1;
        joined = true;
      }
    if (!joined)
      break;
    for (std::size_t i = 0; i < n; ++i)
      if (joinRoot[root[i]])
        in[i] = 1;
  }
  if (!bridges.empty())
  {
    std::vector<std::vector<std::pair<int, double>>> extra(n);
    for (const auto& [a, b] : bridges)
    {
      const double d = (points[a] - points[b]).norm();
      extra[a].emplace_back(b, d);
      extra[b].emplace_back(a, d);
    }
    Graph joinedGraph;
    joinedGraph.offset.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      for (int e = graph.offset[i]; e < graph.offset[i + 1]; ++e)
      {
        joinedGraph.target.push_back(graph.target[e]);
        joinedGraph.weight.push_back(graph.weight[e]);
      }
      for (const auto& [j, d] : extra[i])
      {
        joinedGraph.target.push_back(j);
        joinedGraph.weight.push_back(d);
      }
      joinedGraph.offset[i + 1] = static_cast<int>(joinedGraph.target.size());
    }
    graph = std::move(joinedGraph);
  }
  return in;
}

/// The subgraph on the points with keep[i] (renumbered by `index`: old id -> new id or -1).
Graph Subgraph(const Graph& graph, const std::vector<int>& kept, const std::vector<int>& index)
{
  Graph sub;
  sub.offset.assign(kept.size() + 1, 0);
  for (std::size_t k = 0; k < kept.size(); ++k)
  {
    const int i = kept[k];
    for (int e = graph.offset[i]; e < graph.offset[i + 1]; ++e)
      if (index[graph.target[e]] >= 0)
      {
        sub.target.push_back(index[graph.target[e]]);
        sub.weight.push_back(graph.weight[e]);
      }
    sub.offset[k + 1] = static_cast<int>(sub.target.size());
  }
  return sub;
}

/// Dijkstra from every point within `band` of the lowest one (ties broken by point id: deterministic).
void Geodesic(const std::vector<Eigen::Vector3d>& points, const Graph& graph, const Eigen::Vector3d& up, double band,
  std::vector<double>& distance, std::vector<int>& previous)
{
  const std::size_t n = points.size();
  distance.assign(n, std::numeric_limits<double>::infinity());
  previous.assign(n, -1);
  double low = std::numeric_limits<double>::infinity();
  for (const auto& p : points)
    low = std::min(low, p.dot(up));
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (std::size_t i = 0; i < n; ++i)
    if (points[i].dot(up) <= low + band)
    {
      distance[i] = 0.0;
      queue.emplace(0.0, static_cast<int>(i));
    }
  while (!queue.empty())
  {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > distance[i])
      continue;
    for (int e = graph.offset[i]; e < graph.offset[i + 1]; ++e)
    {
      const int j = graph.target[e];
      const double nd = d + graph.weight[e];
      if (nd < distance[j])
      {
        distance[j] = nd;
        previous[j] = i;
        queue.emplace(nd, j);
      }
    }
  }
}
} // namespace

double PointSpacing(const std::vector<Eigen::Vector3d>& points, const ParallelFor& parallel)
{
  PointGrid grid(points, PointGrid::CellFor(points, 4.0));
  return Median(MeanNeighbourDistance(points, grid, SpacingNeighbours, parallel));
}

std::string CleanAndConnect(const std::vector<Eigen::Vector3d>& all, const std::vector<int>& candidates,
  const TreeFitParameters& options, const ParallelFor& parallel, Wood& wood)
{
  std::vector<Eigen::Vector3d> points;
  points.reserve(candidates.size());
  for (int i : candidates)
    points.push_back(all[i]);
  PointGrid grid(points, PointGrid::CellFor(points, 4.0));
  const std::vector<double> mean = MeanNeighbourDistance(points, grid, SpacingNeighbours, parallel);
  const double spacing = Median(mean);
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    return "the points have no spacing (all at one place?)";
  if (std::string shape = CheckShape(points, spacing); !shape.empty())
    return shape;
  // Outliers on a log scale of the mean neighbour distance.
  std::vector<double> logs;
  for (double m : mean)
    if (std::isfinite(m) && m > 0.0)
      logs.push_back(std::log(m));
  const double centre = Median(logs);
  std::vector<double> deviation;
  for (double l : logs)
    deviation.push_back(std::abs(l - centre));
  const double mad = std::max(1.4826 * Median(deviation), 0.05);
  std::vector<int> inliers;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(mean[i]) && mean[i] > 0.0 && std::log(mean[i]) <= centre + options.outlierSigma * mad)
      inliers.push_back(static_cast<int>(i));
  std::vector<Eigen::Vector3d> clean;
  for (int i : inliers)
    clean.push_back(points[i]);
  Graph graph = NeighbourGraph(clean, spacing, parallel);
  const std::vector<unsigned char> in = JoinComponents(clean, options.up, spacing, parallel, graph);
  std::vector<int> kept, index(clean.size(), -1);
  for (std::size_t i = 0; i < clean.size(); ++i)
    if (in[i])
    {
      index[i] = static_cast<int>(kept.size());
      kept.push_back(static_cast<int>(i));
    }
  if (kept.size() < static_cast<std::size_t>(MinTreePoints))
  {
    std::ostringstream message;
    message << "only " << kept.size() << " points are connected to the base (at least " << MinTreePoints << " needed)";
    return message.str();
  }
  wood.spacing = spacing;
  wood.graph = Subgraph(graph, kept, index);
  for (int k : kept)
  {
    wood.points.push_back(clean[k]);
    wood.input.push_back(candidates[inliers[k]]);
  }
  Geodesic(wood.points, wood.graph, options.up, 6.0 * spacing, wood.geodesic, wood.previous);
  return {};
}

} // namespace treefit
} // namespace plantmorph
