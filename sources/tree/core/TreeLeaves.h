// SPDX-License-Identifier: GPL-3.0-or-later
// Leaves of paper 004 (sec. 2.3, 3.4; docs/methods/tree-from-sketch.md). Plain C++ (Eigen), no VTK.
//
// Leaves sit on the twigs: the branches without children in the finished tree (the template's depth-0 twigs, and
// also a branch whose children were all deleted, or a stroke branch without subtree). Leaf j = 1..LeafCount of a
// twig sits at pos_j = (1 - LeafRatio) + j*LeafRatio/LeafCount (the children's rule; LeafType Sympodial: all at the
// tip, a whorl), turned about the twig by frac(j*a/b)*360 deg and away from it by LeafAngle, its base on the twig's
// surface. Its axes: x across the blade, y along the midrib, z the blade's normal; a quad or an instanced leaf mesh
// (base at its origin, midrib along +Y, XY plane) is placed with them, TreeLeaf::length long.
//
// Leaf sizes: young leaves near a shoot's tip are smaller, and leaves of one plant vary at random. Leaf j's length is
// LeafScale * (1 + t_j (LeafTipScale - 1)) * exp(LeafScaleSpread * z_j): t_j = j / LeafCount is its place along the
// leafy stretch (0 at the stretch's start, pos 1 - LeafRatio; 1 at the twig's tip; every leaf of a Sympodial whorl
// or of LeafRatio 0 sits at the tip, t = 1), and z_j a standard normal drawn from the stream (Seed, leaf id), so the
// same Seed gives the same sizes and a leaf's size does not depend on the others. The taper is linear in the leaf's
// place; the spread is log-normal (the log of a length has standard deviation LeafScaleSpread; its median is the
// taper's length). LeafTipScale 1 and LeafScaleSpread 0 (the defaults) give every leaf LeafScale exactly.
//
// LeafType Willow first reshapes every template twig into the willow's pendulous Bezier curve, control points
// (0, 0), (0.1, -0.05), (0.1, -0.4), (0.1, -0.8) times the twig's length, in the vertical plane through the twig's
// base direction (local x the horizontal part of that direction, local y world +Y); leaves then spread along it.
#pragma once

#include "TreeTemplate.h"

#include <string>

namespace plantmorph
{

/// Reshapes willow twigs and fills tree.leaves (see above). Returns an empty string, or an error if the leaves
/// would exceed MaxSegments (the memory budget, shared with segments); tree.leaves is then empty.
std::string PlaceLeaves(const TreeParameters& settings, Tree& tree);

/// Leaf `leafId`'s length at place t in [0, 1] along its twig's leafy stretch (see above).
double LeafLength(const TreeParameters& settings, double t, int leafId);

/// The willow twig's Bezier control points (unit length), x outward, y up.
const std::vector<Eigen::Vector2d>& WillowControlPoints();

} // namespace plantmorph
