// SPDX-License-Identifier: GPL-3.0-or-later
// Palmate (lobed) leaves of Model B: paper 002 sec. 4, Fig. 8 (docs/methods/leaf-outline.md).
//
// Lobe 1 is the simple space-curve leaf (SpaceCurveLeaf.h, flat: no torsion, Opening 0): its half-margin from the
// base, mirrored in its chord. Lobe k+1 starts on lobe k's integrated half-margin at the arc-length fraction
// `lobeStart`, its initial tangent turned clockwise from lobe k's by `lobeAngle` (its angle to the x-axis is
// smaller, as the paper says, so it heads away from lobe k), and it is lobe k's shape scaled by `lobeScale` (the
// half-margin's length scaled, S*h kept, so every lobe is a similar "incomplete elliptic leaf"). Its other half is
// its half-margin mirrored in its own chord; the pair of lobes k+1 on the other side of the leaf is the mirror
// image in lobe 1's axis. 3 lobes use lobes 1-2, 5 lobes lobes 1-3.
//
// Where a lobe's start falls between two samples of the previous lobe's margin it is added there as a sample (so
// the two lobes share that vertex exactly), unless a sample lies within 0.3 of the spacing, which is then used.
//
// Blade: the union of the lobe polygons (CGAL Boolean set operations, exact constructions) is one simple outline;
// the lobes' overlapping parts are simply inside it. Crossing points of lobe margins (the sinuses) become outline
// vertices; samples within 0.3 of the spacing of a crossing or a lobe start are dropped so no sliver triangles form.
// The midveins are straight lines from the base to each lobe's tip (the paper draws "each lobe's main vein" last
// and gives no construction; a palmate leaf's primaries radiate from the petiole), sampled at the margin spacing,
// and meshed as constraints with the outline (BladeMesher: CGAL constrained Delaunay, paper or quality mode), so
// every midvein is an interior feature line of one manifold blade. Parameters for which a lobe covers the base or
// another lobe's tip, the lobes enclose a hole, or a midvein leaves the blade are refused with a message.
//
// LeafUV (the canonical rectangle, with the base collapsed to the point (0, 0) as for a fan-shaped leaf): the
// lobes' tips, from right to left, sit on the top edge v = 1 at u_j = ((n-1)/2 - j)/n (0 for lobe 1); midvein j is
// the line u = u_j, v = arc-length fraction. The outline from the base to the rightmost tip maps to the right edge
// u = 0.5 and on along the top edge to that tip, between two tips to the top edge between their u, and from the
// leftmost tip back down the left edge u = -0.5; by arc-length fraction along each piece. Interior points take
// the mean-value interpolation over the sector between two neighbouring midveins that holds them (clamped to the
// sector's u range and to [0, 1]).
#pragma once

#include "SpaceCurveLeaf.h"

namespace plantmorph
{

/// The palmate leaf of `parameters` (lobes 3 or 5). Empty on success; otherwise a message naming the property at
/// fault, and `leaf` is empty.
std::string BuildPalmateLeaf(
  const SpaceCurveParameters& parameters, const SpaceCurveMeshParameters& settings, LeafGeometry& leaf);

} // namespace plantmorph
