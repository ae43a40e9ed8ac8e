// SPDX-License-Identifier: GPL-3.0-or-later
#include "VenationBlade.h"

#include <plantmorph/PlaneFit.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace plantmorph
{

namespace
{
/// Whether the blade projects onto its least-squares plane one to one and nearly true to size: every triangle keeps
/// its orientation and a non-zero area, and the projected area is at least 0.8 of the surface's (a tilt of at most
/// about 37 degrees on average).
bool ProjectsOneToOne(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles, const FittedPlane& fit)
{
  if (triangles.empty())
    return false;
  double surface = 0.0, projected = 0.0;
  int positive = 0, negative = 0;
  for (const auto& t : triangles)
  {
    const Eigen::Vector3d face = (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
    const double along = face.dot(fit.normal);
    if (!(face.norm() > 0.0))
      continue; // a degenerate triangle (a collapsed base) has no orientation to keep
    surface += face.norm();
    projected += std::abs(along);
    if (along > 1e-12 * face.norm())
      ++positive;
    else if (along < -1e-12 * face.norm())
      ++negative;
  }
  return (positive == 0 || negative == 0) && positive + negative > 0 && projected >= 0.8 * surface;
}
} // namespace

std::vector<Eigen::Vector2d> VenationWorkingPlane(const std::vector<Eigen::Vector3d>& points,
  const std::vector<Eigen::Vector2d>& uv, const std::vector<std::array<int, 3>>& triangles, bool& flat)
{
  std::vector<Eigen::Vector2d> plane(points.size());
  flat = true;
  if (AllAtSameHeight(points))
  {
    for (std::size_t i = 0; i < points.size(); ++i)
      plane[i] = points[i].head<2>();
    return plane;
  }
  Eigen::Vector3d low = points.front(), high = points.front();
  for (const Eigen::Vector3d& x : points)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const FittedPlane fitted = FitPlane(points);
  if (fitted.maxDeviation <= 1e-6 * (high - low).norm())
  {
    const Eigen::Vector3d e1 = fitted.major;
    const Eigen::Vector3d e2 = fitted.normal.cross(e1);
    for (std::size_t i = 0; i < points.size(); ++i)
      plane[i] = Eigen::Vector2d((points[i] - fitted.centroid).dot(e1), (points[i] - fitted.centroid).dot(e2));
    return plane;
  }
  // Curved but one-to-one onto its least-squares plane (a fitted scan, a gently bent blade): that projection, which
  // keeps the blade's own shape (its lobes, its width along its length) where LeafUV need not (LeafFitFilter's u
  // is +-0.5 at both margins at every height, a rectangle).
  if (ProjectsOneToOne(points, triangles, fitted))
  {
    const Eigen::Vector3d e1 = fitted.major;
    const Eigen::Vector3d e2 = fitted.normal.cross(e1);
    for (std::size_t i = 0; i < points.size(); ++i)
      plane[i] = Eigen::Vector2d((points[i] - fitted.centroid).dot(e1), (points[i] - fitted.centroid).dot(e2));
    return plane;
  }
  // Curved: |dP|^2 ~ a du^2 + b dv^2 over the edges, least squares for a and b.
  flat = false;
  Eigen::Matrix2d normalMatrix = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int i = t[k], j = t[(k + 1) % 3];
      const Eigen::Vector2d row(
        (uv[i].x() - uv[j].x()) * (uv[i].x() - uv[j].x()), (uv[i].y() - uv[j].y()) * (uv[i].y() - uv[j].y()));
      normalMatrix += row * row.transpose();
      rhs += row * (points[i] - points[j]).squaredNorm();
    }
  }
  Eigen::Vector2d ab = normalMatrix.ldlt().solve(rhs);
  const double fallback = (high - low).norm();
  const double su = ab.x() > 0.0 && std::isfinite(ab.x()) ? std::sqrt(ab.x()) : fallback;
  const double sv = ab.y() > 0.0 && std::isfinite(ab.y()) ? std::sqrt(ab.y()) : fallback;
  for (std::size_t i = 0; i < points.size(); ++i)
    plane[i] = Eigen::Vector2d(su * uv[i].x(), sv * uv[i].y());
  return plane;
}

