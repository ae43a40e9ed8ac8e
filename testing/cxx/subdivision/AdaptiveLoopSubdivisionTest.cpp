// SPDX-License-Identifier: GPL-3.0-or-later
// AdaptiveLoopSubdivide (filters/subdivision/core) on flat arrays: the oracle (with adaptivity off it is plain Loop subdivision,
// checked against a brute-force reference written here with std::map edges), conformity after random adaptive
// levels, flat regions left alone, the Fixed rule keeping margin and midvein bit-identical, point data following the
// position stencils, the Region rule, and the refusals (non-manifold, bad settings, budget, abort).
#include "AdaptiveLoopSubdivision.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "MeshInvariants.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <thread>

namespace plantmorph
{
namespace
{

using Tri = std::array<int, 3>;

// ---------------------------------------------------------------------------------------------------------------
// Meshes

AdaptiveLoopMesh Icosahedron(bool perturb)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  AdaptiveLoopMesh mesh;
  mesh.points = { -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t,
    0, -1, -t, 0, 1 };
  mesh.triangles = { 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
    3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1 };
  if (perturb)
  {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (double& x : mesh.points)
      x += jitter(random);
  }
  return mesh;
}

/// The ginkgo blade of LeafOutlineSource (quality mode), lifted by a bump so it is curved; region = the blade's.
AdaptiveLoopMesh Blade(int resolution = 16, double bump = 0.6)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  LeafGeometry leaf;
  const std::string error =
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf);
  EXPECT_EQ(error, "");
  AdaptiveLoopMesh mesh;
  for (const auto& p : leaf.blade.points)
  {
    mesh.points.push_back(p.x());
    mesh.points.push_back(p.y());
    mesh.points.push_back(bump * std::sin(0.8 * p.x()) * std::cos(0.5 * p.y()) + 0.05 * p.x() * p.x());
  }
  for (const auto& t : leaf.blade.triangles)
    mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
  mesh.region = leaf.blade.region;
  mesh.attributeComponents = 2;
  for (const auto& uv : leaf.blade.uv)
  {
    mesh.attributes.push_back(uv.x());
    mesh.attributes.push_back(uv.y());
  }
  return mesh;
}

/// A flat n x n grid in z = 0 over [0, 1]^2, triangles counter-clockwise.
AdaptiveLoopMesh Grid(int n)
{
  AdaptiveLoopMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
    {
      mesh.points.push_back(static_cast<double>(i) / n);
      mesh.points.push_back(static_cast<double>(j) / n);
      mesh.points.push_back(0.0);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.triangles.insert(mesh.triangles.end(), { a, b, d, a, d, c });
    }
  return mesh;
}

/// A parallel-for over three threads, to check that results do not depend on how the work is cut.
void ThreeThreadFor(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body)
{
  std::vector<std::thread> threads;
  const std::size_t parts = 3;
  for (std::size_t p = 0; p < parts; ++p)
    threads.emplace_back([&, p] { body(n * p / parts, n * (p + 1) / parts); });
  for (auto& t : threads)
    t.join();
}

