// SPDX-License-Identifier: GPL-3.0-or-later
// Eq. (2) through the segment grid (StrokeSegmentGrid.h) against its oracle, the exhaustive search
// (StrokeSearch::Exhaustive): random stroke sets give bit-identical trees and stroke reports, exact ties included.
#include "TreeStrokes.h"
#include "TreeTestStrokes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>

using namespace plantmorph;

namespace
{
TreeParameters Settings(std::uint64_t seed)
{
  TreeParameters s;
  s.mode = TreeMode::Strokes;
  s.strokesOnly = true;
  s.leaves = false;
  s.segmentsPerBranch = 6;
  s.seed = seed;
  return s;
}

/// Both searches on the same strokes; every branch and report compared exactly.
void ExpectSameTrees(
  const TreeParameters& s, const std::vector<std::vector<Eigen::Vector3d>>& strokes, const Tree& start)
{
  Tree grid = start, exhaustive = start;
  const std::string a = AddStrokes(s, strokes, grid, StrokeSearch::Grid);
  const std::string b = AddStrokes(s, strokes, exhaustive, StrokeSearch::Exhaustive);
  ASSERT_EQ(a, b);
  ASSERT_EQ(grid.branches.size(), exhaustive.branches.size());
  for (std::size_t i = 0; i < grid.branches.size(); ++i)
  {
    const TreeBranch &g = grid.branches[i], &e = exhaustive.branches[i];
    ASSERT_EQ(g.id, e.id) << i;
    ASSERT_EQ(g.parentId, e.parentId) << "branch " << i;
    ASSERT_EQ(g.position, e.position) << "branch " << i;
    ASSERT_EQ(g.centre, e.centre) << "branch " << i;
    ASSERT_EQ(g.radii, e.radii) << "branch " << i;
  }
  ASSERT_EQ(grid.strokes.size(), exhaustive.strokes.size());
  for (std::size_t k = 0; k < grid.strokes.size(); ++k)
  {
    ASSERT_EQ(grid.strokes[k].parentId, exhaustive.strokes[k].parentId) << "stroke " << k;
    ASSERT_EQ(grid.strokes[k].distance, exhaustive.strokes[k].distance) << "stroke " << k;
    ASSERT_EQ(grid.strokes[k].lambda, exhaustive.strokes[k].lambda) << "stroke " << k;
  }
}
} // namespace

TEST(StrokeAttachment, GridMatchesTheExhaustiveSearchOnRandomStrokes)
{
  for (std::uint64_t seed = 1; seed <= 12; ++seed)
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const bool onPoints = seed % 2 == 0; // exact ties at shared points, or strokes starting near branches
    const auto strokes = tree_test::RandomStrokes(300, seed % 3 == 0 ? 2 : 5, seed, onPoints);
    ExpectSameTrees(Settings(seed), strokes, Tree());
  }
}

TEST(StrokeAttachment, GridMatchesTheExhaustiveSearchWithOverridesAndTemplateBranches)
{
  TreeParameters s = Settings(7);
  for (int k = 1; k < 200; k += 7)
  {
    BranchOverride edit;
    edit.u = (k % 3) / 3.0 + 0.1;
    edit.length = k % 2 ? 5.0 : std::numeric_limits<double>::quiet_NaN();
    edit.angle = k % 5 == 0 ? 40.0 : std::numeric_limits<double>::quiet_NaN();
    s.overrides[k] = edit;
  }
  ExpectSameTrees(s, tree_test::RandomStrokes(200, 4, 99, true), Tree());
  // Strokes added to a template tree (its branches indexed before the first stroke).
  TreeParameters t = Settings(3);
  t.mode = TreeMode::TemplateAndStrokes;
  t.depth = 3;
  t.childCount = 4;
  Tree start;
  t.mode = TreeMode::Template;
  ASSERT_EQ(BuildTree(t, {}, start), "");
  t.mode = TreeMode::TemplateAndStrokes;
  auto strokes = tree_test::RandomStrokes(150, 3, 5, false);
  strokes.erase(strokes.begin()); // every stroke attaches to the template or an earlier stroke
  ExpectSameTrees(t, strokes, start);
}

TEST(StrokeAttachment, PointsFarFromEverythingAndDegenerateExtentsStillMatch)
{
  // All strokes on one line (zero-area extent), a stroke far away (the grid gives up: the exhaustive search answers).
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  for (int k = 0; k < 60; ++k)
  {
    strokes.push_back(tree_test::Line({ { double(k), 0 }, { double(k) + 1.5, 0 } }));
  }
  strokes.push_back(tree_test::Line({ { 1e12, 1e12 }, { 1e12 + 1, 1e12 } }));
  strokes.push_back(tree_test::Line({ { -1e300, 0 }, { 0, 1e300 } }));
  strokes.push_back(tree_test::Line({ { 3, 0 }, { 3, 5 } }));
  ExpectSameTrees(Settings(1), strokes, Tree());
}

TEST(StrokeAttachment, TenThousandStrokesEachBecomeABranch)
{
  // Not a timed assertion (the speed is benchmarks/filters/tree_benchmark.cpp's BM_StrokeAttach, grid against the
  // exhaustive search): the time is printed, and every stroke of a large random set must become its own branch.
  const auto strokes = tree_test::RandomStrokes(10000, 2, 42, false);
  Tree tree;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(AddStrokes(Settings(1), strokes, tree), "");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "  10000 strokes attached through the grid in " << seconds << " s\n";
  EXPECT_EQ(tree.branches.size(), strokes.size());
}
