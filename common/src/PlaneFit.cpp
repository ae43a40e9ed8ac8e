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

} // namespace plantmorph