AdaptiveLoopParameters PlainLoop(int levels)
{
  AdaptiveLoopParameters s;
  s.edgeAngleThreshold = 180.0;
  s.flatnessThreshold = 1.0;
  s.featureRule = FeatureRule::Loop;
  s.midveinIsFeature = false;
  s.maximumLevel = levels;
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// The brute-force reference: one level of plain Loop with crease rules on the boundary, written independently.
// Odd points are numbered after the even ones in the order of std::map<(min, max)>.

AdaptiveLoopMesh ReferenceLoopLevel(const AdaptiveLoopMesh& in)
{
  const int nV = static_cast<int>(in.NumberOfPoints());
  std::map<std::pair<int, int>, std::vector<int>> opposite;
  std::vector<std::set<int>> neighbours(nV);
  for (std::size_t t = 0; t < in.NumberOfTriangles(); ++t)
    for (int c = 0; c < 3; ++c)
    {
      const int a = in.triangles[3 * t + c], b = in.triangles[3 * t + (c + 1) % 3],
                o = in.triangles[3 * t + (c + 2) % 3];
      opposite[{ std::min(a, b), std::max(a, b) }].push_back(o);
      neighbours[a].insert(b);
      neighbours[b].insert(a);
    }
  std::vector<std::vector<int>> boundaryNeighbours(nV);
  for (const auto& [edge, opp] : opposite)
    if (opp.size() == 1)
    {
      boundaryNeighbours[edge.first].push_back(edge.second);
      boundaryNeighbours[edge.second].push_back(edge.first);
    }
  AdaptiveLoopMesh out;
  const auto P = [&in](int i, int j) { return in.points[3 * i + j]; };
  for (int v = 0; v < nV; ++v)
    for (int j = 0; j < 3; ++j)
    {
      double x;
      const auto& bn = boundaryNeighbours[v];
      if (neighbours[v].empty())
        x = P(v, j);
      else if (bn.size() == 2)
        x = 0.75 * P(v, j) + 0.125 * (P(bn[0], j) + P(bn[1], j));
      else if (!bn.empty())
        x = P(v, j);
      else
      {
        const int n = static_cast<int>(neighbours[v].size());
        const double beta =
          n == 3 ? 3.0 / 16.0 : (5.0 / 8.0 - std::pow(3.0 / 8.0 + std::cos(2.0 * M_PI / n) / 4.0, 2)) / n;
        double sum = 0.0;
        for (int w : neighbours[v])
          sum += P(w, j);
        x = (1.0 - n * beta) * P(v, j) + beta * sum;
      }
      out.points.push_back(x);
    }
  std::map<std::pair<int, int>, int> oddId;
  for (const auto& [edge, opp] : opposite)
  {
    oddId[edge] = static_cast<int>(out.points.size() / 3);
    for (int j = 0; j < 3; ++j)
      out.points.push_back(opp.size() == 1
          ? 0.5 * (P(edge.first, j) + P(edge.second, j))
          : 0.375 * (P(edge.first, j) + P(edge.second, j)) + 0.125 * (P(opp[0], j) + P(opp[1], j)));
  }
  for (std::size_t t = 0; t < in.NumberOfTriangles(); ++t)
  {
    const int* v = in.triangles.data() + 3 * t;
    int m[3];
    for (int c = 0; c < 3; ++c)
      m[c] = oddId.at({ std::min(v[c], v[(c + 1) % 3]), std::max(v[c], v[(c + 1) % 3]) });
    out.triangles.insert(
      out.triangles.end(), { v[0], m[0], m[2], m[0], v[1], m[1], m[2], m[1], v[2], m[0], m[1], m[2] });
  }
  return out;
}

/// Triangles with their smallest id first (orientation kept), sorted.
std::vector<Tri> CanonicalTriangles(const LoopArray<int>& triangles)
{
  std::vector<Tri> out;
  for (std::size_t i = 0; i < triangles.size(); i += 3)
  {
    Tri t{ triangles[i], triangles[i + 1], triangles[i + 2] };
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

testing::Triangles AsTriangles(const LoopArray<int>& triangles)
{
  testing::Triangles out;
  for (std::size_t i = 0; i < triangles.size(); i += 3)
    out.push_back({ triangles[i], triangles[i + 1], triangles[i + 2] });
  return out;
}

double MaxDifference(const LoopArray<double>& a, const LoopArray<double>& b)
{
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

void ExpectOracle(const AdaptiveLoopMesh& input, int levels)
{
  AdaptiveLoopMesh reference = input;
  reference.attributes.clear();
  reference.attributeComponents = 0;
  for (int level = 1; level <= levels; ++level)
  {
    reference = ReferenceLoopLevel(reference);
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, PlainLoop(level));
    ASSERT_EQ(result.error, "");
    ASSERT_EQ(result.levels, level);
    ASSERT_EQ(result.mesh.NumberOfPoints(), reference.NumberOfPoints()) << "level " << level;
    EXPECT_LT(MaxDifference(result.mesh.points, reference.points), 1e-12) << "level " << level;
    EXPECT_EQ(CanonicalTriangles(result.mesh.triangles), CanonicalTriangles(reference.triangles)) << "level " << level;
    ASSERT_EQ(result.trianglesPerLevel.size(), static_cast<std::size_t>(level + 1));
    for (int l = 0; l <= level; ++l)
      EXPECT_EQ(result.trianglesPerLevel[l], input.NumberOfTriangles() << (2 * l));
  }
}

/// Fixed or Refine features: every input point of the margin or midvein (Region 1 or 4) is in the output bit for bit,
/// and the output has one boundary loop with `boundaryFactor` times the input loop's points. `featurePoints`
/// receives how many points were checked.
void ExpectFeaturePointsKept(
  const AdaptiveLoopMesh& input, const AdaptiveLoopMesh& output, std::size_t boundaryFactor, std::size_t& featurePoints)
{
  featurePoints = 0;
  for (std::size_t v = 0; v < input.NumberOfPoints(); ++v)
    if (input.region[v] == 1 || input.region[v] == 4)
    {
      ++featurePoints;
      for (int j = 0; j < 3; ++j)
        ASSERT_EQ(output.points[3 * v + j], input.points[3 * v + j]) << "point " << v;
    }
  const auto loopsIn = testing::BoundaryLoops(AsTriangles(input.triangles));
  const auto loopsOut = testing::BoundaryLoops(AsTriangles(output.triangles));
  ASSERT_EQ(loopsOut.size(), 1u);
  EXPECT_EQ(loopsOut[0].size(), boundaryFactor * loopsIn[0].size());
}

/// Interior edges in two triangles, boundary edges in one, Euler characteristic and boundary loops kept.
void ExpectConforming(const AdaptiveLoopMesh& input, const AdaptiveLoopMesh& output, const std::string& what)
{
  const auto inUse = testing::EdgeUse(AsTriangles(input.triangles));
  const auto outUse = testing::EdgeUse(AsTriangles(output.triangles));
  for (const auto& [edge, count] : outUse)
    ASSERT_TRUE(count == 1 || count == 2)
      << what << ": edge " << edge.first << "-" << edge.second << " in " << count << " triangles";
  const auto euler = [](std::size_t v, std::size_t e, std::size_t f) {
    return static_cast<long>(v) - static_cast<long>(e) + static_cast<long>(f);
  };
  EXPECT_EQ(euler(input.NumberOfPoints(), inUse.size(), input.NumberOfTriangles()),
    euler(output.NumberOfPoints(), outUse.size(), output.NumberOfTriangles()))
    << what;
  EXPECT_EQ(testing::BoundaryLoops(AsTriangles(input.triangles)).size(),
    testing::BoundaryLoops(AsTriangles(output.triangles)).size())
    << what;
  // Every point is used (an odd point used by one side only would be a T-junction).
  std::vector<int> used(output.NumberOfPoints(), 0);
  for (int v : output.triangles)
    used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << what;
  // Orientation kept: a directed edge appears at most once.
  std::set<std::pair<int, int>> directed;
  for (std::size_t i = 0; i < output.triangles.size(); i += 3)
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(directed.insert({ output.triangles[i + c], output.triangles[i + (c + 1) % 3] }).second) << what;
}

// ---------------------------------------------------------------------------------------------------------------

TEST(AdaptiveLoopSubdivision, OracleClosedMeshIsPlainLoop)
{
  ExpectOracle(Icosahedron(true), 4);
}

TEST(AdaptiveLoopSubdivision, OracleOpenMeshIsPlainLoopWithBoundaryRules)
{
  ExpectOracle(Blade(12), 3);
}

TEST(AdaptiveLoopSubdivision, ConformingAfterRandomAdaptiveLevels)
{
  std::mt19937_64 random(20261121);
  std::uniform_real_distribution<double> angle(90.0, 180.0), flatness(0.9, 1.0);
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10) };
  for (int trial = 0; trial < 24; ++trial)
  {
    const AdaptiveLoopMesh& input = meshes[trial % 2];
    AdaptiveLoopParameters s;
    s.edgeAngleThreshold = angle(random);
    s.flatnessThreshold = flatness(random);
    s.featureRule = static_cast<FeatureRule>(trial % 3);
    s.maximumLevel = 1 + trial % 4;
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
    ASSERT_EQ(result.error, "");
    const std::string what = "trial " + std::to_string(trial) + " angle " + std::to_string(s.edgeAngleThreshold);
    ExpectConforming(input, result.mesh, what);
    EXPECT_EQ(result.trianglesPerLevel.back(), result.mesh.NumberOfTriangles());
    EXPECT_EQ(result.mesh.origin.size(), result.mesh.NumberOfTriangles());
  }
}

TEST(AdaptiveLoopSubdivision, AdaptiveSplitsOnlySomeEdgesAndMakesTwoAndThreeWaySplits)
{
  AdaptiveLoopParameters s;
  s.edgeAngleThreshold = 177.0;
  s.flatnessThreshold = 0.995;
  s.maximumLevel = 1;
  const AdaptiveLoopMesh input = Blade(16);
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  const std::size_t n = input.NumberOfTriangles(), m = result.mesh.NumberOfTriangles();
  EXPECT_GT(m, n);
  EXPECT_LT(m, 4 * n);
  // Children per parent: some parents have 2 or 3 children (the 1-to-2 and 1-to-3 splits).
  std::vector<int> children(n, 0);
  for (int o : result.mesh.origin)
    ++children[o];
  EXPECT_GT(std::count(children.begin(), children.end(), 2), 0);
  EXPECT_GT(std::count(children.begin(), children.end(), 3), 0);
  EXPECT_GT(std::count(children.begin(), children.end(), 4), 0);
  ExpectConforming(input, result.mesh, "one adaptive level");
}

TEST(AdaptiveLoopSubdivision, FlatMeshIsLeftUntouched)
{
  AdaptiveLoopMesh input = Grid(8);
  AdaptiveLoopParameters s; // adaptive defaults, Fixed
  s.maximumLevel = 3;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  EXPECT_EQ(result.levels, 0);
  EXPECT_EQ(result.mesh.points, input.points);
  EXPECT_EQ(result.mesh.triangles, input.triangles);
  EXPECT_EQ(result.trianglesPerLevel, std::vector<std::size_t>{ input.NumberOfTriangles() });
}

TEST(AdaptiveLoopSubdivision, FlatPartOfABentMeshIsLeftUntouched)
{
  // A 16 x 16 grid folded along x = 0.75: only triangles next to the fold bend.
  AdaptiveLoopMesh input = Grid(16);
  for (std::size_t i = 0; i < input.NumberOfPoints(); ++i)
    if (input.points[3 * i] > 0.75)
      input.points[3 * i + 2] = 0.5 * (input.points[3 * i] - 0.75);
  AdaptiveLoopParameters s;
  s.edgeAngleThreshold = 179.0;
  s.flatnessThreshold = 0.9999;
  s.maximumLevel = 1;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  ASSERT_EQ(result.levels, 1);
  EXPECT_GT(result.mesh.NumberOfTriangles(), input.NumberOfTriangles());
  // Points at least two grid steps from the fold keep their place bit for bit; their triangles are not split.
  const auto farFromFold = [&input](int v) { return std::abs(input.points[3 * v] - 0.75) > 2.0 / 16.0 + 1e-12; };
  for (std::size_t v = 0; v < input.NumberOfPoints(); ++v)
    if (farFromFold(static_cast<int>(v)))
    {
      for (int j = 0; j < 3; ++j)
        ASSERT_EQ(result.mesh.points[3 * v + j], input.points[3 * v + j]) << "point " << v;
    }
  const auto outTriangles = CanonicalTriangles(result.mesh.triangles);
  for (const Tri& t : CanonicalTriangles(input.triangles))
    if (farFromFold(t[0]) && farFromFold(t[1]) && farFromFold(t[2]))
    {
      EXPECT_TRUE(std::binary_search(outTriangles.begin(), outTriangles.end(), t));
    }
  ExpectConforming(input, result.mesh, "fold");
}

TEST(AdaptiveLoopSubdivision, FixedRuleKeepsMarginAndMidveinBitIdentical)
{
  const AdaptiveLoopMesh input = Blade(16);
  AdaptiveLoopParameters s;
  s.edgeAngleThreshold = 180.0;
  s.flatnessThreshold = 1.0;
  s.featureRule = FeatureRule::Fixed;
  s.maximumLevel = 3;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  ASSERT_EQ(result.levels, 3);
  // No new point on the margin or the midvein: the boundary is the input's polygon, the midvein its polyline.
  std::size_t featurePoints = 0;
  ExpectFeaturePointsKept(input, result.mesh, 1, featurePoints);
  ASSERT_GT(featurePoints, 20u);
  const std::size_t midveinIn = std::count(input.region.begin(), input.region.end(), 1);
  const std::size_t midveinOut = std::count(result.mesh.region.begin(), result.mesh.region.end(), 1);
  EXPECT_EQ(midveinOut, midveinIn);
  EXPECT_GT(result.mesh.NumberOfTriangles(), 20 * input.NumberOfTriangles());
}

TEST(AdaptiveLoopSubdivision, RefineRuleSamplesFeatureCurvesWithoutMovingThem)
{
  const AdaptiveLoopMesh input = Blade(12);
  AdaptiveLoopParameters s = PlainLoop(2);
  s.featureRule = FeatureRule::Refine;
  s.midveinIsFeature = true;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  // Input margin and midvein points stay; the boundary has 4 times the points; every new margin point lies on the
  // input boundary polygon (x, y and z).
  std::size_t featurePoints = 0;
  ExpectFeaturePointsKept(input, result.mesh, 4, featurePoints);
  const std::size_t midveinIn = std::count(input.region.begin(), input.region.end(), 1);
  const std::size_t midveinOut = std::count(result.mesh.region.begin(), result.mesh.region.end(), 1);
  EXPECT_EQ(midveinOut, 4 * (midveinIn - 1) + 1);
}

TEST(AdaptiveLoopSubdivision, AttributesFollowThePositionStencils)
{
  AdaptiveLoopMesh input = Blade(12);
  // Attribute = the position itself, plus the old LeafUV: after any adaptive run it must equal the output positions.
  input.attributeComponents = 5;
  LoopArray<double> attributes;
  for (std::size_t v = 0; v < input.NumberOfPoints(); ++v)
  {
    attributes.insert(attributes.end(), input.points.begin() + 3 * v, input.points.begin() + 3 * v + 3);
    attributes.insert(attributes.end(), input.attributes.begin() + 2 * v, input.attributes.begin() + 2 * v + 2);
  }
  input.attributes = attributes;
  for (const FeatureRule rule : { FeatureRule::Fixed, FeatureRule::Loop, FeatureRule::Refine })
  {
    AdaptiveLoopParameters s;
    s.featureRule = rule;
    s.edgeAngleThreshold = 175.0;
    s.flatnessThreshold = 0.999;
    s.maximumLevel = 3;
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
    ASSERT_EQ(result.error, "");
    ASSERT_EQ(result.mesh.attributes.size(), 5 * result.mesh.NumberOfPoints());
    for (std::size_t v = 0; v < result.mesh.NumberOfPoints(); ++v)
    {
      for (int j = 0; j < 3; ++j)
        ASSERT_EQ(result.mesh.attributes[5 * v + j], result.mesh.points[3 * v + j]);
      // LeafUV stays in the canonical leaf's range (convex weights on a disk, up to Loop's small overshoot).
      EXPECT_GE(result.mesh.attributes[5 * v + 3], -0.5 - 1e-9);
      EXPECT_LE(result.mesh.attributes[5 * v + 3], 0.5 + 1e-9);
    }
  }
}

TEST(AdaptiveLoopSubdivision, RegionRule)
{
  const AdaptiveLoopMesh input = Blade(12);
  AdaptiveLoopParameters s = PlainLoop(2);
  s.featureRule = FeatureRule::Refine;
  s.midveinIsFeature = true;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  const auto& out = result.mesh;
  ASSERT_EQ(out.region.size(), out.NumberOfPoints());
  // Boundary points are margin (4) or midvein ends (1); interior points are blade (0) or midvein (1), and a
  // midvein point sits between two midvein neighbours on the midvein's line (Refine keeps it straight).
  std::set<int> boundary;
  for (const auto& loop : testing::BoundaryLoops(AsTriangles(out.triangles)))
    boundary.insert(loop.begin(), loop.end());
  for (std::size_t v = 0; v < out.NumberOfPoints(); ++v)
  {
    const int r = out.region[v];
    if (boundary.count(static_cast<int>(v)))
    {
      EXPECT_TRUE(r == 4 || r == 1) << v;
    }
    else
    {
      EXPECT_TRUE(r == 0 || r == 1) << v << " region " << r;
    }
    if (v < input.NumberOfPoints())
    {
      EXPECT_EQ(r, input.region[v]); // even points keep theirs
    }
  }
  EXPECT_GT(
    std::count(out.region.begin(), out.region.end(), 1), std::count(input.region.begin(), input.region.end(), 1));
}

TEST(AdaptiveLoopSubdivision, NonManifoldEdgeIsRefusedWithItsIds)
{
  AdaptiveLoopMesh mesh;
  mesh.points = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1 };
  mesh.triangles = { 0, 1, 2, 1, 0, 3, 0, 1, 4 };
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(mesh, PlainLoop(2));
  EXPECT_NE(result.error.find("non-manifold"), std::string::npos) << result.error;
  EXPECT_NE(result.error.find("edge (0, 1) in 3 triangles"), std::string::npos) << result.error;
  EXPECT_TRUE(result.mesh.points.empty());
  EXPECT_TRUE(result.mesh.triangles.empty());
}

