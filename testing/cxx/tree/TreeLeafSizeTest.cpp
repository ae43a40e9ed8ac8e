// SPDX-License-Identifier: GPL-3.0-or-later
// Leaf sizes of TreeFromSketchSource's algorithm layer (sources/tree/core/TreeLeaves.h): the defaults give every leaf
// LeafScale bit for bit; LeafTipScale tapers the lengths linearly along the leafy stretch, measured on each leaf's
// place on its straight twig; LeafScaleSpread gives log-normal lengths whose sample statistics over thousands of
// leaves match the standard deviation asked for; the same Seed gives the same sizes; the sizes move no leaf.
#include "TreeLeaves.h"
#include "TreeTemplate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

using namespace plantmorph;

namespace
{
/// Table 1 middle at depth 3: 27 straight twigs.
TreeParameters LeafyTree(int leafCount)
{
  TreeParameters s;
  ApplyTreePreset(2, s);
  s.depth = 3;
  s.leaves = true;
  s.leafCount = leafCount;
  s.leafScale = 0.7;
  return s;
}

Tree Built(const TreeParameters& s)
{
  Tree tree;
  EXPECT_EQ(BuildTree(s, {}, tree), "");
  return tree;
}

/// The log of each leaf's length over `expected(leaf)`.
template <typename Expected>
std::vector<double> LogRatios(const Tree& tree, Expected expected)
{
  std::vector<double> logs;
  for (const TreeLeaf& leaf : tree.leaves)
  {
    logs.push_back(std::log(leaf.length / expected(leaf)));
  }
  return logs;
}

void MeanAndDeviation(const std::vector<double>& values, double& mean, double& deviation)
{
  mean = 0.0;
  for (double v : values)
  {
    mean += v;
  }
  mean /= static_cast<double>(values.size());
  double sum = 0.0;
  for (double v : values)
  {
    sum += (v - mean) * (v - mean);
  }
  deviation = std::sqrt(sum / static_cast<double>(values.size() - 1));
}
} // namespace

TEST(TreeLeafSize, DefaultsGiveEveryLeafLeafScaleAndSizesMoveNoLeaf)
{
  const TreeParameters s = LeafyTree(5);
  const Tree plain = Built(s);
  ASSERT_EQ(plain.leaves.size(), 27u * 5u);
  for (const TreeLeaf& leaf : plain.leaves)
  {
    EXPECT_EQ(leaf.length, s.leafScale); // bit for bit: the leaves' output is the same as without the properties
  }
  TreeParameters varied = s;
  varied.leafTipScale = 0.4;
  varied.leafScaleSpread = 0.3;
  const Tree sized = Built(varied);
  ASSERT_EQ(sized.leaves.size(), plain.leaves.size());
  int differing = 0;
  for (std::size_t k = 0; k < sized.leaves.size(); ++k)
  {
    EXPECT_EQ(sized.leaves[k].id, plain.leaves[k].id);
    EXPECT_EQ(sized.leaves[k].branchId, plain.leaves[k].branchId);
    EXPECT_EQ(sized.leaves[k].origin, plain.leaves[k].origin);
    EXPECT_EQ(sized.leaves[k].axes, plain.leaves[k].axes);
    differing += sized.leaves[k].length != plain.leaves[k].length;
  }
  EXPECT_EQ(differing, static_cast<int>(sized.leaves.size()));
}

TEST(TreeLeafSize, LengthsTaperLinearlyAlongTheLeafyStretch)
{
  TreeParameters s = LeafyTree(5);
  s.leafTipScale = 0.4;
  const Tree tree = Built(s);
  std::map<int, const TreeBranch*> twigs;
  for (const TreeBranch& b : tree.branches)
  {
    twigs[b.id] = &b;
  }
  for (const TreeLeaf& leaf : tree.leaves)
  {
    // The leaf's place measured on its straight twig: its base projected on the axis, as a fraction of the length.
    const TreeBranch& twig = *twigs.at(leaf.branchId);
    ASSERT_TRUE(twig.straight);
    const double pos = (leaf.origin - twig.centre.front()).dot(twig.frame.col(1)) / twig.length;
    const double t = (pos - (1.0 - s.leafRatio)) / s.leafRatio;
    EXPECT_NEAR(leaf.length, s.leafScale * (1.0 + t * (s.leafTipScale - 1.0)), 1e-12);
  }
  // The last leaf of a twig sits at its tip and is LeafTipScale * LeafScale long.
  EXPECT_NEAR(tree.leaves[4].length, 0.4 * s.leafScale, 1e-15);
  // A whorl sits at the tip: every leaf the tip's length.
  s.leafType = LeafType::Sympodial;
  for (const TreeLeaf& leaf : Built(s).leaves)
  {
    EXPECT_NEAR(leaf.length, 0.4 * s.leafScale, 1e-15);
  }
}