std::vector<Eigen::Vector3d> RaisedAlongNormals(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::array<int, 3>>& triangles, std::vector<Eigen::Vector3d> normals,
  const std::vector<double>& heights)
{
  if (normals.size() != points.size())
  {
    normals.assign(points.size(), Eigen::Vector3d::Zero());
    for (const auto& t : triangles)
    {
      const Eigen::Vector3d face = (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
      for (int k = 0; k < 3; ++k)
        normals[t[k]] += face;
    }
  }
  std::vector<Eigen::Vector3d> raised(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double length = normals[i].norm();
    const Eigen::Vector3d up = length > 0.0 ? Eigen::Vector3d(normals[i] / length) : Eigen::Vector3d::UnitZ();
    raised[i] = points[i] + heights[i] * up;
  }
  return raised;
}
namespace
{
double SignedArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c)
{
  return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
}

Eigen::Vector3d Barycentric(
  const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c)
{
  const double area = SignedArea(a, b, c);
  return Eigen::Vector3d(SignedArea(p, b, c), SignedArea(a, p, c), SignedArea(a, b, p)) / area;
}

} // namespace

Eigen::Vector2d ClosestOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d d = b - a;
  const double length2 = d.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(d) / length2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

std::array<int, 2> BladeLocator::Grid::Cell(const Eigen::Vector2d& p) const
{
  return { std::clamp(static_cast<int>(std::floor((p.x() - this->low.x()) / this->cell)), 0, this->width - 1),
    std::clamp(static_cast<int>(std::floor((p.y() - this->low.y()) / this->cell)), 0, this->height - 1) };
}

void BladeLocator::Grid::Build(const std::vector<Eigen::Vector2d>& points,
  const std::vector<std::array<int, 3>>& triangles, const std::vector<char>& usable)
{
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d high = -low;
  std::size_t count = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    if (!usable[t])
      continue;
    ++count;
    for (int v : triangles[t])
    {
      low = low.cwiseMin(points[v]);
      high = high.cwiseMax(points[v]);
    }
  }
  const Eigen::Vector2d extent = (high - low).cwiseMax(Eigen::Vector2d::Constant(1e-12));
  // About two triangles per cell.
  this->cell = std::max(std::sqrt(extent.x() * extent.y() / std::max<double>(1.0, 0.5 * count)), 1e-12);
  this->low = low;
  this->width = std::max(1, std::min(4096, static_cast<int>(std::ceil(extent.x() / this->cell))));
  this->height = std::max(1, std::min(4096, static_cast<int>(std::ceil(extent.y() / this->cell))));
  this->cell = std::max(extent.x() / this->width, extent.y() / this->height);
  this->cells.assign(static_cast<std::size_t>(this->width) * this->height, {});
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    if (!usable[t])
      continue;
    Eigen::Vector2d a = points[triangles[t][0]], b = a;
    for (int v : triangles[t])
    {
      a = a.cwiseMin(points[v]);
      b = b.cwiseMax(points[v]);
    }
    const auto c0 = this->Cell(a), c1 = this->Cell(b);
    for (int y = c0[1]; y <= c1[1]; ++y)
    {
      for (int x = c0[0]; x <= c1[0]; ++x)
        this->cells[this->Index(x, y)].push_back(static_cast<int>(t));
    }
  }
}