TEST(AdaptiveLoopSubdivision, NonManifoldVertexIsRefusedWithItsId)
{
  // Two triangles touching only at point 2 (a bow tie), and two closed pyramids sharing their apex (point 0).
  AdaptiveLoopMesh bowtie;
  bowtie.points = { 0, 0, 0, 1, 0, 0, 0.5, 0.5, 0, 1, 1, 0, 0, 1, 0 };
  bowtie.triangles = { 0, 1, 2, 2, 3, 4 };
  AdaptiveLoopResult result = AdaptiveLoopSubdivide(bowtie, PlainLoop(1));
  EXPECT_NE(result.error.find("point 2 joins"), std::string::npos) << result.error;
  EXPECT_TRUE(result.mesh.points.empty());

  AdaptiveLoopMesh pinched;
  pinched.points = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1, -1, 0, 0, 0, -1, 0, -1, -1, -1 };
  pinched.triangles = { 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2, 0, 4, 5, 0, 5, 6, 0, 6, 4, 4, 6, 5 };
  result = AdaptiveLoopSubdivide(pinched, PlainLoop(1));
  EXPECT_NE(result.error.find("point 0 joins"), std::string::npos) << result.error;
  EXPECT_TRUE(result.mesh.triangles.empty());
}

TEST(AdaptiveLoopSubdivision, BadSettingsAndInputAreRefusedByName)
{
  const AdaptiveLoopMesh mesh = Icosahedron(false);
  AdaptiveLoopParameters s = PlainLoop(1);
  s.edgeAngleThreshold = std::nan("");
  EXPECT_NE(
    AdaptiveLoopSubdivide(mesh, s).error.find("EdgeAngleThreshold = nan is outside the accepted range [0, 180]"),
    std::string::npos);
  s = PlainLoop(1);
  s.flatnessThreshold = 1.5;
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("FlatnessThreshold"), std::string::npos);
  s = PlainLoop(MaxAdaptiveLoopLevel + 1);
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("MaximumLevel = 11 is outside the accepted range [0, 10]"),
    std::string::npos);

  AdaptiveLoopMesh nan = mesh;
  nan.points[7] = std::nan("");
  const AdaptiveLoopResult r = AdaptiveLoopSubdivide(nan, PlainLoop(1));
  EXPECT_NE(r.error.find("point 2 has a non-finite coordinate"), std::string::npos) << r.error;
  EXPECT_TRUE(r.mesh.points.empty());

  AdaptiveLoopMesh degenerate = mesh;
  degenerate.triangles[1] = degenerate.triangles[0];
  EXPECT_NE(AdaptiveLoopSubdivide(degenerate, PlainLoop(1)).error.find("degenerate"), std::string::npos);
}

