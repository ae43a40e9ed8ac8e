// SPDX-License-Identifier: GPL-3.0-or-later
// Model C (B-spline leaf, paper 003): blades of every preset are manifold disks that tile their outline, the margins
// pass through their control points, LeafUV is exact on the outline and a mean-value interpolation inside, bad
// control points are refused with the property's name.
#include "BSplineLeaf.h"
#include "MeshInvariants.h"

#include <plantmorph/DataContract.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <tuple>

namespace plantmorph
{
namespace
{
using testing::BoundaryLoops;
using testing::DistanceToPolyline;
using testing::EdgeUse;
using testing::InsideOrOn;
using testing::SignedArea;

LeafGeometry Build(const BSplineLeafParameters& p, bool quality, int resolution = 40)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  settings.quality = quality;
  LeafGeometry leaf;
  EXPECT_EQ(BuildBSplineLeaf(p, settings, leaf), "");
  return leaf;
}

class EveryBSplinePreset : public ::testing::TestWithParam<std::tuple<int, bool>>
{
protected:
  BSplineLeafParameters Parameters() const
  {
    return MakeBSplinePreset(static_cast<BSplinePreset>(std::get<0>(GetParam())), 8.0, 6.0, 7);
  }
  bool Quality() const { return std::get<1>(GetParam()); }
};

TEST_P(EveryBSplinePreset, BladeIsAManifoldDiskThatTilesItsOutline)
{
  const LeafGeometry leaf = Build(Parameters(), Quality());
  const BladeMesh& mesh = leaf.blade;
  ASSERT_GT(mesh.triangles.size(), 50u);
  for (const auto& [edge, count] : EdgeUse(mesh.triangles))
    ASSERT_LE(count, 2);
  const auto loops = BoundaryLoops(mesh.triangles);
  ASSERT_EQ(loops.size(), 1u);
  std::vector<Eigen::Vector2d> outline;
  for (int id : leaf.rightMargin)
    outline.push_back(mesh.points[id]);
  for (auto it = leaf.leftMargin.rbegin() + 1; it != leaf.leftMargin.rend(); ++it)
    outline.push_back(mesh.points[*it]);
  double area = 0.0, outlineArea = 0.0;
  for (std::size_t i = 0; i + 1 < outline.size(); ++i)
    outlineArea += 0.5 * (outline[i].x() * outline[i + 1].y() - outline[i].y() * outline[i + 1].x());
  for (const auto& t : mesh.triangles)
  {
    ASSERT_GT(SignedArea(mesh.points, t), 0.0);
    area += SignedArea(mesh.points, t);
    const Eigen::Vector2d centroid = (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]) / 3.0;
    ASSERT_TRUE(InsideOrOn(centroid, outline, 1e-9)) << "triangle outside the outline";
  }
  EXPECT_NEAR(area, outlineArea, 1e-10 * outlineArea);
  // Boundary vertices are exactly the margin samples plus base and apex.
  const std::set<int> boundary(loops[0].begin(), loops[0].end());
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const int id = static_cast<int>(i);
    if (id != leaf.midvein.front() && id != leaf.midvein.back())
    {
      EXPECT_EQ(boundary.count(id) > 0, mesh.region[i] == RegionMargin);
    }
  }
}

TEST_P(EveryBSplinePreset, MarginsPassThroughTheirControlPoints)
{
  const BSplineLeafParameters p = Parameters();
  const LeafGeometry leaf = Build(p, Quality(), 200);
  for (int side = 0; side < 2; ++side)
  {
    std::vector<Eigen::Vector2d> line;
    for (int id : side == 0 ? leaf.leftMargin : leaf.rightMargin)
      line.push_back(leaf.blade.points[id]);
    for (const Eigen::Vector3d& c : side == 0 ? p.leftMargin : p.rightMargin)
      EXPECT_LT(DistanceToPolyline(c.head<2>(), line), 2e-3) << "control point " << c.transpose(); // sagitta, R = 200
  }
}

