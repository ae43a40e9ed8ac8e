// SPDX-License-Identifier: GPL-3.0-or-later
// True vein orders (docs/methods/venation.md "Vein orders"): 1 primary, 2 secondary, 3 tertiary (a
// reticulum vein joining primaries or secondaries at both ends), 4 the finer reticulum (veins that only subdivide
// areoles), 5 free-ending veinlets. Checked on a hand-built network against a hand count, and on presets as
// invariants: both reticulum orders occur, mean widths do not increase with order, and every vein of order 2 or
// more starts or ends on a vein of lower or equal order.
#include "VeinGraph.h"
#include "VeinNetworkMeasures.h"
#include "VenationGrowth.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace plantmorph
{
namespace
{

/// Adds a vein of `order` along the given nodes.
int Path(VeinGraph& graph, const std::vector<int>& nodes, int order)
{
  const int vein = graph.AddVein(order);
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i)
    graph.AddEdge(nodes[i], nodes[i + 1], vein);
  return vein;
}

TEST(VeinOrder, ReticulumOrdersMatchAHandCount)
{
  // A midvein x = 2 (y 0..4) in a 4 x 4 margin, secondaries y = 1 and y = 3 to the right, and the reticulum:
  //   T  (3,1)-(3,2)-(3,3): from secondary to secondary: tertiary (3)
  //   R1 (3,2)-(2,2): from T to the midvein: only subdivides the areole T closes: 4
  //   R2 (3.5,1)-(3.5,1.5): from a secondary to a free end: 4
  //   R3 (3.5,3)-(3.5,4): from a secondary to the margin (the margin does not count): 4
  //   V  a veinlet (order 5) and the margin (0) keep theirs.
  VeinGraph graph(Eigen::Vector2d(-1, -1), Eigen::Vector2d(5, 5), 0.5);
  auto node = [&](double x, double y) { return graph.AddNode(Eigen::Vector2d(x, y)); };
  const int c00 = node(0, 0), c40 = node(4, 0), c44 = node(4, 4), c04 = node(0, 4);
  const int m0 = node(2, 0), m1 = node(2, 1), m2 = node(2, 2), m3 = node(2, 3), m4 = node(2, 4);
  const int s11 = node(3, 1), s12 = node(3.5, 1), s13 = node(4, 1);
  const int s31 = node(3, 3), s32 = node(3.5, 3), s33 = node(4, 3);
  const int t2 = node(3, 2), r2 = node(3.5, 1.5), r3 = node(3.5, 4), v0 = node(2.5, 2.5), v1 = node(2.7, 2.5);
  const int margin = Path(graph, { c00, m0, c40, s13, s33, c44, r3, m4, c04, c00 }, VeinOrderMargin);
  const int primary = Path(graph, { m0, m1, m2, m3, m4 }, VeinOrderPrimary);
  const int secondary1 = Path(graph, { m1, s11, s12, s13 }, VeinOrderSecondary);
  const int secondary3 = Path(graph, { m3, s31, s32, s33 }, VeinOrderSecondary);
  const int t = Path(graph, { s11, t2, s31 }, VeinOrderTertiary);
  const int r1 = Path(graph, { t2, m2 }, VeinOrderTertiary);
  const int r2v = Path(graph, { s12, r2 }, VeinOrderTertiary);
  const int r3v = Path(graph, { s32, r3 }, VeinOrderTertiary);
  const int veinlet = Path(graph, { v0, v1 }, VeinOrderVeinlet);

  const std::vector<int> orders = ReticulumOrders(graph);
  ASSERT_EQ(orders.size(), graph.Veins().size());
  EXPECT_EQ(orders[margin], VeinOrderMargin);
  EXPECT_EQ(orders[primary], VeinOrderPrimary);
  EXPECT_EQ(orders[secondary1], VeinOrderSecondary);
  EXPECT_EQ(orders[secondary3], VeinOrderSecondary);
  EXPECT_EQ(orders[t], VeinOrderTertiary);
  EXPECT_EQ(orders[r1], VeinOrderQuaternary);
  EXPECT_EQ(orders[r2v], VeinOrderQuaternary);
  EXPECT_EQ(orders[r3v], VeinOrderQuaternary);
  EXPECT_EQ(orders[veinlet], VeinOrderVeinlet);
}

VenationResult GrowOn(const LeafGeometry& leaf, const VenationParameters& p)
{
  VenationResult result;
  EXPECT_EQ(GrowVenation({ leaf.blade.points, leaf.blade.uv, leaf.blade.triangles }, p, result), "");
  return result;
}

TEST(VeinOrder, PresetsHaveBothReticulumOrdersNarrowingWithOrderAndJoinedToLowerOrders)
{
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry leaf;
  ASSERT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, 5.0), settings, leaf), "");
  for (const VenationPreset preset : { VenationPreset::PaperMulberry, VenationPreset::Poplar, VenationPreset::Tomato })
  {
    SCOPED_TRACE(VenationPresetName(preset));
    VenationParameters p = MakeVenationPreset(preset);
    p.seed = 3;
    const VenationResult r = GrowOn(leaf, p);
    VeinNetworkMeasures m;
    ASSERT_EQ(MeasureVenation({ leaf.blade.points, leaf.blade.uv, leaf.blade.triangles }, r, m), "");
    std::cout << VenationPresetName(preset) << ": length by order 1-5";
    for (int o = 1; o < VeinOrderCount; ++o)
      std::cout << " " << m.length[o];
    std::cout << "; mean width";
    for (int o = 1; o < VeinOrderCount; ++o)
      std::cout << " " << m.meanWidth[o];
    std::cout << "\n";
    EXPECT_GT(m.length[VeinOrderTertiary], 0.0);
    EXPECT_GT(m.length[VeinOrderQuaternary], 0.0);
    // Widths do not increase with order (over the orders present).
    double previous = m.meanWidth[VeinOrderPrimary];
    for (int o = VeinOrderSecondary; o < VeinOrderCount; ++o)
    {
      if (m.length[o] == 0.0)
        continue;
      EXPECT_LE(m.meanWidth[o], previous + 1e-12) << "order " << o;
      previous = m.meanWidth[o];
    }
    // Every vein of order >= 2 starts or ends on another vein of lower or equal order.
    std::vector<std::vector<std::size_t>> veinsAt(r.nodes.size());
    for (std::size_t v = 0; v < r.veins.size(); ++v)
    {
      for (int n : r.veins[v].nodes)
        veinsAt[n].push_back(v);
    }
    for (std::size_t v = 0; v < r.veins.size(); ++v)
    {
      const auto& vein = r.veins[v];
      if (vein.order < VeinOrderSecondary)
        continue;
      bool joined = false;
      for (int end : { vein.nodes.front(), vein.nodes.back() })
      {
        for (std::size_t w : veinsAt[end])
          joined = joined || (w != v && r.veins[w].order <= vein.order);
      }
      EXPECT_TRUE(joined) << "vein " << v << " of order " << vein.order;
    }
    // A tertiary joins primaries or secondaries at both ends (the rule itself, seen from the output).
    std::vector<char> major(r.nodes.size(), 0);
    for (const auto& vein : r.veins)
    {
      if (vein.order > VeinOrderSecondary)
        continue;
      for (int n : vein.nodes)
        major[n] = 1;
    }
    for (const auto& vein : r.veins)
    {
      if (vein.order == VeinOrderTertiary)
      {
        EXPECT_TRUE(major[vein.nodes.front()] && major[vein.nodes.back()]);
      }
    }
  }
}

} // namespace
} // namespace plantmorph