std::string BladeLocator::Build(const VenationBlade& blade)
{
  this->Blade = &blade;
  const std::size_t n = blade.points.size();
  if (blade.triangles.empty())
    return "the blade has no triangles";
  if (blade.uv.size() != n)
    return "the blade's LeafUV array does not cover every point";
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!blade.points[i].allFinite() || !blade.uv[i].allFinite())
      return "point " + std::to_string(i) + " has a non-finite coordinate or LeafUV";
  }
  this->PlaneUsable.assign(blade.triangles.size(), 0);
  this->UVUsable.assign(blade.triangles.size(), 0);
  this->TotalArea = 0.0;
  double edgeSum = 0.0;
  std::map<std::pair<int, int>, int> edgeUse;
  std::map<std::pair<int, int>, std::pair<int, int>> directed; // undirected edge -> its direction in a triangle
  for (std::size_t t = 0; t < blade.triangles.size(); ++t)
  {
    const auto& tri = blade.triangles[t];
    for (int v : tri)
    {
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        return "triangle " + std::to_string(t) + " refers to a point that does not exist";
    }
    const double area = SignedArea(blade.points[tri[0]], blade.points[tri[1]], blade.points[tri[2]]);
    const double areaUV = SignedArea(blade.uv[tri[0]], blade.uv[tri[1]], blade.uv[tri[2]]);
    this->PlaneUsable[t] = std::abs(area) > 0.0;
    this->UVUsable[t] = std::abs(areaUV) > 0.0;
    this->TotalArea += std::abs(area);
    for (int k = 0; k < 3; ++k)
    {
      int a = tri[k], b = tri[(k + 1) % 3];
      edgeSum += (blade.points[a] - blade.points[b]).norm();
      if (area < 0.0)
        std::swap(a, b); // the direction that keeps the triangle on its left
      const auto key = std::minmax(a, b);
      if (++edgeUse[key] > 2)
        return "edge (" + std::to_string(key.first) + ", " + std::to_string(key.second) +
          ") is shared by more than two triangles: the blade must be a manifold surface";
      directed[key] = { a, b };
    }
  }
  this->MeanEdge = edgeSum / (3.0 * blade.triangles.size());
  if (!(this->TotalArea > 0.0))
    return "the blade has no area in its plane";

  // Boundary loops: edges of one triangle, each directed with the blade on its left.
  std::map<int, int> next;
  for (const auto& [key, count] : edgeUse)
  {
    if (count != 1)
      continue;
    const auto [a, b] = directed[key];
    if (next.count(a))
      return "the blade's boundary touches itself at point " + std::to_string(a);
    next[a] = b;
  }
  this->Loops.clear();
  std::map<int, char> used;
  for (const auto& [first, second] : next)
  {
    (void)second;
    if (used[first])
      continue;
    std::vector<int> loop;
    int v = first;
    while (!used[v])
    {
      used[v] = 1;
      loop.push_back(v);
      const auto it = next.find(v);
      if (it == next.end())
        return "the blade's boundary is not closed at point " + std::to_string(v);
      v = it->second;
    }
    this->Loops.push_back(loop);
  }
  if (this->Loops.empty())
    return "the blade has no boundary (a closed surface has no margin to grow veins to)";
  auto loopArea = [&](const std::vector<int>& loop) {
    double twice = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i)
    {
      const Eigen::Vector2d& a = blade.points[loop[i]];
      const Eigen::Vector2d& b = blade.points[loop[(i + 1) % loop.size()]];
      twice += a.x() * b.y() - a.y() * b.x();
    }
    return 0.5 * twice;
  };
  std::stable_sort(this->Loops.begin(), this->Loops.end(), [&](const std::vector<int>& a, const std::vector<int>& b) {
    return std::abs(loopArea(a)) > std::abs(loopArea(b));
  });

  this->Low = blade.points.front();
  this->High = blade.points.front();
  for (const Eigen::Vector2d& p : blade.points)
  {
    this->Low = this->Low.cwiseMin(p);
    this->High = this->High.cwiseMax(p);
  }
  this->PlaneGrid.Build(blade.points, blade.triangles, this->PlaneUsable);
  bool anyUV = false;
  for (char u : this->UVUsable)
    anyUV = anyUV || u;
  if (!anyUV)
    return "the blade's LeafUV has no area (every triangle is degenerate in (u, v))";
  this->UVGrid.Build(blade.uv, blade.triangles, this->UVUsable);
  return {};
}

