// SPDX-License-Identifier: GPL-3.0-or-later
// The MTG graph as axes and points (BuildMtgGeometry), and a tree written as FORM-A (WriteMtg).
#include "FormatText.h"
#include "MtgText.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

namespace plantmorph
{

namespace
{
using Point = std::array<double, 3>;

/// The axes of `scale`: an entity that follows ('<') an entity without successor yet continues its axis; any other
/// (no parent, '+', a second '<') starts one.
std::vector<MtgAxis> AxesOf(const MtgGraph& graph, int scale, std::vector<long long>& axisOf)
{
  std::vector<MtgAxis> axes;
  std::vector<char> continued(graph.entities.size(), 0);
  axisOf.assign(graph.entities.size(), -1);
  for (std::size_t e = 0; e < graph.entities.size(); ++e)
  {
    const MtgEntity& entity = graph.entities[e];
    if (entity.scale != scale)
    {
      continue;
    }
    const long long p = entity.parent;
    if (p >= 0 && entity.edge == '<' && !continued[static_cast<std::size_t>(p)] &&
      axisOf[static_cast<std::size_t>(p)] >= 0)
    {
      continued[static_cast<std::size_t>(p)] = 1;
      axisOf[e] = axisOf[static_cast<std::size_t>(p)];
      axes[static_cast<std::size_t>(axisOf[e])].entities.push_back(static_cast<long long>(e));
      continue;
    }
    MtgAxis axis;
    axis.entities.push_back(static_cast<long long>(e));
    axis.bearer = p >= 0 && axisOf[static_cast<std::size_t>(p)] >= 0 ? p : -1;
    axis.parentAxis = axis.bearer >= 0 ? axisOf[static_cast<std::size_t>(p)] : -1;
    axis.order = axis.parentAxis >= 0 ? axes[static_cast<std::size_t>(axis.parentAxis)].order + 1 : 0;
    if (axis.bearer >= 0 && entity.edge == '<')
    {
      continued[static_cast<std::size_t>(p)] = 1;
    }
    axisOf[e] = static_cast<long long>(axes.size());
    axes.push_back(std::move(axis));
  }
  return axes;
}

double Value(const MtgGraph& graph, int feature, std::size_t entity)
{
  return feature >= 0 && graph.features[static_cast<std::size_t>(feature)].kind != MtgFeatureKind::Text
    ? graph.numbers[static_cast<std::size_t>(feature)][entity]
    : std::numeric_limits<double>::quiet_NaN();
}

/// The default layout (no coordinates): see BuildMtgGeometry.
void DefaultLayout(const MtgGraph& graph, MtgGeometry& g)
{
  int length = graph.FeatureIndex("Length");
  length = length >= 0 ? length : graph.FeatureIndex("length");
  std::vector<Point> directions(g.axes.size());
  std::vector<int> children(g.axes.size(), 0);
  const double s = std::sqrt(0.5);
  for (std::size_t a = 0; a < g.axes.size(); ++a)
  {
    const MtgAxis& axis = g.axes[a];
    Point at = { 0.0, 0.0, 0.0 };
    Point d = { 0.0, 1.0, 0.0 };
    if (axis.parentAxis >= 0)
    {
      const Point& pd = directions[static_cast<std::size_t>(axis.parentAxis)];
      const double side = children[static_cast<std::size_t>(axis.parentAxis)]++ % 2 == 0 ? 1.0 : -1.0;
      d = { s * pd[0] - side * s * pd[1], side * s * pd[0] + s * pd[1], 0.0 }; // +-45 degrees about z
      at = g.positions[static_cast<std::size_t>(axis.bearer)];
    }
    directions[a] = d;
    for (const long long e : axis.entities)
    {
      const double l = Value(graph, length, static_cast<std::size_t>(e));
      const double step = std::isfinite(l) && l > 0.0 ? l : 1.0;
      for (int k = 0; k < 3; ++k)
      {
        at[static_cast<std::size_t>(k)] += step * d[static_cast<std::size_t>(k)];
      }
      g.positions[static_cast<std::size_t>(e)] = at;
    }
  }
}
/// The points of one axis: the entities with XX, YY, ZZ at theirs; the others between the measured ones around them,
/// linearly by rank (before the first measured one from the bearer's point, after the last one at it).
template <typename Located>
void PlaceAxis(const MtgGraph& graph, const MtgAxis& axis, const Located& located, MtgGeometry& g)
{
  const int xx = graph.FeatureIndex("XX"), yy = graph.FeatureIndex("YY"), zz = graph.FeatureIndex("ZZ");
  const std::size_t n = axis.entities.size();
  // The last measured point before the run and its rank (-1: the bearer's point, before the first entity).
  bool havePrevious = axis.bearer >= 0;
  Point previous = havePrevious ? g.positions[static_cast<std::size_t>(axis.bearer)] : Point{ 0.0, 0.0, 0.0 };
  double previousRank = -1.0;
  std::size_t k = 0;
  while (k < n)
  {
    std::size_t next = k;
    while (next < n && !located(static_cast<std::size_t>(axis.entities[next])))
    {
      ++next;
    }
    const Point end = next < n ? Point{ Value(graph, xx, static_cast<std::size_t>(axis.entities[next])),
      Value(graph, yy, static_cast<std::size_t>(axis.entities[next])),
      Value(graph, zz, static_cast<std::size_t>(axis.entities[next])) }
                               : previous;
    const Point start = havePrevious ? previous : end;
    for (std::size_t j = k; j < next; ++j) // the unmeasured run [k, next)
    {
      const double t = next < n && havePrevious
        ? (static_cast<double>(j) - previousRank) / (static_cast<double>(next) - previousRank)
        : 0.0;
      Point& p = g.positions[static_cast<std::size_t>(axis.entities[j])];
      for (std::size_t c = 0; c < 3; ++c)
      {
        p[c] = start[c] + t * (end[c] - start[c]);
      }
      ++g.placedWithoutCoordinates;
    }
    if (next < n)
    {
      g.positions[static_cast<std::size_t>(axis.entities[next])] = end;
      previous = end, previousRank = static_cast<double>(next), havePrevious = true;
    }
    k = next + 1;
  }
}
} // namespace

MtgGeometry BuildMtgGeometry(const MtgGraph& graph)
{
  MtgGeometry g;
  const int xx = graph.FeatureIndex("XX"), yy = graph.FeatureIndex("YY"), zz = graph.FeatureIndex("ZZ");
  const auto located = [&](std::size_t e) {
    return std::isfinite(Value(graph, xx, e)) && std::isfinite(Value(graph, yy, e)) &&
      std::isfinite(Value(graph, zz, e));
  };
  g.scale = -1;
  for (std::size_t e = 1; e < graph.entities.size(); ++e)
  {
    if (located(e))
    {
      g.scale = std::max(g.scale, graph.entities[e].scale);
    }
  }
  g.explicitCoordinates = g.scale > 0;
  g.scale = g.explicitCoordinates ? g.scale : graph.FinestScale();
  std::vector<long long> axisOf;
  g.axes = AxesOf(graph, g.scale, axisOf);
  g.positions.assign(graph.entities.size(), Point{ 0.0, 0.0, 0.0 });
  if (!g.explicitCoordinates)
  {
    DefaultLayout(graph, g);
    g.warning = "no entity has XX, YY, ZZ coordinates: the topology is laid out by default in the XY plane (y up; "
                "branches at 45 degrees, each entity one Length, or 1, further)";
    return g;
  }
  for (const MtgAxis& axis : g.axes)
  {
    PlaceAxis(graph, axis, located, g);
  }
  if (g.placedWithoutCoordinates)
  {
    g.warning = std::to_string(g.placedWithoutCoordinates) + " entities of scale " + std::to_string(g.scale) +
      " have no XX, YY, ZZ: each is placed on its axis between the measured entities around it (linearly by rank; "
      "from its bearer's point before the first, at the last measured point after it)";
  }
  return g;
}

namespace
{
/// One line of the MTG: section: the code in `column`, then the features' columns.
void WriteLine(std::ostream& out, std::size_t column, std::size_t codeColumns, const std::string& code,
  const MtgTreeBranch& b, std::size_t k)
{
  out << std::string(column, '\t') << code << std::string(codeColumns - column, '\t');
  const auto& p = b.points[k];
  out << ExactNumber(p[0]) << '\t' << ExactNumber(p[1]) << '\t' << ExactNumber(p[2]) << '\t';
  if (k < b.radii.size() && std::isfinite(b.radii[k]))
  {
    out << ExactNumber(2.0 * b.radii[k]);
  }
  out << '\n';
}

std::size_t Nearest(const MtgTreeBranch& parent, const std::array<double, 3>& p)
{
  std::size_t best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < parent.points.size(); ++k)
  {
    double d = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      d += (parent.points[k][static_cast<std::size_t>(c)] - p[static_cast<std::size_t>(c)]) *
        (parent.points[k][static_cast<std::size_t>(c)] - p[static_cast<std::size_t>(c)]);
    }
    if (d < bestDistance)
    {
      best = k, bestDistance = d;
    }
  }
  return best;
}
} // namespace

