// SPDX-License-Identifier: GPL-3.0-or-later
// Model B of LeafOutlineSource: the space-curve leaf of paper 002 (docs/methods/leaf-outline.md).
//
// One half-margin is integrated from the Frenet-Serret equations with the chosen curvature and torsion families
// (plantmorph::IntegrateFrenet), from the base at the origin with the paper's initial frame rotated by
// `initialAngle` (default -45 degrees: T0 = (cos 45, -sin 45, 0), N0 = (sin 45, cos 45, 0), B0 = +Z, Fig. 5).
//
// Symmetry plane: contains the half-margin's chord c; its unit normal g solves |g| = 1, g.c = 0, g.e_z = Opening
// (paper eq. (9)): Opening 0 is a plane perpendicular to XY (an open leaf), values towards +-1 close it. Of the two
// solutions the one with g.T0 > 0 is taken (the initial tangent lies on the half-margin's own side). The other
// half-margin is the mirror image in that plane.
//
// Midvein: each margin sample is projected orthogonally onto the symmetry plane (eq. (3)); the projection's offset
// from the chord is split into a vertical part, scaled by `midveinStretchZ`, and a horizontal part, scaled by
// `midveinStretchXY` (eq. (2); 0 puts the midvein on the chord in plan view). Midvein sample i is that offset
// added to the point i/Resolution of the way along the chord (not to the projection's own place along it), so
// the midvein advances monotonically even where a strongly bent margin hooks back. Both end points are the
// margins'. A flat leaf whose strips would fold (a margin hooking back across them) is refused with a message.
//
// Surface: rows of samples at equal arc length s_i = i*S/Resolution on both margins and the midvein (row 0 is the
// base, the last row the apex, single vertices); each row holds `columns` points from the left margin to the
// midvein and as many to the right margin, linearly; consecutive rows are joined by quads split into two
// triangles (fans at base and apex). LeafUV: u = -0.5..0..0.5 across a row, v = arc-length fraction along the
// midvein. Finally the leaf is rotated so its chord lies along +Y (minimal rotation), base at the origin, and the
// half-margin on the -X side is the left one.
#pragma once

#include "LeafGeometry.h"

#include <plantmorph/CurvatureFamily.h>
#include <plantmorph/FrenetSerret.h>

#include <cstddef>
#include <functional>
#include <string>

namespace plantmorph
{

struct SpaceCurveParameters
{
  double length = 5.0; ///< S: arc length of a half-margin
  CurvatureFamily curvature;
  CurvatureFamily torsion; ///< torsion.mu = 0 (eta) gives a plane leaf
  double opening = 0.0;    ///< cosine of the angle between the symmetry plane's normal and +Z, (-1, 1)
  double midveinStretchZ = 1.0;
  double midveinStretchXY = 0.0;
  double initialAngle = -45.0; ///< degrees: direction of the initial tangent in the XY plane
  FrenetMethod method = FrenetMethod::RK45;
  double tolerance = 1e-10; ///< RK45 tolerance (relative to the length)
  int rk4StepsPerSample = 4;

  // Palmate leaves (paper 002 sec. 4, Fig. 8; see PalmateLeaf.h). lobes = 1 is the simple leaf above.
  int lobes = 1;           ///< 1, 3 or 5
  double lobeStart = 0.2;  ///< arc-length fraction of the previous lobe's half-margin where a lobe starts, (0, 1)
  double lobeAngle = 45.0; ///< degrees by which a lobe's initial tangent turns away from the previous one's, (0, 90]
  double lobeScale = 0.85; ///< a lobe's size relative to the previous lobe's, (0, 1.5]
  /// Palmate leaves: sub-lobes on each side of every lobe (a pinnately lobed lobe, as a watermelon's), [0, 8];
  /// 0 (the default) leaves the lobes entire (PalmateLeaf.h).
  int subLobes = 0;
  double subLobeDepth = 0.5; ///< the sinuses' depth, a fraction of the lobe's half-width there, (0, 0.9]
  /// Palmate leaves: every sinus between neighbouring lobes cut towards the base to (1 - sinusDepth) of the shorter
  /// lobe's length (its tip's distance from the base) when it is not that deep already, [0, 0.95]; 0 (the default)
  /// keeps the lobes' union as it is (PalmateLeaf.h).
  double sinusDepth = 0.0;

  SpaceCurveParameters() { torsion.mu = 0.0; }
};

struct SpaceCurveMeshParameters
{
  int resolution = 60; ///< rows (arc-length samples) from base to apex
  int columns = 6;     ///< points per half row, margin to midvein
  /// Palmate leaves only (meshed with CGAL, as Model C): paper mode (false) or quality refinement, vertex budget,
  /// progress.
  bool quality = true;
  std::size_t maxVertices = 20000000;
  std::function<bool(double)> progress;
};

inline constexpr int MaxStripColumns = 200;

/// Empty on success; otherwise a message naming the parameter and its accepted range, and `leaf` is empty.
/// lobes > 1 builds the palmate leaf (BuildPalmateLeaf).
std::string BuildSpaceCurveLeaf(
  const SpaceCurveParameters& parameters, const SpaceCurveMeshParameters& settings, LeafGeometry& leaf);

/// Empty when the parameters and settings are in range; otherwise the message naming the property and its range.
std::string ValidateSpaceCurveParameters(
  const SpaceCurveParameters& parameters, const SpaceCurveMeshParameters& settings);

/// The half-margin alone (frames at the arc lengths i*S/pieces), for tests and the palmate lobes.
std::string IntegrateHalfMargin(const SpaceCurveParameters& parameters, int pieces, std::vector<FrenetFrame>& frames);

} // namespace plantmorph
