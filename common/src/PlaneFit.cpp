// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/PlaneFit.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace plantmorph
{

bool AllAtSameHeight(const std::vector<Eigen::Vector3d>& points)
{
  for (const Eigen::Vector3d& x : points)
    if (x.z() != points.front().z())
      return false;
  return true;
}

FittedPlane FitPlane(const std::vector<Eigen::Vector3d>& points)
{
  FittedPlane plane;
  for (const Eigen::Vector3d& x : points)
    plane.centroid += x;
  plane.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& x : points)
    covariance += (x - plane.centroid) * (x - plane.centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  plane.normal = solver.eigenvectors().col(0); // eigenvalues ascending
  if (plane.normal.z() < 0.0)
    plane.normal = -plane.normal;
  plane.major = solver.eigenvectors().col(2);
  plane.moments = solver.eigenvalues();
  for (const Eigen::Vector3d& x : points)
    plane.maxDeviation = std::max(plane.maxDeviation, std::abs((x - plane.centroid).dot(plane.normal)));
  return plane;
}

bool FitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector3d& circle)
{
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const Eigen::Vector2d& p : points)
  {
    const double x = p.x(), y = p.y();
    const Eigen::Vector3d row(x, y, 1.0);
    ata += row * row.transpose();
    atb -= row * (x * x + y * y);
  }
  const Eigen::Vector3d s = ata.ldlt().solve(atb);
  const double a = -s[0] / 2, b = -s[1] / 2, r2 = a * a + b * b - s[2];
  if (!s.allFinite() || !(r2 > 0.0))
    return false;
  circle = Eigen::Vector3d(a, b, std::sqrt(r2));
  return true;
}

double ConvexHullArea(std::vector<Eigen::Vector2d> p)
{
  if (p.size() < 3)
    return 0.0;
  std::sort(p.begin(), p.end(),
    [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y(); });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0)
      --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i)
  {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i - 1]) <= 0)
      --k;
    hull[k++] = p[i - 1];
  }
  double area = 0;
  for (std::size_t i = 0; i + 1 < k; ++i)
    area += hull[i].x() * hull[i + 1].y() - hull[i + 1].x() * hull[i].y();
  return 0.5 * std::abs(area);
}

} // namespace plantmorph
