// SPDX-License-Identifier: GPL-3.0-or-later
// How far the welded junctions reach from the skeleton (BranchJunctions.h "Reach"): every point of the
// welded surface must lie within 1.6 local radii of the skeleton, on Table 1's templates, stroke trees at every
// StrokeSubtreeDepth, edited and merged trees, and the surface stays one closed, oriented, manifold piece per tree.
//
// The measure ("reach") of a surface point x: the smallest, over the skeleton's segments, of |x - p| / r(p), p the
// segment's point nearest x and r(p) the tube's input radius interpolated there (the template radius, not the pipe
// model's narrowed one). A point on a tube's wall has reach 1 (a mitre ring's vertex too: it lies on both
// cylinders); a point in the crook between a parent and its child that is k radii from both has reach k. Taking the
// smallest ratio rather than the ratio at the nearest segment keeps a parent's wall beside a thin child's base from
// counting as "far from the child". Points sampled: every vertex and a barycentric grid (edges in thirds and the
// centroid) on every triangle, so a large flat hull facet cannot hide its middle. Segments searched: those of the
// triangle's own tube and its family (parent, grandparent, children, siblings), which holds every tube of any
// junction the triangle belongs to; searching fewer segments can only raise the reach, so a bound that holds here
// holds for the whole skeleton.
#include "BranchJunctions.h"
#include "BranchTubes.h"
#include "SmallConvexHull.h"
#include "TreeMerge.h"
#include "TreeStrokes.h"
#include "TreeTemplate.h"
#include "TreeTestMerge.h"
#include "TreeTestStrokes.h"

#include <MeshInvariants.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

using namespace plantmorph;
using tree_test::MergeOntoBranch3;
using tree_test::SkeletonOf;

namespace
{
struct Reach
{
  double surface = 0.0;  ///< largest reach over the sampled surface points
  double vertices = 0.0; ///< largest reach over the mesh's vertices
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  std::size_t tube = 0; ///< owner of the triangle with the largest reach
};

Eigen::Vector3d Point(const TubeMesh& mesh, std::int64_t i)
{
  const std::size_t k = 3 * static_cast<std::size_t>(i);
  return { mesh.points[k], mesh.points[k + 1], mesh.points[k + 2] };
}

/// |x - p| / r(p) over tube t's segments, smallest.
double ReachOf(const Eigen::Vector3d& x, const TubeInput& t)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < t.centre.size(); ++k)
  {
    const Eigen::Vector3d a = t.centre[k], d = t.centre[k + 1] - t.centre[k];
    const double len2 = d.squaredNorm();
    if (len2 == 0.0)
      continue;
    const double f = std::clamp((x - a).dot(d) / len2, 0.0, 1.0);
    const double distance = (x - (a + f * d)).norm();
    const double r = t.radii[k] + f * (t.radii[k + 1] - t.radii[k]);
    best = std::min(best, distance <= 1e-12 ? 0.0 : distance / r);
  }
  return best;
}

Reach MeasureReach(const std::vector<TubeInput>& tubes, const TubeMesh& mesh)
{
  std::vector<std::vector<std::size_t>> children(tubes.size());
  for (std::size_t t = 0; t < tubes.size(); ++t)
    if (tubes[t].parent >= 0)
      children[static_cast<std::size_t>(tubes[t].parent)].push_back(t);
  Reach reach;
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    std::set<std::size_t> family{ t };
    family.insert(children[t].begin(), children[t].end());
    if (tubes[t].parent >= 0)
    {
      const std::size_t p = static_cast<std::size_t>(tubes[t].parent);
      family.insert(p);
      family.insert(children[p].begin(), children[p].end());
      if (tubes[p].parent >= 0)
        family.insert(static_cast<std::size_t>(tubes[p].parent));
    }
    const auto measure = [&](const Eigen::Vector3d& x) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t f : family)
        best = std::min(best, ReachOf(x, tubes[f]));
      return best;
    };
    for (auto f = mesh.triangleOffsets[t]; f < mesh.triangleOffsets[t + 1]; ++f)
    {
      const std::int32_t* v = &mesh.triangles[3 * static_cast<std::size_t>(f)];
      const Eigen::Vector3d a = Point(mesh, v[0]), b = Point(mesh, v[1]), c = Point(mesh, v[2]);
      for (int i = 0; i <= 3; ++i)
        for (int j = 0; i + j <= 3; ++j)
        {
          const Eigen::Vector3d x = (i * a + j * b + (3 - i - j) * c) / 3.0;
          const double value = measure(x);
          const bool vertex = i == 3 || j == 3 || i + j == 0;
          if (vertex)
            reach.vertices = std::max(reach.vertices, value);
          if (value > reach.surface)
            reach.surface = value, reach.where = x, reach.tube = t;
        }
    }
  }
  return reach;
}

