// SPDX-License-Identifier: GPL-3.0-or-later
// The network measures (VeinNetworkMeasures.h) against hand counts on small networks: a 2 x 2 grid
// of unit squares, two rectangles of areas 1 and 3 side by side, a star with one arm ending on the margin, and the
// pipe-model tree of space colonization (a tree: loopiness 1, no areoles); the areole histogram's bins and counts,
// and MeasureVenation's blade area and margin on a rectangle.
#include "VeinNetworkMeasures.h"

#include <gtest/gtest.h>

namespace plantmorph
{
namespace
{
VenationResult::Polyline Vein(std::vector<int> nodes, int order)
{
  VenationResult::Polyline line;
  line.nodes = std::move(nodes);
  line.order = order;
  return line;
}

TEST(VeinNetworkMeasures, TwoByTwoGridOfUnitSquares)
{
  // Nodes 3 x 3 at integer points (id = 3 y + x); rows are secondaries, columns tertiaries.
  VenationResult r;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      r.nodes.emplace_back(x, y);
  r.width.assign(9, 0.1);
  for (int k = 0; k < 3; ++k)
  {
    r.veins.push_back(Vein({ 3 * k, 3 * k + 1, 3 * k + 2 }, VeinOrderSecondary));
    r.veins.push_back(Vein({ k, 3 + k, 6 + k }, VeinOrderTertiary));
  }
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, 4.0, {}, 1e-9, m), "");
  EXPECT_DOUBLE_EQ(m.totalLength, 12.0);
  EXPECT_DOUBLE_EQ(m.length[VeinOrderSecondary], 6.0);
  EXPECT_DOUBLE_EQ(m.length[VeinOrderTertiary], 6.0);
  EXPECT_DOUBLE_EQ(m.vla, 3.0);
  EXPECT_EQ(m.areoles, 4u);
  EXPECT_DOUBLE_EQ(m.areoleMean, 1.0);
  EXPECT_DOUBLE_EQ(m.areoleMedian, 1.0);
  EXPECT_NEAR(m.areoleCV, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.spanningLength, 8.0); // 9 nodes, 8 unit edges
  EXPECT_DOUBLE_EQ(m.loopiness, 8.0 / 12.0);
  EXPECT_EQ(m.branchPoints, 5u); // 4 edge midpoints (degree 3) and the centre (degree 4)
  EXPECT_EQ(m.freeEnds, 0u);     // corners have degree 2
  EXPECT_DOUBLE_EQ(m.branchPointsPerArea, 1.25);
  EXPECT_DOUBLE_EQ(m.meanWidth[VeinOrderSecondary], 0.1);
}

TEST(VeinNetworkMeasures, RectanglesOfAreaOneAndThree)
{
  // (0,0) (1,0) (4,0) bottom, a primary of width 0.3; (0,1) (1,1) (4,1) top, a secondary of width 0.2; three
  // vertical tertiaries between them (width 0.25, the mean of their ends).
  VenationResult r;
  r.nodes = { { 0, 0 }, { 1, 0 }, { 4, 0 }, { 0, 1 }, { 1, 1 }, { 4, 1 } };
  r.width = { 0.3, 0.3, 0.3, 0.2, 0.2, 0.2 };
  r.veins = { Vein({ 0, 1, 2 }, VeinOrderPrimary), Vein({ 3, 4, 5 }, VeinOrderSecondary),
    Vein({ 0, 3 }, VeinOrderTertiary), Vein({ 1, 4 }, VeinOrderTertiary), Vein({ 2, 5 }, VeinOrderTertiary) };
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, 8.0, {}, 1e-9, m), "");
  EXPECT_DOUBLE_EQ(m.totalLength, 11.0);
  EXPECT_EQ(m.areoles, 2u);
  ASSERT_EQ(m.areoleAreas.size(), 2u);
  EXPECT_DOUBLE_EQ(m.areoleAreas[0], 1.0);
  EXPECT_DOUBLE_EQ(m.areoleAreas[1], 3.0);
  EXPECT_DOUBLE_EQ(m.areoleMean, 2.0);
  EXPECT_DOUBLE_EQ(m.areoleMedian, 2.0);
  EXPECT_DOUBLE_EQ(m.areoleCV, 0.5);       // population standard deviation 1 over mean 2
  EXPECT_DOUBLE_EQ(m.spanningLength, 7.0); // three of the unit square's edges, the right side, one long edge
  EXPECT_DOUBLE_EQ(m.loopiness, 7.0 / 11.0);
  EXPECT_EQ(m.branchPoints, 2u);
  EXPECT_EQ(m.freeEnds, 0u);
  EXPECT_DOUBLE_EQ(m.meanWidth[VeinOrderPrimary], 0.3);
  EXPECT_DOUBLE_EQ(m.meanWidth[VeinOrderSecondary], 0.2);
  EXPECT_DOUBLE_EQ(m.meanWidth[VeinOrderTertiary], 0.25);
  EXPECT_DOUBLE_EQ(m.length[VeinOrderTertiary], 3.0);
}

