// SPDX-License-Identifier: GPL-3.0-or-later
// Model B (space-curve leaf, paper 002): the strip mesh is a manifold disk, flat leaves are mirror-symmetric and
// face +Z, growth at fixed mu is an exact similarity, the symmetry plane mirrors the margins, bad input is refused.
#include "MeshInvariants.h"
#include "SpaceCurveLeaf.h"

#include <plantmorph/DataContract.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

namespace plantmorph
{
namespace
{
using testing::BoundaryLoops;
using testing::EdgeUse;
using testing::SignedArea;

/// Paper 002 Fig. 1: triangular curvature, mu = 2, lambda = 0.7.
SpaceCurveParameters FigureOne(double length = 5.0)
{
  SpaceCurveParameters p;
  p.length = length;
  p.curvature.type = CurvatureFamily::Triangular;
  p.curvature.mu = 2.0;
  p.curvature.lambda = 0.7;
  return p;
}

/// Paper 002 Fig. 5: triangular curvature mu = 5 and torsion eta = 4, lambda = 0.95.
SpaceCurveParameters FigureFive(double length = 5.0)
{
  SpaceCurveParameters p = FigureOne(length);
  p.curvature.mu = 5.0;
  p.curvature.lambda = 0.95;
  p.torsion = p.curvature;
  p.torsion.mu = 4.0;
  return p;
}

LeafGeometry Build(const SpaceCurveParameters& p, int resolution = 40, int columns = 5)
{
  SpaceCurveMeshParameters settings;
  settings.resolution = resolution;
  settings.columns = columns;
  LeafGeometry leaf;
  EXPECT_EQ(BuildSpaceCurveLeaf(p, settings, leaf), "");
  return leaf;
}

std::vector<Eigen::Vector3d> Points(const LeafGeometry& leaf)
{
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
    points.emplace_back(leaf.blade.points[i].x(), leaf.blade.points[i].y(), leaf.z[i]);
  return points;
}

void ExpectManifoldDisk(const LeafGeometry& leaf)
{
  const auto use = EdgeUse(leaf.blade.triangles);
  for (const auto& [edge, count] : use)
    ASSERT_LE(count, 2);
  const auto loops = BoundaryLoops(leaf.blade.triangles);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(static_cast<long>(leaf.blade.points.size()) - static_cast<long>(use.size()) +
      static_cast<long>(leaf.blade.triangles.size()),
    1L);
  // The boundary is exactly the two margins (Region 4) plus base and apex.
  std::size_t margin = 0;
  for (int r : leaf.blade.region)
    margin += r == RegionMargin;
  // (Palmate leaves: plus every further lobe's tip.)
  EXPECT_EQ(loops[0].size(), margin + 2 + leaf.lobeMidveins.size());
  for (int id : loops[0])
  {
    bool lobeTip = false;
    for (const std::vector<int>& lobe : leaf.lobeMidveins)
      lobeTip = lobeTip || id == lobe.back();
    EXPECT_TRUE(
      leaf.blade.region[id] == RegionMargin || id == leaf.midvein.front() || id == leaf.midvein.back() || lobeTip);
  }
}

TEST(SpaceCurveLeaf, FlatLeafIsAMirrorSymmetricManifoldFacingUp)
{
  const LeafGeometry leaf = Build(FigureOne());
  ExpectManifoldDisk(leaf);
  for (double z : leaf.z)
    EXPECT_NEAR(z, 0.0, 1e-12);
  for (const auto& t : leaf.blade.triangles)
    ASSERT_GT(SignedArea(leaf.blade.points, t), 0.0) << "normal must face +Z";
  for (const Eigen::Vector3d& n : leaf.normals)
    EXPECT_NEAR(n.z(), 1.0, 1e-12);
  ASSERT_EQ(leaf.leftMargin.size(), leaf.rightMargin.size());
  for (std::size_t i = 0; i < leaf.leftMargin.size(); ++i)
  {
    const Eigen::Vector2d& l = leaf.blade.points[leaf.leftMargin[i]];
    const Eigen::Vector2d& r = leaf.blade.points[leaf.rightMargin[i]];
    EXPECT_NEAR(l.x(), -r.x(), 1e-12);
    EXPECT_NEAR(l.y(), r.y(), 1e-12);
    if (i > 0 && i + 1 < leaf.leftMargin.size())
    {
      EXPECT_LT(l.x(), 0.0);
    }
  }
  // Base at the origin, chord (and, for a flat leaf, the whole midvein) along +Y.
  EXPECT_LT(leaf.blade.points[leaf.midvein.front()].norm(), 1e-15);
  for (int id : leaf.midvein)
    EXPECT_NEAR(leaf.blade.points[id].x(), 0.0, 1e-12);
  EXPECT_GT(leaf.blade.points[leaf.midvein.back()].y(), 0.0);
}

TEST(SpaceCurveLeaf, GrowingAtFixedMuScalesTheWholeMesh)
{
  for (const SpaceCurveParameters& small : { FigureOne(1.0), FigureFive(1.0) })
  {
    SpaceCurveParameters large = small;
    large.length = 3.0;
    const std::vector<Eigen::Vector3d> a = Points(Build(small)), b = Points(Build(large));
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_LT((b[i] / 3.0 - a[i]).norm(), 1e-9) << "point " << i;
  }
}

TEST(SpaceCurveLeaf, MarginsAreMirrorImagesInTheSymmetryPlane)
{
  for (double opening : { 0.0, 0.25, -0.4 })
  {
    SpaceCurveParameters p = FigureFive();
    p.opening = opening;
    const LeafGeometry leaf = Build(p);
    ExpectManifoldDisk(leaf);
    const std::vector<Eigen::Vector3d> x = Points(leaf);
    // Every left-right pair differs along one direction g, and their midpoints lie in one plane through the base
    // with normal g.
    const std::size_t middle = leaf.leftMargin.size() / 2;
    const Eigen::Vector3d g = (x[leaf.leftMargin[middle]] - x[leaf.rightMargin[middle]]).normalized();
    for (std::size_t i = 1; i + 1 < leaf.leftMargin.size(); ++i)
    {
      const Eigen::Vector3d d = x[leaf.leftMargin[i]] - x[leaf.rightMargin[i]];
      EXPECT_LT(d.normalized().cross(g).norm(), 1e-9) << "opening " << opening << " row " << i;
      EXPECT_NEAR((0.5 * (x[leaf.leftMargin[i]] + x[leaf.rightMargin[i]])).dot(g), 0.0, 1e-9);
    }
  }
}

TEST(SpaceCurveLeaf, TorsionMakesAThreeDimensionalLeaf)
{
  const LeafGeometry leaf = Build(FigureFive());
  double low = 0, high = 0;
  for (double z : leaf.z)
  {
    low = std::min(low, z);
    high = std::max(high, z);
  }
  EXPECT_GT(high - low, 0.05 * 5.0);
  for (const Eigen::Vector3d& n : leaf.normals)
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
}

TEST(SpaceCurveLeaf, LeafUVAndRegionFollowTheDataContract)
{
  const LeafGeometry leaf = Build(FigureFive(), 30, 4);
  const BladeMesh& blade = leaf.blade;
  for (std::size_t i = 0; i < blade.uv.size(); ++i)
  {
    EXPECT_TRUE(blade.uv[i].x() >= -0.5 && blade.uv[i].x() <= 0.5 && blade.uv[i].y() >= 0 && blade.uv[i].y() <= 1);
  }
  for (int id : leaf.leftMargin)
    EXPECT_TRUE(blade.uv[id].x() == -0.5 || id == leaf.midvein.front() || id == leaf.midvein.back());
  double previous = -1;
  for (int id : leaf.midvein)
  {
    EXPECT_EQ(blade.region[id], RegionMidvein);
    EXPECT_EQ(blade.uv[id].x(), 0.0);
    EXPECT_GT(blade.uv[id].y(), previous);
    previous = blade.uv[id].y();
  }
  EXPECT_EQ(blade.uv[leaf.midvein.front()].y(), 0.0);
  EXPECT_EQ(blade.uv[leaf.midvein.back()].y(), 1.0);
  // Rows of 2 * columns + 1 points between base and apex: (rows - 1) * 9 + 2 points.
  EXPECT_EQ(blade.points.size(), 29u * 9u + 2u);
  // The outline's points come first (the Outline port takes the blade's first points).
  int largest = 0;
  for (const std::vector<int>* line : { &leaf.leftMargin, &leaf.rightMargin, &leaf.midvein })
    for (int id : *line)
      largest = std::max(largest, id);
  EXPECT_EQ(largest + 1, 3 * 29 + 2);
}

TEST(SpaceCurveLeaf, RK4AndRK45Agree)
{
  SpaceCurveParameters p = FigureFive();
  p.method = FrenetMethod::RK4;
  p.rk4StepsPerSample = 8;
  const std::vector<Eigen::Vector3d> a = Points(Build(p));
  p.method = FrenetMethod::RK45;
  p.tolerance = 1e-12;
  const std::vector<Eigen::Vector3d> b = Points(Build(p));
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_LT((a[i] - b[i]).norm(), 1e-7);
}

TEST(SpaceCurveLeaf, BadInputGivesAMessageAndNoLeaf)
{
  auto message = [](SpaceCurveParameters p, int resolution = 20) {
    SpaceCurveMeshParameters settings;
    settings.resolution = resolution;
    LeafGeometry leaf;
    const std::string error = BuildSpaceCurveLeaf(p, settings, leaf);
    EXPECT_TRUE(leaf.blade.points.empty() && leaf.blade.triangles.empty());
    return error;
  };
  SpaceCurveParameters p = FigureOne();
  p.length = 0.0;
  EXPECT_EQ(message(p), "CurveLength = 0 is outside the accepted range (0, 1e6]");
  p = FigureOne();
  p.curvature.lambda = 1.5;
  EXPECT_EQ(message(p), "CurvatureLambda = 1.5 is outside the accepted range [0, 1]");
  p = FigureOne();
  p.opening = 1.0;
  EXPECT_EQ(message(p), "Opening = 1 is outside the accepted range (-1, 1)");
  p = FigureOne();
  p.curvature.mu = std::nan("");
  EXPECT_NE(message(p).find("CurvatureMu = nan"), std::string::npos);
  p = FigureOne();
  p.curvature.mu = 14.0; // turns the margin past the chord
  EXPECT_NE(message(p).find("Curvature:"), std::string::npos) << message(p);
  EXPECT_EQ(message(FigureOne(), 1), "Resolution = 1 is outside the accepted range [2, 4000]");
}

} // namespace
} // namespace plantmorph

#include "SpaceCurvePresets.h"

namespace plantmorph
{
namespace
{
TEST(SpaceCurveLeaf, EveryPaperFigurePresetBuildsAManifoldBlade)
{
  for (int k = 1; k < SpaceCurvePresetCount; ++k)
  {
    const auto preset = static_cast<SpaceCurvePreset>(k);
    SCOPED_TRACE(SpaceCurvePresetName(preset));
    const LeafGeometry leaf = Build(MakeSpaceCurvePreset(preset, 5.0));
    ASSERT_FALSE(leaf.blade.triangles.empty());
    ExpectManifoldDisk(leaf);
  }
}
} // namespace
} // namespace plantmorph
