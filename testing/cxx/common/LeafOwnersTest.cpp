// SPDX-License-Identifier: GPL-3.0-or-later
// The one leaf-owner rule of the per-leaf filters (LeafFitFilter, VenationFilter, WiltingSimulator):
// plantmorph::LeafOwners in common/vtk/PlantMorphLeafExchange.h. A worked example (largest first, ties: the smaller
// LeafId; each to the least loaded rank, ties: the lower rank), and on random leaf sizes for 1-5 ranks the list
// scheduling bound (the most and the least loaded rank differ by at most the largest leaf) and determinism. The
// fitters' OwnerExchange (common/vtk/PlantMorphOwnerExchange.h) serially: 64-bit ids kept apart, values round-trip.
// The per-leaf filters' LeafPlan (VenationFilter, WiltingSimulator): LeafIds above 2^31 read exactly, kept apart from
// the int they would wrap to, and written back exactly.
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkType.h"
#include "vtkTypeInt64Array.h"

#include "PlantMorphLeafExchange.h"
#include "PlantMorphOwnerExchange.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
  const std::map<vtkTypeInt64, vtkIdType> mine{ { 3, 10 }, { 7, 2 }, { (vtkTypeInt64(1) << 40) + 1, 5 } };
  const auto all = plantmorph::LeafCountsOfRanks(nullptr, mine);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0], mine);
}

TEST(OwnerExchange, SerialKeepsSixtyFourBitIdsApartAndRoundTrips)
{
  // Groups 5 and 5 + 2^32 (the same int after a cast) and -1: three groups, in ascending id order.
  const vtkTypeInt64 high = 5 + (vtkTypeInt64(1) << 32);
  const plantmorph::LocalGroups local{ { high, { 0, 3 } }, { 5, { 1 } }, { -1, { 2, 4 } } };
  const plantmorph::OwnerExchange exchange(nullptr, local);
  ASSERT_EQ(exchange.Ids(), (std::vector<vtkTypeInt64>{ -1, 5, high }));
  ASSERT_EQ(exchange.Owned(), (std::vector<std::size_t>{ 0, 1, 2 }));
  EXPECT_FALSE(exchange.AnyRank(false));
  EXPECT_TRUE(exchange.AnyRank(true));
  // Two values per point; each group gets its points' values in input order.
  const std::vector<double> values{ 0, 0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5 };
  const std::vector<std::vector<double>> sent = exchange.SendValues(local, values, 2);
  ASSERT_EQ(sent.size(), 3u);
  EXPECT_EQ(sent[0], (std::vector<double>{ 2, 2.5, 4, 4.5 }));
  EXPECT_EQ(sent[1], (std::vector<double>{ 1, 1.5 }));
  EXPECT_EQ(sent[2], (std::vector<double>{ 0, 0.5, 3, 3.5 }));
  // Back: every point's values where it was, NaN for a point of no group.
  const std::vector<double> back = exchange.ReturnValues(local, 6, sent, 2);
  ASSERT_EQ(back.size(), 12u);
  EXPECT_EQ(std::vector<double>(back.begin(), back.begin() + 10), values);
  EXPECT_TRUE(std::isnan(back[10]) && std::isnan(back[11]));
  EXPECT_EQ(exchange.GatherRows({ 1, 2, 3 }, 1), (std::vector<double>{ 1, 2, 3 }));
  EXPECT_EQ(exchange.GatherBlocks({ { 1 }, {}, { 2, 3 } }), (std::vector<std::vector<double>>{ { 1 }, {}, { 2, 3 } }));
}

TEST(LeafPlan, LeafIdsAboveTheIntRangeStayApartAndSurvive)
{
  // Six points in three leaves by a 64-bit point array LeafId: 5, 5 + 2^32 (5 again after a cast to int) and 2^40;
  // three triangles, one per leaf.
  const vtkTypeInt64 wrap = 5 + (vtkTypeInt64(1) << 32), high = vtkTypeInt64(1) << 40;
  vtkNew<vtkPolyData> piece;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> triangles;
  vtkNew<vtkTypeInt64Array> ids;
  ids->SetName("LeafId");
  const vtkTypeInt64 leaves[3] = { 5, wrap, high };
  for (int leaf = 0; leaf < 3; ++leaf)
  {
    const vtkIdType first = points->GetNumberOfPoints();
    for (int corner = 0; corner < 3; ++corner)
    {
      points->InsertNextPoint(leaf, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
      ids->InsertNextValue(leaves[leaf]);
    }
    const vtkIdType cell[3] = { first, first + 1, first + 2 };
    triangles->InsertNextCell(3, cell);
  }
  piece->SetPoints(points);
  piece->SetPolys(triangles);
  piece->GetPointData()->AddArray(ids);
  std::vector<plantmorph::LeafIdType> leafOf;
  ASSERT_EQ(plantmorph::IdentifyLeaves(piece, leafOf), "");
  EXPECT_EQ(leafOf, (std::vector<plantmorph::LeafIdType>{ 5, 5, 5, wrap, wrap, wrap, high, high, high }));
  ASSERT_TRUE(plantmorph::LeafIdsOfPoints(piece, leafOf));
  EXPECT_EQ(leafOf[4], wrap);
  const plantmorph::LeafPlan plan(piece); // serially: every leaf owned here
  EXPECT_EQ(plan.LeafIds(), (std::vector<plantmorph::LeafIdType>{ 5, wrap, high }));
  EXPECT_EQ(plan.Owned(), plan.LeafIds());
  EXPECT_TRUE(plan.WideIds());
  const std::vector<vtkSmartPointer<vtkPolyData>> whole = plan.Leaves();
  ASSERT_EQ(whole.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
  {
    EXPECT_EQ(whole[k]->GetNumberOfPoints(), 3);
    EXPECT_EQ(whole[k]->GetNumberOfCells(), 1);
  }
  // Marked as the filters mark their outputs: a 64-bit array with the exact id; the rows keep their id order.
  vtkNew<vtkPolyData> marked;
  marked->ShallowCopy(whole[1]);
  marked->GetPointData()->RemoveArray("LeafId");
  plantmorph::MarkLeaf(marked, wrap, plan.WideIds());
  auto* mark = vtkTypeInt64Array::SafeDownCast(marked->GetPointData()->GetArray("LeafId"));
  ASSERT_NE(mark, nullptr);
  EXPECT_EQ(mark->GetValue(2), wrap);
  vtkNew<vtkTable> rows;
  vtkNew<vtkDoubleArray> value;
  value->SetName("Value");
  value->InsertNextValue(1.0);
  rows->AddColumn(value);
  vtkNew<vtkTable> all;
  plantmorph::AppendRows(all, plantmorph::WithLeafColumn(rows, high, true));
  plantmorph::AppendRows(all, plantmorph::WithLeafColumn(rows, wrap, true));
  EXPECT_EQ(plantmorph::LeafIdValue(vtkDataArray::SafeDownCast(all->GetColumn(0)), 0), high);
  EXPECT_EQ(plantmorph::LeafIdValue(vtkDataArray::SafeDownCast(all->GetColumn(0)), 1), wrap);
  // Ids of a floating-point array are rounded; not finite: no leaf.
  vtkNew<vtkDoubleArray> real;
  real->InsertNextValue(3.0e9 + 0.2);
  real->InsertNextValue(std::nan(""));
  EXPECT_EQ(plantmorph::LeafIdValue(real, 0), vtkTypeInt64(3000000000));
  EXPECT_EQ(plantmorph::LeafIdValue(real, 1), plantmorph::NoLeaf);
}
