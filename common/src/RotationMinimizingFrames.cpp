// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <cmath>

namespace plantmorph
{

Eigen::Vector3d PerpendicularTo(const Eigen::Vector3d& tangent, const Eigen::Vector3d& hint)
{
  Eigen::Vector3d v = hint - hint.dot(tangent) * tangent;
  if (v.norm() < 1e-12 * std::max(1.0, hint.norm()))
  {
    // Any perpendicular: the axis least aligned with the tangent.
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
    if (std::abs(tangent.y()) < std::abs(tangent.x()))
    {
      axis = Eigen::Vector3d::UnitY();
    }
    if (std::abs(tangent.z()) < std::abs(axis.dot(tangent)))
    {
      axis = Eigen::Vector3d::UnitZ();
    }
    v = axis - axis.dot(tangent) * tangent;
  }
  return v.normalized();
}

std::vector<Eigen::Vector3d> PolylineTangents(const std::vector<Eigen::Vector3d>& points)
{
  const std::size_t n = points.size();
  std::vector<Eigen::Vector3d> directions;
  for (std::size_t k = 0; k + 1 < n; ++k)
  {
    const Eigen::Vector3d d = points[k + 1] - points[k];
    const double length = d.norm();
    directions.push_back(length > 0.0 ? Eigen::Vector3d(d / length) : Eigen::Vector3d::Zero());
  }
  // Zero-length segments borrow the nearest non-zero direction (forward, then backward).
  for (std::size_t k = directions.size(); k-- > 1;)
  {
    if (directions[k - 1].isZero() && !directions[k].isZero())
    {
      directions[k - 1] = directions[k];
    }
  }
  for (std::size_t k = 1; k < directions.size(); ++k)
  {
    if (directions[k].isZero())
    {
      directions[k] = directions[k - 1];
    }
  }
  std::vector<Eigen::Vector3d> tangents(n, Eigen::Vector3d::UnitY());
  if (directions.empty() || directions.front().isZero())
  {
    return tangents;
  }
  tangents[0] = directions.front();
  tangents[n - 1] = directions.back();
  for (std::size_t k = 1; k + 1 < n; ++k)
  {
    const Eigen::Vector3d sum = directions[k - 1] + directions[k];
    // A full reversal has no bisector: keep the incoming direction.
    tangents[k] = sum.norm() > 1e-12 ? Eigen::Vector3d(sum.normalized()) : directions[k - 1];
  }
  return tangents;
}

std::vector<OrthonormalFrame> RotationMinimizingFrames(const std::vector<Eigen::Vector3d>& points,
  const std::vector<Eigen::Vector3d>& tangents, const Eigen::Vector3d& initialNormal)
{
  std::vector<OrthonormalFrame> frames(points.size());
  if (points.empty() || tangents.size() != points.size())
  {
    frames.clear();
    return frames;
  }
  frames[0].tangent = tangents[0].normalized();
  frames[0].normal = PerpendicularTo(frames[0].tangent, initialNormal);
  frames[0].binormal = frames[0].normal.cross(frames[0].tangent);
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
  {
    const OrthonormalFrame& f = frames[i];
    const Eigen::Vector3d t1 = tangents[i + 1].normalized();
    Eigen::Vector3d r = f.normal;
    Eigen::Vector3d t = f.tangent;
    const Eigen::Vector3d v1 = points[i + 1] - points[i];
    const double c1 = v1.squaredNorm();
    if (c1 > 0.0)
    {
      r -= (2.0 / c1) * v1.dot(r) * v1;
      t -= (2.0 / c1) * v1.dot(t) * v1;
    }
    const Eigen::Vector3d v2 = t1 - t;
    const double c2 = v2.squaredNorm();
    if (c2 > 0.0)
    {
      r -= (2.0 / c2) * v2.dot(r) * v2;
    }
    OrthonormalFrame& g = frames[i + 1];
    g.tangent = t1;
    // Re-orthonormalise against rounding drift over long polylines.
    g.normal = PerpendicularTo(t1, r);
    g.binormal = g.normal.cross(t1);
  }
  return frames;
}

} // namespace plantmorph
