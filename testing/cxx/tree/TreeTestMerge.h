// SPDX-License-Identifier: GPL-3.0-or-later
// The merge the tree tests share: another tree's skeleton and the placement that grafts it onto this tree.
#pragma once

#include "TreeTemplate.h"

#include <vector>

namespace plantmorph
{
namespace tree_test
{
/// The skeleton (ids, parents, centre lines, radii) of a built tree, as the merge input takes it.
inline std::vector<SkeletonBranch> SkeletonOf(const Tree& tree)
{
  std::vector<SkeletonBranch> skeleton;
  for (const TreeBranch& b : tree.branches)
    skeleton.push_back({ b.id, b.parentId, b.centre, b.radii });
  return skeleton;
}

/// Grafts the merged tree onto branch 3 (a child of the trunk) at 0.3 of its length, turned 40 degrees out and 70
/// about it, at half its size.
inline void MergeOntoBranch3(TreeParameters& m)
{
  m.mergeParent = 3;
  m.mergeU = 0.3;
  m.mergeAngle = 40.0;
  m.mergeRotation = 70.0;
  m.mergeScale = 0.5;
}
} // namespace tree_test
} // namespace plantmorph
