// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 1-3 of the tree fit (TreeFit.h): spacing, outliers, the neighbour graph, joining its components across
// occlusion gaps, geodesic distances from the base.
#include "PointGrid.h"
#include "TreeFitInternal.h"

#include <plantmorph/graph/DisjointSets.h>
#include <plantmorph/statistics/Median.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <tuple>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr int SpacingNeighbours = 6;
constexpr int GraphNeighbours = 10;
constexpr double GraphReach = 8.0;       // spacings
constexpr double GapReach = 25.0;        // spacings
constexpr int MinComponent = 5;          // points
constexpr double ShortcutReach = 4.0;    // spacings: a gap the nearest-neighbour graph leaves between two surfaces...
constexpr double ShortcutSaving = 50.0;  // ...is bridged when the shortest path round it is this many spacings longer
constexpr double FacingReach = GapReach; // spacings: a wider gap between two chain ends facing each other...
constexpr double FacingCosine = 0.7071;  // ...within 45 degrees each (their directions over FlowLength spacings)
constexpr double FlowLength = 10.0;      // spacings
constexpr double LineReach = 8.0;        // a sparse point's own spacings: the ball its line is judged in...
constexpr int LinePoints = 8;            // ...holding at least this many sparse points...
constexpr double LineSpread = 0.3;       // ...across its main direction at most this share of the spread along it
constexpr double LineLength = 12.0;      // own spacings: a sparse line at least this long is a far branch

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

/// The graph: each point linked to its GraphNeighbours nearest within GraphReach spacings (symmetrised), searched in
/// a grid of cells 3 spacings wide (2 made the search visit more empty cells: 20 % slower on 10^6 points). The
/// queries run in the grid's cell order (on 10^6 points, queries in the points' order were cache misses, and the
/// cost per point grew with the cloud); the rows are built in flat arrays, each sorted by neighbour on its own
/// (in parallel: a row's content does not depend on the threads).
Graph NeighbourGraph(const std::vector<Eigen::Vector3d>& points, double spacing, const ParallelFor& parallel)
{
  const std::size_t n = points.size();
  constexpr std::size_t K = GraphNeighbours;
  PointGrid grid(points, 4.0 * spacing);
  const std::vector<int>& order = grid.SortedIds();
  std::vector<int> nearId(n * K, -1);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t o = begin; o < end; ++o)
    {
      const auto i = static_cast<std::size_t>(order[o]);
      const auto near = grid.Nearest(points[i], GraphNeighbours, static_cast<int>(i), GraphReach * spacing);
      for (std::size_t t = 0; t < near.size(); ++t)
        nearId[i * K + t] = near[t].second;
    }
  });
  // Both directions of every link, row by row, counted and scattered in parallel: a row's links arrive in any order,
  // and are sorted below, so the graph does not depend on the threads.
  std::vector<std::atomic<int>> fill(n);
  for (auto& f : fill)
    f.store(0, std::memory_order_relaxed);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t t = i * K; t < i * K + K && nearId[t] >= 0; ++t)
      {
        fill[i].fetch_add(1, std::memory_order_relaxed);
        fill[static_cast<std::size_t>(nearId[t])].fetch_add(1, std::memory_order_relaxed);
      }
  });
  std::vector<int> offset(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    offset[i + 1] = offset[i] + fill[i].load(std::memory_order_relaxed);
    fill[i].store(offset[i], std::memory_order_relaxed);
  }
  std::vector<int> links(static_cast<std::size_t>(offset[n]));
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t t = i * K; t < i * K + K && nearId[t] >= 0; ++t)
      {
        const int j = nearId[t];
        links[static_cast<std::size_t>(fill[i].fetch_add(1, std::memory_order_relaxed))] = j;
        links[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)].fetch_add(1, std::memory_order_relaxed))] =
          static_cast<int>(i);
      }
  });
  // Each row sorted, a neighbour kept once; its length the points' distance (as the search measured it).
  std::vector<int> size(n, 0);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto first = links.begin() + offset[i], last = links.begin() + offset[i + 1];
      std::sort(first, last);
      size[i] = static_cast<int>(std::unique(first, last) - first);
    }
  });
  Graph graph;
  graph.offset.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    graph.offset[i + 1] = graph.offset[i] + size[i];
  graph.target.resize(static_cast<std::size_t>(graph.offset[n]));
  graph.weight.resize(graph.target.size());
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (int e = 0; e < size[i]; ++e)
      {
        const int j = links[static_cast<std::size_t>(offset[i] + e)];
        graph.target[static_cast<std::size_t>(graph.offset[i] + e)] = j;
        graph.weight[static_cast<std::size_t>(graph.offset[i] + e)] =
          std::sqrt((points[static_cast<std::size_t>(j)] - points[i]).squaredNorm());
      }
  });
  return graph;
}

