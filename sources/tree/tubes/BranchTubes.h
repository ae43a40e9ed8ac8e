// SPDX-License-Identifier: GPL-3.0-or-later
// Watertight branch tubes (docs/methods/tree-from-sketch.md). Plain C++ (Eigen), no VTK.
//
// Each branch is one closed tube along its centre line: `sides` vertices per ring, one ring per centre point, shared
// by the two segments meeting there. A ring at an interior point lies in the bisector (mitre) plane of the two
// segments and is the exact intersection of that plane with both segments' cylinders (an ellipse, semi-axes r and
// r / cos(bend/2)), so consecutive segments meet without gap or overlap. The rings' angular origin is transported
// without twist: ring k's cross-section directions are carried along segment k - 1 unchanged (the exact
// rotation-minimising transport of a polyline; common/RotationMinimizingFrames.h's double reflection is its
// smooth-curve counterpart), so each segment is an exact prism or frustum cut by two planes, and a tube of constant
// radius has volume (ring polygon area) x (centre-line length). The base is closed by a fan to its
// centre; the end by a fan to its centre (end radius > 0, sympodial) or to a single apex point (end radius 0,
// monopodial). Every edge is in exactly two triangles, triangles face outwards.
//
// TCoords: v runs along the tube from 0 at its base to 1 at its end (by arc length); u runs around it,
// u = 1 - |1 - 2j/sides| for ring vertex j (0 at the frame's normal, 1 opposite, back to 0): a mirrored wrap needs
// no seam, so the points are shared and the surface stays closed. Cap centres get u = 0.5. Normals: the ring
// direction (radial) for ring vertices, -/+ the tangent for the cap centres and the apex.
//
// Joints (a tube with a `parent`), "seated tubes" (TreeFromSketchSource's `Joints` = 1; the default, welded joints
// that make one closed surface per tree, is BuildWeldedTubes in BranchJunctions.h): the tube's base ring is seated
// on the parent tube's faceted surface. Ring-0
// vertex j slides along its own lateral edge (the line through it and ring-1 vertex j, so the first segment stays
// the same prism or frustum, its side faces planar) to the last point where that line leaves the parent tube's
// triangles before ring 1 (at most 0.95 of the way there; looking back at most 4 (child + parent radius)); the base
// cap's centre slides along the axis likewise.
// So the child's wall starts exactly on the parent's surface: neither buried in the parent nor floating off it.
// What remains (the parent surface is not cut, no Boolean union): the child's base cap lies inside the parent (a
// lens between it and the parent's surface patch inside the ring is inside both tubes). A ring vertex whose line
// meets the parent nowhere before ring 1 cannot touch it: this happens where the child is wider than its parent
// there (always so in the monopodial template, whose child radius r(1 - 0.618 pos) exceeds the parent's linear taper
// r(1 - pos)) and at sympodial forks, where part of a child's base hangs past the parent's end cap. Such a vertex
// slides to the point of its line closest to the parent's centre line (within that window), so the
// child's wall reaches down beside the parent and its base cap shows there as a ledge outside the parent (no hole:
// every tube is closed); `missed` counts them. `clamped` counts those whose exit lies beyond 0.95 of the way to
// ring 1 (they stay inside the parent, at 0.95), `buried` those whose ring-1 vertex is itself inside the parent (a
// child starting on its parent's axis, angle 0: left in place). Parents are seated before their children (parent
// index < child index).
//
// Bends: ring k's mitre ellipse reaches r_k tan(bend_k / 2) along the centre line on the inner side; while
// consecutive ones do not cross (each segment longer than r_k tan(bend_k/2) + r_{k+1} tan(bend_{k+1}/2)) the tube
// does not self-intersect; bends above 170 degrees are clamped to 170 in the ring's stretch.
#pragma once

#include <plantmorph/ParallelFor.h>
#include <plantmorph/memory/CloudArray.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

struct TubeInput
{
  std::vector<Eigen::Vector3d> centre;               ///< at least 2 points; coincident consecutive points are removed
  std::vector<double> radii;                         ///< one per centre point, > 0 except possibly the last
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX(); ///< where ring vertex 0 points at the base
  /// Index of the tube this one grows from (its base ring is seated on that tube's surface), or -1. Must be smaller
  /// than this tube's own index.
  std::int64_t parent = -1;
};

/// How the base rings of tubes with a parent were seated (see above): ring vertices in all.
struct JointReport
{
  std::int64_t seated = 0;  ///< on the parent's surface
  std::int64_t missed = 0;  ///< their line misses the parent: moved to its closest approach to the parent's axis
  std::int64_t clamped = 0; ///< exit beyond 0.95 of the way to ring 1: left inside the parent at 0.95
  std::int64_t buried = 0;  ///< ring 1 itself is inside the parent: left in place (inside)
};

