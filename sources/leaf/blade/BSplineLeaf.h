// SPDX-License-Identifier: GPL-3.0-or-later
// Model C of LeafOutlineSource: the B-spline leaf of paper 003 (sec. 2.1, 2.2, 2.4; docs/methods/leaf-outline.md).
//
// Three interpolating cubic B-splines (plantmorph::CubicBSpline2d, chord-length parameters): the midvein from the
// base (its first control point) to the apex (its last), and the left and right margins, which start at the base
// and end at the apex (a margin's control points that do not start or end there get the base or apex added).
// Each curve is sampled at the midvein's spacing (its length / Resolution) and the blade is meshed with CGAL's
// constrained Delaunay triangulation (plantmorph::MeshBlade, paper or quality mode), the midvein a constraint, so
// the two halves share the midvein samples.
//
// LeafUV: a margin or midvein sample has v = its arc-length fraction along its curve and u = -0.5 (left margin),
// 0 (midvein) or 0.5 (right margin); an interior point takes the mean-value-coordinate interpolation of the
// LeafUV of the boundary of the half blade it lies in (a convex combination, clamped to the canonical ranges).
//
// 3-D curves: the samples are meshed in their least-squares plane (normal towards +Z, second axis along the
// base-to-apex direction; exactly the XY plane when every control point has the same z), outline vertices keep
// their exact 3-D samples, and interior points are lifted off the plane by the mean-value interpolation of the
// outline's heights over their half blade. TCoords are those of the flat blade in that plane (eq. (6)).
#pragma once

#include "LeafGeometry.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

struct BSplineLeafParameters
{
  std::vector<Eigen::Vector3d> midvein;     ///< base to apex, at least 2 points
  std::vector<Eigen::Vector3d> leftMargin;  ///< base to apex, through x < 0 for a leaf along +Y
  std::vector<Eigen::Vector3d> rightMargin; ///< base to apex, through x > 0
};

/// Parametric initialiser and presets (control points for a leaf along +Y with its base at the origin).
enum class BSplinePreset : int
{
  Custom = 0,   ///< the user's control points
  Elliptic = 1, ///< a plain elliptic blade from length, width and control-point count (paper 003 Fig. 1)
  Cucumber = 2, ///< broad, cordate base, shallow palmate lobes, acute apex
  PinOak = 3,   ///< deeply lobed (pin oak: sinuses reaching most of the way to the midvein)
};

inline constexpr int BSplinePresetCount = 4;

/// Control points for a preset: `length` along +Y, `width` across, `count` control points per margin (>= 3).
BSplineLeafParameters MakeBSplinePreset(BSplinePreset preset, double length, double width, int count);
std::string BSplinePresetName(BSplinePreset preset);

/// The control points from three drawn polylines (LeafOutlineSource's ControlPoints input), into `parameters`'
/// midvein and margins, scaled by `scale` about the midvein's base. With `regions` (one per line: 1 midvein, 4
/// margin) the first midvein and the first two margins are taken and the left margin is the one on the left of the
/// base-to-apex direction seen from +Z; without, exactly three lines: left margin, right margin, midvein. Each
/// margin is turned to run from the base. "" or the message.
std::string ControlPointsFromLines(const std::vector<std::vector<Eigen::Vector3d>>& lines,
  const std::vector<int>* regions, double scale, BSplineLeafParameters& parameters);

/// Empty on success; otherwise a message naming the property at fault, and `leaf` is empty.
std::string BuildBSplineLeaf(
  const BSplineLeafParameters& parameters, const LeafMeshParameters& settings, LeafGeometry& leaf);

} // namespace plantmorph
