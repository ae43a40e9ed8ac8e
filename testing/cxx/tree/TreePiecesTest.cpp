// SPDX-License-Identifier: GPL-3.0-or-later
// A tree built by pieces (one per MPI rank; BranchPieces.h): for 1..5 pieces, the pieces' triangles together are the
// whole build's, each exactly once (compared as a sorted multiset of triangles written out by their corners' exact
// coordinates, normals and TCoords, with the owning tube: point ids may differ), on a template tree and a stroke
// tree, welded and seated; each piece is a valid mesh by itself (ids in range, every point used, no directed edge
// twice, no edge in more than two triangles) whose open edges are all matched, reversed, by other pieces; the plan
// is balanced and splits a forest by tree.
#include "BranchJunctions.h"
#include "BranchPieces.h"
#include "BranchTubes.h"
#include "TreeMerge.h"
#include "TreeTemplate.h"
#include "TreeTestMerge.h"
#include "TreeTestStrokes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace plantmorph;
using tree_test::MergeOntoBranch3;
using tree_test::SkeletonOf;

namespace
{
/// One triangle by value: 3 corners x (x, y, z, nx, ny, nz, u, v), rotated so the smallest corner comes first
/// (orientation kept), then the owning tube.
using Corner = std::array<double, 8>;
using TriangleKey = std::pair<std::array<Corner, 3>, std::size_t>;

std::vector<TriangleKey> Triangles(const TubeMesh& mesh)
{
  const std::size_t tubes = mesh.triangleOffsets.size() - 1;
  std::vector<TriangleKey> keys;
  for (std::size_t t = 0; t < tubes; ++t)
  {
    for (auto f = mesh.triangleOffsets[t]; f < mesh.triangleOffsets[t + 1]; ++f)
    {
      std::array<Corner, 3> corners;
      for (std::size_t k = 0; k < 3; ++k)
      {
        const std::size_t p = static_cast<std::size_t>(mesh.triangles[3 * static_cast<std::size_t>(f) + k]);
        corners[k] = { mesh.points[3 * p], mesh.points[3 * p + 1], mesh.points[3 * p + 2], mesh.normals[3 * p],
          mesh.normals[3 * p + 1], mesh.normals[3 * p + 2], mesh.tcoords[2 * p], mesh.tcoords[2 * p + 1] };
      }
      std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
      keys.emplace_back(corners, t);
    }
  }
  return keys;
}

using Position = std::array<double, 3>;

Position At(const TubeMesh& mesh, std::int32_t p)
{
  const std::size_t i = 3 * static_cast<std::size_t>(p);
  return { mesh.points[i], mesh.points[i + 1], mesh.points[i + 2] };
}

/// A piece's own validity; adds its directed edges (by position) to `edges`.
void ExpectValidPiece(
  const TubeMesh& mesh, const std::string& what, std::map<std::pair<Position, Position>, int>& edges)
{
  std::vector<char> used(mesh.PointCount(), 0);
  std::map<std::pair<std::int32_t, std::int32_t>, int> directed;
  for (std::size_t f = 0; f < mesh.TriangleCount(); ++f)
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      const std::int32_t a = mesh.triangles[3 * f + k], b = mesh.triangles[3 * f + (k + 1) % 3];
      ASSERT_TRUE(a >= 0 && static_cast<std::size_t>(a) < mesh.PointCount()) << what;
      used[static_cast<std::size_t>(a)] = 1;
      ++directed[{ a, b }];
      ++edges[{ At(mesh, a), At(mesh, b) }];
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << what << ": unused points";
  for (const auto& [edge, uses] : directed)
  {
    EXPECT_EQ(uses, 1) << what << ": directed edge " << edge.first << "-" << edge.second << " used " << uses << "x";
    if (uses != 1)
      return;
  }
}

enum class Joints
{
  Welded,
  Seated
};

std::string Build(const std::vector<TubeInput>& tubes, int sides, Joints joints, TubeMesh& mesh,
  const std::vector<char>* selected = nullptr)
{
  return joints == Joints::Welded ? BuildWeldedTubes(tubes, sides, mesh, SerialFor, nullptr, selected)
                                  : BuildTubes(tubes, sides, mesh, SerialFor, nullptr, selected);
}

/// Pieces 1..5 of `tree`: their triangles are the whole build's, each piece valid, the open edges matched.
void ExpectPiecesMakeTheWhole(const Tree& tree, int sides, Joints joints, const std::string& name)
{
  const std::vector<TubeInput> tubes = TreeTubeInputs(tree);
  TubeMesh whole;
  ASSERT_EQ(Build(tubes, sides, joints, whole), "");
  std::vector<TriangleKey> expected = Triangles(whole);
  std::sort(expected.begin(), expected.end());
  ASSERT_GT(expected.size(), 0u);
  JunctionReport wholeReport;
  if (joints == Joints::Welded)
  {
    ASSERT_EQ(BuildWeldedTubes(tubes, sides, whole, SerialFor, &wholeReport), "");
  }
  for (int pieces = 1; pieces <= 5; ++pieces)
  {
    const std::string what = name + ", " + std::to_string(pieces) + " pieces";
    const std::vector<int> plan = PlanPieces(tubes, MergedRoots(tree), pieces);
    std::vector<TriangleKey> together;
    std::map<std::pair<Position, Position>, int> edges;
    JunctionReport sum;
    for (int piece = 0; piece < pieces; ++piece)
    {
      const std::vector<char> selected = TubesOfPiece(plan, piece);
      TubeMesh mesh;
      if (joints == Joints::Welded)
      {
        JunctionReport report;
        ASSERT_EQ(BuildWeldedTubes(tubes, sides, mesh, SerialFor, &report, &selected), "");
        sum.junctions += report.junctions, sum.welded += report.welded, sum.merged += report.merged;
        sum.endJunctions += report.endJunctions, sum.narrowed += report.narrowed, sum.fallback += report.fallback;
      }
      else
      {
        ASSERT_EQ(Build(tubes, sides, joints, mesh, &selected), "");
      }
      for (std::size_t t = 0; t < tubes.size(); ++t)
      {
        if (!selected[t])
        {
          EXPECT_EQ(mesh.triangleOffsets[t + 1], mesh.triangleOffsets[t]) << what;
        }
      }
      ExpectValidPiece(mesh, what + ", piece " + std::to_string(piece), edges);
      const std::vector<TriangleKey> mine = Triangles(mesh);
      together.insert(together.end(), mine.begin(), mine.end());
    }
    std::sort(together.begin(), together.end());
    EXPECT_EQ(together.size(), expected.size()) << what;
    EXPECT_TRUE(together == expected) << what << ": the pieces' triangles are not the whole build's";
    // Open edges of one piece are closed by another: the union's directed edges pair up as the whole's do.
    std::size_t unmatched = 0;
    for (const auto& [edge, uses] : edges)
    {
      const auto reverse = edges.find({ edge.second, edge.first });
      unmatched += uses != 1 || reverse == edges.end() || reverse->second != 1 ? 1 : 0;
    }
    if (joints == Joints::Welded)
    {
      EXPECT_EQ(unmatched, 0u) << what << ": the welded pieces together are not closed";
      EXPECT_EQ(sum.junctions, wholeReport.junctions) << what;
      EXPECT_EQ(sum.welded, wholeReport.welded) << what;
      EXPECT_EQ(sum.merged, wholeReport.merged) << what;
      EXPECT_EQ(sum.endJunctions, wholeReport.endJunctions) << what;
      EXPECT_EQ(sum.narrowed, wholeReport.narrowed) << what;
      EXPECT_EQ(sum.fallback, wholeReport.fallback) << what;
    }
  }
}

TreeParameters Template(int preset, int depth)
{
  TreeParameters s;
  ApplyTreePreset(preset, s);
  s.depth = depth;
  s.leaves = false;
  return s;
}
} // namespace

