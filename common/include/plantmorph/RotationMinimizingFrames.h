// SPDX-License-Identifier: GPL-3.0-or-later
// Rotation-minimising frames along a polyline (docs/methods/tree-from-sketch.md: tube rings transported without twist).
//
// The double reflection method of Wang, Juettler, Zheng and Liu, "Computation of rotation minimizing frames", ACM TOG
// 27(1), 2008: from frame i to frame i + 1, reflect in the plane bisecting x_i and x_{i+1}, then in the plane that
// maps the reflected tangent onto t_{i+1}. Fourth-order accurate approximation of the exact RMF of a smooth curve
// (its normal's rotation about the tangent is -integral of torsion), exact for a polyline whose vertex tangents are
// the bisectors (the frame turns only about the bend axis). Coincident points or tangents are handled (the
// reflection is skipped). Plain C++ (Eigen), no VTK.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace plantmorph
{

struct OrthonormalFrame
{
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitY();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  Eigen::Vector3d binormal = Eigen::Vector3d::UnitZ(); ///< normal x tangent
};

/// Frames at every point: tangents[i] is the (unit) tangent at points[i]; the first normal is `initialNormal` made
/// perpendicular to tangents[0] (any perpendicular if it is parallel); binormal = normal x tangent, so that
/// (normal, tangent, binormal) is right-handed like a branch's local (x, y, z) with the branch along y. Both vectors
/// must have the same size; empty input gives no frames.
std::vector<OrthonormalFrame> RotationMinimizingFrames(const std::vector<Eigen::Vector3d>& points,
  const std::vector<Eigen::Vector3d>& tangents, const Eigen::Vector3d& initialNormal);

/// Unit vertex tangents of a polyline: the bisector (normalised sum of the unit directions of the two segments) at
/// interior points, the segment direction at the ends; zero-length segments borrow their neighbour's direction.
std::vector<Eigen::Vector3d> PolylineTangents(const std::vector<Eigen::Vector3d>& points);

/// A unit vector perpendicular to `tangent` close to `hint` (any perpendicular when they are parallel).
Eigen::Vector3d PerpendicularTo(const Eigen::Vector3d& tangent, const Eigen::Vector3d& hint);

} // namespace plantmorph