/// One closed, oriented, manifold surface per tree: every directed edge once with its reverse once (EdgeUse: every
/// undirected edge in two triangles), one connected piece per root plus one per fallback child, each a sphere.
void ExpectClosedPerTree(
  const std::vector<TubeInput>& tubes, const TubeMesh& mesh, const JunctionReport& report, const std::string& what)
{
  plantmorph::testing::Triangles triangles;
  for (std::size_t f = 0; f < mesh.TriangleCount(); ++f)
    triangles.push_back({ mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2] });
  int badEdges = 0;
  for (const auto& [edge, count] : plantmorph::testing::EdgeUse(triangles))
    badEdges += count != 2;
  std::set<std::pair<int, int>> directed;
  int repeated = 0;
  for (const auto& t : triangles)
    for (int e = 0; e < 3; ++e)
      repeated += !directed.insert({ t[e], t[(e + 1) % 3] }).second;
  EXPECT_EQ(badEdges, 0) << what;
  EXPECT_EQ(repeated, 0) << what; // with every edge in two triangles: consistently oriented
  // Components through shared vertices (a closed manifold's pieces), and V - E + F = 2 per piece.
  std::vector<int> root(mesh.PointCount());
  for (std::size_t i = 0; i < root.size(); ++i)
    root[i] = static_cast<int>(i);
  const auto find = [&](int x) {
    while (root[static_cast<std::size_t>(x)] != x)
      x = root[static_cast<std::size_t>(x)] = root[static_cast<std::size_t>(root[static_cast<std::size_t>(x)])];
    return x;
  };
  std::set<int> used;
  for (const auto& t : triangles)
    for (int e = 0; e < 3; ++e)
    {
      used.insert(t[e]);
      root[static_cast<std::size_t>(find(t[e]))] = find(t[(e + 1) % 3]);
    }
  std::set<int> pieces;
  for (int v : used)
    pieces.insert(find(v));
  std::size_t roots = 0;
  for (const TubeInput& t : tubes)
    roots += t.parent < 0;
  EXPECT_EQ(pieces.size(), roots + static_cast<std::size_t>(report.fallback)) << what;
  const long long euler = static_cast<long long>(used.size()) - static_cast<long long>(directed.size() / 2) +
    static_cast<long long>(triangles.size());
  EXPECT_EQ(euler, 2 * static_cast<long long>(pieces.size())) << what;
  double volume = 0.0;
  for (const auto& t : triangles)
    volume += Point(mesh, t[0]).dot(Point(mesh, t[1]).cross(Point(mesh, t[2]))) / 6.0;
  EXPECT_GT(volume, 0.0) << what; // outward
}

