// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeMerge.h"

#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace plantmorph
{

namespace
{
std::string NotATree(const std::string& what)
{
  return "Merge input is not a tree: " + what +
    " (connect a tree skeleton with BranchId and ParentId: another TreeFromSketchSource's Skeleton output, port 1)";
}

double ArcLength(const std::vector<Eigen::Vector3d>& centre)
{
  double total = 0.0;
  for (std::size_t k = 1; k < centre.size(); ++k)
  {
    total += (centre[k] - centre[k - 1]).norm();
  }
  return total;
}
} // namespace

long long MergeIdBase(const TreeParameters& s, std::size_t strokeCount)
{
  long long base = 0;
  if (s.mode != TreeMode::Strokes)
  {
    base += SubtreeSize(s.childCount, s.depth);
  }
  if (s.mode != TreeMode::Template)
  {
    const long long block = SubtreeSize(s.childCount, s.strokesOnly ? 0 : s.strokeSubtreeDepth);
    base += static_cast<long long>(strokeCount) * block;
  }
  return base;
}

std::string ValidateSkeletonIsTree(const std::vector<SkeletonBranch>& second)
{
  if (second.empty())
  {
    return NotATree("it has no branches");
  }
  std::map<long long, std::size_t> index;
  long long roots = 0;
  for (std::size_t i = 0; i < second.size(); ++i)
  {
    const SkeletonBranch& b = second[i];
    std::ostringstream where;
    where << "branch " << b.id;
    if (b.id < 0)
      return NotATree("BranchId " + std::to_string(b.id) + " is negative");
    if (!index.emplace(b.id, i).second)
      return NotATree("BranchId " + std::to_string(b.id) + " appears on more than one polyline");
    if (b.parentId < -1)
      return NotATree(where.str() + " has ParentId " + std::to_string(b.parentId) + " (-1 or a BranchId expected)");
    roots += b.parentId == -1 ? 1 : 0;
    if (b.centre.size() < 2 || b.radii.size() != b.centre.size())
      return NotATree(where.str() + " has fewer than 2 points (or not one Radius per point)");
    for (std::size_t k = 0; k < b.centre.size(); ++k)
    {
      if (!b.centre[k].allFinite() || !std::isfinite(b.radii[k]) || b.radii[k] < 0.0)
        return NotATree(where.str() + ", point " + std::to_string(k) + ": point or Radius not finite, or Radius < 0");
    }
    if (!(b.radii[0] > 0.0))
      return NotATree(where.str() + " has Radius 0 at its base");
    if (!(ArcLength(b.centre) > 0.0))
      return NotATree(where.str() + " has zero length");
  }
  if (roots != 1)
    return NotATree(std::to_string(roots) + " branches have ParentId -1 (exactly one root expected)");
  std::size_t reached = 0;
  std::map<long long, std::vector<std::size_t>> children;
  std::size_t root = 0;
  for (std::size_t i = 0; i < second.size(); ++i)
  {
    if (second[i].parentId == -1)
    {
      root = i;
      continue;
    }
    if (!index.count(second[i].parentId))
      return NotATree("branch " + std::to_string(second[i].id) + " has ParentId " + std::to_string(second[i].parentId) +
        ", which is no branch of it");
    children[second[i].parentId].push_back(i);
  }
  std::vector<std::size_t> stack = { root };
  while (!stack.empty())
  {
    const std::size_t i = stack.back();
    stack.pop_back();
    ++reached;
    for (std::size_t c : children[second[i].id])
      stack.push_back(c);
  }
  if (reached != second.size())
    return NotATree(std::to_string(second.size() - reached) + " branches are not reachable from the root (a cycle)");
  return {};
}

std::string MergeTree(
  const TreeParameters& s, std::size_t strokeCount, const std::vector<SkeletonBranch>& second, Tree& tree)
{
  std::string error = ValidateSkeletonIsTree(second);
  if (!error.empty())
  {
    return error;
  }
  const long long base = MergeIdBase(s, strokeCount);
  long long largest = 0;
  std::size_t root = 0;
  std::map<long long, std::vector<std::size_t>> children;
  for (std::size_t i = 0; i < second.size(); ++i)
  {
    largest = std::max(largest, second[i].id);
    if (second[i].parentId == -1)
      root = i;
    else
      children[second[i].parentId].push_back(i);
  }
  if (base + largest > std::numeric_limits<int>::max())
  {
    std::ostringstream out;
    out << "Merge input: its BranchIds up to " << largest << " plus this tree's id base " << base
        << " exceed 2147483647 (merge a smaller tree, or lower this tree's Depth or ChildCount)";
    return out.str();
  }

  // Placement of the root, with the root's own override of u, angle and rotation.
  const int rootId = static_cast<int>(base + second[root].id);
  double u = s.mergeU, angle = s.mergeAngle, rotation = s.mergeRotation;
  for (const auto& [id, o] : s.overrides)
  {
    if (id < base || id > base + largest)
      continue;
    if (id == rootId)
    {
      u = std::isnan(o.u) ? u : o.u;
      angle = std::isnan(o.angle) ? angle : o.angle;
      rotation = std::isnan(o.rotation) ? rotation : o.rotation;
    }
    else if (!std::isnan(o.u) || !std::isnan(o.angle) || !std::isnan(o.rotation))
    {
      std::ostringstream out;
      out << "BranchOverrides row of branch " << id << ": u, angle and rotation_angle apply to the merged tree's root ("
          << rootId << ") only; the other merged branches keep the second tree's shape (edit branch " << id - base
          << " in the second tree's own source, or override its length and radius here)";
      return out.str();
    }
  }
  const TreeBranch* host = nullptr;
  Eigen::Matrix3d rotationMatrix;
  Eigen::Vector3d target;
  if (s.mergeParent >= 0)
  {
    for (const TreeBranch& b : tree.branches)
    {
      host = b.id == s.mergeParent ? &b : host;
    }
    if (!host)
    {
      std::ostringstream out;
      out << "MergeParentBranch = " << s.mergeParent
          << " names no branch of this tree (deleted, or not one of its BranchIds; -1 makes a second trunk)";
      return out.str();
    }
    Eigen::Vector3d axisPoint;
    Eigen::Matrix3d frame;
    double radius = 0.0;
    BranchFrameAt(*host, u, axisPoint, frame, radius);
    rotationMatrix = frame * RotationY(rotation) * RotationZ(angle);
    target = ChildBase(axisPoint, frame, radius, angle, rotation);
  }
  else
  {
    rotationMatrix = RotationY(rotation) * RotationZ(angle);
    target = s.mergeOffset;
  }
  const Eigen::Vector3d rootBase = second[root].centre[0];
  const auto place = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    return target + s.mergeScale * (rotationMatrix * (x - rootBase));
  };

  // Preorder from the root; deleted branches take their subtrees with them. Length overrides move sub-branches.
  struct Visit
  {
    std::size_t index;
    int parentDepth;
    Eigen::Vector3d shift;
  };
  std::vector<Visit> stack = { { root, host ? host->depth : -1, Eigen::Vector3d::Zero() } };
  tree.mergeIdBase = base;
  while (!stack.empty())
  {
    const Visit visit = stack.back();
    stack.pop_back();
    const SkeletonBranch& source = second[visit.index];
    TreeBranch b;
    b.id = static_cast<int>(base + source.id);
    if (s.deletedBranches.count(b.id))
    {
      continue;
    }
    b.parentId = source.parentId == -1 ? (host ? host->id : -1) : static_cast<int>(base + source.parentId);
    b.depth = visit.parentDepth + 1;
    b.level = 0;
    b.mergedId = static_cast<int>(source.id);
    b.straight = false;
    b.centre.resize(source.centre.size());
    for (std::size_t k = 0; k < source.centre.size(); ++k)
    {
      b.centre[k] = place(source.centre[k]) + visit.shift;
    }
    b.radii = source.radii;
    for (double& r : b.radii)
    {
      r *= s.mergeScale;
    }
    double stretch = 1.0;
    const auto found = s.overrides.find(b.id);
    if (found != s.overrides.end())
    {
      const BranchOverride& o = found->second;
      if (!std::isnan(o.length))
      {
        stretch = o.length / ArcLength(b.centre);
        for (std::size_t k = 1; k < b.centre.size(); ++k)
        {
          b.centre[k] = b.centre[0] + stretch * (b.centre[k] - b.centre[0]);
        }
      }
      if (!std::isnan(o.radius))
      {
        const double factor = o.radius / b.radii[0];
        for (double& r : b.radii)
        {
          r *= factor;
        }
      }
    }
    b.length = ArcLength(b.centre);
    b.radius = b.radii.front();
    b.radiusEnd = b.radii.back();
    if (source.parentId == -1)
    {
      b.position = host ? u : 0.0;
      b.angle = angle;
      b.rotation = rotation;
    }
    const Eigen::Vector3d y = PolylineTangents(b.centre)[0];
    const Eigen::Vector3d z = PerpendicularTo(y, rotationMatrix.col(2));
    b.frame.col(1) = y;
    b.frame.col(2) = z;
    b.frame.col(0) = y.cross(z);
    // Children: pushed in reverse so they come out in input order.
    const auto& kids = children[source.id];
    for (auto it = kids.rbegin(); it != kids.rend(); ++it)
    {
      const Eigen::Vector3d childBase = place(second[*it].centre[0]) + visit.shift;
      stack.push_back({ *it, b.depth, visit.shift + (stretch - 1.0) * (childBase - b.centre[0]) });
    }
    tree.branches.push_back(std::move(b));
  }
  return {};
}

std::vector<char> MergedRoots(const Tree& tree)
{
  std::map<int, bool> merged;
  for (const TreeBranch& b : tree.branches)
    merged[b.id] = b.mergedId >= 0;
  std::vector<char> roots(tree.branches.size(), 0);
  for (std::size_t t = 0; t < tree.branches.size(); ++t)
  {
    const TreeBranch& b = tree.branches[t];
    const auto parent = merged.find(b.parentId);
    roots[t] = b.mergedId >= 0 && (parent == merged.end() || !parent->second) ? 1 : 0;
  }
  return roots;
}

} // namespace plantmorph
