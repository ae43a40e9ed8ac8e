// SPDX-License-Identifier: GPL-3.0-or-later
// What every LeafOutlineSource model produces, before it becomes vtkPolyData: a blade mesh with LeafUV, Region and
// TCoords (flat, z = 0, unless `z` is filled), and the outline polylines as point ids into the blade's points.
#pragma once

#include "BladeMesher.h"

#include <Eigen/Core>

#include <array>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

struct LeafGeometry
{
  BladeMesh blade;
  std::vector<Eigen::Vector2d> tcoords;       ///< paper 003 eq. (6): bounding-box normalised x, y of the flat blade
  std::vector<int> leftMargin;                ///< base to apex, through u < 0
  std::vector<int> rightMargin;               ///< base to apex, through u > 0
  std::vector<int> midvein;                   ///< base to apex
  std::vector<std::vector<int>> lobeMidveins; ///< palmate leaves: each lateral lobe's midvein, base to its tip
  std::vector<int> subLobeTips;               ///< palmate leaves with sub-lobes: the sub-lobes' tips on the margin
  std::size_t uvInversionFailures = 0;        ///< interior points whose LeafUV fell back to the neighbours' mean
  std::vector<double> z;                      ///< height of every blade point; empty for a flat blade (z = 0)
  std::vector<Eigen::Vector3d> normals;       ///< unit normal of every blade point; empty for a flat blade (+Z)
};

/// Area-weighted vertex normals of a triangle mesh given by 3-D points (zero-area neighbourhoods get +Z).
std::vector<Eigen::Vector3d> VertexNormals(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles);

struct LeafMeshParameters
{
  int resolution = 60; ///< segments along the midvein; the margins are sampled at the same spacing
  bool quality = true; ///< CGAL Delaunay refinement (min angle ~20.7 deg, max edge = the midvein spacing)
  std::size_t maxVertices = 20000000;
  std::function<bool(double)> progress; ///< fraction in [0, 1]; false aborts
};

inline constexpr int MinResolution = 2;
inline constexpr int MaxResolution = 4000;

/// Empty when `resolution` is in [MinResolution, MaxResolution], else the message naming Resolution and its range.
std::string ValidateResolution(int resolution);

/// The mesher options for these settings: the meshing mode, edges of `spacing` (the midvein spacing), the vertex
/// budget, and the settings' progress mapped onto [0.05, 0.9] (sampling before, output after).
BladeMeshParameters MeshParametersFor(const LeafMeshParameters& settings, double spacing);

/// Runs `build` (returning an error message or "") on an emptied `leaf`, and empties it again if it failed: a
/// model's builder either fills the whole leaf or leaves nothing.
template <typename Build>
std::string BuildAllOrNothing(LeafGeometry& leaf, Build&& build)
{
  leaf = LeafGeometry();
  std::string error = build();
  if (!error.empty())
    leaf = LeafGeometry();
  return error;
}

/// TCoords of eq. (6) for the given points.
std::vector<Eigen::Vector2d> BoundingBoxTextureCoordinates(const std::vector<Eigen::Vector2d>& points);

/// Length of the curve over [a, b], as a polyline of `samples` pieces.
double CurveLength(const std::function<Eigen::Vector2d(double)>& curve, double a, double b, int samples = 4096);

/// Parameters t0 = a < t1 < ... < tn = b that cut the curve into `pieces` pieces of equal arc length
/// (to the accuracy of a dense polyline); {a} when pieces < 1 or the curve has no length.
std::vector<double> SampleByArcLength(
  const std::function<Eigen::Vector2d(double)>& curve, double a, double b, int pieces);

/// Winding-number test: is p inside the closed polygon (first point not repeated)? Points on an edge may go either
/// way.
bool InsidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

/// Mean-value coordinates interpolation at x of values given at the vertices of a closed polygon (x inside it;
/// exact at vertices, linear along edges). In a non-convex polygon the weights may be negative: callers clamp.
Eigen::Vector2d MeanValueInterpolate(
  const std::vector<Eigen::Vector2d>& polygon, const std::vector<Eigen::Vector2d>& values, const Eigen::Vector2d& x);

} // namespace plantmorph
