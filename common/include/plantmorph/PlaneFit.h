// SPDX-License-Identifier: GPL-3.0-or-later
// The least-squares plane of a point set: what a leaf's mesher and the venation filter use to find the plane a
// curved or tilted blade lies in; and the algebraic circle through points in a plane, which the tree fit and the
// segmentation fit across a stem; the area of a convex hull in a plane (a crown's projection, a leaf's outline).
// Plain C++17 (Eigen), no VTK.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace plantmorph
{

/// True when every point has exactly the z of the first (a blade made in the XY plane; also true for no points).
bool AllAtSameHeight(const std::vector<Eigen::Vector3d>& points);

struct FittedPlane
{
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); ///< unit, the direction of least spread, turned towards +Z
  Eigen::Vector3d major = Eigen::Vector3d::UnitX();  ///< unit, the direction of largest spread (its sign arbitrary)
  double maxDeviation = 0.0;                         ///< the largest |distance| of a point from the plane
  /// The covariance's eigenvalues, ascending: the sums of the points' squared offsets from the centroid along the
  /// normal, the middle direction and `major` (a line's points: the last far above the middle one).
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
};

/// The plane through the points' centroid whose normal is the eigenvector of their covariance with the smallest
/// eigenvalue (least squares of the distances to the plane). At least one point.
FittedPlane FitPlane(const std::vector<Eigen::Vector3d>& points);

/// Kasa's algebraic circle fit of points in a plane (x^2 + y^2 + D x + E y + F = 0, linear least squares):
/// circle = (centre x, centre y, radius). False when the solution is not finite or gives no positive squared radius;
/// points that determine no circle (on a line) may still give one of any size: callers judge the fit by its residuals.
bool FitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector3d& circle);

/// The area of the convex hull of points in a plane (Andrew's monotone chain); 0 for fewer than three points.
double ConvexHullArea(std::vector<Eigen::Vector2d> points);

} // namespace plantmorph
