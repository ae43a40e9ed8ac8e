// SPDX-License-Identifier: GPL-3.0-or-later
// Triangulates a flat leaf blade with CGAL's constrained Delaunay triangulation (docs/methods/leaf-outline.md).
//
// Input: the outline as a closed counter-clockwise loop of boundary samples, and the midvein as a polyline of
// samples from the base to the apex (both of which are outline samples too). The midvein is a constraint, so the
// two half blades are meshed with one shared set of midvein vertices: one connected manifold with the midvein as an
// interior feature line. Faces are kept only inside the outline (CGAL's domain marking from the infinite face), so
// concave outlines get no triangle outside them.
//
// Paper mode: the plain constrained Delaunay triangulation of the samples. Quality mode: CGAL's Delaunay mesher
// without edge refinement (Delaunay_mesher_no_edge_refinement_2) refines the interior to a minimum angle of about
// 20.7 degrees (B = 0.125) and a maximum edge length. It never splits the outline or the midvein: the caller
// samples them at the target spacing already, so margin and midvein vertices are exactly the samples, with their
// exact LeafUV, in both modes. Interior Steiner points take their `LeafUV` from a caller-supplied solver (Model A
// inverts its map) seeded with the mean LeafUV of already-known neighbours.
//
// Plain C++ (CGAL, Eigen), no VTK.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

struct BladeOutline
{
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2d> uv; ///< LeafUV of every point
  std::vector<int> region;         ///< Region of every point (RegionMargin, RegionMidvein, ...)
  std::vector<int> boundary;       ///< closed loop of point ids, counter-clockwise, first not repeated at the end
  std::vector<int> midvein;        ///< polyline of point ids, base to apex; its ends are on the boundary
  /// Further interior feature lines (a palmate leaf's lobe midveins): polylines of point ids whose two ends are
  /// outline points and whose other points and segments lie strictly inside the outline. Constraints like the
  /// midvein: they are never split and no triangle crosses them.
  std::vector<std::vector<int>> veins;
};

struct BladeMeshParameters
{
  bool quality = true;
  double maxEdgeLength = 0.0;         ///< quality mode's size bound (required > 0 there)
  double shapeBound = 0.125;          ///< CGAL's B = sin^2 of the smallest angle allowed
  std::size_t maxVertices = 20000000; ///< refinement beyond this fails with a message instead of exhausting memory
  /// Called now and then with a fraction in [0, 1]; returning false aborts the meshing.
  std::function<bool(double)> progress;
};

struct BladeMesh
{
  std::vector<Eigen::Vector2d> points; ///< the outline's points first, in their order, then Steiner points
  std::vector<Eigen::Vector2d> uv;
  std::vector<int> region;
  std::vector<std::array<int, 3>> triangles; ///< counter-clockwise
};

/// Computes the LeafUV of an interior Steiner point at `xy`, from a guess (the mean LeafUV of its known neighbours).
using UVSolver = std::function<Eigen::Vector2d(const Eigen::Vector2d& xy, const Eigen::Vector2d& guess)>;

/// Checks that the outline is a simple polygon, counter-clockwise, that the midvein runs inside it from boundary to
/// boundary, and that every further vein runs inside it between two boundary points. Crossings between the
/// midvein and the veins are found when they are inserted (MeshBlade). Empty string: valid.
std::string ValidateBladeOutline(const BladeOutline& outline);

/// Meshes the blade. Returns an empty string on success; otherwise a message (the mesh is then empty).
std::string MeshBlade(
  const BladeOutline& outline, const BladeMeshParameters& options, const UVSolver& solveUV, BladeMesh& mesh);

/// Signed area of a closed polygon given by point ids (positive when counter-clockwise).
double PolygonArea(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& loop);

} // namespace plantmorph
