// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafGeometry.h"

#include <plantmorph/RangeError.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace plantmorph
{

std::vector<Eigen::Vector2d> BoundingBoxTextureCoordinates(const std::vector<Eigen::Vector2d>& points)
{
  std::vector<Eigen::Vector2d> tcoords(points.size(), Eigen::Vector2d::Zero());
  if (points.empty())
    return tcoords;
  Eigen::Vector2d low = points.front(), high = points.front();
  for (const Eigen::Vector2d& p : points)
  {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const Eigen::Vector2d extent = high - low;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    for (int k = 0; k < 2; ++k)
      tcoords[i][k] = extent[k] > 0.0 ? (points[i][k] - low[k]) / extent[k] : 0.0;
  }
  return tcoords;
}

std::string ValidateResolution(int resolution)
{
  return CheckRange(resolution >= MinResolution && resolution <= MaxResolution, "Resolution", resolution,
    "[" + std::to_string(MinResolution) + ", " + std::to_string(MaxResolution) + "]");
}

BladeMeshParameters MeshParametersFor(const LeafMeshParameters& settings, double spacing)
{
  BladeMeshParameters options;
  options.quality = settings.quality;
  options.maxEdgeLength = spacing;
  options.maxVertices = settings.maxVertices;
  if (settings.progress)
  {
    const std::function<bool(double)> progress = settings.progress;
    options.progress = [progress](double f) { return progress(0.05 + 0.85 * f); };
  }
  return options;
}

std::vector<Eigen::Vector3d> VertexNormals(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles)
{
  std::vector<Eigen::Vector3d> normals(points.size(), Eigen::Vector3d::Zero());
  for (const auto& t : triangles)
  {
    // The cross product's length is twice the area: summing it weights each face by its area.
    const Eigen::Vector3d n = (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
    for (int id : t)
      normals[id] += n;
  }
  for (Eigen::Vector3d& n : normals)
  {
    const double length = n.norm();
    n = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
  }
  return normals;
}

double CurveLength(const std::function<Eigen::Vector2d(double)>& curve, double a, double b, int samples)
{
  double length = 0.0;
  Eigen::Vector2d previous = curve(a);
  for (int i = 1; i <= samples; ++i)
  {
    const Eigen::Vector2d p = curve(a + (b - a) * i / samples);
    length += (p - previous).norm();
    previous = p;
  }
  return length;
}

std::vector<double> SampleByArcLength(
  const std::function<Eigen::Vector2d(double)>& curve, double a, double b, int pieces)
{
  if (pieces < 1)
    return { a };
  const int n = pieces;
  // Cumulative chord length on a dense polyline, fine enough for the wiggliest preset margin.
  const int dense = std::max(4096, 16 * n);
  std::vector<double> length(dense + 1, 0.0);
  Eigen::Vector2d previous = curve(a);
  for (int i = 1; i <= dense; ++i)
  {
    const Eigen::Vector2d p = curve(a + (b - a) * i / dense);
    length[i] = length[i - 1] + (p - previous).norm();
    previous = p;
  }
  if (!(length.back() > 0.0))
    return { a };
  std::vector<double> parameters(n + 1);
  parameters.front() = a;
  parameters.back() = b;
  int j = 0;
  for (int k = 1; k < n; ++k)
  {
    const double target = length.back() * k / n;
    while (length[j + 1] < target)
      ++j;
    const double piece = length[j + 1] - length[j];
    const double f = piece > 0.0 ? (target - length[j]) / piece : 0.0;
    parameters[k] = a + (b - a) * (j + f) / dense;
  }
  return parameters;
}

bool InsidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p)
{
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

Eigen::Vector2d MeanValueInterpolate(
  const std::vector<Eigen::Vector2d>& polygon, const std::vector<Eigen::Vector2d>& values, const Eigen::Vector2d& x)
{
  const std::size_t n = polygon.size();
  std::vector<Eigen::Vector2d> s(n);
  std::vector<double> r(n), halfTangent(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    s[i] = polygon[i] - x;
    r[i] = s[i].norm();
    if (r[i] < 1e-14)
      return values[i];
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t j = (i + 1) % n;
    const double area = s[i].x() * s[j].y() - s[i].y() * s[j].x(); // twice the signed area
    const double dot = s[i].dot(s[j]);
    if (std::abs(area) < 1e-14 * r[i] * r[j] && dot < 0.0)
    {
      // On the edge: linear interpolation along it.
      const double t = r[i] / (r[i] + r[j]);
      return (1.0 - t) * values[i] + t * values[j];
    }
    halfTangent[i] = area / (r[i] * r[j] + dot); // tan(alpha_i / 2)
  }
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double w = (halfTangent[(i + n - 1) % n] + halfTangent[i]) / r[i];
    sum += w * values[i];
    total += w;
  }
  return sum / total;
}

} // namespace plantmorph
