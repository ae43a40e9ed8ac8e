// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshInvariants.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph::testing
{

std::map<std::pair<int, int>, int> EdgeUse(const Triangles& triangles)
{
  std::map<std::pair<int, int>, int> use;
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = t[k], b = t[(k + 1) % 3];
      ++use[{ std::min(a, b), std::max(a, b) }];
    }
  }
  return use;
}

double SignedArea(const std::vector<Eigen::Vector2d>& points, const std::array<int, 3>& t)
{
  const Eigen::Vector2d e1 = points[t[1]] - points[t[0]];
  const Eigen::Vector2d e2 = points[t[2]] - points[t[0]];
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

std::vector<std::vector<int>> BoundaryLoops(const Triangles& triangles)
{
  // Directed boundary edges keep the triangles' orientation, so each vertex has one successor.
  const auto use = EdgeUse(triangles);
  std::map<int, int> next;
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = t[k], b = t[(k + 1) % 3];
      if (use.at({ std::min(a, b), std::max(a, b) }) == 1)
      {
        if (next.count(a))
          return {}; // a vertex where the boundary pinches: not a manifold boundary
        next[a] = b;
      }
    }
  }
  std::vector<std::vector<int>> loops;
  while (!next.empty())
  {
    std::vector<int> loop;
    int v = next.begin()->first;
    while (next.count(v))
    {
      loop.push_back(v);
      const int w = next[v];
      next.erase(v);
      v = w;
    }
    if (v != loop.front())
      return {};
    loops.push_back(loop);
  }
  return loops;
}

bool InsideOrOn(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon, double tolerance)
{
  if (DistanceToPolyline(p, polygon) <= tolerance)
    return true;
  int winding = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const double cross = (b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y());
    if (a.y() <= p.y() && b.y() > p.y() && cross > 0)
      ++winding;
    else if (a.y() > p.y() && b.y() <= p.y() && cross < 0)
      --winding;
  }
  return winding != 0;
}

double DistanceToPolyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i)
  {
    const Eigen::Vector2d d = line[i + 1] - line[i];
    const double t = d.squaredNorm() > 0 ? std::clamp((p - line[i]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (p - (line[i] + t * d)).norm());
  }
  return best;
}

} // namespace plantmorph::testing