TEST(TreePieces, TemplateTreeWeldedAndSeated)
{
  for (int preset : { 1, 2 })
  {
    const TreeParameters s = Template(preset, 3);
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    ASSERT_GT(tree.branches.size(), 20u);
    ExpectPiecesMakeTheWhole(tree, s.sides, Joints::Welded, std::string("welded ") + TreePresetName(preset));
    ExpectPiecesMakeTheWhole(tree, s.sides, Joints::Seated, std::string("seated ") + TreePresetName(preset));
  }
}

TEST(TreePieces, StrokeTreeWeldedAndSeated)
{
  TreeParameters s;
  s.mode = TreeMode::Strokes;
  s.leaves = false;
  Tree tree;
  ASSERT_EQ(BuildTree(s, tree_test::SampleStrokes(), tree), "");
  ASSERT_GT(tree.branches.size(), 20u);
  ExpectPiecesMakeTheWhole(tree, s.sides, Joints::Welded, "welded stroke tree");
  ExpectPiecesMakeTheWhole(tree, s.sides, Joints::Seated, "seated stroke tree");
}

TEST(TreePieces, MergedTreeAndForest)
{
  TreeParameters second = Template(2, 2);
  Tree other;
  ASSERT_EQ(BuildTree(second, {}, other), "");
  const std::vector<SkeletonBranch> skeleton = SkeletonOf(other);
  TreeParameters m = Template(1, 2);
  MergeOntoBranch3(m); // a child of the trunk
  Tree merged;
  ASSERT_EQ(BuildTree(m, {}, &skeleton, merged), "");
  ExpectPiecesMakeTheWhole(merged, m.sides, Joints::Welded, "merged tree");

  // A forest of two equal trees (a second trunk beside the first): two pieces are the two trees.
  Tree first;
  TreeParameters f = Template(2, 2);
  ASSERT_EQ(BuildTree(f, {}, first), "");
  const std::vector<SkeletonBranch> twin = SkeletonOf(first);
  f.mergeParent = -1;
  f.mergeOffset = Eigen::Vector3d(30.0, 0.0, 0.0);
  Tree forest;
  ASSERT_EQ(BuildTree(f, {}, &twin, forest), "");
  ASSERT_EQ(forest.branches.size(), 2 * first.branches.size());
  const std::vector<int> plan = PlanPieces(TreeTubeInputs(forest), MergedRoots(forest), 2);
  for (std::size_t t = 0; t < forest.branches.size(); ++t)
    EXPECT_EQ(plan[t], forest.branches[t].mergedId >= 0 ? 1 : 0) << "branch " << forest.branches[t].id;
  ExpectPiecesMakeTheWhole(forest, f.sides, Joints::Welded, "forest");
}