BladeLocation BladeLocator::Find(const Grid& grid, const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p,
  double tolerance, const std::vector<char>& usable) const
{
  BladeLocation best;
  double bestMin = -std::numeric_limits<double>::max();
  const auto c = grid.Cell(p);
  for (int t : grid.cells[grid.Index(c[0], c[1])])
  {
    if (!usable[t])
      continue;
    const auto& tri = this->Blade->triangles[t];
    const Eigen::Vector3d w = Barycentric(p, points[tri[0]], points[tri[1]], points[tri[2]]);
    const double smallest = w.minCoeff();
    if (smallest > bestMin)
    {
      // The tolerance is a distance: a weight of -x is a distance of x times the height over that vertex.
      const double size = std::max({ (points[tri[0]] - points[tri[1]]).norm(), (points[tri[1]] - points[tri[2]]).norm(),
        (points[tri[2]] - points[tri[0]]).norm() });
      const double twiceArea = 2.0 * std::abs(SignedArea(points[tri[0]], points[tri[1]], points[tri[2]]));
      const double height = twiceArea / std::max(size, 1e-300);
      if (smallest >= 0.0 || -smallest * height <= tolerance)
      {
        bestMin = smallest;
        best.triangle = t;
        best.weights = w;
      }
    }
  }
  if (best.triangle >= 0 && bestMin < 0.0)
  {
    // Within the tolerance outside: clamp onto the triangle.
    best.weights = best.weights.cwiseMax(0.0);
    best.weights /= best.weights.sum();
  }
  return best;
}

BladeLocation BladeLocator::Locate(const Eigen::Vector2d& p, double tolerance) const
{
  return this->Find(this->PlaneGrid, this->Blade->points, p, tolerance, this->PlaneUsable);
}

BladeLocation BladeLocator::LocateUV(const Eigen::Vector2d& uv) const
{
  BladeLocation found = this->Find(this->UVGrid, this->Blade->uv, uv, 1e-12, this->UVUsable);
  if (found.triangle >= 0)
    return found;
  // Outside the LeafUV image: the nearest triangle, ring by ring of cells.
  const Grid& grid = this->UVGrid;
  const auto c = grid.Cell(uv);
  double bestDistance = std::numeric_limits<double>::max();
  Eigen::Vector2d bestPoint = uv;
  for (int ring = 0; ring <= std::max(grid.width, grid.height); ++ring)
  {
    if (found.triangle >= 0 && (ring - 1) * grid.cell > bestDistance)
      break;
    for (int y = c[1] - ring; y <= c[1] + ring; ++y)
    {
      for (int x = c[0] - ring; x <= c[0] + ring; ++x)
      {
        if (x < 0 || y < 0 || x >= grid.width || y >= grid.height ||
          (std::abs(x - c[0]) != ring && std::abs(y - c[1]) != ring))
          continue;
        for (int t : grid.cells[grid.Index(x, y)])
        {
          const auto& tri = this->Blade->triangles[t];
          const Eigen::Vector2d& a = this->Blade->uv[tri[0]];
          const Eigen::Vector2d& b = this->Blade->uv[tri[1]];
          const Eigen::Vector2d& d = this->Blade->uv[tri[2]];
          for (const Eigen::Vector2d& q :
            { ClosestOnSegment(uv, a, b), ClosestOnSegment(uv, b, d), ClosestOnSegment(uv, d, a) })
          {
            const double distance = (q - uv).norm();
            if (distance < bestDistance)
            {
              bestDistance = distance;
              bestPoint = q;
              found.triangle = t;
            }
          }
        }
      }
    }
  }
  if (found.triangle >= 0)
  {
    const auto& tri = this->Blade->triangles[found.triangle];
    found.weights =
      Barycentric(bestPoint, this->Blade->uv[tri[0]], this->Blade->uv[tri[1]], this->Blade->uv[tri[2]]).cwiseMax(0.0);
    found.weights /= found.weights.sum();
  }
  return found;
}

Eigen::Vector2d BladeLocator::PointAtUV(const Eigen::Vector2d& uv) const
{
  return this->Interpolate(this->Blade->points, this->LocateUV(uv));
}

} // namespace plantmorph
