// SPDX-License-Identifier: GPL-3.0-or-later
#include "VeinNetworkMeasures.h"

#include <plantmorph/graph/DisjointSets.h>

#include "VeinGraph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace plantmorph
{
namespace
{
struct Segment
{
  int a, b, order;
  double length, width;
};

double DistanceToPolygon(const Eigen::Vector2d& x, const std::vector<Eigen::Vector2d>& polygon)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const Eigen::Vector2d a = polygon[i], d = polygon[(i + 1) % polygon.size()] - a;
    const double t = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (a + t * d - x).norm());
  }
  return best;
}

void MeasureAreoles(const VenationResult& veins, const std::vector<Segment>& segments, VeinNetworkMeasures& m)
{
  if (veins.nodes.empty())
    return;
  Eigen::Vector2d low = veins.nodes.front(), high = low;
  for (const Eigen::Vector2d& x : veins.nodes)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const double pad = 1e-6 * std::max(1.0, (high - low).maxCoeff());
  const double cell =
    std::max((high - low).maxCoeff() / std::max(1.0, std::sqrt(static_cast<double>(segments.size()))), pad);
  VeinGraph graph(low - Eigen::Vector2d::Constant(pad), high + Eigen::Vector2d::Constant(pad), cell);
  for (const Eigen::Vector2d& x : veins.nodes)
    graph.AddNode(x);
  const int vein = graph.AddVein(VeinOrderPrimary);
  for (const Segment& s : segments)
    graph.AddEdge(s.a, s.b, vein);
  // A tree's face walk encloses no area; rounding can leave a few 1e-15 of it, which is no areole.
  const double tiny = 1e-12 * (high - low).squaredNorm();
  for (const VeinGraph::Face& face : graph.Faces(false))
    if (face.area > tiny)
      m.areoleAreas.push_back(face.area);
  std::sort(m.areoleAreas.begin(), m.areoleAreas.end());
  m.areoles = m.areoleAreas.size();
  if (m.areoles == 0)
    return;
  const double n = static_cast<double>(m.areoles);
  m.areoleMean = std::accumulate(m.areoleAreas.begin(), m.areoleAreas.end(), 0.0) / n;
  const std::size_t mid = m.areoles / 2;
  m.areoleMedian = m.areoles % 2 ? m.areoleAreas[mid] : 0.5 * (m.areoleAreas[mid - 1] + m.areoleAreas[mid]);
  double squares = 0.0;
  for (double a : m.areoleAreas)
    squares += (a - m.areoleMean) * (a - m.areoleMean);
  m.areoleCV = std::sqrt(squares / n) / m.areoleMean;
}
} // namespace

