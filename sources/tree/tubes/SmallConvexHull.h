// SPDX-License-Identifier: GPL-3.0-or-later
// Convex hull of a small point set (a welded junction's tens of points; BranchJunctions.h), built by incremental
// insertion with a distance tolerance. Plain C++ (Eigen), no VTK, no CGAL: for ~30 points it is several times faster
// than a CGAL Triangulation_3 (whose cells and exact fallbacks for the junctions' coplanar ring points dominated the
// welded tubes' time, benchmarks/README.md "tree").
//
// Points are inserted in index order after a first tetrahedron (point 0, the point farthest from it, the point
// farthest from their line, the point farthest from their plane). A point sees a facet when it lies more than
// `tolerance` x (the set's bounding-box diagonal) in front of the facet's plane; a point that sees none is inside or
// on the hull and is skipped, so points coplanar with a facet (a ring's own vertices) join its neighbours' fans: a
// planar face may be triangulated by any fan. The result is checked: every directed edge used once with its reverse
// once (closed, consistently oriented), and no point more than the tolerance in front of any facet (convex). A point
// set with fewer than four points or no tetrahedron of positive volume, repeated points included, fails.
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace plantmorph
{

/// Outward facets (counter-clockwise seen from outside), as indices into `points`, each rotated so that its smallest
/// index is first, sorted. Returns false (facets empty) when the hull is degenerate or fails its check.
bool SmallConvexHull(
  const std::vector<Eigen::Vector3d>& points, std::vector<std::array<long, 3>>& facets, double tolerance = 1e-9);

} // namespace plantmorph
