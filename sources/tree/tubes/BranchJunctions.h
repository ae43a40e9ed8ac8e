// SPDX-License-Identifier: GPL-3.0-or-later
// Welded branch joints: the tubes of a tree as ONE closed surface per connected tree, joined by convex-hull
// junctions (the idea of Baerentzen, Misztal and Welnicka, "Converting skeletal structures to quad dominant meshes",
// 2012: cut the tubes back from a branch node, take the convex hull of the cut rings, keep the tubes outside it).
// Plain C++ (Eigen, a CGAL Triangulation_3 on exact predicates for the hulls), no VTK. The tubes themselves (rings, mitres, frames,
// caps, TCoords, normals) are those of BuildTubes (BranchTubes.h).
//
// Junctions. A child's node is the point of its parent's centre line nearest to the child's first centre point.
// For each child, in a loop that only grows distances:
//  - its ring at arc length p along the child (initially (0.2 r_parent + r_child |cos a|) / sin a beyond the
//    parent's surface, a the angle between the child and the parent's axis; 0.3 r_child at the parent's end) and the parent's rings at
//    lo = node - s0 and hi = node + s1, where s0, s1 cover the child's ring and every dropped part of the child
//    (its base ring and centre-point rings before p) along the parent's axis, plus 0.3 r_parent;
//  - the child's ring is cut in a plane turned 30 deg from its cross-section towards the parent's axis (at most
//    90 deg - a: a cut parallel to the parent's axis), so it clears the parent by lying beside it rather than by
//    being pulled out along a steep child; the parent's rings are cut perpendicular to their segment;
//  - the junction's points: those rings (on the tube's own frustum) plus the
//    dropped tube parts' rings (the child's base ring and centre rings before p, the parent's centre rings between
//    lo and hi, and at an end junction the parent's end ring or apex). A ring is usable only if it is a face of
//    their convex hull with every other point at least 0.05 of its radius inside its plane; a ring that is not
//    grows its distance (a child's pull by 1.1x, the parent's margins by 1.3x; at most 48 rounds: then the junction
//    falls back). In a junction of several children two ways come first: crowded siblings (one's ring in front of
//    the other's plane) get thinner bases, 0.85x a round down to 0.35 of the parent's radius (the pipe model's
//    narrowing, further), and a child's ring behind the parent's far ring tilts 15 deg more (up to 75 deg). A tilted
//    ring must end before the child's next kept ring (that ring's mitre included), else its pull grows past it.
//  - children whose intervals [lo, hi] on one parent overlap share one junction (merged, re-checked, repeated).
//  - an interval reaching the parent's end (or, for a parent that ends in a point, where the parent's radius is
//    below 0.2 of its radius at the node) makes an end junction: no ring after, the parent's end is dropped (a
//    sympodial fork, a monopodial child at pos 1).
// The hull's facets lying in a ring (all three corners in one ring) are dropped (the ring's own cap), the rest join
// the tubes, which now start/stop at those rings and share their points. So the surface is closed and consistently
// oriented, with no internal faces and no ledge, and it contains every tube (the hull contains the dropped parts).
// The hull is convex: where branches meet at a small angle it is a blob larger than the exact union (the tests
// measure the volume against the union of two cylinders). Reach: no point of the welded surface is farther
// than 1.6 local radii from the skeleton on Table 1's templates, stroke trees and edited and merged trees
// (testing/cxx/tree/JunctionReachTest.cpp measures 1.24-1.57); before the tilted rings and the crowded-sibling rule,
// merged junctions pulled their rings out until each cleared the parent's far ring and its siblings, and the hull
// of those far rings filled the crook (2.5 local radii on the three-stroke tree).
//
// Pipe model: a lateral child (not an end junction) wider than 0.9 of its parent's radius at the node gets its base
// radius limited to that (only its first segment tapers from the limit to the template's radius at its second
// centre point; skeleton radii are unchanged). The monopodial template (child r(1 - 0.618 pos) against the
// parent's r(1 - pos)) needs this for every child; without it the hull would swallow the parent around the node.
//
// Fallback: a child whose junction cannot be built (its ring cannot be pulled back within 0.85 of its length, a
// junction interval reaching the parent's own base junction or base, a child along its parent's axis (angle below
// 5 deg) not at the parent's end, or a hull that does not have every ring as a face) stays its own closed tube
// starting where its skeleton starts (on its parent's surface; not seated: it overlaps its parent, no hole),
// counted in `fallback`. Junctions of two generations are never merged (a child whose junction would reach into its
// parent's own base junction falls back); a child at its parent's end therefore starts its search at 0.3 of its
// radius, so its ring stays close and leaves room for its own children: Table 1's three templates at full depth
// have no fallback.
// The hull is computed as the boundary of a CGAL Triangulation_3 of the junction's points (BranchJunctions.cpp).
// Parents are decided before their children (parent index < child index), each parent's children at once, levels
// in parallel; hulls in parallel; the result does not depend on the thread count (bit for bit).
//
// Output layout: TubeMesh as BuildTubes, tube t owning its rings' points and triangles; a junction's facets belong
// to the lowest-index child whose ring they touch (else the parent); dropped-part points that are hull corners
// belong to their tube. Branches that cross each other away from a junction (the templates' subtrees do) are NOT
// united: they still intersect.
#pragma once

#include "BranchTubes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

struct JunctionReport
{
  std::int64_t junctions = 0;              ///< convex hulls built
  std::int64_t welded = 0;                 ///< children joined by a junction
  std::int64_t merged = 0;                 ///< junctions holding more than one child
  std::int64_t endJunctions = 0;           ///< junctions at a parent's end (forks)
  std::int64_t narrowed = 0;               ///< children whose base radius the pipe model limited
  std::int64_t fallback = 0;               ///< children left as their own closed tube (see "Fallback")
  std::vector<std::int64_t> fallbackTubes; ///< their indices, ascending
};

/// BuildTubes' tubes, joined at their parents by convex-hull junctions (see above). Same inputs and errors as
/// BuildTubes.
///
/// Pieces: with `selected` (one entry per tube, 1: build it; BranchPieces.h plans them) only those tubes' points and
/// triangles are made, each exactly as in the whole build (the junctions are decided for the selected tubes, their
/// families and their ancestors only, which is all a junction depends on), plus copies of the other tubes' points
/// their facets use; the mesh is then KeepTubes' (BranchPieces.h). A junction's facets stay with the tube that owns
/// them (above), so a junction whose tubes lie in two pieces is computed in both and each writes its own facets.
/// The report then counts the junctions on the selected tubes and the selected tubes' narrowing and fallback:
/// summed over the pieces of a plan, the whole build's counts.
std::string BuildWeldedTubes(const std::vector<TubeInput>& tubes, int sides, TubeMesh& mesh,
  const ParallelFor& parallel = SerialFor, JunctionReport* report = nullptr,
  const std::vector<char>* selected = nullptr);

} // namespace plantmorph
