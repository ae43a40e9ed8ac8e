// SPDX-License-Identifier: GPL-3.0-or-later
#include "SmallConvexHull.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace plantmorph
{

namespace
{
struct Facet
{
  std::array<long, 3> v;
  Eigen::Vector3d normal; ///< unit, outward
  double offset = 0.0;    ///< normal . v[0]
  bool alive = true;
};

bool MakeFacet(const std::vector<Eigen::Vector3d>& p, long a, long b, long c, Facet& f)
{
  const Eigen::Vector3d n = (p[static_cast<std::size_t>(b)] - p[static_cast<std::size_t>(a)])
                              .cross(p[static_cast<std::size_t>(c)] - p[static_cast<std::size_t>(a)]);
  const double length = n.norm();
  if (!(length > 0.0))
    return false;
  f.v = { a, b, c };
  f.normal = n / length;
  f.offset = f.normal.dot(p[static_cast<std::size_t>(a)]);
  f.alive = true;
  return true;
}

template <class Distance>
long Farthest(const std::vector<Eigen::Vector3d>& p, double& best, const Distance& distance)
{
  long index = -1;
  best = -1.0;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    const double d = distance(p[i]);
    if (d > best)
      best = d, index = static_cast<long>(i);
  }
  return index;
}
} // namespace

bool SmallConvexHull(const std::vector<Eigen::Vector3d>& p, std::vector<std::array<long, 3>>& facets, double tolerance)
{
  facets.clear();
  if (p.size() < 4)
    return false;
  Eigen::Vector3d lo = p[0], hi = p[0];
  for (const Eigen::Vector3d& x : p)
    lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double eps = tolerance * (hi - lo).norm();
  if (!(eps > 0.0))
    return false;

  // The first tetrahedron.
  double d1 = 0.0, d2 = 0.0, d3 = 0.0;
  const long i0 = 0;
  const long i1 = Farthest(p, d1, [&](const Eigen::Vector3d& x) { return (x - p[0]).norm(); });
  const Eigen::Vector3d axis = (p[static_cast<std::size_t>(i1)] - p[0]).normalized();
  const long i2 = Farthest(p, d2, [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d r = x - p[0];
    return (r - r.dot(axis) * axis).norm();
  });
  if (!(d1 > eps) || !(d2 > eps))
    return false;
  const Eigen::Vector3d plane =
    (p[static_cast<std::size_t>(i1)] - p[0]).cross(p[static_cast<std::size_t>(i2)] - p[0]).normalized();
  const long i3 = Farthest(p, d3, [&](const Eigen::Vector3d& x) { return std::abs((x - p[0]).dot(plane)); });
  if (!(d3 > eps))
    return false;
  std::vector<Facet> hull;
  hull.reserve(4 * p.size());
  // Orient each facet away from the fourth corner.
  const std::array<std::array<long, 4>, 4> tetra{ { { i0, i1, i2, i3 }, { i0, i3, i1, i2 }, { i1, i3, i2, i0 },
    { i0, i2, i3, i1 } } };
  for (const auto& t : tetra)
  {
    Facet f;
    if (!MakeFacet(p, t[0], t[1], t[2], f))
      return false;
    if (f.normal.dot(p[static_cast<std::size_t>(t[3])]) - f.offset > 0.0)
    {
      if (!MakeFacet(p, t[0], t[2], t[1], f))
        return false;
    }
    hull.push_back(f);
  }

  // Insert the rest in order.
  std::vector<std::pair<long, long>> visibleEdges, horizon;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    const long li = static_cast<long>(i);
    if (li == i0 || li == i1 || li == i2 || li == i3)
      continue;
    visibleEdges.clear();
    horizon.clear();
    bool sees = false;
    for (Facet& f : hull)
    {
      if (f.alive && f.normal.dot(p[i]) - f.offset > eps)
      {
        f.alive = false;
        sees = true;
        for (int e = 0; e < 3; ++e)
          visibleEdges.emplace_back(f.v[static_cast<std::size_t>(e)], f.v[static_cast<std::size_t>((e + 1) % 3)]);
      }
    }
    if (!sees)
      continue;
    std::sort(visibleEdges.begin(), visibleEdges.end());
    for (const auto& [a, b] : visibleEdges)
    {
      if (!std::binary_search(visibleEdges.begin(), visibleEdges.end(), std::make_pair(b, a)))
        horizon.emplace_back(a, b);
    }
    for (const auto& [a, b] : horizon)
    {
      Facet f;
      if (!MakeFacet(p, a, b, li, f))
        return false;
      hull.push_back(f);
    }
    if (hull.size() > 64 * p.size())
    {
      // Compact the dead facets away.
      hull.erase(std::remove_if(hull.begin(), hull.end(), [](const Facet& f) { return !f.alive; }), hull.end());
    }
  }

  // Check: closed and oriented (every directed edge once, its reverse once), and convex.
  std::vector<std::pair<long, long>> edges;
  for (const Facet& f : hull)
  {
    if (!f.alive)
      continue;
    for (int e = 0; e < 3; ++e)
      edges.emplace_back(f.v[static_cast<std::size_t>(e)], f.v[static_cast<std::size_t>((e + 1) % 3)]);
    for (const Eigen::Vector3d& x : p)
    {
      if (f.normal.dot(x) - f.offset > eps)
        return false;
    }
    std::array<long, 3> v = f.v;
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    facets.push_back(v);
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t k = 0; k < edges.size(); ++k)
  {
    const bool repeated = k + 1 < edges.size() && edges[k + 1] == edges[k];
    if (repeated || !std::binary_search(edges.begin(), edges.end(), std::make_pair(edges[k].second, edges[k].first)))
    {
      facets.clear();
      return false;
    }
  }
  std::sort(facets.begin(), facets.end());
  return true;
}

} // namespace plantmorph
