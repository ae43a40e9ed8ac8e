// SPDX-License-Identifier: GPL-3.0-or-later
// Model A end to end: the blade is a manifold disk that tiles the outline exactly, with LeafUV, Region and TCoords as
// the data contract says, for every preset and both meshing modes.
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "MeshInvariants.h"

#include <plantmorph/DataContract.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <set>
#include <string>
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

LeafGeometry Build(DeformedRectanglePreset preset, bool quality, int resolution = 40)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  settings.quality = quality;
  LeafGeometry leaf;
  const std::string error = BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(preset, 5.0), settings, leaf);
  EXPECT_EQ(error, "") << PresetName(preset);
  return leaf;
}

/// The outline as a closed polygon of points: up the right margin, down the left one.
std::vector<Eigen::Vector2d> OutlinePolygon(const LeafGeometry& leaf)
{
  std::vector<Eigen::Vector2d> polygon;
  for (int id : leaf.rightMargin)
    polygon.push_back(leaf.blade.points[id]);
  for (auto it = leaf.leftMargin.rbegin() + 1; it != leaf.leftMargin.rend(); ++it)
    polygon.push_back(leaf.blade.points[*it]);
  return polygon; // ends at the base, which is its first point: closed
}

double Area(const std::vector<Eigen::Vector2d>& closed)
{
  double twice = 0.0;
  for (std::size_t i = 0; i + 1 < closed.size(); ++i)
    twice += closed[i].x() * closed[i + 1].y() - closed[i].y() * closed[i + 1].x();
  return 0.5 * twice;
}

/// The area the model's outline encloses, from a boundary sampled 20,000 times per rectangle edge.
double TrueArea(DeformedRectanglePreset preset)
{
  const DeformedRectangleModel model(MakeDeformedRectanglePreset(preset, 5.0));
  std::vector<Eigen::Vector2d> polygon;
  const int n = 20000;
  const Eigen::Vector2d corners[5] = { { 0.5, 0.0 }, { 0.5, 1.0 }, { -0.5, 1.0 }, { -0.5, 0.0 }, { 0.5, 0.0 } };
  for (int edge = 0; edge < 4; ++edge)
  {
    for (int i = 0; i < n; ++i)
    {
      const Eigen::Vector2d uv = corners[edge] + (corners[edge + 1] - corners[edge]) * (double(i) / n);
      polygon.push_back(model.Evaluate(uv.x(), uv.y()));
    }
  }
  polygon.push_back(polygon.front());
  return Area(polygon);
}

class EveryPreset : public ::testing::TestWithParam<std::tuple<int, bool>>
{
protected:
  DeformedRectanglePreset Preset() const { return static_cast<DeformedRectanglePreset>(std::get<0>(GetParam())); }
  bool Quality() const { return std::get<1>(GetParam()); }
};

TEST_P(EveryPreset, BladeIsAnOrientedManifoldDisk)
{
  const LeafGeometry leaf = Build(Preset(), Quality());
  const BladeMesh& mesh = leaf.blade;
  ASSERT_FALSE(mesh.triangles.empty());
  for (const auto& t : mesh.triangles)
    ASSERT_GT(SignedArea(mesh.points, t), 0.0) << "triangle not counter-clockwise (normal not +Z)";
  const auto use = EdgeUse(mesh.triangles);
  for (const auto& [edge, count] : use)
    ASSERT_LE(count, 2) << "edge " << edge.first << "-" << edge.second << " in " << count << " triangles";
  const auto loops = BoundaryLoops(mesh.triangles);
  ASSERT_EQ(loops.size(), 1u) << "the boundary must be one closed loop";
  // Every point is used, and Euler's formula for a disk holds: F = n_boundary + 2 n_interior - 2.
  std::set<int> used;
  for (const auto& t : mesh.triangles)
    used.insert(t.begin(), t.end());
  ASSERT_EQ(used.size(), mesh.points.size());
  const std::size_t boundary = loops[0].size(), interior = mesh.points.size() - boundary;
  EXPECT_EQ(mesh.triangles.size(), boundary + 2 * interior - 2);
  EXPECT_EQ(
    static_cast<long>(mesh.points.size()) - static_cast<long>(use.size()) + static_cast<long>(mesh.triangles.size()),
    1L);
}