TEST(AdaptiveLoopSubdivision, TriangleBudgetIsAnErrorNotAHalfMesh)
{
  AdaptiveLoopParameters s = PlainLoop(3);
  s.maximumTriangles = 20 * 16 * 4 - 1; // level 3 makes 20 * 64
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(Icosahedron(false), s);
  EXPECT_NE(result.error.find("MaximumTriangles"), std::string::npos) << result.error;
  EXPECT_TRUE(result.mesh.triangles.empty());
  EXPECT_TRUE(result.trianglesPerLevel.empty());
}

TEST(AdaptiveLoopSubdivision, AbortLeavesNothing)
{
  AdaptiveLoopParameters s = PlainLoop(3);
  int calls = 0;
  s.progress = [&calls](double fraction) {
    EXPECT_GE(fraction, 0.0);
    EXPECT_LE(fraction, 1.0);
    return ++calls < 4;
  };
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(Icosahedron(false), s);
  EXPECT_TRUE(result.aborted);
  EXPECT_EQ(result.error, "");
  EXPECT_TRUE(result.mesh.points.empty());
}

TEST(AdaptiveLoopSubdivision, ThreadedRunIsBitIdenticalToSerial)
{
  AdaptiveLoopParameters s;
  s.edgeAngleThreshold = 176.0;
  s.flatnessThreshold = 0.998;
  s.featureRule = FeatureRule::Loop;
  s.maximumLevel = 4;
  const AdaptiveLoopMesh input = Blade(20);
  const AdaptiveLoopResult serial = AdaptiveLoopSubdivide(input, s);
  s.parallelFor = ThreeThreadFor;
  const AdaptiveLoopResult threaded = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(serial.error, "");
  EXPECT_EQ(serial.mesh.points, threaded.mesh.points);
  EXPECT_EQ(serial.mesh.triangles, threaded.mesh.triangles);
  EXPECT_EQ(serial.mesh.attributes, threaded.mesh.attributes);
  EXPECT_EQ(serial.mesh.region, threaded.mesh.region);
  EXPECT_EQ(serial.mesh.origin, threaded.mesh.origin);
}

TEST(AdaptiveLoopSubdivision, UserMarkedFeatureEdgesStayUnderFixed)
{
  AdaptiveLoopMesh input = Icosahedron(true);
  input.featureEdges = { { 0, 11 }, { 11, 5 }, { 5, 0 } };
  AdaptiveLoopParameters s = PlainLoop(2);
  s.featureRule = FeatureRule::Fixed;
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
  ASSERT_EQ(result.error, "");
  for (int v : { 0, 11, 5 })
  {
    for (int j = 0; j < 3; ++j)
      EXPECT_EQ(result.mesh.points[3 * v + j], input.points[3 * v + j]);
  }
  // The marked edges are still edges of the output (never split).
  const auto use = testing::EdgeUse(AsTriangles(result.mesh.triangles));
  EXPECT_EQ(use.count({ 0, 11 }), 1u);
  EXPECT_EQ(use.count({ 5, 11 }), 1u);
  EXPECT_EQ(use.count({ 0, 5 }), 1u);
  ExpectConforming(input, result.mesh, "marked");
}

// ---------------------------------------------------------------------------------------------------------------
// RefinementRule::SurfaceError

