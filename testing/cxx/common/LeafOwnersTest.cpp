// SPDX-License-Identifier: GPL-3.0-or-later
// The one leaf-owner rule of the per-leaf filters (LeafFitFilter, VenationFilter, WiltingSimulator):
// plantmorph::LeafOwners in common/vtk/PlantMorphLeafExchange.h. A worked example (largest first, ties: the smaller
// LeafId; each to the least loaded rank, ties: the lower rank), and on random leaf sizes for 1-5 ranks the list
// scheduling bound (the most and the least loaded rank differ by at most the largest leaf) and determinism.
#include "vtkType.h"

#include "PlantMorphLeafExchange.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using plantmorph::LeafOwners;

TEST(LeafOwners, WorkedExample)
{
  // Leaves (ascending LeafId) of 4, 10, 7, 10 and 2 points on 2 ranks: 10 (leaf 1) -> rank 0; 10 (leaf 3) -> rank 1;
  // 7 -> rank 0 (10 vs 10: the lower rank), loads 17 / 10; 4 -> rank 1 (14); 2 -> rank 1 (16).
  EXPECT_EQ(LeafOwners({ 4, 10, 7, 10, 2 }, 2), (std::vector<int>{ 1, 0, 0, 1, 1 }));
  EXPECT_EQ(LeafOwners({ 4, 10, 7, 10, 2 }, 1), (std::vector<int>(5, 0)));
  EXPECT_EQ(LeafOwners({ 3, 3, 3 }, 5), (std::vector<int>{ 0, 1, 2 })); // more ranks than leaves
  EXPECT_TRUE(LeafOwners({}, 3).empty());
}

TEST(LeafOwners, LoadsDifferByAtMostTheLargestLeaf)
{
  std::mt19937 random(21);
  std::uniform_int_distribution<vtkIdType> size(1, 100000);
  for (int trial = 0; trial < 50; ++trial)
  {
    std::vector<vtkIdType> points(1 + trial % 40);
    for (vtkIdType& p : points)
      p = size(random);
    for (int ranks = 1; ranks <= 5; ++ranks)
    {
      const std::vector<int> owners = LeafOwners(points, ranks);
      ASSERT_EQ(owners.size(), points.size());
      EXPECT_EQ(owners, LeafOwners(points, ranks)) << "deterministic";
      std::vector<vtkIdType> load(static_cast<std::size_t>(ranks), 0);
      for (std::size_t leaf = 0; leaf < points.size(); ++leaf)
      {
        ASSERT_TRUE(owners[leaf] >= 0 && owners[leaf] < ranks);
        load[static_cast<std::size_t>(owners[leaf])] += points[leaf];
      }
      const vtkIdType largest = *std::max_element(points.begin(), points.end());
      const auto [low, high] = std::minmax_element(load.begin(), load.end());
      EXPECT_LE(*high - *low, largest) << ranks << " ranks, " << points.size() << " leaves";
    }
  }
}

TEST(LeafCountsOfRanks, SerialIsThisRankAlone)
{
  const std::map<int, vtkIdType> mine{ { 3, 10 }, { 7, 2 } };
  const auto all = plantmorph::LeafCountsOfRanks(nullptr, mine);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0], mine);
}
