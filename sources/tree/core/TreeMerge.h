// SPDX-License-Identifier: GPL-3.0-or-later
// Merging a second tree into this one (docs/methods/tree-from-sketch.md; paper 004 sec. 3.2 and Fig. 11: at a segment
// of a branch the user adds a new branch with its sub-branches, giving a merged tree). Plain C++ (Eigen), no VTK.
//
// The second tree is a skeleton: branches with ids, parent ids, centre lines and radii, e.g. another
// TreeFromSketchSource's Skeleton output (its BranchId / ParentId cell arrays, Radius point array). It must be one
// tree: ids >= 0 and unique, exactly one root (ParentId -1), every other ParentId naming one of its branches, every
// branch reachable from the root (no cycles), at least 2 finite points a branch, radii finite and >= 0 with the first
// > 0. Anything else is refused with a message starting "Merge input is not a tree:".
//
// Placement: a similarity x -> target + MergeScale * R * (x - root base), root base = the first point of its root.
// - MergeParentBranch >= 0: the second tree grows from that branch of this tree as a template child would (its +Y
//   becomes the child direction): R = F(MergeU) * R_y(MergeRotation) * R_z(MergeAngle), F the branch's frame at
//   MergeU, target = the branch's surface point there (ChildBase). The branch must exist (not deleted).
// - MergeParentBranch = -1: a second trunk, R = R_y(MergeRotation) * R_z(MergeAngle), target = MergeOffset.
// Radii scale by MergeScale. Merged branches grow no template children; leaves grow on merged twigs like on others.
//
// Ids: merged branch = base + its id in the second tree, base = the first id this tree's own properties can never
// use (the template's SubtreeSize(ChildCount, Depth) unless Mode is Strokes, plus one block per stroke). They do not
// depend on deletions or overrides of any branch, so DeletedBranches and BranchOverrides address merged branches
// and keep their meaning in saved state files (they shift only if this tree's Depth, ChildCount, Mode or number of
// strokes changes, like stroke ids). base + the largest id must stay below 2^31.
//
// Editing merged branches: DeletedBranches removes a merged branch and its merged subtree. BranchOverrides: radius
// scales the branch's radii (taper kept) so its base radius is the value; length scales its centre line about its
// base, its sub-branches moving with their bases; u, angle and rotation_angle of the merged root replace MergeU,
// MergeAngle and MergeRotation (u is meaningless for a second trunk and ignored). u, angle and rotation_angle of any
// other merged branch are refused with an error: its shape is the second tree's, so edit that branch in the second
// tree's own source (by its id there, this id - base).
#pragma once

#include "TreeTemplate.h"

#include <string>
#include <vector>

namespace plantmorph
{

/// The first BranchId this tree's own properties never use (see above) for `strokeCount` strokes.
long long MergeIdBase(const TreeParameters& settings, std::size_t strokeCount);

/// Empty if `second` is one tree as above, else the message.
std::string ValidateSkeletonIsTree(const std::vector<SkeletonBranch>& second);

/// Appends the second tree's branches to `tree` (after its own branches and strokes, before leaves). Returns an
/// empty string or an error naming the input or property.
std::string MergeTree(
  const TreeParameters& settings, std::size_t strokeCount, const std::vector<SkeletonBranch>& second, Tree& tree);

/// For splitting into pieces (BranchPieces.h' PlanPieces): 1 for each merged tree's root (a merged branch whose
/// parent is not merged; a second trunk has no parent anyway), so a merged tree is a unit of its own; one per branch.
std::vector<char> MergedRoots(const Tree& tree);

} // namespace plantmorph