TEST_P(EveryBSplinePreset, LeafUVIsExactOnTheOutlineAndInRangeInside)
{
  const LeafGeometry leaf = Build(Parameters(), Quality());
  const BladeMesh& mesh = leaf.blade;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const Eigen::Vector2d& uv = mesh.uv[i];
    ASSERT_TRUE(uv.x() >= -0.5 && uv.x() <= 0.5 && uv.y() >= 0.0 && uv.y() <= 1.0);
    if (mesh.region[i] == RegionMargin)
    {
      EXPECT_EQ(std::abs(uv.x()), 0.5);
    }
    if (mesh.region[i] == RegionMidvein)
    {
      EXPECT_EQ(uv.x(), 0.0);
    }
    // Interior points take u of their own half's sign.
    if (mesh.region[i] == RegionBlade)
    {
      EXPECT_EQ(uv.x() < 0, mesh.points[i].x() < 0) << "point " << mesh.points[i].transpose();
    }
  }
  double previous = -1;
  for (int id : leaf.midvein)
  {
    EXPECT_GT(mesh.uv[id].y(), previous);
    previous = mesh.uv[id].y();
  }
}

INSTANTIATE_TEST_SUITE_P(BSplineLeaf, EveryBSplinePreset,
  ::testing::Combine(::testing::Range(1, BSplinePresetCount), ::testing::Bool()),
  [](const ::testing::TestParamInfo<std::tuple<int, bool>>& info) {
    return BSplinePresetName(static_cast<BSplinePreset>(std::get<0>(info.param))) +
      (std::get<1>(info.param) ? "Quality" : "Paper");
  });

TEST(BSplineLeaf, MeanValueCoordinatesReproduceAffineFunctions)
{
  // An L-shaped (concave) polygon; values an affine function of position: MVC reproduce it exactly inside.
  const std::vector<Eigen::Vector2d> polygon = { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 3 }, { 0, 3 } };
  auto f = [](const Eigen::Vector2d& x) { return Eigen::Vector2d(0.3 * x.x() - 2 * x.y() + 1, x.x() + x.y()); };
  std::vector<Eigen::Vector2d> values;
  for (const Eigen::Vector2d& p : polygon)
    values.push_back(f(p));
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k)
  {
    const Eigen::Vector2d x = k % 2 ? Eigen::Vector2d(0.05 + 3.9 * u(random), 0.05 + 0.9 * u(random))
                                    : Eigen::Vector2d(0.05 + 0.9 * u(random), 0.05 + 2.9 * u(random));
    EXPECT_LT((MeanValueInterpolate(polygon, values, x) - f(x)).norm(), 1e-12);
  }
  EXPECT_LT((MeanValueInterpolate(polygon, values, { 2.0, 0.0 }) - f({ 2.0, 0.0 })).norm(), 1e-12); // on an edge
  EXPECT_EQ(MeanValueInterpolate(polygon, values, polygon[3]), values[3]);                          // at a vertex
}

TEST(BSplineLeaf, SameControlPointsGiveBitIdenticalOutput)
{
  const BSplineLeafParameters p = MakeBSplinePreset(BSplinePreset::PinOak, 8.0, 6.0, 7);
  const LeafGeometry a = Build(p, true), b = Build(p, true);
  EXPECT_TRUE(a.blade.points == b.blade.points);
  EXPECT_TRUE(a.blade.uv == b.blade.uv);
  EXPECT_TRUE(a.blade.triangles == b.blade.triangles);
}

TEST(BSplineLeaf, BadControlPointsGiveAMessageAndNoLeaf)
{
  auto message = [](const BSplineLeafParameters& p) {
    LeafMeshParameters settings;
    settings.resolution = 30;
    LeafGeometry leaf;
    const std::string error = BuildBSplineLeaf(p, settings, leaf);
    EXPECT_TRUE(leaf.blade.points.empty() && leaf.midvein.empty());
    return error;
  };
  const BSplineLeafParameters good = MakeBSplinePreset(BSplinePreset::Elliptic, 8.0, 4.0, 5);
  BSplineLeafParameters p = good;
  p.midvein.resize(1);
  EXPECT_EQ(message(p), "MidveinPoints: control points: need at least 2, got 1");
  p = good;
  p.rightMargin[2].x() = std::nan("");
  EXPECT_NE(message(p).find("RightMarginPoints: control points: point"), std::string::npos) << message(p);
  p = good;
  p.leftMargin.clear();
  EXPECT_EQ(message(p), "LeftMarginPoints: needs at least one control point besides the base and the apex");
  p = good;
  p.rightMargin[2].x() = -3.0; // the right margin crosses the midvein
  EXPECT_NE(message(p).find("MidveinPoints/LeftMarginPoints/RightMarginPoints: outline:"), std::string::npos)
    << message(p);
  p = good;
  std::swap(p.leftMargin, p.rightMargin); // a mirrored leaf: the outline runs clockwise
  EXPECT_NE(message(p).find("outline:"), std::string::npos) << message(p);
}

} // namespace
} // namespace plantmorph