TEST(TreeLeafSize, SpreadIsLogNormalWithTheStandardDeviationAskedFor)
{
  TreeParameters s = LeafyTree(200); // 5,400 leaves
  s.leafScaleSpread = 0.15;
  s.seed = 7;
  const Tree tree = Built(s);
  const double n = static_cast<double>(tree.leaves.size());
  ASSERT_EQ(tree.leaves.size(), 27u * 200u);
  std::vector<double> logs = LogRatios(tree, [&](const TreeLeaf&) { return s.leafScale; });
  double mean = 0.0, deviation = 0.0;
  MeanAndDeviation(logs, mean, deviation);
  // Within four standard errors: of the mean sigma / sqrt(n), of the deviation sigma / sqrt(2 (n - 1)).
  EXPECT_NEAR(mean, 0.0, 4.0 * 0.15 / std::sqrt(n));
  EXPECT_NEAR(deviation, 0.15, 4.0 * 0.15 / std::sqrt(2.0 * (n - 1.0)));
  // Normal in the log: 68.27 % within one deviation, 95.45 % within two (binomial standard errors).
  for (const auto& [k, share] : { std::pair<double, double>(1.0, 0.6827), std::pair<double, double>(2.0, 0.9545) })
  {
    double inside = 0.0;
    for (double v : logs)
    {
      inside += std::abs(v) <= k * 0.15 ? 1.0 : 0.0;
    }
    EXPECT_NEAR(inside / n, share, 4.0 * std::sqrt(share * (1.0 - share) / n)) << k << " deviations";
  }
  // Neighbours on a twig are independent: the correlation of consecutive leaves' logs is within noise of 0.
  double covariance = 0.0;
  for (std::size_t k = 1; k < logs.size(); ++k)
  {
    covariance += (logs[k] - mean) * (logs[k - 1] - mean);
  }
  EXPECT_NEAR(covariance / (n - 1.0) / (deviation * deviation), 0.0, 4.0 / std::sqrt(n));

  // With a taper the spread is about the tapered length.
  s.leafTipScale = 0.5;
  const Tree tapered = Built(s);
  logs = LogRatios(tapered, [&](const TreeLeaf& leaf) {
    const int j = leaf.id % 200 + 1;
    return s.leafScale * (1.0 + (j / 200.0) * (s.leafTipScale - 1.0));
  });
  MeanAndDeviation(logs, mean, deviation);
  EXPECT_NEAR(mean, 0.0, 4.0 * 0.15 / std::sqrt(n));
  EXPECT_NEAR(deviation, 0.15, 4.0 * 0.15 / std::sqrt(2.0 * (n - 1.0)));
}

TEST(TreeLeafSize, TheSameSeedGivesTheSameSizes)
{
  TreeParameters s = LeafyTree(5);
  s.leafScaleSpread = 0.2;
  s.leafTipScale = 0.6;
  s.seed = 3;
  const Tree a = Built(s), b = Built(s);
  s.seed = 4;
  const Tree c = Built(s);
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  ASSERT_EQ(a.leaves.size(), c.leaves.size());
  int same = 0;
  for (std::size_t k = 0; k < a.leaves.size(); ++k)
  {
    EXPECT_EQ(a.leaves[k].length, b.leaves[k].length);
    same += a.leaves[k].length == c.leaves[k].length;
  }
  EXPECT_EQ(same, 0);
  // A leaf's size is its own: LeafLength by its id gives it.
  EXPECT_EQ(LeafLength(s, 1.0, 9), c.leaves[9].length);
}

TEST(TreeLeafSize, BadSizesNameTheProperty)
{
  Tree tree;
  TreeParameters s = LeafyTree(3);
  s.leafTipScale = 0.0;
  EXPECT_NE(BuildTree(s, {}, tree).find("LeafTipScale = 0 is outside the accepted range (0, 10]"), std::string::npos);
  EXPECT_TRUE(tree.branches.empty() && tree.leaves.empty());
  s.leafTipScale = 1.0;
  s.leafScaleSpread = -0.1;
  EXPECT_NE(
    BuildTree(s, {}, tree).find("LeafScaleSpread = -0.1 is outside the accepted range [0, 1]"), std::string::npos);
  s.leafScaleSpread = std::nan("");
  EXPECT_NE(BuildTree(s, {}, tree).find("LeafScaleSpread"), std::string::npos);
}