/// The graph with extra links (per point: (neighbour, length), both directions listed), each row's own links first;
/// the rows placed first, then filled (no growing arrays).
Graph WithLinks(const Graph& graph, const std::vector<std::vector<std::pair<int, double>>>& extra)
{
  const std::size_t n = extra.size();
  Graph linked;
  linked.offset.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    linked.offset[i + 1] =
      linked.offset[i] + (graph.offset[i + 1] - graph.offset[i]) + static_cast<int>(extra[i].size());
  linked.target.resize(static_cast<std::size_t>(linked.offset[n]));
  linked.weight.resize(linked.target.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    auto e = static_cast<std::size_t>(linked.offset[i]);
    std::copy(graph.target.begin() + graph.offset[i], graph.target.begin() + graph.offset[i + 1],
      linked.target.begin() + static_cast<std::ptrdiff_t>(e));
    std::copy(graph.weight.begin() + graph.offset[i], graph.weight.begin() + graph.offset[i + 1],
      linked.weight.begin() + static_cast<std::ptrdiff_t>(e));
    e += static_cast<std::size_t>(graph.offset[i + 1] - graph.offset[i]);
    for (const auto& [j, d] : extra[i])
    {
      linked.target[e] = j;
      linked.weight[e++] = d;
    }
  }
  return linked;
}

