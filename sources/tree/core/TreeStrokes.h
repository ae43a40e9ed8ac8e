// SPDX-License-Identifier: GPL-3.0-or-later
// Strokes to 3-D branches (paper 004 sec. 3; docs/methods/tree-from-sketch.md). Plain C++ (Eigen), no VTK.
//
// Each stroke (points in the image plane XY, in drawing order) becomes one branch:
// 1. n = StrokeControlPoints of its m points, point i at index floor(i*(m - 1)/(n - 1)), are the control points of
//    a Bezier curve of degree n - 1, sampled at SegmentsPerBranch + 1 equally spaced parameters.
// 2. The first stroke is the trunk (Mode Strokes); every later one attaches to the existing branch whose centre
//    line, projected onto the image plane, comes closest to its first point P (eq. (2)); ties are broken by
//    RandomStream(Seed, stroke index). The attachment point C = lambda*A + (1 - lambda)*B (on the parent's 3-D
//    segment, with the lambda of P's projection onto its image) is inserted into the parent's centre line, and it
//    replaces the first control point, so the branch starts exactly at C.
// 3. A sample q lifts to C + (dx, dy, dx * tan(phi)), (dx, dy) = q - C in the image plane, phi the chosen rotation
//    angle: the lifted branch projects exactly onto the smoothed stroke, lies in the plane through C's vertical that
//    makes theta with the image plane (theta = phi mapped to [0, 90) from its quadrant), and each segment's length
//    is eq. (3), sqrt(dx^2 / cos^2(theta) + dy^2). The branch's length |l2| is the sum over its segments (the
//    paper's single segment l3 generalised to a curved stroke); |l3| is the sampled stroke's planar length.
// 4. theta* solves |l2(theta*)| = L* = epsilon * (parent length) (bisection; |l2| grows with theta), 0 when
//    L* <= |l3| or the stroke is vertical. Candidates are the phyllotaxis angles frac(i*a/b)*360, i = 1..b, in
//    quadrants 1 and 2 for a stroke whose chord goes to -x, 0 and 3 otherwise (90 and 270 are excluded: theta < 90).
//    The candidate equal to theta* (1e-9 deg) wins, else the nearer in relative length error of the two either side
//    (the smaller theta on a tie); with no candidate in the quadrants the stroke stays in the image plane (theta 0,
//    phi 0 or 180).
// 5. Radius: the trunk's is Radius; a stroke child's is the template's rule at its pos on the parent (monopodial
//    parent radius*(1 - 0.618*pos), sympodial the parent's radius there), tapering to the type's end radius.
// 6. Unless StrokesOnly, every stroke branch then grows a template subtree of StrokeSubtreeDepth levels (after all
//    strokes are placed, so strokes attach only to strokes and, in Mode "Template and strokes", template branches).
//
// Ids: stroke k is base + k*block, its subtree numbered in preorder inside the block (block = the subtree's size,
// base = the template's size in Mode "Template and strokes", else 0).
//
// BranchOverrides of a stroke branch (NaN keeps), applied in this order before its subtree grows and before later
// strokes look for their parents:
// - rotation_angle replaces the chosen phyllotaxis angle phi of step 3 (the paper's rotation angle of a stroke
//   branch): the branch still projects exactly onto its stroke, theta follows from phi's quadrant and the length from
//   eq. (3). phi = 90 or 270 (mod 360) is refused: that plane is perpendicular to the image (tan phi infinite).
// - length: the lifted branch is scaled about C to that arc length (it then projects onto the stroke scaled about C).
// - u: the branch moves rigidly so that C is the parent's centre-line point at arc-length fraction u (inserted
//   there instead of the eq. (2) point); its radius rule uses the new u.
// - angle: the branch turns rigidly about C, in the plane of the parent's tangent at C and its own first direction,
//   until that first direction makes `angle` degrees with the parent's tangent.
// - radius: its base radius (tapering to the type's end radius as before).
// The trunk stroke has no parent: its u, angle and rotation_angle are ignored (as the template trunk's are); its
// length and radius apply. Overrides that change the geometry (all but radius and rotation_angle) make the branch
// leave its stroke: that is the user's explicit edit.
#pragma once

#include "StrokeFiles.h" // the stroke-file readers (ParseStrokeCsv, ParseStrokeSvg, ReadStrokeFile)
#include "TreeTemplate.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

/// How eq. (2) finds the nearest segments: a uniform grid over the segments (StrokeSegmentGrid.h; about
/// O(n log n) for n strokes), or every segment of the tree for every stroke (O(n^2); the grid's oracle in the tests).
/// Both give the same attachments.
enum class StrokeSearch
{
  Grid,
  Exhaustive,
};

/// Adds the strokes' branches (and their subtrees) to `tree` (see above). Returns an empty string or an error
/// naming the Strokes input and the stroke; the caller then discards the tree.
std::string AddStrokes(const TreeParameters& settings, const std::vector<std::vector<Eigen::Vector3d>>& strokes,
  Tree& tree, StrokeSearch search = StrokeSearch::Grid);

/// Eq. (2): distance from p to segment ab, with mu in [0, 1] the position of the closest point (0 at a).
double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double& mu);

/// Eq. (1): signed angle in degrees from segment vector a to b in the image plane, sign of (b x a).e_z.
double SignedSegmentAngle(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// Eq. (3) summed over a planar polyline: the length of its lift to a plane at theta (radians) to the image plane.
double LiftedLength(const std::vector<Eigen::Vector2d>& samples, double theta);

} // namespace plantmorph