std::string WriteMtg(std::ostream& out, const std::vector<MtgTreeBranch>& branches)
{
  std::unordered_map<long long, std::size_t> byId;
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    if (branches[b].id < 0 || branches[b].points.empty())
    {
      return "branch " + std::to_string(b) + (branches[b].id < 0 ? " has a negative BranchId" : " has no point");
    }
    if (!byId.emplace(branches[b].id, b).second)
    {
      return "BranchId " + std::to_string(branches[b].id) + " is used twice";
    }
  }
  // children[parent] sorted by the parent's point they branch on; roots: no parent among the branches.
  std::vector<std::multimap<std::size_t, std::size_t>> children(branches.size());
  std::vector<std::size_t> roots;
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    const auto parent = byId.find(branches[b].parentId);
    if (parent == byId.end() || parent->second == b)
    {
      roots.push_back(b);
      continue;
    }
    const MtgTreeBranch& p = branches[parent->second];
    children[parent->second].emplace(Nearest(p, branches[b].points.front()), b);
  }
  // Depths (the code column of each branch), by an explicit walk from the roots; a branch never reached is on a cycle.
  std::vector<std::size_t> depth(branches.size(), std::numeric_limits<std::size_t>::max());
  std::vector<std::size_t> stack(roots.begin(), roots.end()), order;
  for (const std::size_t r : roots)
  {
    depth[r] = 0;
  }
  std::size_t deepest = 0;
  while (!stack.empty())
  {
    const std::size_t b = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, depth[b]);
    for (const auto& [k, c] : children[b])
    {
      depth[c] = depth[b] + 1;
      stack.push_back(c);
    }
  }
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    if (depth[b] == std::numeric_limits<std::size_t>::max())
    {
      return "BranchId " + std::to_string(branches[b].id) + " is on a cycle of ParentIds (no root above it)";
    }
  }
  const std::size_t codeColumns = deepest + 1;
  out
    << "CODE:\tFORM-A\n\nCLASSES:\nSYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
    << "$\t0\tFREE\tFREE\tIMPLICIT\nP\t1\tFREE\tFREE\tIMPLICIT\nA\t2\tFREE\tFREE\tIMPLICIT\n"
    << "S\t3\tLINEAR\tFREE\tIMPLICIT\n\nDESCRIPTION:\nLEFT\tRIGHT\tRELTYPE\tMAX\nA\tA\t+\t?\nS\tS\t<\t1\nS\tS\t+\t?\n\n"
    << "FEATURES:\nNAME\tTYPE\nXX\tREAL\nYY\tREAL\nZZ\tREAL\ndiam\tREAL\n\nMTG:\nENTITY-CODE"
    << std::string(codeColumns, '\t') << "XX\tYY\tZZ\tdiam\n";
  // Each branch's segments in order, its children's lines right after the segment they branch on (an explicit stack
  // of (branch, next point), so deep trees need no recursion).
  std::size_t plant = 0;
  for (const std::size_t r : roots)
  {
    std::vector<std::pair<std::size_t, std::size_t>> walk{ { r, 0 } };
    while (!walk.empty())
    {
      auto& [b, k] = walk.back();
      const MtgTreeBranch& branch = branches[b];
      if (k == branch.points.size())
      {
        walk.pop_back();
        continue;
      }
      const std::string segment = "S" + std::to_string(k + 1);
      const std::string axis = "A" + std::to_string(branch.id) + "/" + segment;
      const std::string code = k > 0 ? "^<" + segment
        : depth[b] == 0              ? "/P" + std::to_string(++plant) + "/" + axis
                                     : "+" + axis;
      WriteLine(out, depth[b], codeColumns, code, branch, k);
      const std::size_t at = k++;
      const auto range = children[b].equal_range(at);
      std::vector<std::size_t> here;
      for (auto it = range.first; it != range.second; ++it)
      {
        here.push_back(it->second);
      }
      for (auto it = here.rbegin(); it != here.rend(); ++it)
      {
        walk.emplace_back(*it, 0); // the last pushed is written first: children in file order
      }
    }
  }
  return out ? std::string() : std::string("the file could not be written");
}

} // namespace plantmorph
