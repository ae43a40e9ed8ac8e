// SPDX-License-Identifier: GPL-3.0-or-later
// Invariants of a flat triangle mesh, computed by brute force for the tests.
#pragma once

#include <Eigen/Core>

#include <array>
#include <map>
#include <utility>
#include <vector>

namespace plantmorph::testing
{

using Triangles = std::vector<std::array<int, 3>>;

/// Undirected edge -> number of triangles that use it.
std::map<std::pair<int, int>, int> EdgeUse(const Triangles& triangles);

/// Signed area of a triangle (positive: counter-clockwise).
double SignedArea(const std::vector<Eigen::Vector2d>& points, const std::array<int, 3>& t);

/// The boundary edges (used once), chained into closed loops of vertex ids; empty when they do not chain.
std::vector<std::vector<int>> BoundaryLoops(const Triangles& triangles);

/// Winding-number test for a closed polygon (first point repeated at the end); points on its edges count as inside.
bool InsideOrOn(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon, double tolerance);

/// Distance from p to the polyline.
double DistanceToPolyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line);

} // namespace plantmorph::testing