/// Joins the graph's components to the one holding the base across gaps up to GapReach spacings: candidate bridges
/// between components meeting in neighbouring voxels of that size (the closest pair of up to 16 points of each in the
/// two voxels), then Kruskal's shortest-first union. Returns, per point, whether it is in the joined tree; the bridges
/// used are added to the graph.
std::vector<unsigned char> JoinComponents(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
  double spacing, const ParallelFor& parallel, Graph& graph)
{
  const std::size_t n = points.size();
  DisjointSets<int> sets(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int e = graph.offset[i]; e < graph.offset[i + 1]; ++e)
      sets.Join(static_cast<int>(i), graph.target[e]);
  std::vector<int> root(n), size(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    ++size[root[i] = sets.Find(static_cast<int>(i))];
  // The base component: the largest among those reaching within a few spacings of the lowest point.
  std::size_t lowest = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (points[i].dot(up) < points[lowest].dot(up))
      lowest = i;
  int base = root[lowest];
  for (std::size_t i = 0; i < n; ++i)
    if (points[i].dot(up) < points[lowest].dot(up) + 10.0 * spacing && size[root[i]] > size[base])
      base = root[i];
  // Voxels of side GapReach spacings: (voxel key, component, point), sorted.
  const double cell = GapReach * spacing;
  auto key = [&](const Eigen::Vector3d& p, int dx, int dy, int dz) {
    const auto f = [&](double v, int d) { return static_cast<std::int64_t>(std::floor(v / cell)) + d + (1 << 20); };
    return (f(p.x(), dx) << 42) | (f(p.y(), dy) << 21) | f(p.z(), dz);
  };
  std::vector<std::tuple<std::int64_t, int, int>> cells;
  for (std::size_t i = 0; i < n; ++i)
    if (size[root[i]] >= MinComponent)
      cells.emplace_back(key(points[i], 0, 0, 0), root[i], static_cast<int>(i));
  std::sort(cells.begin(), cells.end());
  // Runs of one (voxel, component): [begin, end) in cells.
  std::vector<std::pair<int, int>> runs;
  for (std::size_t k = 0; k < cells.size();)
  {
    std::size_t e = k;
    while (e < cells.size() && std::get<0>(cells[e]) == std::get<0>(cells[k]) &&
      std::get<1>(cells[e]) == std::get<1>(cells[k]))
      ++e;
    runs.emplace_back(static_cast<int>(k), static_cast<int>(e));
    k = e;
  }
  auto runOf = [&](std::int64_t voxel) {
    return std::lower_bound(runs.begin(), runs.end(), voxel,
      [&](const std::pair<int, int>& r, std::int64_t v) { return std::get<0>(cells[r.first]) < v; });
  };
  std::vector<std::vector<std::tuple<double, int, int>>> found(runs.size());
  parallel(runs.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t r = b; r < e; ++r)
    {
      const auto [begin, end] = runs[r];
      const Eigen::Vector3d& p0 = points[std::get<2>(cells[begin])];
      const int component = std::get<1>(cells[begin]);
      const std::int64_t self = std::get<0>(cells[begin]);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
          {
            const std::int64_t voxel = key(p0, dx, dy, dz);
            if (voxel < self)
              continue; // each pair of voxels once
            for (auto it = runOf(voxel); it != runs.end() && std::get<0>(cells[it->first]) == voxel; ++it)
            {
              const int other = std::get<1>(cells[it->first]);
              if (other == component || (voxel == self && other < component))
                continue;
              std::tuple<double, int, int> best{ std::numeric_limits<double>::infinity(), -1, -1 };
              const int stepA = std::max(1, (end - begin) / 16), stepB = std::max(1, (it->second - it->first) / 16);
              for (int x = begin; x < end; x += stepA)
                for (int y = it->first; y < it->second; y += stepB)
                {
                  const int i = std::get<2>(cells[x]), j = std::get<2>(cells[y]);
                  best =
                    std::min(best, std::make_tuple((points[i] - points[j]).norm(), std::min(i, j), std::max(i, j)));
                }
              if (std::get<0>(best) <= cell)
                found[r].push_back(best);
            }
          }
    }
  });
  std::vector<std::tuple<double, int, int>> bridges;
  for (const auto& f : found)
    bridges.insert(bridges.end(), f.begin(), f.end());
  std::sort(bridges.begin(), bridges.end());
  DisjointSets<int> joined(n);
  std::vector<std::vector<std::pair<int, double>>> extra(n);
  bool any = false;
  for (const auto& [d, i, j] : bridges)
  {
    if (!joined.Join(root[i], root[j]))
      continue;
    extra[i].emplace_back(j, d);
    extra[j].emplace_back(i, d);
    any = true;
  }
  // Parts still apart whose own axis points back at the tree across a longer hidden stretch.
  std::vector<int> group(n, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (size[root[i]] >= MinComponent)
      group[i] = joined.Find(root[i]);
  for (const auto& [d, i, j] : BridgesAlongAxes(points, group, joined.Find(base), spacing))
  {
    joined.Join(root[i], root[j]);
    extra[i].emplace_back(j, d);
    extra[j].emplace_back(i, d);
    any = true;
  }
  std::vector<unsigned char> in(n, 0);
  const int baseSet = joined.Find(base);
  for (std::size_t i = 0; i < n; ++i)
    in[i] = size[root[i]] >= MinComponent && joined.Find(root[i]) == baseSet ? 1 : 0;
  if (any)
    graph = WithLinks(graph, extra);
  return in;
}

/// The subgraph on the points `kept` (renumbered by `index`: old id -> new id or -1); rows counted and filled in
/// parallel (each row its own: the same graph on any number of threads).
Graph Subgraph(
  const Graph& graph, const std::vector<int>& kept, const std::vector<int>& index, const ParallelFor& parallel)
{
  Graph sub;
  sub.offset.assign(kept.size() + 1, 0);
  parallel(kept.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      for (int e = graph.offset[kept[k]]; e < graph.offset[kept[k] + 1]; ++e)
        sub.offset[k + 1] += index[graph.target[e]] >= 0 ? 1 : 0;
  });
  for (std::size_t k = 0; k < kept.size(); ++k)
    sub.offset[k + 1] += sub.offset[k];
  sub.target.resize(static_cast<std::size_t>(sub.offset[kept.size()]));
  sub.weight.resize(sub.target.size());
  parallel(kept.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
    {
      auto at = static_cast<std::size_t>(sub.offset[k]);
      for (int e = graph.offset[kept[k]]; e < graph.offset[kept[k] + 1]; ++e)
        if (index[graph.target[e]] >= 0)
        {
          sub.target[at] = index[graph.target[e]];
          sub.weight[at++] = graph.weight[e];
        }
    }
  });
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