/// Welds the tree, checks the surface, measures and prints its reach; returns the surface reach.
double CheckTree(const Tree& tree, int sides, const std::string& what)
{
  const std::vector<TubeInput> tubes = TreeTubeInputs(tree);
  TubeMesh mesh;
  JunctionReport report;
  EXPECT_EQ(BuildWeldedTubes(tubes, sides, mesh, SerialFor, &report), "") << what;
  ExpectClosedPerTree(tubes, mesh, report, what);
  const Reach reach = MeasureReach(tubes, mesh);
  std::printf("%s: %zu tubes, junctions %lld (merged %lld, at ends %lld), fallback %lld; reach: surface %.3f, "
              "vertices %.3f local radii (worst on tube %zu at %.3f %.3f %.3f)\n",
    what.c_str(), tubes.size(), (long long)report.junctions, (long long)report.merged, (long long)report.endJunctions,
    (long long)report.fallback, reach.surface, reach.vertices, reach.tube, reach.where.x(), reach.where.y(),
    reach.where.z());
  return reach.surface;
}

constexpr double Bound = 1.6;

/// The measured tree: the first three sample strokes (testing/python/tree/test_tree_from_sketch.py's), trunk first.
std::vector<std::vector<Eigen::Vector3d>> ThreeStrokes()
{
  auto strokes = tree_test::SampleStrokes();
  strokes.resize(3);
  return strokes;
}

TreeParameters Preset(int preset)
{
  TreeParameters s;
  ApplyTreePreset(preset, s);
  s.leaves = false;
  return s;
}
} // namespace

TEST(JunctionReach, ThreeStrokeTreeAtEveryStrokeSubtreeDepth)
{
  // Mode Strokes with the source's defaults (StrokeSubtreeDepth 2, 8 children, 4 segments a branch, 6 sides), and
  // the other depths: 0 (strokes alone), 1 and 3 (with fewer children, to keep the brute force short).
  for (int depth = 0; depth <= 3; ++depth)
  {
    TreeParameters s;
    s.mode = TreeMode::Strokes;
    s.leaves = false;
    s.strokesOnly = depth == 0;
    s.strokeSubtreeDepth = std::max(depth, 1);
    if (depth == 3)
      s.childCount = 4;
    Tree tree;
    ASSERT_EQ(BuildTree(s, ThreeStrokes(), tree), "");
    EXPECT_LE(CheckTree(tree, s.sides, "three strokes, StrokeSubtreeDepth " + std::to_string(depth)), Bound);
  }
}

TEST(JunctionReach, Table1Presets)
{
  for (int preset = 1; preset <= 3; ++preset)
  {
    TreeParameters s = Preset(preset);
    s.depth = preset == 2 ? 4 : 3;
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    EXPECT_LE(CheckTree(tree, s.sides, std::string("preset ") + TreePresetName(preset)), Bound);
  }
}

TEST(JunctionReach, EditedAndMergedTrees)
{
  TreeParameters e = Preset(1);
  e.depth = 2;
  e.deletedBranches = { 2, 20 };
  e.overrides[11].length = 3.0;
  e.overrides[11].angle = 70.0;
  e.overrides[29].radius = 0.05;
  e.overrides[5].angle = 15.0; // a narrow crook
  Tree edited;
  ASSERT_EQ(BuildTree(e, {}, edited), "");
  EXPECT_LE(CheckTree(edited, e.sides, "edited preset 1"), Bound);

  TreeParameters second = Preset(2);
  second.depth = 2;
  Tree other;
  ASSERT_EQ(BuildTree(second, {}, other), "");
  const std::vector<SkeletonBranch> skeleton = SkeletonOf(other);
  TreeParameters m = Preset(1);
  m.depth = 2;
  MergeOntoBranch3(m); // a child of the trunk
  Tree merged;
  ASSERT_EQ(BuildTree(m, {}, &skeleton, merged), "");
  EXPECT_LE(CheckTree(merged, m.sides, "merged"), Bound);
}