TEST_P(EveryPreset, BladeTilesTheOutlineExactly)
{
  const LeafGeometry leaf = Build(Preset(), Quality());
  const std::vector<Eigen::Vector2d> outline = OutlinePolygon(leaf);
  double area = 0.0;
  const double tolerance = 1e-9 * 5.0;
  for (const auto& t : leaf.blade.triangles)
  {
    area += SignedArea(leaf.blade.points, t);
    const Eigen::Vector2d centroid =
      (leaf.blade.points[t[0]] + leaf.blade.points[t[1]] + leaf.blade.points[t[2]]) / 3.0;
    ASSERT_TRUE(InsideOrOn(centroid, outline, tolerance)) << "triangle outside the outline";
    for (int id : t)
      ASSERT_TRUE(InsideOrOn(leaf.blade.points[id], outline, tolerance)) << "vertex outside the outline";
  }
  // All inside, all positively oriented, and the same total area: no overlaps, no gaps.
  EXPECT_NEAR(area, Area(outline), 1e-10 * Area(outline));
}

TEST_P(EveryPreset, AreaConvergesToTheModelOutline)
{
  const double exact = TrueArea(Preset());
  const auto error = [&](int resolution) {
    double area = 0.0;
    const LeafGeometry leaf = Build(Preset(), Quality(), resolution);
    for (const auto& t : leaf.blade.triangles)
      area += SignedArea(leaf.blade.points, t);
    return std::abs(area - exact) / exact;
  };
  const double coarse = error(40), fine = error(80);
  EXPECT_LT(coarse, 5e-3) << "sampling error at Resolution 40";
  // Chord sampling loses area quadratically in the spacing: halving it should cut the error by about 4.
  EXPECT_LT(fine, 0.35 * coarse + 1e-7);
}

TEST_P(EveryPreset, LeafUVRegionAndTCoordsFollowTheDataContract)
{
  const LeafGeometry leaf = Build(Preset(), Quality());
  const BladeMesh& mesh = leaf.blade;
  const DeformedRectangleModel model(MakeDeformedRectanglePreset(Preset(), 5.0));
  EXPECT_EQ(leaf.uvInversionFailures, 0u);
  ASSERT_EQ(mesh.uv.size(), mesh.points.size());
  ASSERT_EQ(mesh.region.size(), mesh.points.size());
  ASSERT_EQ(leaf.tcoords.size(), mesh.points.size());

  // Outline points (the first ones) sit exactly where the model puts their LeafUV; Steiner points on the margin or
  // the midvein lie on the chord between two samples; interior points map back to themselves.
  std::vector<Eigen::Vector2d> midvein;
  for (int id : leaf.midvein)
    midvein.push_back(mesh.points[id]);
  const std::vector<Eigen::Vector2d> outline = OutlinePolygon(leaf);
  const std::size_t samples = *std::max_element(leaf.midvein.begin(), leaf.midvein.end()) + 1;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const Eigen::Vector2d& uv = mesh.uv[i];
    ASSERT_TRUE(uv.x() >= -0.5 && uv.x() <= 0.5 && uv.y() >= 0.0 && uv.y() <= 1.0) << uv.transpose();
    const double offset = (model.Evaluate(uv.x(), uv.y()) - mesh.points[i]).norm();
    if (mesh.region[i] == RegionBlade || i < samples)
      EXPECT_LT(offset, 1e-8) << "point " << i << " region " << mesh.region[i];
    else
      EXPECT_LT(offset, 0.05) << "Steiner point " << i << " far from its LeafUV";
    if (mesh.region[i] == RegionMidvein)
    {
      EXPECT_EQ(uv.x(), 0.0);
      EXPECT_LT(DistanceToPolyline(mesh.points[i], midvein), 1e-9);
    }
    if (mesh.region[i] == RegionMargin)
    {
      EXPECT_TRUE(std::abs(uv.x()) == 0.5 || uv.y() == 0.0 || uv.y() == 1.0) << uv.transpose();
      EXPECT_LT(DistanceToPolyline(mesh.points[i], outline), 1e-9);
    }
    for (int k = 0; k < 2; ++k)
      ASSERT_TRUE(leaf.tcoords[i][k] >= 0.0 && leaf.tcoords[i][k] <= 1.0);
  }
}

