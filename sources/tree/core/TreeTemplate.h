// SPDX-License-Identifier: GPL-3.0-or-later
// Template trees of paper 004 (sec. 2, Table 1; docs/methods/tree-from-sketch.md), the tree model shared by strokes,
// leaves and tube meshes, and the one entry point BuildTree. Plain C++ (Eigen), no VTK.
//
// Coordinates: the tree grows along +Y from the origin (the paper's model matrices translate along Y), the image
// plane of traced strokes is XY, depth (the lifting of strokes) is Z.
//
// Every branch has a base frame F = [x y z] (columns, orthonormal, y along the branch). The trunk's is the identity;
// child i of a branch gets F_child = F_parent(pos) * R_y(rotation_angle) * R_z(angle), the paper's tree_render
// matrices (rotation about the parent's axis by frac(i*a/b)*360 deg, then divergence by `angle` from it). Its
// direction is F_parent * (-sin(angle) cos(rot), cos(angle), sin(angle) sin(rot)).
//
// Choices where the paper and spec are silent:
// - Branch ids are preorder numbers of the complete (unedited) template: child i of a branch with id p whose
//   children have `l` levels below them gets p + 1 + (i - 1) * SubtreeSize(l). They do not depend on deletions or
//   overrides, so a saved state keeps naming the same branches. Stroke branches: see TreeStrokes.h.
// - A child's skeleton starts on its parent's surface: at the parent's centre point at pos plus the parent's
//   radius there along the child's outward direction (on the axis when angle = 0; on the circumscribed circle of the
//   parent's `Sides`-gon). Its tube is then welded to the parent's by a convex-hull junction (BranchJunctions.h) or,
//   with seated tubes, its base ring is seated on the parent tube's faceted surface (BranchTubes.h, "Joints");
//   TreeTubeInputs gives each tube its parent's index.
// - Overrides (length, radius, u = pos, angle, rotation) replace the formula's value for that branch; its children
//   derive from the overridden values (a longer branch has longer children).
// - Depth-0 twigs (recursion level 0) are lengthened by TwigScale (epsilon_leaf = 1.2), as the paper's
//   generate_leaf(&length) does, whether or not leaves are drawn; the formula tests account for it.
// - Merging a second tree (docs/methods/tree-from-sketch.md; paper 004 sec. 3.2 and Fig. 11: "at a segment of a
//   branch the user adds a new branch with its sub-branches, giving a merged tree"): see TreeMerge.h.
#pragma once

#include "BranchTubes.h"