AdaptiveLoopParameters ByError(double tolerance, int levels, FeatureRule rule)
{
  AdaptiveLoopParameters s;
  s.refinementRule = RefinementRule::SurfaceError;
  s.errorTolerance = tolerance;
  s.maximumLevel = levels;
  s.featureRule = rule;
  return s;
}

TEST(AdaptiveLoopSubdivision, SurfaceErrorSplitsAnEdgeExactlyWhenItsOddPointIsTheToleranceOffItsChord)
{
  // Two triangles on the edge (a, b) = (0,0,0)-(1,0,0), opposite points (0.5, +-1, z): the normals' sum is +z, and
  // Loop's odd point (3a + 3b + c + d) / 8 lies (c + d - a - b) . z / 8 = z / 4 above the chord midpoint. All four
  // points are on the boundary (Fixed: their limit offsets are 0), so the estimate is exactly z / 4.
  AdaptiveLoopMesh quad;
  const double z = 0.4;
  quad.points = { 0, 0, 0, 1, 0, 0, 0.5, 1, z, 0.5, -1, z };
  quad.triangles = { 0, 1, 2, 1, 0, 3 };
  const AdaptiveLoopResult below = AdaptiveLoopSubdivide(quad, ByError(0.0999, 1, FeatureRule::Fixed));
  const AdaptiveLoopResult above = AdaptiveLoopSubdivide(quad, ByError(0.1001, 1, FeatureRule::Fixed));
  ASSERT_EQ(below.error, "");
  ASSERT_EQ(above.error, "");
  ASSERT_EQ(below.mesh.NumberOfTriangles(), 4u);
  EXPECT_NEAR(below.mesh.points[3 * 4 + 2], 2.0 * z / 8.0, 1e-15); // the odd point, z / 4
  EXPECT_EQ(above.mesh.NumberOfTriangles(), 2u);
  EXPECT_EQ(above.levels, 0);
  // The estimate is along the normal: sliding c and d in the plane (a non-parallelogram quad) changes nothing.
  AdaptiveLoopMesh flat = quad;
  flat.points = { 0, 0, 0, 1, 0, 0, 0.9, 1, 0, 0.2, -1.3, 0 };
  EXPECT_EQ(AdaptiveLoopSubdivide(flat, ByError(1e-12, 1, FeatureRule::Fixed)).levels, 0);
}

TEST(AdaptiveLoopSubdivision, SurfaceErrorLeavesFlatPartsOfAnyTriangleShapeUntouched)
{
  // A flat grid with its interior points slid in the plane (irregular triangles): Loop moves them only in the
  // plane, so nothing is refined at any positive tolerance (Fixed and Refine; Loop's crease rule would round the
  // square's corners, a real change of the outline). Then the same grid folded: only the fold refines.
  AdaptiveLoopMesh input = Grid(12);
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> jitter(-0.3 / 12.0, 0.3 / 12.0);
  for (std::size_t i = 0; i < input.NumberOfPoints(); ++i)
  {
    const double x = input.points[3 * i], y = input.points[3 * i + 1];
    if (x > 0.0 && x < 1.0 && y > 0.0 && y < 1.0)
    {
      input.points[3 * i] += jitter(random);
      input.points[3 * i + 1] += jitter(random);
    }
  }
  for (int r = 0; r < 3; r += 2)
  {
    const AdaptiveLoopResult flat = AdaptiveLoopSubdivide(input, ByError(1e-12, 3, static_cast<FeatureRule>(r)));
    ASSERT_EQ(flat.error, "");
    EXPECT_EQ(flat.levels, 0) << "rule " << r;
    EXPECT_EQ(flat.mesh.points, input.points);
  }
  AdaptiveLoopMesh folded = input;
  for (std::size_t i = 0; i < folded.NumberOfPoints(); ++i)
    if (folded.points[3 * i] > 0.5)
      folded.points[3 * i + 2] = 0.5 * (folded.points[3 * i] - 0.5);
  const AdaptiveLoopResult result = AdaptiveLoopSubdivide(folded, ByError(1e-4, 2, FeatureRule::Fixed));
  ASSERT_EQ(result.error, "");
  ASSERT_EQ(result.levels, 2);
  EXPECT_GT(result.mesh.NumberOfTriangles(), folded.NumberOfTriangles());
  const AdaptiveLoopResult uniform = AdaptiveLoopSubdivide(folded, ByError(0.0, 2, FeatureRule::Fixed));
  EXPECT_LT(2 * result.mesh.NumberOfTriangles(), uniform.mesh.NumberOfTriangles());
  // Points more than two (jittered) grid steps from the fold keep their place; their triangles are not split.
  const auto far = [&folded](int v) { return std::abs(folded.points[3 * v] - 0.5) > 2.6 / 12.0; };
  std::size_t farPoints = 0;
  for (std::size_t v = 0; v < folded.NumberOfPoints(); ++v)
    if (far(static_cast<int>(v)))
    {
      ++farPoints;
      for (int j = 0; j < 3; ++j)
        ASSERT_EQ(result.mesh.points[3 * v + j], folded.points[3 * v + j]) << "point " << v;
    }
  EXPECT_GT(farPoints, 50u);
  const auto outTriangles = CanonicalTriangles(result.mesh.triangles);
  for (const Tri& t : CanonicalTriangles(folded.triangles))
    if (far(t[0]) && far(t[1]) && far(t[2]))
    {
      EXPECT_TRUE(std::binary_search(outTriangles.begin(), outTriangles.end(), t));
    }
  ExpectConforming(folded, result.mesh, "fold, surface error");
}

TEST(AdaptiveLoopSubdivision, SurfaceErrorConformingAndMonotoneOnRandomTolerances)
{
  std::mt19937_64 random(20261122);
  std::uniform_real_distribution<double> exponent(-6.0, 0.0);
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10) };
  for (int trial = 0; trial < 30; ++trial)
  {
    const AdaptiveLoopMesh& input = meshes[trial % 2];
    const double tolerance = std::pow(10.0, exponent(random));
    AdaptiveLoopParameters s = ByError(tolerance, 1 + trial % 4, static_cast<FeatureRule>(trial % 3));
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
    ASSERT_EQ(result.error, "");
    const std::string what = "trial " + std::to_string(trial) + " tolerance " + std::to_string(tolerance);
    ExpectConforming(input, result.mesh, what);
    EXPECT_EQ(result.trianglesPerLevel.back(), result.mesh.NumberOfTriangles());
    // One level: the split set only shrinks as the tolerance grows.
    s.maximumLevel = 1;
    const std::size_t n1 = AdaptiveLoopSubdivide(input, s).mesh.NumberOfTriangles();
    s.errorTolerance = 2.0 * tolerance;
    EXPECT_LE(AdaptiveLoopSubdivide(input, s).mesh.NumberOfTriangles(), n1) << what;
  }
}