TEST(VeinNetworkMeasures, StarWithOneArmOnTheMargin)
{
  // Centre (0,0); arms to (1,0), (0,2) and (-3,0); the blade is the square [-3, 3]^2, so (-3,0) is on the margin.
  VenationResult r;
  r.nodes = { { 0, 0 }, { 1, 0 }, { 0, 2 }, { -3, 0 } };
  r.width = { 0.2, 0.1, 0.1, 0.1 };
  r.veins = { Vein({ 3, 0, 1 }, VeinOrderPrimary), Vein({ 0, 2 }, VeinOrderSecondary) };
  const std::vector<Eigen::Vector2d> margin = { { -3, -3 }, { 3, -3 }, { 3, 3 }, { -3, 3 } };
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVeinNetwork(r, 36.0, margin, 1e-9, m), "");
  EXPECT_DOUBLE_EQ(m.totalLength, 6.0);
  EXPECT_DOUBLE_EQ(m.loopiness, 1.0);
  EXPECT_EQ(m.areoles, 0u);
  EXPECT_EQ(m.branchPoints, 1u);
  EXPECT_EQ(m.freeEnds, 2u); // (1,0) and (0,2); (-3,0) ends on the margin
  EXPECT_DOUBLE_EQ(m.freeEndsPerArea, 2.0 / 36.0);
  EXPECT_DOUBLE_EQ(m.meanWidth[VeinOrderPrimary], (3.0 * 0.15 + 1.0 * 0.15) / 4.0);
  // Without a margin every end is free.
  ASSERT_EQ(MeasureVeinNetwork(r, 36.0, {}, 1e-9, m), "");
  EXPECT_EQ(m.freeEnds, 3u);
}

TEST(VeinNetworkMeasures, BadInputGivesAMessage)
{
  VenationResult r;
  r.nodes = { { 0, 0 }, { 1, 0 } };
  r.width = { 0.1, 0.1 };
  r.veins = { Vein({ 0, 5 }, VeinOrderPrimary) };
  VeinNetworkMeasures m;
  EXPECT_NE(MeasureVeinNetwork(r, 1.0, {}, 1e-9, m), "");
  r.veins = { Vein({ 0, 1 }, VeinOrderPrimary) };
  EXPECT_NE(MeasureVeinNetwork(r, 0.0, {}, 1e-9, m).find("bladeArea"), std::string::npos);
}

TEST(AreoleHistogram, EqualBinsFromTheSmallestToTheLargestArea)
{
  // Areas 1..10 in 3 bins of width 3: [1, 4) holds 1, 2, 3; [4, 7) 4, 5, 6; [7, 10] 7, 8, 9, 10.
  const AreoleHistogram h = MakeAreoleHistogram({ 10, 1, 2, 3, 4, 5, 6, 7, 8, 9 }, 3);
  ASSERT_EQ(h.count.size(), 3u);
  EXPECT_EQ(h.count, (std::vector<std::size_t>{ 3, 3, 4 }));
  EXPECT_DOUBLE_EQ(h.lower[0], 1.0);
  EXPECT_DOUBLE_EQ(h.upper[0], 4.0);
  EXPECT_DOUBLE_EQ(h.lower[2], 7.0);
  EXPECT_DOUBLE_EQ(h.upper[2], 10.0);
  // One bin holds all; equal areas get bins of positive width; no areas, no bins.
  EXPECT_EQ(MakeAreoleHistogram({ 2, 5, 3 }, 1).count, (std::vector<std::size_t>{ 3 }));
  const AreoleHistogram same = MakeAreoleHistogram({ 2, 2, 2 }, 4);
  EXPECT_EQ(same.count, (std::vector<std::size_t>{ 3, 0, 0, 0 }));
  EXPECT_GT(same.upper[3], same.lower[0]);
  EXPECT_TRUE(MakeAreoleHistogram({}, 5).count.empty());
  EXPECT_TRUE(MakeAreoleHistogram({ 1.0 }, 0).count.empty());
}

TEST(VeinNetworkMeasures, MeasureVenationUsesTheBladesAreaAndOuterMargin)
{
  // A 4 x 2 rectangle of two triangles; a vein from the bottom edge's middle (on the margin) to the centre (free)
  // and a branch from there to the right edge (on the margin): one free end (the centre is a corner of degree 2).
  VenationBlade blade;
  blade.points = { { 0, 0 }, { 4, 0 }, { 4, 2 }, { 0, 2 } };
  blade.uv = { { -0.5, 0 }, { 0.5, 0 }, { 0.5, 1 }, { -0.5, 1 } };
  blade.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  VenationResult r;
  r.nodes = { { 2, 0 }, { 2, 1 }, { 3, 1 }, { 4, 1 } };
  r.width = { 0.1, 0.1, 0.1, 0.1 };
  r.leafLength = 2.0;
  r.veins = { Vein({ 0, 1 }, VeinOrderPrimary), Vein({ 1, 2 }, VeinOrderSecondary) };
  VeinNetworkMeasures m;
  ASSERT_EQ(MeasureVenation(blade, r, m), "");
  EXPECT_DOUBLE_EQ(m.bladeArea, 8.0);
  EXPECT_DOUBLE_EQ(m.vla, 2.0 / 8.0);
  EXPECT_EQ(m.freeEnds, 1u); // (3, 1); (2, 0) lies on the margin
  r.veins[1] = Vein({ 1, 2, 3 }, VeinOrderSecondary);
  ASSERT_EQ(MeasureVenation(blade, r, m), "");
  EXPECT_EQ(m.freeEnds, 0u); // (4, 1) lies on the margin too
  EXPECT_EQ(m.branchPoints, 0u);
}

} // namespace
} // namespace plantmorph