TEST_P(EveryPreset, MarginAndMidveinAreExactlyTheBoundaryAndFeatureVertices)
{
  const LeafGeometry leaf = Build(Preset(), Quality());
  const BladeMesh& mesh = leaf.blade;
  const auto loops = BoundaryLoops(mesh.triangles);
  ASSERT_EQ(loops.size(), 1u);
  const std::set<int> boundary(loops[0].begin(), loops[0].end());
  const int base = leaf.midvein.front(), apex = leaf.midvein.back();
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const int id = static_cast<int>(i);
    const bool onBoundary = boundary.count(id) > 0;
    if (id == base || id == apex)
    {
      EXPECT_TRUE(onBoundary);
      EXPECT_EQ(mesh.region[i], RegionMidvein);
    }
    else
    {
      EXPECT_EQ(onBoundary, mesh.region[i] == RegionMargin) << "point " << i;
    }
  }
  // The midvein is a chain of mesh edges from base to apex (through any Steiner points on it).
  const auto use = EdgeUse(mesh.triangles);
  std::size_t midveinEdges = 0;
  for (const auto& [edge, count] : use)
  {
    if (mesh.region[edge.first] == RegionMidvein && mesh.region[edge.second] == RegionMidvein &&
      std::abs(mesh.uv[edge.first].y() - mesh.uv[edge.second].y()) > 0)
    {
      const Eigen::Vector2d mid = 0.5 * (mesh.points[edge.first] + mesh.points[edge.second]);
      std::vector<Eigen::Vector2d> line;
      for (int m : leaf.midvein)
        line.push_back(mesh.points[m]);
      if (DistanceToPolyline(mid, line) < 1e-9)
      {
        ++midveinEdges;
        EXPECT_EQ(count, 2) << "the midvein must be interior";
      }
    }
  }
  std::size_t midveinPoints = 0;
  for (int r : mesh.region)
    midveinPoints += r == RegionMidvein;
  EXPECT_EQ(midveinEdges, midveinPoints - 1);
}

TEST_P(EveryPreset, SameParametersGiveBitIdenticalOutput)
{
  const LeafGeometry a = Build(Preset(), Quality());
  const LeafGeometry b = Build(Preset(), Quality());
  ASSERT_EQ(a.blade.points.size(), b.blade.points.size());
  EXPECT_TRUE(a.blade.points == b.blade.points);
  EXPECT_TRUE(a.blade.uv == b.blade.uv);
  EXPECT_TRUE(a.blade.triangles == b.blade.triangles);
}

INSTANTIATE_TEST_SUITE_P(DeformedRectangleLeaf, EveryPreset,
  ::testing::Combine(::testing::Range(1, DeformedRectanglePresetCount), ::testing::Bool()),
  [](const ::testing::TestParamInfo<std::tuple<int, bool>>& info) {
    return PresetName(static_cast<DeformedRectanglePreset>(std::get<0>(info.param))) +
      (std::get<1>(info.param) ? "Quality" : "Paper");
  });

TEST(DeformedRectangleLeaf, QualityModeRespectsAngleAndEdgeBounds)
{
  // Refined triangles have angles >= ~20.7 degrees (CGAL's B = 0.125) except in the outline's own sharp corners.
  // Edges stay within the midvein spacing except near the outline and midvein, which are never split (a
  // circumcentre that would encroach on them is not inserted): there they stay within 1.5 times the spacing.
  const LeafGeometry leaf = Build(DeformedRectanglePreset::Lobed, true, 50);
  const BladeMesh& mesh = leaf.blade;
  const double spacing = (mesh.points[leaf.midvein[1]] - mesh.points[leaf.midvein[0]]).norm();
  std::size_t small = 0, long_ = 0;
  for (const auto& t : mesh.triangles)
  {
    bool longEdge = false;
    for (int k = 0; k < 3; ++k)
    {
      const double length = (mesh.points[t[(k + 1) % 3]] - mesh.points[t[k]]).norm();
      EXPECT_LE(length, 1.5 * spacing);
      longEdge |= length > spacing * (1 + 1e-6);
    }
    long_ += longEdge;
    // CGAL bounds shortest edge / circumradius: B = 0.125 means sin(min angle) >= sqrt(0.125)/... ~ 20.7 degrees.
    double minAngle = 180.0;
    for (int k = 0; k < 3; ++k)
    {
      const Eigen::Vector2d a = mesh.points[t[(k + 1) % 3]] - mesh.points[t[k]];
      const Eigen::Vector2d b = mesh.points[t[(k + 2) % 3]] - mesh.points[t[k]];
      minAngle = std::min(minAngle, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI);
    }
    small += minAngle < 20.0;
  }
  // Only triangles in the margin's own sharp sinuses may stay below the bound.
  EXPECT_LT(small, mesh.triangles.size() / 50) << small << " of " << mesh.triangles.size();
  EXPECT_LT(long_, mesh.triangles.size() / 10) << long_ << " of " << mesh.triangles.size();
  std::cout << "[ Lobed, Resolution 50 ] " << mesh.triangles.size() << " triangles, " << small
            << " with an angle < 20 degrees, " << long_ << " with an edge longer than the spacing\n";
}