namespace
{
/// Checks a hull against brute force: closed and oriented (each directed edge once, its reverse once), V - E + F = 2,
/// every point behind or on every facet's plane (tolerance), every facet of positive area. Returns the corners used.
std::set<long> ExpectConvexHull(const std::vector<Eigen::Vector3d>& p, const std::vector<std::array<long, 3>>& facets)
{
  std::map<std::pair<long, long>, int> directed;
  std::set<long> corners;
  for (const auto& f : facets)
  {
    const Eigen::Vector3d n =
      (p[std::size_t(f[1])] - p[std::size_t(f[0])]).cross(p[std::size_t(f[2])] - p[std::size_t(f[0])]);
    EXPECT_GT(n.norm(), 0.0);
    for (const Eigen::Vector3d& x : p)
      EXPECT_LE(n.normalized().dot(x - p[std::size_t(f[0])]), 1e-9);
    for (int e = 0; e < 3; ++e)
    {
      ++directed[{ f[std::size_t(e)], f[std::size_t((e + 1) % 3)] }];
      corners.insert(f[std::size_t(e)]);
    }
  }
  for (const auto& [edge, count] : directed)
  {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({ edge.second, edge.first }), 1u);
  }
  EXPECT_EQ(long(corners.size()) - long(directed.size() / 2) + long(facets.size()), 2);
  return corners;
}
} // namespace

TEST(SmallConvexHull, CubeWithInteriorPointsHasTwelveFacetsOnItsCorners)
{
  std::vector<Eigen::Vector3d> p;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> inside(-0.9, 0.9);
  for (int i = 0; i < 20; ++i)
    p.emplace_back(inside(random), inside(random), inside(random));
  for (int k = 0; k < 8; ++k)
    p.emplace_back(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
  std::vector<std::array<long, 3>> facets;
  ASSERT_TRUE(SmallConvexHull(p, facets));
  EXPECT_EQ(facets.size(), 12u); // two per face of the cube
  const std::set<long> corners = ExpectConvexHull(p, facets);
  EXPECT_EQ(corners, (std::set<long>{ 20, 21, 22, 23, 24, 25, 26, 27 }));
}

TEST(SmallConvexHull, TwoRingsAndAnApexLikeAJunction)
{
  // Two hexagonal rings in parallel planes (coplanar, cocircular points, as a junction's cut rings) and a point past
  // one of them: 6 + 6 side facets between the rings, 4 in the far cap, 6 in the apex's fan; every point a corner.
  std::vector<Eigen::Vector3d> p;
  for (int ring = 0; ring < 2; ++ring)
    for (int j = 0; j < 6; ++j)
      p.emplace_back(std::cos(j * 3.14159265358979 / 3), ring * 2.0, std::sin(j * 3.14159265358979 / 3));
  p.emplace_back(0.1, 3.5, 0.0);
  p.emplace_back(0.0, 1.0, 0.2); // inside
  std::vector<std::array<long, 3>> facets;
  ASSERT_TRUE(SmallConvexHull(p, facets));
  EXPECT_EQ(facets.size(), 12u + 4u + 6u);
  EXPECT_EQ(ExpectConvexHull(p, facets).size(), 13u);
}

TEST(SmallConvexHull, RandomCloudsAgreeWithBruteForce)
{
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial)
  {
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i < 10 + trial; ++i)
      p.emplace_back(normal(random), 0.3 * normal(random), normal(random));
    std::vector<std::array<long, 3>> facets;
    ASSERT_TRUE(SmallConvexHull(p, facets)) << trial;
    ExpectConvexHull(p, facets); // every point behind every facet: the hull holds the cloud
  }
}

TEST(SmallConvexHull, DegenerateSetsFail)
{
  std::vector<std::array<long, 3>> facets;
  EXPECT_FALSE(SmallConvexHull({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, facets));
  EXPECT_FALSE(SmallConvexHull({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0.5, 0.2, 0 } }, facets));
  EXPECT_FALSE(SmallConvexHull({ { 0, 0, 0 }, { 1, 1, 1 }, { 2, 2, 2 }, { 3, 3, 3 } }, facets));
  EXPECT_TRUE(facets.empty());
}