TEST(AdaptiveLoopSubdivision, SurfaceErrorToleranceIsValidated)
{
  const AdaptiveLoopMesh mesh = Icosahedron(false);
  AdaptiveLoopParameters s = ByError(-1e-3, 1, FeatureRule::Fixed);
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("ErrorTolerance = -0.001 is outside the accepted range [0, inf]"),
    std::string::npos);
  s.errorTolerance = std::nan("");
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("ErrorTolerance"), std::string::npos);
  s.errorTolerance = 0.1;
  s.refinementRule = static_cast<RefinementRule>(3);
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("RefinementRule = 3 is outside the accepted range {0, 1, 2} "
                                                      "(0 Dihedral angle, 1 Surface error, 2 Chord error)"),
    std::string::npos);
  s.refinementRule = RefinementRule::ChordError;
  s.errorTolerance = -1.0;
  EXPECT_NE(AdaptiveLoopSubdivide(mesh, s).error.find("ErrorTolerance = -1 is outside the accepted range [0, inf]"),
    std::string::npos);
}

// ---------------------------------------------------------------------------------------------------------------
// RefinementRule::ChordError

AdaptiveLoopParameters ByChord(double tolerance, int levels, FeatureRule rule)
{
  AdaptiveLoopParameters s = ByError(tolerance, levels, rule);
  s.refinementRule = RefinementRule::ChordError;
  return s;
}

/// A tube of radius 1 around the x axis, x in [0, 1] in n steps, `around` points per ring, every quad cut along
/// the same diagonal: its rulings (edges along x) are straight lines of the cylinder.
AdaptiveLoopMesh Tube(int n, int around)
{
  AdaptiveLoopMesh mesh;
  for (int i = 0; i <= n; ++i)
    for (int k = 0; k < around; ++k)
    {
      const double angle = 2.0 * 3.14159265358979323846 * k / around;
      mesh.points.insert(mesh.points.end(), { static_cast<double>(i) / n, std::cos(angle), std::sin(angle) });
    }
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < around; ++k)
    {
      const int a = i * around + k, b = i * around + (k + 1) % around, c = a + around, d = b + around;
      mesh.triangles.insert(mesh.triangles.end(), { a, c, d, a, d, b });
    }
  return mesh;
}

/// The two error rules' shared guarantees are checked for both (Tube is defined above for the Chord error tests).
const RefinementRule kErrorRules[] = { RefinementRule::SurfaceError, RefinementRule::ChordError };

AdaptiveLoopParameters ByRule(RefinementRule rule, double tolerance, int levels, FeatureRule featureRule)
{
  return rule == RefinementRule::ChordError ? ByChord(tolerance, levels, featureRule)
                                            : ByError(tolerance, levels, featureRule);
}

TEST(AdaptiveLoopSubdivision, ErrorRulesZeroToleranceIsUniformLoopBitForBit)
{
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10), Tube(4, 8) };
  for (const RefinementRule rule : kErrorRules)
    for (const AdaptiveLoopMesh& input : meshes)
      for (int r = 0; r < 3; ++r)
      {
        AdaptiveLoopParameters uniform;
        uniform.edgeAngleThreshold = 180.0;
        uniform.flatnessThreshold = 1.0;
        uniform.featureRule = static_cast<FeatureRule>(r);
        uniform.maximumLevel = 3;
        // FlatnessThreshold and EdgeAngleThreshold are not used by the error rules: set them to adaptive values.
        AdaptiveLoopParameters byRule = ByRule(rule, 0.0, 3, uniform.featureRule);
        byRule.edgeAngleThreshold = 120.0;
        byRule.flatnessThreshold = 0.5;
        const AdaptiveLoopResult a = AdaptiveLoopSubdivide(input, uniform);
        const AdaptiveLoopResult b = AdaptiveLoopSubdivide(input, byRule);
        const std::string what =
          "refinement rule " + std::to_string(static_cast<int>(rule)) + ", feature rule " + std::to_string(r);
        ASSERT_EQ(a.error, "");
        ASSERT_EQ(b.error, "");
        ASSERT_EQ(b.levels, 3);
        EXPECT_EQ(a.mesh.points, b.mesh.points) << what;
        EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << what;
        EXPECT_EQ(a.mesh.attributes, b.mesh.attributes) << what;
        EXPECT_EQ(a.mesh.region, b.mesh.region) << what;
        EXPECT_EQ(a.trianglesPerLevel, b.trianglesPerLevel) << what;
      }
  // And with the Loop rule and no midvein features, zero tolerance is the oracle-checked plain Loop.
  for (const RefinementRule rule : kErrorRules)
  {
    AdaptiveLoopParameters plain = ByRule(rule, 0.0, 2, FeatureRule::Loop);
    plain.midveinIsFeature = false;
    EXPECT_EQ(
      AdaptiveLoopSubdivide(Blade(10), plain).mesh.points, AdaptiveLoopSubdivide(Blade(10), PlainLoop(2)).mesh.points);
  }
}

TEST(AdaptiveLoopSubdivision, ErrorRulesInfiniteToleranceLeavesTheInput)
{
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10) };
  for (const RefinementRule rule : kErrorRules)
    for (const AdaptiveLoopMesh& input : meshes)
      for (int r = 0; r < 3; ++r)
        for (const double tolerance : { std::numeric_limits<double>::infinity(), 1e6 })
        {
          const AdaptiveLoopResult result =
            AdaptiveLoopSubdivide(input, ByRule(rule, tolerance, 4, static_cast<FeatureRule>(r)));
          ASSERT_EQ(result.error, "");
          EXPECT_EQ(result.levels, 0);
          EXPECT_EQ(result.mesh.points, input.points);
          EXPECT_EQ(result.mesh.triangles, input.triangles);
          EXPECT_EQ(result.mesh.attributes, input.attributes);
        }
}

TEST(AdaptiveLoopSubdivision, ErrorRulesKeepFixedFeaturesBitIdentical)
{
  const AdaptiveLoopMesh input = Blade(14);
  for (const RefinementRule rule : kErrorRules)
  {
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, ByRule(rule, 1e-4, 3, FeatureRule::Fixed));
    ASSERT_EQ(result.error, "");
    ASSERT_GT(result.levels, 0);
    std::size_t featurePoints = 0;
    ExpectFeaturePointsKept(input, result.mesh, 1, featurePoints);
    EXPECT_GT(featurePoints, 20u);
  }
}