#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace plantmorph
{

enum class TreeType : int
{
  Monopodial = 0,
  Sympodial = 1
};

enum class TreeMode : int
{
  Template = 0,          ///< the template tree alone
  Strokes = 1,           ///< the first stroke is the trunk; template subtrees grow on the stroke branches
  TemplateAndStrokes = 2 ///< strokes are added to (merged into) the template tree, each on its nearest branch
};

enum class LeafType : int
{
  Monopodial = 0, ///< leaves spread over the LeafRatio part of each twig, phyllotaxis a/b
  Sympodial = 1,  ///< a whorl of leaves at each twig's tip, phyllotaxis a/b
  Willow = 2      ///< pendulous twigs (a Bezier curve), leaves spread along them
};

/// One row of BranchOverrides: NaN keeps the computed value.
struct BranchOverride
{
  double length = std::numeric_limits<double>::quiet_NaN();
  double radius = std::numeric_limits<double>::quiet_NaN();
  double u = std::numeric_limits<double>::quiet_NaN();
  double angle = std::numeric_limits<double>::quiet_NaN();    ///< degrees
  double rotation = std::numeric_limits<double>::quiet_NaN(); ///< degrees
};

struct TreeParameters
{
  TreeMode mode = TreeMode::Template;
  TreeType type = TreeType::Monopodial;
  double length = 12.0; ///< trunk length
  double radius = 0.4;  ///< trunk base radius
  int depth = 4;        ///< recursion depth: levels of children below the trunk
  int phyllotaxisA = 3; ///< a of the phyllotaxis fraction a/b (turns)
  int phyllotaxisB = 8; ///< b (leaves or branches per a turns)
  int childCount = 8;
  double ratio = 0.7;               ///< children sit on the last `ratio` of their parent
  double lengthScale = 0.8;         ///< sympodial child length / parent length
  double monopodialAngle = 34.4;    ///< degrees, 90 * 0.382
  double sympodialAngle = 55.6;     ///< degrees, 90 * 0.618
  int segmentsPerBranch = 4;        ///< DIVID
  double twigScale = 1.2;           ///< epsilon_leaf: depth-0 twigs are this much longer
  int sides = 6;                    ///< vertices per tube ring
  long long maxSegments = 20000000; ///< memory budget: more skeleton segments than this is an error

  // Strokes (TreeStrokes.h).
  int strokeControlPoints = 4;
  double strokeLengthRatio = 0.0; ///< epsilon of the length rule; <= 0: 0.6 monopodial, 0.8 sympodial
  bool strokesOnly = false;       ///< no template subtrees on stroke branches
  int strokeSubtreeDepth = 2;     ///< levels of template subtree grown on each stroke branch

  // Leaves (TreeLeaves.h).
  bool leaves = true;
  LeafType leafType = LeafType::Monopodial;
  int leafCount = 6;
  double leafRatio = 0.6;
  double leafScale = 1.0;
  double leafAngle = 45.0;      ///< degrees between a leaf's midrib and its twig
  double leafTipScale = 1.0;    ///< a leaf's length at the twig's tip over LeafScale (linear along the leafy stretch)
  double leafScaleSpread = 0.0; ///< standard deviation of the natural log of a leaf's length (0: no spread)

  std::uint64_t seed = 0;

  // Merging a second tree (TreeMerge.h); used when BuildTree is given one.
  int mergeParent = 0;        ///< BranchId it grows from, or -1: a second trunk standing at mergeOffset
  double mergeU = 0.5;        ///< position on that branch, [0, 1]
  double mergeAngle = 34.4;   ///< divergence from that branch (or tilt from +Y of a second trunk), degrees
  double mergeRotation = 0.0; ///< rotation about that branch (or about +Y of a second trunk), degrees
  double mergeScale = 1.0;    ///< uniform scale of the second tree
  Eigen::Vector3d mergeOffset = Eigen::Vector3d::Zero(); ///< base of a second trunk

  std::set<int> deletedBranches;
  std::map<int, BranchOverride> overrides;

  /// Empty if valid, else a message naming the first bad property and its accepted range.
  std::string Validate() const;
  double Angle() const { return this->type == TreeType::Monopodial ? this->monopodialAngle : this->sympodialAngle; }
  double StrokeRatio() const
  {
    return this->strokeLengthRatio > 0.0 ? this->strokeLengthRatio : (this->type == TreeType::Monopodial ? 0.6 : 0.8);
  }
};

/// Table 1's three templates (1 left, 2 middle, 3 right); 0 (Custom) and unknown numbers change nothing. Sets type,
/// depth, ratio, length, radius, a, b and childCount.
void ApplyTreePreset(int preset, TreeParameters& settings);
const char* TreePresetName(int preset);
constexpr int TreePresetCount = 4;

struct TreeBranch
{
  int id = 0;
  int parentId = -1;      ///< -1 for the trunk
  int depth = 0;          ///< 0 trunk, parent's + 1 (the data contract's Depth)
  int level = 0;          ///< template levels still to grow below it (0: a twig)
  int childIndex = 0;     ///< i in 1..childCount for template children, 0 otherwise
  int strokeIndex = -1;   ///< the stroke it came from, or -1
  int mergedId = -1;      ///< its BranchId in the merged second tree, or -1 (not merged)
  bool straight = true;   ///< centre line is a straight segment along frame.col(1)
  double position = 0.0;  ///< pos: fraction of the parent's arc length where it starts
  double length = 0.0;    ///< arc length of the centre line
  double radius = 0.0;    ///< base radius
  double radiusEnd = 0.0; ///< end radius (0: the tube closes in a point)
  double angle = 0.0;     ///< divergence from the parent, degrees
  double rotation = 0.0;  ///< rotation about the parent, degrees
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Vector3d> centre; ///< skeleton points, base to tip
  std::vector<double> radii;           ///< radius at each skeleton point
};

struct TreeLeaf
{
  int branchId = 0;
  int id = 0; ///< LeafId: the leaf's index in Tree::leaves (unique over the tree, the same for the same seed)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< the leaf's base on its twig's surface
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity(); ///< columns: across the blade, along the midrib, normal (unit)
  double length = 1.0; ///< the blade's length along its midrib (LeafLength in TreeLeaves.h)
};

/// What happened to one stroke (TreeStrokes.h).
struct StrokeReport
{
  int branchId = -1;
  int parentId = -1;             ///< -1 for the trunk
  double distance = 0.0;         ///< eq. (2) distance from the stroke's first point to the parent
  double lambda = 0.0;           ///< C = lambda*A + (1 - lambda)*B on the parent segment AB
  double targetLength = 0.0;     ///< L* = epsilon * parent length
  double planarLength = 0.0;     ///< |l3|: the smoothed stroke's length in the image plane
  double recommendedTheta = 0.0; ///< theta*, degrees
  double rotation = 0.0;         ///< the chosen phyllotaxis rotation angle phi, degrees (tan(phi) lifts dx to z)
  double theta = 0.0;            ///< the chosen plane angle in [0, 90), degrees
};

struct Tree
{
  std::vector<TreeBranch> branches; ///< parents before children
  std::vector<TreeLeaf> leaves;
  std::vector<StrokeReport> strokes;
  long long mergeIdBase = -1; ///< merged branch ids are this + their id in the second tree (-1: nothing merged)
  long long SegmentCount() const;
};

/// One branch of a second tree to merge: what a TreeFromSketchSource's Skeleton output carries per polyline.
struct SkeletonBranch
{
  long long id = 0;
  long long parentId = -1; ///< -1 for its root
  std::vector<Eigen::Vector3d> centre;
  std::vector<double> radii;
};

/// The tubes of a tree's branches for BuildTubes: centre lines, radii, frames, and each branch's parent index (its
/// tube is welded to, or its base ring seated on, the parent's tube).
std::vector<TubeInput> TreeTubeInputs(const Tree& tree);

/// Number of branches of a complete template with `levels` levels of `childCount` children below its root (root
/// included): 1 + c + ... + c^levels; saturates at 2^62.
long long SubtreeSize(int childCount, int levels);

/// frac(i * a / b) * 360 degrees, computed exactly in integers: ((i * a) mod b) * 360 / b.
double PhyllotaxisAngle(long long i, int a, int b);

/// Builds the tree: template and/or strokes (x, y of each point; z ignored), deletions, overrides, leaves.
/// Returns an empty string or an error message naming the property (tree empty then).
std::string BuildTree(
  const TreeParameters& settings, const std::vector<std::vector<Eigen::Vector3d>>& strokes, Tree& tree);
/// The same, then merges `second` (a second tree's skeleton; none when null or empty) as TreeMerge.h describes.
std::string BuildTree(const TreeParameters& settings, const std::vector<std::vector<Eigen::Vector3d>>& strokes,
  const std::vector<SkeletonBranch>* second, Tree& tree);

// Building blocks, used by TreeStrokes and TreeLeaves and exposed for the tests.

/// The point, unit frame (y along the centre line) and radius at arc-length fraction `pos` of a branch; curved
/// branches carry a rotation-minimising frame from their base frame.
void BranchFrameAt(
  const TreeBranch& branch, double pos, Eigen::Vector3d& point, Eigen::Matrix3d& frame, double& radius);
/// Rotation about the local y axis, then about z, in degrees (the paper's two matrices).
Eigen::Matrix3d RotationY(double degrees);
Eigen::Matrix3d RotationZ(double degrees);

/// Grows the template children of tree.branches[index] (and theirs) in preorder, honouring deletions and overrides.
void GrowTemplateChildren(const TreeParameters& settings, std::size_t index, Tree& tree);

/// Where a child at (angle, rotation) starts: the parent's axis point plus the parent's radius along the child's
/// outward direction (the axis point itself when angle is 0 or 180).
Eigen::Vector3d ChildBase(const Eigen::Vector3d& axisPoint, const Eigen::Matrix3d& parentFrame, double parentRadius,
  double angle, double rotation);

/// Sets the centre line and radii of a straight branch from its frame, base point, length and radii.
void MakeStraightBranch(const TreeParameters& settings, const Eigen::Vector3d& base, TreeBranch& branch);

} // namespace plantmorph