namespace plantmorph
{
namespace
{
std::vector<Eigen::Vector3d> Positions(const LeafGeometry& leaf)
{
  std::vector<Eigen::Vector3d> x;
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
    x.emplace_back(leaf.blade.points[i].x(), leaf.blade.points[i].y(), leaf.z.empty() ? 0.0 : leaf.z[i]);
  return x;
}

TEST(BSplineLeaf, PointsInATiltedPlaneGiveABladeInThatPlane)
{
  BSplineLeafParameters p = MakeBSplinePreset(BSplinePreset::Cucumber, 8.0, 7.0, 7);
  for (std::vector<Eigen::Vector3d>* curve : { &p.midvein, &p.leftMargin, &p.rightMargin })
    for (Eigen::Vector3d& x : *curve)
      x.z() = 0.5 * x.y() + 0.2 * x.x() + 1.0;
  const LeafGeometry leaf = Build(p, true);
  ASSERT_FALSE(leaf.z.empty());
  for (const Eigen::Vector3d& x : Positions(leaf))
    ASSERT_NEAR(x.z(), 0.5 * x.y() + 0.2 * x.x() + 1.0, 1e-9);
  const Eigen::Vector3d normal = Eigen::Vector3d(-0.2, -0.5, 1.0).normalized();
  for (const Eigen::Vector3d& n : leaf.normals)
    ASSERT_GT(n.dot(normal), 1.0 - 1e-9);
}

TEST(BSplineLeaf, CurvedControlPointsGiveACurledManifoldBlade)
{
  // A blade curled across: every control point on the cylinder z = 0.12 x^2.
  BSplineLeafParameters p = MakeBSplinePreset(BSplinePreset::Elliptic, 8.0, 6.0, 7);
  for (std::vector<Eigen::Vector3d>* curve : { &p.leftMargin, &p.rightMargin })
    for (Eigen::Vector3d& x : *curve)
      x.z() = 0.12 * x.x() * x.x();
  const LeafGeometry leaf = Build(p, true);
  const std::vector<Eigen::Vector3d> x = Positions(leaf);
  ASSERT_FALSE(leaf.z.empty());
  for (const auto& [edge, count] : EdgeUse(leaf.blade.triangles))
    ASSERT_LE(count, 2);
  ASSERT_EQ(BoundaryLoops(leaf.blade.triangles).size(), 1u);
  // Outline vertices are the curves' samples: the margins' heights come from their control points; interior
  // points are lifted between them.
  double high = 0.0;
  for (int id : leaf.rightMargin)
    high = std::max(high, x[id].z());
  EXPECT_GT(high, 0.12 * 2.9 * 2.9 * 0.9);
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    EXPECT_GE(x[i].z(), -1e-9);
    EXPECT_LE(x[i].z(), high + 1e-9);
  }
  for (const Eigen::Vector3d& n : leaf.normals)
    EXPECT_GT(n.z(), 0.5); // the blade faces up
  // TCoords are the flat blade's: still spanning [0, 1].
  double lowT = 1, highT = 0;
  for (const Eigen::Vector2d& t : leaf.tcoords)
  {
    lowT = std::min(lowT, t.x());
    highT = std::max(highT, t.x());
  }
  EXPECT_EQ(lowT, 0.0);
  EXPECT_EQ(highT, 1.0);
}
} // namespace
} // namespace plantmorph