TEST(AdaptiveLoopSubdivision, ChordErrorRefinesATubeAcrossItsRulingsOnly)
{
  // On the tube (8 points per ring, 45 degrees apart), an interior ruling (two ends of valence 6 at the same
  // angle) has equal end normals (sagitta 0) and its odd point lies on the chord between the ends' moved positions
  // (the rings are congruent): only half of e = |n . (c + d - a - b)| / 8 = (1 - cos 45) / 4 = 0.073 counts,
  // 0.037. Ring edges and diagonals bend with the circle: sagitta |(N_b - N_a) . (b - a)| / 8 =
  // 4 sin^2(22.5) / 8 = 0.073. A tolerance of 0.05 splits those and keeps the rulings; the Surface error rule at
  // the same tolerance splits the rulings too.
  const int n = 6, around = 8;
  const AdaptiveLoopMesh tube = Tube(n, around);
  const double tolerance = 0.05;
  const AdaptiveLoopResult chord = AdaptiveLoopSubdivide(tube, ByChord(tolerance, 1, FeatureRule::Fixed));
  const AdaptiveLoopResult error = AdaptiveLoopSubdivide(tube, ByError(tolerance, 1, FeatureRule::Fixed));
  ASSERT_EQ(chord.error, "");
  ASSERT_EQ(error.error, "");
  const auto use = testing::EdgeUse(AsTriangles(chord.mesh.triangles));
  const auto errorUse = testing::EdgeUse(AsTriangles(error.mesh.triangles));
  const auto has = [](const std::map<std::pair<int, int>, int>& edges, int p, int q) {
    return edges.count({ std::min(p, q), std::max(p, q) }) == 1;
  };
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < around; ++k)
    {
      const int a = i * around + k, b = i * around + (k + 1) % around, c = a + around, d = b + around;
      if (i > 0 && i + 1 < n) // rulings touching a rim: the rim does not move (Fixed), so e' is not 0 there
      {
        EXPECT_TRUE(has(use, a, c)) << "ruling " << a << "-" << c << " split";
        EXPECT_FALSE(has(errorUse, a, c)) << "Surface error: ruling " << a << "-" << c << " kept";
      }
      EXPECT_FALSE(has(use, a, d)) << "diagonal " << a << "-" << d << " not split";
      if (i > 0) // ring 0 is a rim: boundary edges, never split under Fixed
      {
        EXPECT_FALSE(has(use, a, b)) << "ring edge " << a << "-" << b << " not split";
      }
    }
  EXPECT_LT(chord.mesh.NumberOfTriangles(), error.mesh.NumberOfTriangles());
  ExpectConforming(tube, chord.mesh, "tube, chord error");
  // Three levels at a tolerance 16 times finer (one level's edges have a quarter of the sagitta): the rulings lag
  // behind, so fewer triangles than the Surface error rule makes at the same tolerance.
  const AdaptiveLoopResult three = AdaptiveLoopSubdivide(tube, ByChord(tolerance / 16.0, 3, FeatureRule::Fixed));
  const AdaptiveLoopResult threeByError = AdaptiveLoopSubdivide(tube, ByError(tolerance / 16.0, 3, FeatureRule::Fixed));
  ASSERT_EQ(three.error, "");
  ASSERT_EQ(three.levels, 3);
  EXPECT_LT(three.mesh.NumberOfTriangles(), threeByError.mesh.NumberOfTriangles());
  ExpectConforming(tube, three.mesh, "tube, chord error, 3 levels");
}

TEST(AdaptiveLoopSubdivision, ChordErrorConformingAndDeterministicOnRandomTolerances)
{
  std::mt19937_64 random(20261123);
  std::uniform_real_distribution<double> exponent(-6.0, 0.0);
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10), Tube(5, 9) };
  for (int trial = 0; trial < 30; ++trial)
  {
    const AdaptiveLoopMesh& input = meshes[trial % 3];
    const double tolerance = std::pow(10.0, exponent(random));
    AdaptiveLoopParameters s = ByChord(tolerance, 1 + trial % 4, static_cast<FeatureRule>(trial % 3));
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, s);
    ASSERT_EQ(result.error, "");
    const std::string what = "trial " + std::to_string(trial) + " tolerance " + std::to_string(tolerance);
    ExpectConforming(input, result.mesh, what);
    EXPECT_EQ(result.trianglesPerLevel.back(), result.mesh.NumberOfTriangles());
    EXPECT_EQ(result.mesh.origin.size(), result.mesh.NumberOfTriangles());
    s.parallelFor = ThreeThreadFor;
    const AdaptiveLoopResult again = AdaptiveLoopSubdivide(input, s);
    EXPECT_EQ(again.mesh.points, result.mesh.points) << what;
    EXPECT_EQ(again.mesh.triangles, result.mesh.triangles) << what;
    EXPECT_EQ(again.mesh.attributes, result.mesh.attributes) << what;
  }
}

TEST(AdaptiveLoopSubdivision, ChordErrorAttributesFollowThePositionStencils)
{
  AdaptiveLoopMesh input = Blade(12);
  input.attributeComponents = 3; // the position itself: after any run it must equal the output positions
  input.attributes = input.points;
  for (const FeatureRule rule : { FeatureRule::Fixed, FeatureRule::Loop, FeatureRule::Refine })
  {
    const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, ByChord(3e-4, 3, rule));
    ASSERT_EQ(result.error, "");
    ASSERT_GT(result.levels, 0);
    EXPECT_EQ(result.mesh.attributes, result.mesh.points);
  }
}

TEST(AdaptiveLoopSubdivision, ChordErrorDoublesTheEstimateNextToPointsThatNeverMove)
{
  // SurfaceError's quad: the edge (a, b) = (0,0,0)-(1,0,0), opposite points (0.5, +-1, z), all four on the
  // boundary. Both ends have the same normal (sagitta 0) and, under Fixed and Refine, never move (limit offsets 0,
  // e' = e = z / 4): the estimate is max(0, z / 4, z / 8) = z / 4, doubled for an edge with an end that never moves:
  // the edge splits exactly when the tolerance is at most z / 2, where the Surface error rule needs z / 4.
  AdaptiveLoopMesh quad;
  const double z = 0.4;
  quad.points = { 0, 0, 0, 1, 0, 0, 0.5, 1, z, 0.5, -1, z };
  quad.triangles = { 0, 1, 2, 1, 0, 3 };
  for (const FeatureRule rule : { FeatureRule::Fixed, FeatureRule::Refine })
  {
    const AdaptiveLoopResult below = AdaptiveLoopSubdivide(quad, ByChord(0.1999, 1, rule));
    const AdaptiveLoopResult above = AdaptiveLoopSubdivide(quad, ByChord(0.2001, 1, rule));
    ASSERT_EQ(below.error, "");
    ASSERT_EQ(above.error, "");
    EXPECT_EQ(below.levels, 1) << "feature rule " << static_cast<int>(rule);
    EXPECT_EQ(above.levels, 0) << "feature rule " << static_cast<int>(rule);
    EXPECT_EQ(above.mesh.points, quad.points);
  }
  EXPECT_EQ(AdaptiveLoopSubdivide(quad, ByError(0.1001, 1, FeatureRule::Fixed)).levels, 0);
}