std::string MeasureVeinNetwork(const VenationResult& veins, double bladeArea,
  const std::vector<Eigen::Vector2d>& margin, double tolerance, VeinNetworkMeasures& measures)
{
  measures = VeinNetworkMeasures();
  if (!(bladeArea > 0.0) || !std::isfinite(bladeArea))
    return "bladeArea must be positive";
  if (veins.width.size() != veins.nodes.size())
    return "the network's widths do not match its nodes";
  // Segments, each once (a segment two veins share counts for the lower order).
  std::vector<Segment> segments;
  std::vector<std::pair<std::pair<int, int>, std::size_t>> keys;
  for (const auto& vein : veins.veins)
  {
    if (vein.order < VeinOrderPrimary || vein.order > VeinOrderVeinlet)
      return "a vein's order is outside [1, 5]";
    for (std::size_t i = 0; i + 1 < vein.nodes.size(); ++i)
    {
      const int a = vein.nodes[i], b = vein.nodes[i + 1];
      if (a < 0 || b < 0 || a >= static_cast<int>(veins.nodes.size()) || b >= static_cast<int>(veins.nodes.size()))
        return "a vein names a node that does not exist";
      if (a == b)
        continue;
      keys.push_back({ { std::min(a, b), std::max(a, b) }, segments.size() });
      segments.push_back(
        { a, b, vein.order, (veins.nodes[a] - veins.nodes[b]).norm(), 0.5 * (veins.width[a] + veins.width[b]) });
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> keep(segments.size(), 1);
  for (std::size_t k = 1; k < keys.size(); ++k)
  {
    if (keys[k].first == keys[k - 1].first)
    {
      Segment& kept = segments[keys[k - 1].second];
      kept.order = std::min(kept.order, segments[keys[k].second].order);
      keep[keys[k].second] = 0;
      keys[k].second = keys[k - 1].second;
    }
  }
  std::vector<Segment> unique;
  for (std::size_t s = 0; s < segments.size(); ++s)
    if (keep[s])
      unique.push_back(segments[s]);
  segments = std::move(unique);

  VeinNetworkMeasures& m = measures;
  m.bladeArea = bladeArea;
  double widthLength[VeinOrderCount] = {};
  std::vector<int> degree(veins.nodes.size(), 0);
  for (const Segment& s : segments)
  {
    m.length[s.order] += s.length;
    widthLength[s.order] += s.width * s.length;
    m.totalLength += s.length;
    ++degree[s.a];
    ++degree[s.b];
  }
  for (int o = 1; o < VeinOrderCount; ++o)
    m.meanWidth[o] = m.length[o] > 0.0 ? widthLength[o] / m.length[o] : 0.0;
  m.vla = m.totalLength / bladeArea;
  for (std::size_t n = 0; n < degree.size(); ++n)
  {
    m.branchPoints += degree[n] >= 3;
    m.freeEnds += degree[n] == 1 && (margin.empty() || DistanceToPolygon(veins.nodes[n], margin) > tolerance);
  }
  m.branchPointsPerArea = static_cast<double>(m.branchPoints) / bladeArea;
  m.freeEndsPerArea = static_cast<double>(m.freeEnds) / bladeArea;
  // Minimum spanning forest (Kruskal; equal lengths in segment order).
  std::vector<std::size_t> order(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(
    order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return segments[x].length < segments[y].length; });
  DisjointSets<int> trees(veins.nodes.size());
  for (std::size_t k : order)
    if (trees.Join(segments[k].a, segments[k].b))
      m.spanningLength += segments[k].length;
  m.loopiness = m.totalLength > 0.0 ? m.spanningLength / m.totalLength : 1.0;
  MeasureAreoles(veins, segments, m);
  return {};
}

std::string MeasureVenation(const VenationBlade& blade, const VenationResult& veins, VeinNetworkMeasures& measures)
{
  measures = VeinNetworkMeasures();
  BladeLocator locator;
  const std::string error = locator.Build(blade);
  if (!error.empty())
    return error;
  std::vector<Eigen::Vector2d> margin;
  if (!locator.BoundaryLoops().empty())
    for (int id : locator.BoundaryLoops().front())
      margin.push_back(blade.points[id]);
  const double length = veins.leafLength > 0.0 ? veins.leafLength : (locator.Upper() - locator.Lower()).norm();
  return MeasureVeinNetwork(veins, locator.Area(), margin, 1e-6 * length, measures);
}

AreoleHistogram MakeAreoleHistogram(const std::vector<double>& areas, int bins)
{
  AreoleHistogram h;
  if (areas.empty() || bins < 1)
    return h;
  const auto [lowest, highest] = std::minmax_element(areas.begin(), areas.end());
  const double low = *lowest;
  double width = (*highest - low) / bins;
  if (!(width > 0.0))
    width = (low != 0.0 ? std::abs(low) : 1.0) * 1e-6 / bins;
  h.count.assign(static_cast<std::size_t>(bins), 0);
  for (int b = 0; b < bins; ++b)
  {
    h.lower.push_back(low + b * width);
    h.upper.push_back(b + 1 == bins ? std::max(*highest, low + bins * width) : low + (b + 1) * width);
  }
  for (double a : areas)
  {
    const double at = std::floor((a - low) / width);
    const int b = std::clamp(static_cast<int>(std::min(at, static_cast<double>(bins))), 0, bins - 1);
    ++h.count[static_cast<std::size_t>(b)];
  }
  return h;
}

} // namespace plantmorph