/// Whether every neighbour of point i is nearer the base: the far end of a chain of shortest paths.
bool ChainEnd(const Wood& wood, const Graph& graph, std::size_t i)
{
  const double g = wood.geodesic[i];
  bool end = std::isfinite(g);
  for (int e = graph.offset[i]; e < graph.offset[i + 1] && end; ++e)
    end = wood.geodesic[graph.target[e]] <= g;
  return end;
}

/// The unit direction in which the shortest paths arrive at point i: from the point FlowLength spacings back along
/// its path (zero when the path is shorter than a spacing).
Eigen::Vector3d ArrivalDirection(const Wood& wood, int i)
{
  int k = i;
  while (wood.previous[k] >= 0 && wood.geodesic[i] - wood.geodesic[k] < FlowLength * wood.spacing)
    k = wood.previous[k];
  const Eigen::Vector3d d = wood.points[i] - wood.points[k];
  return d.norm() > wood.spacing ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
}

/// Shortcuts across the gaps the neighbour graph leaves inside a component: the 10 nearest neighbours of a point on a
/// densely scanned surface all lie on that surface, so two surfaces a few spacings apart (a branch's base and the
/// leader's tip it leaves, where leaves hid the junction) are not linked; when the two are joined elsewhere (the
/// branch's far end touching another branch's twigs), the shortest paths reach the branch from its tip and the
/// skeleton runs down it backwards, a branch of the wrong order at an angle over 90 degrees. At every chain end (a
/// local maximum of the geodesic distance), a point within ShortcutReach spacings whose path plus the gap is
/// ShortcutSaving spacings shorter is linked to it. A wider gap, up to FacingReach spacings (a stretch of a branch
/// whose wood was hidden by leaves or labelled leaf), is bridged the same way only between two chain ends whose
/// paths arrive facing each other: the branch's part beyond the gap, reached backwards from elsewhere, ends at the
/// gap pointing back at the part before it, which ends there pointing on; a chain end beside another branch is not
/// joined to it. Returns whether any link was added.
bool AddShortcuts(const Wood& wood, const ParallelFor& parallel, Graph& graph)
{
  const std::size_t n = wood.points.size();
  const double reach = ShortcutReach * wood.spacing, saving = ShortcutSaving * wood.spacing;
  const double facingReach = FacingReach * wood.spacing;
  std::vector<unsigned char> end(n, 0);
  std::vector<Eigen::Vector3d> arrival(n, Eigen::Vector3d::Zero());
  parallel(n, [&](std::size_t begin, std::size_t stop) {
    for (std::size_t i = begin; i < stop; ++i)
      if ((end[i] = ChainEnd(wood, graph, i)))
        arrival[i] = ArrivalDirection(wood, static_cast<int>(i));
  });
  std::vector<int> ends;
  std::vector<Eigen::Vector3d> endPoints;
  for (std::size_t i = 0; i < n; ++i)
    if (end[i])
    {
      ends.push_back(static_cast<int>(i));
      endPoints.push_back(wood.points[i]);
    }
  if (ends.empty())
    return false;
  const PointGrid grid(wood.points, reach), endGrid(endPoints, facingReach);
  std::vector<std::pair<int, double>> link(n, { -1, 0.0 });
  parallel(ends.size(), [&](std::size_t begin, std::size_t stop) {
    std::vector<int> near;
    for (std::size_t k = begin; k < stop; ++k)
    {
      const int i = ends[k];
      double best = wood.geodesic[i] - saving;
      const auto consider = [&](int j, bool facingOnly) {
        const Eigen::Vector3d gap = wood.points[j] - wood.points[i];
        const double d = gap.norm();
        if (facingOnly &&
          (d <= reach || gap.dot(arrival[i]) < FacingCosine * d || -gap.dot(arrival[j]) < FacingCosine * d))
          return;
        if (wood.geodesic[j] + d < best)
        {
          best = wood.geodesic[j] + d;
          link[i] = { j, d };
        }
      };
      near.clear();
      grid.Within(wood.points[i], reach, near);
      for (int j : near)
        consider(j, false);
      near.clear();
      endGrid.Within(wood.points[i], facingReach, near);
      for (int e : near)
        consider(ends[e], true);
    }
  });
  if (std::none_of(link.begin(), link.end(), [](const auto& l) { return l.first >= 0; }))
    return false;
  std::vector<std::vector<std::pair<int, double>>> extra(n);
  for (std::size_t i = 0; i < n; ++i)
    if (link[i].first >= 0)
    {
      extra[i].push_back(link[i]);
      extra[static_cast<std::size_t>(link[i].first)].emplace_back(static_cast<int>(i), link[i].second);
    }
  graph = WithLinks(graph, extra);
  return true;
}