/// The mesh's arrays: malloc memory, unset when sized, plain pages.
template <class T>
using MeshArray = CloudArray<T, false>;

struct TubeMesh
{
  // Unset when sized (the threads write every entry) and handed over uncopied to the VTK output (CloudArray::Release).
  MeshArray<double> points;          ///< x, y, z
  MeshArray<float> normals;          ///< x, y, z per point
  MeshArray<float> tcoords;          ///< u, v per point
  MeshArray<std::int32_t> triangles; ///< three point ids each
  /// Tube t owns points [pointOffsets[t], pointOffsets[t + 1]) and triangles likewise; size tubes + 1.
  std::vector<std::int64_t> pointOffsets;
  std::vector<std::int64_t> triangleOffsets;
  std::size_t PointCount() const { return this->points.size() / 3; }
  std::size_t TriangleCount() const { return this->triangles.size() / 3; }
};

/// A tube's centre line without coincident consecutive points (the later radius kept); `apex`: it ends in a point.
struct CleanedTube
{
  std::vector<Eigen::Vector3d> centre;
  std::vector<double> radii;
  bool apex = false;
};

/// Checks and cleans every tube as BuildTubes does (sides in [3, 256], one radius per point, finite, non-negative
/// radii, positive before the end, at least 2 distinct points, parent -1 or a smaller index); returns an empty string
/// or the message.
std::string CleanTubes(const std::vector<TubeInput>& tubes, int sides, std::vector<CleanedTube>& cleaned);

/// Writes point `index` of `mesh` (position, normal and TCoords (u, v)); the arrays must be sized.
void SetMeshPoint(
  TubeMesh& mesh, std::int64_t index, const Eigen::Vector3d& x, const Eigen::Vector3d& normal, double u, double v);

/// A ring's `sides` vertex angles: cos and sin of 2 pi j / sides, and TCoords' u = 1 - |1 - 2j / sides|.
struct RingAngles
{
  explicit RingAngles(int sides);
  std::vector<double> cosines, sines, around;
};

/// A mitre ring vertex's offset per unit radius: `w` (unit, across the segment of direction `d` ending at the ring)
/// moved along `d` onto the ring's bisector plane of unit normal `plane` (the plane's tilt clamped at 85 degrees).
Eigen::Vector3d MitreOffset(const Eigen::Vector3d& w, const Eigen::Vector3d& d, const Eigen::Vector3d& plane);

/// Writes one tube's triangles into `triangles` from index `q` on: a fan from point `baseCentre` to ring 0 (when
/// >= 0), the strips between rings k and k + 1 (all, or those with bandAfter[k] when it is given), and a fan from
/// ring `rings - 1` to point `end` (when >= 0: an apex when `apex`, else the end cap's centre), all facing outwards.
/// Ring k is the `sides` consecutive point ids from firstRing + k sides. Returns the index after the last written.
std::size_t TubeTriangles(MeshArray<std::int32_t>& triangles, std::size_t q, std::int64_t firstRing, std::size_t rings,
  int sides, std::int64_t baseCentre, std::int64_t end, bool apex, const std::vector<char>* bandAfter = nullptr);

/// Builds all tubes (in parallel through `parallel` when given: offsets are computed first, so the result does
/// not depend on how the range is cut). Returns an empty string or a message (sides out of [3, 256], a tube with
/// fewer than 2 distinct points, a non-finite point or radius, more than 2^31 - 1 points, a parent index not
/// below the tube's own).
/// With `selected` (one entry per tube, 1: build it) only those tubes are kept, as in the whole build: they and their
/// ancestors (whose seated surfaces they are seated on) are built, then cut down by KeepTubes (BranchPieces.h); the
/// report counts the selected tubes' ring vertices.
std::string BuildTubes(const std::vector<TubeInput>& tubes, int sides, TubeMesh& mesh,
  const ParallelFor& parallel = SerialFor, JointReport* joints = nullptr, const std::vector<char>* selected = nullptr);

/// The last crossing of the line p + t e (t < tMax) with tube `tube`'s triangles: the largest such t, or NaN if
/// there is none; *leaving says whether the line leaves the tube there (e against the outward triangle's normal).
double LastCrossing(const TubeMesh& mesh, std::size_t tube, const Eigen::Vector3d& p, const Eigen::Vector3d& e,
  double tMax, bool* leaving = nullptr);

} // namespace plantmorph
