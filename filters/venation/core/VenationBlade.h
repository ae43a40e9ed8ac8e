// SPDX-License-Identifier: GPL-3.0-or-later
// The blade VenationFilter grows veins on: a triangle mesh given in a flat 2-D working plane, with every vertex's
// LeafUV (docs/methods/venation.md). Point location in both spaces goes through uniform grids of triangles, so mapping
// a vein point costs the same however fine the blade.
//
// The blade as given (3-D points, LeafUV, triangles) becomes the working plane by VenationWorkingPlane; vein points
// found in the working plane go back onto the 3-D surface by their triangle and barycentric weights (InterpolateAt),
// and the relief raises the surface's points along its normals (RaisedAlongNormals).
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace plantmorph
{

struct VenationBlade
{
  std::vector<Eigen::Vector2d> points; ///< working-plane coordinates of every vertex
  std::vector<Eigen::Vector2d> uv;     ///< LeafUV of every vertex
  std::vector<std::array<int, 3>> triangles;
};

/// The 2-D working plane of a blade given by its 3-D `points`, their LeafUV `uv` and its `triangles`: the points'
/// own (x, y) when they all have the same z; else, when they lie in one plane (within 1e-6 of the bounding box's
/// diagonal), their coordinates along that plane's major axis and the axis normal to it; else, when the blade
/// projects onto its least-squares plane one to one (every triangle keeping its orientation) and its projected area
/// is at least 0.8 of its area, that projection (a fitted scan's LeafUV is a rectangle: u is +-0.5 at both margins);
/// else (`flat` false: a strongly curved blade) LeafUV scaled by the blade's mean stretch along u and v, su and sv from the least-squares fit of
/// |dP|^2 = su^2 du^2 + sv^2 dv^2 over the triangles' edges (a scale not positive and finite: the diagonal).
std::vector<Eigen::Vector2d> VenationWorkingPlane(const std::vector<Eigen::Vector3d>& points,
  const std::vector<Eigen::Vector2d>& uv, const std::vector<std::array<int, 3>>& triangles, bool& flat);

/// The point of the segment [a, b] nearest p (a when the segment has no length).
Eigen::Vector2d ClosestOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// Where a point fell: its triangle and barycentric weights (summing to 1).
struct BladeLocation
{
  int triangle = -1;
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();
};

/// Per-vertex `values` (Eigen vectors) of the mesh `triangles` interpolated at `at` (a location with a triangle):
/// the weighted values summed from zero in the triangle's vertex order.
template <typename T>
T InterpolateAt(const std::vector<std::array<int, 3>>& triangles, const std::vector<T>& values, const BladeLocation& at)
{
  const auto& t = triangles[static_cast<std::size_t>(at.triangle)];
  T sum = T::Zero();
  for (int k = 0; k < 3; ++k)
    sum += at.weights[k] * values[t[k]];
  return sum;
}

/// Each of `points` moved `heights` along its unit normal: `normals` when given (one per point), else the sum of
/// the cross products of its triangles' edges (area-weighted); a zero normal raises along +z.
std::vector<Eigen::Vector3d> RaisedAlongNormals(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::array<int, 3>>& triangles, std::vector<Eigen::Vector3d> normals,
  const std::vector<double>& heights);

class BladeLocator
{
public:
  /// Indexes the blade; an error message (naming what is wrong with the input) if it cannot be used.
  std::string Build(const VenationBlade& blade);

  /// The triangle holding p in the working plane (points up to `tolerance` outside a triangle count, the best
  /// triangle wins); triangle -1 when p is outside the blade.
  BladeLocation Locate(const Eigen::Vector2d& p, double tolerance) const;
  /// The triangle holding uv in LeafUV space, or the nearest one when uv is outside the blade's LeafUV image (for
  /// example (u, 0) of a blade whose base is one point): then the nearest point of that triangle.
  BladeLocation LocateUV(const Eigen::Vector2d& uv) const;
  /// The working-plane point at LeafUV uv (see LocateUV).
  Eigen::Vector2d PointAtUV(const Eigen::Vector2d& uv) const;
  /// Interpolates per-vertex values at a location.
  template <typename T>
  T Interpolate(const std::vector<T>& values, const BladeLocation& at) const
  {
    const auto& t = this->Blade->triangles[at.triangle];
    return at.weights[0] * values[t[0]] + at.weights[1] * values[t[1]] + at.weights[2] * values[t[2]];
  }

  /// The boundary as closed loops of vertex ids, counter-clockwise in the working plane; the outer loop first.
  const std::vector<std::vector<int>>& BoundaryLoops() const { return this->Loops; }
  double Area() const { return this->TotalArea; }
  Eigen::Vector2d Lower() const { return this->Low; }
  Eigen::Vector2d Upper() const { return this->High; }
  /// Mean edge length of the mesh.
  double EdgeLength() const { return this->MeanEdge; }

private:
  struct Grid
  {
    Eigen::Vector2d low = Eigen::Vector2d::Zero();
    double cell = 1.0;
    int width = 1, height = 1;
    std::vector<std::vector<int>> cells;
    void Build(const std::vector<Eigen::Vector2d>& points, const std::vector<std::array<int, 3>>& triangles,
      const std::vector<char>& usable);
    int Index(int x, int y) const { return y * this->width + x; }
    std::array<int, 2> Cell(const Eigen::Vector2d& p) const;
  };
  BladeLocation Find(const Grid& grid, const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p,
    double tolerance, const std::vector<char>& usable) const;

  const VenationBlade* Blade = nullptr;
  Grid PlaneGrid, UVGrid;
  std::vector<char> PlaneUsable, UVUsable; ///< triangles with a non-zero area in each space
  std::vector<std::vector<int>> Loops;
  double TotalArea = 0.0;
  double MeanEdge = 0.0;
  Eigen::Vector2d Low = Eigen::Vector2d::Zero(), High = Eigen::Vector2d::Zero();
};

} // namespace plantmorph