// The real cost of a piece is the triangles it writes (measured: the two ranks' CPU per piece was measured equal
// to 1 %, 1,423,097 and 1,422,999 triangles of the Depth 5 tree). The plan weighs tubes by segments, so check that
// this proxy holds: each piece's triangles (the welded whole mesh's, by owning tube) are within one tube's
// triangles of an equal share, for the benchmark's Custom template (ChildCount 8) and the presets.
TEST(TreePieces, PiecesWriteEqualTriangles)
{
  for (int preset : { 0, 1, 2 })
  {
    TreeParameters s = Template(preset, 3);
    s.childCount = preset == 0 ? 8 : s.childCount;
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    const std::vector<TubeInput> tubes = TreeTubeInputs(tree);
    TubeMesh whole;
    ASSERT_EQ(BuildWeldedTubes(tubes, s.sides, whole, SerialFor), "");
    std::vector<double> triangles(tubes.size());
    double total = 0.0, heaviest = 0.0;
    for (std::size_t t = 0; t < tubes.size(); ++t)
    {
      triangles[t] = static_cast<double>(whole.triangleOffsets[t + 1] - whole.triangleOffsets[t]);
      total += triangles[t], heaviest = std::max(heaviest, triangles[t]);
    }
    for (int pieces : { 2, 3, 4 })
    {
      const std::vector<int> plan = PlanPieces(tubes, MergedRoots(tree), pieces);
      std::vector<double> load(static_cast<std::size_t>(pieces), 0.0);
      for (std::size_t t = 0; t < tubes.size(); ++t)
        load[static_cast<std::size_t>(plan[t])] += triangles[t];
      for (double l : load)
        EXPECT_NEAR(l, total / pieces, heaviest) << "preset " << preset << ", " << pieces << " pieces of " << total;
    }
  }
}

TEST(TreePieces, PlanIsBalancedAndRunsDepthFirst)
{
  const TreeParameters s = Template(2, 4);
  Tree tree;
  ASSERT_EQ(BuildTree(s, {}, tree), "");
  const std::vector<TubeInput> tubes = TreeTubeInputs(tree);
  double total = 0.0, heaviest = 0.0;
  // The plan's weight: a tube's segments + 1 + its children (BranchPieces.h).
  std::vector<double> weight(tubes.size());
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    weight[t] += std::max(static_cast<double>(tubes[t].centre.size()) - 1.0, 1.0) + 1.0;
    if (tubes[t].parent >= 0)
      weight[static_cast<std::size_t>(tubes[t].parent)] += 1.0;
  }
  for (double w : weight)
    total += w, heaviest = std::max(heaviest, w);
  for (int pieces = 1; pieces <= 7; ++pieces)
  {
    const std::vector<int> plan = PlanPieces(tubes, {}, pieces);
    EXPECT_EQ(plan, PlanPieces(tubes, {}, pieces)) << "deterministic";
    std::vector<double> load(static_cast<std::size_t>(pieces), 0.0);
    for (std::size_t t = 0; t < tubes.size(); ++t)
    {
      ASSERT_TRUE(plan[t] >= 0 && plan[t] < pieces);
      load[static_cast<std::size_t>(plan[t])] += weight[t];
      // Depth-first runs: a child's piece is never before its parent's.
      if (tubes[t].parent >= 0)
      {
        EXPECT_GE(plan[t], plan[static_cast<std::size_t>(tubes[t].parent)]);
      }
    }
    for (double l : load)
      EXPECT_NEAR(l, total / pieces, heaviest) << pieces << " pieces";
  }
  // More pieces than tubes: every tube in one piece, the rest empty.
  const std::vector<TubeInput> two(tubes.begin(), tubes.begin() + 2);
  const std::vector<int> plan = PlanPieces(two, {}, 5);
  EXPECT_NE(plan[0], plan[1]);
  EXPECT_EQ(ValidatePieceRequest(0, 1), "");
  EXPECT_NE(ValidatePieceRequest(2, 2), "");
  EXPECT_NE(ValidatePieceRequest(0, 0), "");
}