/// The sparse points (`pool`, each with its mean neighbour distance `spread`) that make far branches:
/// a branch scanned from farther than the rest (a scanner's spacing grows with range) is sparser than the cloud's
/// outlier threshold along its whole length, but its points lie along a line, the density of that line changing only
/// as slowly as the range does; a stray return lies among no such line, leaves lie in sheets turned every way. A
/// point is on a line when the pool's points within LineReach of its own spacings (at least LinePoints of them) spread
/// across their main direction at most LineSpread of their spread along it, and its log spacing lies within
/// `sigma` robust deviations (`mad`) of their median. Points on a line linked within that reach are one line; a line
/// at least LineLength of its points' median spacings long is kept whole. Returns per pool point whether it is kept.
std::vector<unsigned char> SparseLines(const std::vector<Eigen::Vector3d>& pool, const std::vector<double>& spread,
  double sigma, double mad, const ParallelFor& parallel)
{
  const std::size_t n = pool.size();
  std::vector<unsigned char> keep(n, 0);
  if (n < static_cast<std::size_t>(LinePoints))
    return keep;
  std::vector<double> reach(n);
  for (std::size_t i = 0; i < n; ++i)
    reach[i] = LineReach * spread[i];
  const PointGrid grid(pool, LineReach * Median(spread));
  std::vector<unsigned char> line(n, 0);
  std::vector<std::vector<int>> near(n);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::vector<int>& ball = near[i];
      grid.Within(pool[i], reach[i], ball);
      if (ball.size() < static_cast<std::size_t>(LinePoints))
        continue;
      std::vector<double> logs;
      for (int j : ball)
        logs.push_back(std::log(spread[j]));
      const Eigen::Vector3d l = AxesOf(pool, ball).solver.eigenvalues().cwiseMax(0.0);
      line[i] = std::sqrt(l[1]) <= LineSpread * std::sqrt(l[2]) &&
          std::abs(std::log(spread[i]) - Median(std::move(logs))) <= sigma * mad
        ? 1
        : 0;
    }
  });
  DisjointSets<int> sets(n);
  for (std::size_t i = 0; i < n; ++i)
    if (line[i])
      for (int j : near[i])
        if (line[j])
          sets.Join(static_cast<int>(i), j);
  // Per line: its points, its extent along its main direction against its median spacing.
  std::vector<std::vector<int>> members(n);
  for (std::size_t i = 0; i < n; ++i)
    if (line[i])
      members[sets.Find(static_cast<int>(i))].push_back(static_cast<int>(i));
  for (const std::vector<int>& m : members)
  {
    if (m.size() < static_cast<std::size_t>(LinePoints))
      continue;
    std::vector<double> spacings;
    for (int i : m)
      spacings.push_back(spread[i]);
    const PointAxes axes = AxesOf(pool, m);
    const Eigen::Vector3d& mean = axes.mean;
    const Eigen::Vector3d axis = axes.solver.eigenvectors().col(2);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i : m)
    {
      lo = std::min(lo, (pool[i] - mean).dot(axis));
      hi = std::max(hi, (pool[i] - mean).dot(axis));
    }
    if (hi - lo >= LineLength * Median(std::move(spacings)))
      for (int i : m)
        keep[i] = 1;
  }
  return keep;
}
} // namespace