/// Loop's limit offset of every point (|N_v . (v_inf - v)|, N_v the normalised sum of its triangles' unit normals,
/// v_inf = (1 - n chi) v + chi sum(neighbours)), written here from the formulas; -1 for points on a feature edge
/// (boundary, or both ends in region 1), which the test leaves out.
std::vector<double> LimitOffsets(const AdaptiveLoopMesh& mesh)
{
  const std::size_t nV = mesh.NumberOfPoints();
  const auto use = testing::EdgeUse(AsTriangles(mesh.triangles));
  std::vector<std::set<int>> neighbours(nV);
  std::vector<std::array<double, 3>> normal(nV, { 0.0, 0.0, 0.0 });
  std::vector<bool> onFeature(nV, false);
  for (std::size_t t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const int* v = mesh.triangles.data() + 3 * t;
    const double* p[3] = { &mesh.points[3 * v[0]], &mesh.points[3 * v[1]], &mesh.points[3 * v[2]] };
    const double u[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
    const double w[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
    double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; ++c)
    {
      for (int j = 0; j < 3; ++j)
        normal[v[c]][j] += n[j] / len;
      neighbours[v[c]].insert(v[(c + 1) % 3]);
      neighbours[v[c]].insert(v[(c + 2) % 3]);
      const int a = v[c], b = v[(c + 1) % 3];
      const bool midvein = !mesh.region.empty() && mesh.region[a] == 1 && mesh.region[b] == 1;
      if (use.at({ std::min(a, b), std::max(a, b) }) == 1 || midvein)
        onFeature[a] = onFeature[b] = true;
    }
  }
  std::vector<double> offset(nV, -1.0);
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (onFeature[v] || neighbours[v].empty())
      continue;
    const int n = static_cast<int>(neighbours[v].size());
    const double c = 0.375 + 0.25 * std::cos(2.0 * 3.14159265358979323846 / n);
    const double beta = n == 3 ? 3.0 / 16.0 : (0.625 - c * c) / n;
    const double chi = 1.0 / (3.0 / (8.0 * beta) + n);
    const double len =
      std::sqrt(normal[v][0] * normal[v][0] + normal[v][1] * normal[v][1] + normal[v][2] * normal[v][2]);
    double along = 0.0;
    for (const int w : neighbours[v])
      for (int j = 0; j < 3; ++j)
        along += chi * (mesh.points[3 * w + j] - mesh.points[3 * v + j]) * normal[v][j] / len;
    offset[v] = std::abs(along);
  }
  return offset;
}

TEST(AdaptiveLoopSubdivision, ChordErrorMovesEveryPointWhoseLimitOffsetReachesTheTolerance)
{
  // A point left unmoved stays its limit offset delta off the limit surface, which the chord estimates do not see.
  // So, after one level: a point with delta >= tolerance has moved (one of its edges split, forced if need be), and
  // one with delta / 2 >= tolerance has all its edges split. Tolerances at quantiles of the points' offsets, so
  // both cases and their complements occur.
  const AdaptiveLoopMesh meshes[] = { Icosahedron(true), Blade(10), Blade(13, 1.5) };
  for (std::size_t m = 0; m < 3; ++m)
  {
    const AdaptiveLoopMesh& input = meshes[m];
    const std::vector<double> offset = LimitOffsets(input);
    std::vector<double> sorted;
    for (const double d : offset)
      if (d >= 0.0)
        sorted.push_back(d);
    ASSERT_GT(sorted.size(), 5u);
    std::sort(sorted.begin(), sorted.end());
    std::size_t moved = 0, allSplit = 0, kept = 0;
    const auto at = [&sorted](double quantile) {
      return sorted[static_cast<std::size_t>(quantile * static_cast<double>(sorted.size() - 1))];
    };
    for (const double tolerance : { at(0.2), at(0.5), at(0.8), 0.5 * at(0.5), 0.5 * at(0.2) })
    {
      const AdaptiveLoopResult result = AdaptiveLoopSubdivide(input, ByChord(tolerance, 1, FeatureRule::Fixed));
      ASSERT_EQ(result.error, "");
      const auto use = testing::EdgeUse(AsTriangles(result.mesh.triangles));
      const auto inUse = testing::EdgeUse(AsTriangles(input.triangles));
      for (std::size_t v = 0; v < offset.size(); ++v)
      {
        // (The test's offsets and the filter's agree to rounding, not bit for bit: skip exact ties.)
        if (offset[v] < 0.0 || std::abs(offset[v] - tolerance) <= 1e-9 * tolerance ||
          std::abs(offset[v] / 2.0 - tolerance) <= 1e-9 * tolerance)
          continue;
        const std::string what = "mesh " + std::to_string(m) + " tolerance " + std::to_string(tolerance) + " point " +
          std::to_string(v) + " offset " + std::to_string(offset[v]);
        bool same = true;
        for (int j = 0; j < 3; ++j)
          same = same && result.mesh.points[3 * v + j] == input.points[3 * v + j];
        if (offset[v] >= tolerance)
        {
          EXPECT_FALSE(same) << what;
          ++moved;
        }
        else
          kept += same ? 1 : 0;
        if (offset[v] / 2.0 >= tolerance)
        {
          ++allSplit;
          for (const auto& edge : inUse)
            if (edge.first.first == static_cast<int>(v) || edge.first.second == static_cast<int>(v))
            {
              EXPECT_EQ(use.count(edge.first), 0u)
                << what << ": edge " << edge.first.first << "-" << edge.first.second << " kept";
            }
        }
      }
    }
    EXPECT_GT(moved, 0u) << "mesh " << m;
    EXPECT_GT(allSplit, 0u) << "mesh " << m;
    if (m > 0)
    {
      EXPECT_GT(kept, 0u) << "mesh " << m << ": some points below the tolerance stay";
    }
  }
}

} // namespace
} // namespace plantmorph

TEST(AdaptiveLoopSubdivision, NormalizeAttributeVectorsScalesOnlyItsVectorToUnitLength)
{
  // Three points, five attribute components each: a scalar, the vector at offset 1, a scalar.
  plantmorph::AdaptiveLoopMesh mesh;
  mesh.attributeComponents = 5;
  mesh.attributes = { 7.0, 3.0, 0.0, 4.0, -1.0, /**/ 8.0, 0.0, 0.0, 0.0, -2.0, /**/ 9.0, 0.0, -0.5, 0.0, -3.0 };
  const std::vector<double> expected = { 7.0, 0.6, 0.0, 0.8, -1.0, /**/ 8.0, 0.0, 0.0, 0.0, -2.0, /**/ 9.0, 0.0, -1.0,
    0.0, -3.0 };
  plantmorph::AdaptiveLoopMesh serial = mesh;
  plantmorph::NormalizeAttributeVectors(serial, 1);
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_DOUBLE_EQ(serial.attributes[k], expected[k]) << k;
  // A ParallelFor cutting the range one point at a time gives the same values.
  int calls = 0;
  const plantmorph::ParallelForFunction onePointAtATime = [&calls](std::size_t count, const auto& body) {
    for (std::size_t i = 0; i < count; ++i, ++calls)
      body(i, i + 1);
  };
  plantmorph::NormalizeAttributeVectors(mesh, 1, onePointAtATime);
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(mesh.attributes, serial.attributes);
}