TEST(DeformedRectangleLeaf, PaperModeUsesOnlyTheSamples)
{
  const LeafGeometry leaf = Build(DeformedRectanglePreset::Ginkgo, false, 30);
  const std::size_t samples = leaf.leftMargin.size() + leaf.rightMargin.size() + leaf.midvein.size() - 4;
  EXPECT_EQ(leaf.blade.points.size(), samples);
  EXPECT_EQ(leaf.midvein.size(), 31u); // Resolution segments along the midvein
}

TEST(DeformedRectangleLeaf, GinkgoFanCollapsesItsBaseIntoThePetiolePoint)
{
  const LeafGeometry leaf = Build(DeformedRectanglePreset::Ginkgo, true, 40);
  // The whole v = 0 edge maps to the origin: both margins leave from the base vertex itself, with no duplicate.
  std::size_t atOrigin = 0;
  for (const Eigen::Vector2d& p : leaf.blade.points)
    atOrigin += p.norm() < 1e-12;
  EXPECT_EQ(atOrigin, 1u);
  EXPECT_EQ(leaf.leftMargin.front(), leaf.midvein.front());
  EXPECT_EQ(leaf.rightMargin.front(), leaf.midvein.front());
  // Fan: as wide as 2.2 * b_y at the top.
  double width = 0;
  for (const Eigen::Vector2d& p : leaf.blade.points)
    width = std::max(width, 2 * std::abs(p.x()));
  EXPECT_NEAR(width, 2.2 * 5.0, 1e-9);
}

TEST(DeformedRectangleLeaf, BadInputGivesAMessageAndNoLeaf)
{
  auto message = [](DeformedRectangleParameters p, int resolution) {
    LeafMeshParameters settings;
    settings.resolution = resolution;
    LeafGeometry leaf;
    const std::string error = BuildDeformedRectangleLeaf(p, settings, leaf);
    EXPECT_TRUE(leaf.blade.points.empty() && leaf.blade.triangles.empty() && leaf.midvein.empty());
    return error;
  };
  const DeformedRectangleParameters ginkgo = MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0);
  EXPECT_EQ(message(ginkgo, 1), "Resolution = 1 is outside the accepted range [2, 4000]");
  EXPECT_EQ(message(ginkgo, 4001), "Resolution = 4001 is outside the accepted range [2, 4000]");

  DeformedRectangleParameters nan = ginkgo;
  nan.length = std::nan("");
  EXPECT_NE(message(nan, 20).find("Length"), std::string::npos);

  // A term that swings the right margin across the midvein folds the leaf.
  DeformedRectangleParameters folded;
  folded.width = 1.0;
  folded.length = 5.0;
  ASSERT_EQ(ParseTerms({ 0, 0, -3.0, 1, 1, 1, 0 }, folded.terms), "");
  EXPECT_NE(message(folded, 20).find("fold"), std::string::npos) << message(folded, 20);

  // A margin that crosses itself.
  DeformedRectangleParameters crossing;
  crossing.width = 1.0;
  crossing.length = 5.0;
  ASSERT_EQ(ParseTerms({ 1, 1, 0.8, 1, 6, 1, 0 }, crossing.terms), "");
  EXPECT_NE(message(crossing, 20).find("Terms/Width/Length"), std::string::npos) << message(crossing, 20);

  // The apex on the base: no midvein.
  DeformedRectangleParameters noMidvein;
  noMidvein.width = 1.0;
  noMidvein.length = 5.0;
  ASSERT_EQ(ParseTerms({ 1, 1, -1.0, 2, 0, 0, M_PI / 2 }, noMidvein.terms), "");
  EXPECT_NE(message(noMidvein, 20).find("midvein"), std::string::npos) << message(noMidvein, 20);
}

TEST(DeformedRectangleLeaf, RefinementBeyondTheVertexBudgetStopsWithAMessage)
{
  LeafMeshParameters settings;
  settings.resolution = 400;
  settings.maxVertices = 5000;
  LeafGeometry leaf;
  const std::string error =
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf);
  EXPECT_NE(error.find("MeshQuality: refinement needs more than 5000 vertices"), std::string::npos) << error;
  EXPECT_TRUE(leaf.blade.triangles.empty());
}

TEST(DeformedRectangleLeaf, ProgressIsReportedAndAbortStops)
{
  LeafMeshParameters settings;
  settings.resolution = 200;
  std::vector<double> reported;
  settings.progress = [&](double f) {
    reported.push_back(f);
    return reported.size() < 3;
  };
  LeafGeometry leaf;
  const std::string error =
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf);
  EXPECT_EQ(error, "aborted");
  EXPECT_EQ(reported.size(), 3u);
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_TRUE(leaf.blade.triangles.empty());
}

} // namespace
} // namespace plantmorph