PointAxes AxesOf(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
{
  PointAxes axes;
  for (int j : ids)
    axes.mean += points[j];
  axes.mean /= static_cast<double>(ids.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int j : ids)
    scatter += (points[j] - axes.mean) * (points[j] - axes.mean).transpose();
  axes.solver.compute(scatter);
  return axes;
}

double PointSpacing(const std::vector<Eigen::Vector3d>& points, const ParallelFor& parallel)
{
  PointGrid grid(points, PointGrid::CellFor(points, 4.0));
  return Median(MeanNeighbourDistance(points, grid, SpacingNeighbours, parallel));
}

std::string CleanAndConnect(const std::vector<Eigen::Vector3d>& all, std::vector<int>& candidates,
  const std::vector<int>& others, const TreeFitParameters& options, const ParallelFor& parallel, Wood& wood)
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
  const double mad = std::max(RobustScale(logs, centre), 0.05);
  const double threshold = centre + options.outlierSigma * mad;
  std::vector<int> inliers;
  std::vector<Eigen::Vector3d> clean;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(mean[i]) && mean[i] > 0.0 && std::log(mean[i]) <= threshold)
      inliers.push_back(static_cast<int>(i));
  std::vector<int> source; // per clean point: its id in `all`
  for (int i : inliers)
  {
    clean.push_back(points[i]);
    source.push_back(candidates[static_cast<std::size_t>(i)]);
  }
  // The sparse lines (far branches) among the outliers and among the `others` as sparse, each point's spacing taken
  // among every point (as the scanner left them: a far branch the labels share between wood and leaf is one line):
  // kept, the others' as candidates too.
  // Without others (a scan without labels) every point is a candidate: no copy of them.
  std::vector<Eigen::Vector3d> withOthers;
  std::vector<double> withOthersMean;
  if (!others.empty())
  {
    withOthers = points;
    for (int i : others)
      withOthers.push_back(all[i]);
    const PointGrid everyGrid(withOthers, PointGrid::CellFor(withOthers, 4.0));
    withOthersMean = MeanNeighbourDistance(withOthers, everyGrid, SpacingNeighbours, parallel);
  }
  const std::vector<Eigen::Vector3d>& every = others.empty() ? points : withOthers;
  const std::vector<double>& everyMean = others.empty() ? mean : withOthersMean;
  std::vector<int> pool; // ids into every
  std::vector<Eigen::Vector3d> poolPoints;
  std::vector<double> poolSpread;
  for (std::size_t i = 0; i < every.size(); ++i)
  {
    const double m = i < points.size() ? mean[i] : everyMean[i];
    if (std::isfinite(m) && m > 0.0 && std::log(m) > threshold && std::isfinite(everyMean[i]) && everyMean[i] > 0.0)
    {
      pool.push_back(static_cast<int>(i));
      poolPoints.push_back(every[i]);
      poolSpread.push_back(everyMean[i]);
    }
  }
  const std::vector<unsigned char> far = SparseLines(poolPoints, poolSpread, options.outlierSigma, mad, parallel);
  std::vector<unsigned char> other(clean.size(), 0); // per clean point: one of the others
  for (std::size_t k = 0; k < pool.size(); ++k)
    if (far[k])
    {
      const auto p = static_cast<std::size_t>(pool[k]);
      clean.push_back(poolPoints[k]);
      source.push_back(p < points.size() ? candidates[p] : others[p - points.size()]);
      other.push_back(p < points.size() ? 0 : 1);
    }
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
  wood.graph = Subgraph(graph, kept, index, parallel);
  for (int k : kept)
  {
    wood.points.push_back(clean[k]);
    wood.input.push_back(source[k]);
    if (other[k])
      candidates.push_back(source[k]);
  }
  std::sort(candidates.begin(), candidates.end());
  Geodesic(wood.points, wood.graph, options.up, 6.0 * spacing, wood.geodesic, wood.previous);
  if (AddShortcuts(wood, parallel, wood.graph))
    Geodesic(wood.points, wood.graph, options.up, 6.0 * spacing, wood.geodesic, wood.previous);
  return {};
}

} // namespace treefit
} // namespace plantmorph
