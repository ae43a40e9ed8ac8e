// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFromSketchSource's algorithm layer (docs/methods/tree-from-sketch.md, paper 004): template counts and formulas,
// stable ids, overrides, watertight tubes (closed, manifold, oriented, exact volumes, mitre rings on both cylinders),
// strokes (projection, eq. (3), angle choice, attachment, ties), leaves, determinism, bad input.
#include "BranchJunctions.h"
#include "BranchTubes.h"
#include "TreeLeaves.h"
#include "TreeMerge.h"
#include "TreeStrokes.h"
#include "TreeTemplate.h"
#include "TreeTestMerge.h"
#include "TreeTestStrokes.h"

#include <plantmorph/BezierCurve.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <thread>

using namespace plantmorph;
using tree_test::MergeOntoBranch3;
using tree_test::SkeletonOf;

namespace
{
constexpr double Pi = 3.14159265358979323846;
constexpr double Degree = Pi / 180.0;

TreeParameters Preset(int preset)
{
  TreeParameters s;
  ApplyTreePreset(preset, s);
  s.leaves = false;
  return s;
}

std::map<int, const TreeBranch*> ById(const Tree& tree)
{
  std::map<int, const TreeBranch*> m;
  for (const auto& b : tree.branches)
  {
    m[b.id] = &b;
  }
  return m;
}

std::vector<TubeInput> TubesOf(const Tree& tree)
{
  return TreeTubeInputs(tree);
}

/// Every undirected edge in exactly two triangles, every directed edge once (consistent orientation), and per tube
/// V - E + F = 2 (a sphere). Returns the number of failures.
int ClosedManifoldFailures(const TubeMesh& mesh)
{
  int failures = 0;
  for (std::size_t t = 0; t + 1 < mesh.pointOffsets.size(); ++t)
  {
    std::map<std::pair<int, int>, int> directed;
    for (auto f = mesh.triangleOffsets[t]; f < mesh.triangleOffsets[t + 1]; ++f)
    {
      const int* v = &mesh.triangles[3 * std::size_t(f)];
      for (int e = 0; e < 3; ++e)
      {
        directed[{ v[e], v[(e + 1) % 3] }]++;
        if (v[e] < mesh.pointOffsets[t] || v[e] >= mesh.pointOffsets[t + 1])
          ++failures;
      }
    }
    std::set<std::pair<int, int>> undirected;
    for (const auto& [edge, count] : directed)
    {
      if (count != 1 || directed.count({ edge.second, edge.first }) != 1)
        ++failures;
      undirected.insert({ std::min(edge.first, edge.second), std::max(edge.first, edge.second) });
    }
    const long long V = mesh.pointOffsets[t + 1] - mesh.pointOffsets[t];
    const long long F = mesh.triangleOffsets[t + 1] - mesh.triangleOffsets[t];
    if (V - static_cast<long long>(undirected.size()) + F != 2)
      ++failures;
  }
  return failures;
}

/// Signed volume of tube t by the divergence theorem.
double Volume(const TubeMesh& mesh, std::size_t t)
{
  double volume = 0.0;
  const auto P = [&](int i) {
    return Eigen::Vector3d(
      mesh.points[3 * std::size_t(i)], mesh.points[3 * std::size_t(i) + 1], mesh.points[3 * std::size_t(i) + 2]);
  };
  for (auto f = mesh.triangleOffsets[t]; f < mesh.triangleOffsets[t + 1]; ++f)
  {
    const int* v = &mesh.triangles[3 * std::size_t(f)];
    volume += P(v[0]).dot(P(v[1]).cross(P(v[2]))) / 6.0;
  }
  return volume;
}

double PolygonArea(int sides, double r)
{
  return 0.5 * sides * r * r * std::sin(2.0 * Pi / sides);
}

double Frac(double x)
{
  return x - std::floor(x);
}
} // namespace

TEST(TreeTemplate, BranchCountsOfTable1EqualTheClosedForm)
{
  const long long expected[] = { 0, 1 + 8 + 64 + 512 + 4096, (2187 - 1) / 2, 1 + 10 + 100 + 1000 + 10000 };
  EXPECT_EQ(expected[1], 4681);
  for (int preset = 1; preset <= 3; ++preset)
  {
    Tree tree;
    ASSERT_EQ(BuildTree(Preset(preset), {}, tree), "");
    EXPECT_EQ(static_cast<long long>(tree.branches.size()), expected[preset]) << TreePresetName(preset);
    EXPECT_EQ(SubtreeSize(Preset(preset).childCount, Preset(preset).depth), expected[preset]);
    EXPECT_EQ(tree.SegmentCount(), expected[preset] * 4);
    // Ids are 0..N-1, each once, parents listed before children, depths consecutive.
    std::set<int> seen;
    for (const auto& b : tree.branches)
    {
      EXPECT_TRUE(b.parentId < 0 || seen.count(b.parentId)) << b.id;
      seen.insert(b.id);
    }
    EXPECT_EQ(*seen.rbegin(), expected[preset] - 1);
    EXPECT_EQ(static_cast<long long>(seen.size()), expected[preset]);
  }
}

TEST(TreeTemplate, EveryChildFollowsTheFormulas)
{
  for (int preset = 1; preset <= 3; ++preset)
  {
    const TreeParameters s = Preset(preset);
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    const auto byId = ById(tree);
    const bool mono = s.type == TreeType::Monopodial;
    const TreeBranch& trunk = *byId.at(0);
    EXPECT_DOUBLE_EQ(trunk.length, s.length);
    EXPECT_DOUBLE_EQ(trunk.radius, s.radius);
    EXPECT_DOUBLE_EQ(trunk.radiusEnd, mono ? 0.0 : s.radius / std::sqrt(3.0));
    int checked = 0;
    for (const auto& b : tree.branches)
    {
      EXPECT_EQ(b.centre.size(), 5u); // DIVID = 4 segments
      EXPECT_NEAR((b.centre.back() - b.centre.front()).norm(), b.length, 1e-12 * b.length + 1e-15);
      if (b.parentId < 0)
        continue;
      const TreeBranch& p = *byId.at(b.parentId);
      const int i = b.childIndex;
      const double pos = (1.0 - s.ratio) + i * s.ratio / s.childCount;
      EXPECT_DOUBLE_EQ(b.position, pos);
      const double twig = b.level == 0 ? 1.2 : 1.0;
      const double length = mono ? p.length * (1.0 - 0.618 * pos) : p.length * 0.8;
      // Twigs are 1.2 times longer; undo it on the parent when the parent itself was a twig (never: it has children).
      EXPECT_NEAR(b.length, length * twig, 1e-12 * b.length);
      const double radius = mono ? p.radius * (1.0 - 0.618 * pos) : p.radius + pos * (p.radiusEnd - p.radius);
      EXPECT_NEAR(b.radius, radius, 1e-15);
      EXPECT_NEAR(b.radiusEnd, mono ? 0.0 : radius / std::sqrt(3.0), 1e-15);
      EXPECT_EQ(b.depth, p.depth + 1);
      // Divergence: the angle between the branch and its parent's axis.
      const Eigen::Vector3d d = (b.centre.back() - b.centre.front()).normalized();
      const Eigen::Vector3d py = p.frame.col(1);
      EXPECT_NEAR(std::acos(std::clamp(d.dot(py), -1.0, 1.0)) / Degree, mono ? 34.4 : 55.6, 1e-9);
      // Rotation about the parent: the direction's part across the parent is (-cos rot, sin rot) in (x, z).
      const double rotation = std::atan2(d.dot(p.frame.col(2)), -d.dot(p.frame.col(0))) / Degree;
      const double expected = Frac(double(i) * s.phyllotaxisA / s.phyllotaxisB) * 360.0;
      const double difference = std::remainder(rotation - expected, 360.0);
      EXPECT_NEAR(difference, 0.0, 1e-9) << b.id;
      // It starts on its parent's surface at pos: distance to the parent's axis = the parent's radius there.
      const Eigen::Vector3d axisPoint = p.centre.front() + pos * (p.centre.back() - p.centre.front());
      const Eigen::Vector3d offset = b.centre.front() - axisPoint;
      EXPECT_NEAR(offset.dot(py), 0.0, 1e-12);
      EXPECT_NEAR(offset.norm(), p.radius + pos * (p.radiusEnd - p.radius), 1e-12);
      ++checked;
    }
    EXPECT_EQ(checked, static_cast<int>(tree.branches.size()) - 1);
  }
}

TEST(TreeTemplate, PhyllotaxisAngleIsExactFraction)
{
  for (int b = 1; b < 20; ++b)
    for (int a = 1; a < 20; ++a)
      for (int i = 0; i < 30; ++i)
        EXPECT_NEAR(PhyllotaxisAngle(i, a, b), Frac(double(i) * a / b) * 360.0, 1e-9);
}

TEST(TreeTemplate, IdsAreStableUnderDeletionAndOverridesSurvive)
{
  TreeParameters s = Preset(1);
  Tree full;
  ASSERT_EQ(BuildTree(s, {}, full), "");
  // Branch 2 is the trunk's first child's first child (preorder): it has 1 + 8 + 64 = 73 branches below and with it.
  s.deletedBranches = { 2 };
  s.overrides[600].length = 3.0;
  s.overrides[600].angle = 80.0;
  Tree edited;
  ASSERT_EQ(BuildTree(s, {}, edited), "");
  EXPECT_EQ(edited.branches.size(), full.branches.size() - 73);
  const auto before = ById(full), after = ById(edited);
  const TreeBranch* two = before.at(2);
  for (const auto& [id, b] : before)
  {
    bool inDeleted = false;
    for (int a = id; a >= 0; a = before.at(a)->parentId)
      inDeleted = inDeleted || a == 2;
    EXPECT_EQ(after.count(id) == 0, inDeleted) << id;
    const bool underOverride = [&] {
      for (int a = id; a >= 0; a = before.at(a)->parentId)
        if (a == 600)
          return true;
      return false;
    }();
    if (!inDeleted && !underOverride)
    {
      // Same id, same branch: bit-identical geometry.
      EXPECT_EQ(after.at(id)->centre, b->centre) << id;
    }
  }
  (void)two;
  EXPECT_DOUBLE_EQ(after.at(600)->length, 3.0);
  EXPECT_DOUBLE_EQ(after.at(600)->angle, 80.0);
  // Children derive from the overridden length.
  for (const auto& b : edited.branches)
  {
    if (b.parentId == 600)
    {
      EXPECT_NEAR(b.length, 3.0 * (1.0 - 0.618 * b.position) * (b.level == 0 ? 1.2 : 1.0), 1e-12);
    }
  }
  // Deleting the trunk leaves nothing.
  s.deletedBranches = { 0 };
  ASSERT_EQ(BuildTree(s, {}, edited), "");
  EXPECT_TRUE(edited.branches.empty());
}

TEST(BranchTubes, TemplateTreeSurfaceIsClosedManifoldAndOutward)
{
  for (int preset = 1; preset <= 2; ++preset)
  {
    TreeParameters s = Preset(preset);
    s.depth = preset == 1 ? 2 : 4;
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    TubeMesh mesh;
    ASSERT_EQ(BuildTubes(TubesOf(tree), s.sides, mesh), "");
    EXPECT_EQ(ClosedManifoldFailures(mesh), 0);
    for (std::size_t t = 0; t < tree.branches.size(); ++t)
    {
      // A straight tapering tube is a frustum of a hexagonal pyramid: V = A(r0) h (1 + q + q^2) / 3, q = r1 / r0.
      // That is exact for the trunk; a child's base ring is seated on its parent (its volume is checked against
      // the frustum's bounds: more than the part outside the parent, less than the frustum extended into it).
      const TreeBranch& b = tree.branches[t];
      const double q = b.radiusEnd / b.radius;
      const double expected = PolygonArea(6, b.radius) * (b.length * (1.0 + q + q * q) / 3.0);
      if (b.parentId < 0)
        EXPECT_NEAR(Volume(mesh, t), expected, 1e-9 * expected) << b.id;
      else
        EXPECT_GT(Volume(mesh, t), 0.0) << b.id;
    }
  }
}

TEST(BranchTubes, BentTubeRingsLieOnBothCylindersAndVolumeIsExact)
{
  // A polyline with bends of 30, 60 and 90 degrees in different planes; constant radius.
  const double r = 0.3;
  std::vector<Eigen::Vector3d> c = { { 0, 0, 0 } };
  for (const Eigen::Vector3d& d :
    { Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(std::sin(30 * Degree), std::cos(30 * Degree), 0),
      Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1) })
    c.push_back(c.back() + 2.0 * d);
  TubeInput input{ c, std::vector<double>(c.size(), r), Eigen::Vector3d::UnitX() };
  TubeMesh mesh;
  ASSERT_EQ(BuildTubes({ input }, 8, mesh), "");
  EXPECT_EQ(ClosedManifoldFailures(mesh), 0);
  double length = 0.0;
  for (std::size_t k = 1; k < c.size(); ++k)
    length += (c[k] - c[k - 1]).norm();
  // Mitre joints neither add nor remove volume: V = polygon area * centre-line length, exactly.
  EXPECT_NEAR(Volume(mesh, 0), PolygonArea(8, r) * length, 1e-12 * length);
  // Every ring vertex at an interior point is at distance r from both segments' axes (no gap, no overlap).
  const auto lineDistance = [](const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d d = (b - a).normalized();
    return ((p - a) - (p - a).dot(d) * d).norm();
  };
  for (std::size_t k = 1; k + 1 < c.size(); ++k)
  {
    for (int j = 0; j < 8; ++j)
    {
      const std::size_t i = 1 + k * 8 + std::size_t(j);
      const Eigen::Vector3d p(mesh.points[3 * i], mesh.points[3 * i + 1], mesh.points[3 * i + 2]);
      EXPECT_NEAR(lineDistance(p, c[k - 1], c[k]), r, 1e-12);
      EXPECT_NEAR(lineDistance(p, c[k], c[k + 1]), r, 1e-12);
    }
  }
  // Rings do not cross: each ring's vertices lie strictly ahead of the previous ring's mitre plane.
  const auto tangents = [&](std::size_t k) {
    if (k == 0)
      return Eigen::Vector3d((c[1] - c[0]).normalized());
    if (k + 1 == c.size())
      return Eigen::Vector3d((c[k] - c[k - 1]).normalized());
    return Eigen::Vector3d(((c[k] - c[k - 1]).normalized() + (c[k + 1] - c[k]).normalized()).normalized());
  };
  for (std::size_t k = 0; k + 1 < c.size(); ++k)
    for (int j = 0; j < 8; ++j)
    {
      const std::size_t i = 1 + (k + 1) * 8 + std::size_t(j);
      const Eigen::Vector3d p(mesh.points[3 * i], mesh.points[3 * i + 1], mesh.points[3 * i + 2]);
      EXPECT_GT((p - c[k]).dot(tangents(k)), 0.0);
    }
}

TEST(BranchTubes, RejectsBadTubes)
{
  TubeMesh mesh;
  EXPECT_NE(BuildTubes({ TubeInput{ { { 0, 0, 0 }, { 0, 0, 0 } }, { 1, 1 }, Eigen::Vector3d::UnitX() } }, 6, mesh), "");
  EXPECT_NE(
    BuildTubes({ TubeInput{ { { 0, 0, 0 }, { 0, NAN, 0 } }, { 1, 1 }, Eigen::Vector3d::UnitX() } }, 6, mesh), "");
  EXPECT_NE(BuildTubes({ TubeInput{ { { 0, 0, 0 }, { 0, 1, 0 } }, { 1, 1 }, Eigen::Vector3d::UnitX() } }, 2, mesh), "");
  EXPECT_EQ(mesh.PointCount(), 0u);
}

namespace
{
TreeParameters StrokeParameters()
{
  TreeParameters s;
  s.mode = TreeMode::Strokes;
  s.strokesOnly = true;
  s.leaves = false;
  s.segmentsPerBranch = 16;
  return s;
}

using tree_test::Line;
using tree_test::SampleStrokes;
} // namespace

TEST(TreeStrokes, LiftedBranchesProjectOntoTheirStrokesWithEq3Lengths)
{
  const TreeParameters s = StrokeParameters();
  const auto strokes = SampleStrokes();
  Tree tree;
  ASSERT_EQ(BuildTree(s, strokes, tree), "");
  ASSERT_EQ(tree.branches.size(), strokes.size());
  ASSERT_EQ(tree.strokes.size(), strokes.size());
  const auto byId = ById(tree);
  for (std::size_t k = 0; k < strokes.size(); ++k)
  {
    const StrokeReport& r = tree.strokes[k];
    const TreeBranch& b = *byId.at(r.branchId);
    // The smoothed stroke: control points by the index rule, the first replaced by the attachment point C.
    std::vector<Eigen::Vector2d> controls;
    for (int i : StrokeControlIndices(int(strokes[k].size()), s.strokeControlPoints))
      controls.push_back(strokes[k][std::size_t(i)].head<2>());
    controls[0] = b.centre[0].head<2>();
    const auto q = SampleBezier<2>(controls, s.segmentsPerBranch);
    // Every sample lifts to a centre point straight above it; the other centre points are attachment points of
    // later strokes, inserted on the segments (checked below).
    std::size_t matched = 0;
    for (const auto& point : b.centre)
    {
      const auto exact = std::find_if(
        q.begin(), q.end(), [&](const Eigen::Vector2d& sample) { return (point.head<2>() - sample).norm() < 1e-9; });
      matched += exact != q.end();
    }
    EXPECT_EQ(matched, q.size()) << k;
    for (std::size_t i = 0; i < b.centre.size(); ++i)
    {
      // Every centre point projects onto the smoothed stroke.
      double best = 1e300;
      for (std::size_t m = 0; m + 1 < q.size(); ++m)
      {
        // |AP - mu AB| with mu clamped: no cancellation (eq. (2)'s sqrt(AP^2 - (AP.AB)^2/AB^2) loses digits).
        const Eigen::Vector2d ab = q[m + 1] - q[m], ap = b.centre[i].head<2>() - q[m];
        const double mu = std::clamp(ap.dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        best = std::min(best, (ap - mu * ab).norm());
      }
      EXPECT_LT(best, 1e-9) << k << " " << i;
    }
    double eq3 = 0.0;
    // Length: eq. (3) per segment with the chosen theta, |l2|^2 = |l1 x l3|^2 / cos^2 + (l3.l1)^2, l1 = e_y.
    for (std::size_t i = 0; i + 1 < q.size(); ++i)
    {
      const Eigen::Vector3d l3(q[i + 1].x() - q[i].x(), q[i + 1].y() - q[i].y(), 0.0);
      const Eigen::Vector3d l1 = Eigen::Vector3d::UnitY();
      const double c = std::cos(r.theta * Degree);
      eq3 += std::sqrt(l1.cross(l3).squaredNorm() / (c * c) + std::pow(l3.dot(l1), 2));
    }
    EXPECT_NEAR(b.length, eq3, 1e-9 * eq3);
    // The lifted branch lies in the plane through C's vertical turned by theta: z - zC = (x - xC) tan(phi).
    for (const auto& p : b.centre)
      EXPECT_NEAR(p.z() - b.centre[0].z(), (p.x() - b.centre[0].x()) * std::tan(r.rotation * Degree), 1e-9);
    if (k == 0)
    {
      EXPECT_EQ(r.parentId, -1);
      EXPECT_EQ(b.depth, 0);
      continue;
    }
    // Attachment: C is a vertex of the parent's centre line.
    const TreeBranch& p = *byId.at(r.parentId);
    bool onParent = false;
    for (const auto& x : p.centre)
      onParent = onParent || x == b.centre[0];
    EXPECT_TRUE(onParent) << k;
  }
  EXPECT_EQ(tree.strokes[1].parentId, 0);
  EXPECT_EQ(tree.strokes[2].parentId, 0);
  EXPECT_EQ(tree.strokes[3].parentId, tree.strokes[1].branchId); // (2, 7.8) is nearest stroke 1
}

TEST(TreeStrokes, ChosenAngleIsAPhyllotaxisAngleFromTheRightQuadrantsAndBestOfItsNeighbours)
{
  for (int a = 1; a <= 5; ++a)
  {
    for (int bb : { 3, 5, 8, 13 })
    {
      TreeParameters s = StrokeParameters();
      s.phyllotaxisA = a;
      s.phyllotaxisB = bb;
      Tree tree;
      ASSERT_EQ(BuildTree(s, SampleStrokes(), tree), "");
      const auto byId = ById(tree);
      for (std::size_t k = 1; k < tree.strokes.size(); ++k)
      {
        const StrokeReport& r = tree.strokes[k];
        const TreeBranch& b = *byId.at(r.branchId);
        const bool minusX = b.centre.back().x() < b.centre.front().x();
        // Candidates by brute force.
        std::vector<std::pair<double, double>> candidates;
        for (int i = 1; i <= bb; ++i)
        {
          const double phi = Frac(double(i) * a / bb) * 360.0;
          const int quadrant = int(phi / 90.0);
          const double theta = quadrant == 0 ? phi : quadrant == 1 ? 180 - phi : quadrant == 2 ? phi - 180 : 360 - phi;
          if ((minusX ? (quadrant == 1 || quadrant == 2) : (quadrant == 0 || quadrant == 3)) && theta < 90.0 - 1e-9)
            candidates.push_back({ theta, phi });
        }
        if (candidates.empty())
        {
          EXPECT_EQ(r.theta, 0.0);
          continue;
        }
        bool isCandidate = false;
        for (const auto& c : candidates)
          isCandidate = isCandidate || (std::abs(c.second - r.rotation) < 1e-9 && std::abs(c.first - r.theta) < 1e-9);
        EXPECT_TRUE(isCandidate) << a << "/" << bb << " stroke " << k << " phi " << r.rotation;
        // theta* solves |l2| = L* (or is 0 when the stroke is already long enough).
        const double planar = r.planarLength;
        const double length = [&] {
          std::vector<Eigen::Vector2d> q;
          for (const auto& p : b.centre)
            q.push_back(p.head<2>());
          return LiftedLength(q, r.recommendedTheta * Degree);
        }();
        if (r.targetLength <= planar)
        {
          EXPECT_EQ(r.recommendedTheta, 0.0);
        }
        else
        {
          EXPECT_NEAR(length, r.targetLength, 1e-9 * r.targetLength);
        }
        // Best of the nearest candidates either side of theta* by relative length error.
        std::vector<Eigen::Vector2d> q;
        for (const auto& p : b.centre)
          q.push_back(p.head<2>());
        const auto err = [&](double theta) {
          return std::abs(LiftedLength(q, theta * Degree) - r.targetLength) / r.targetLength;
        };
        double below = -1, above = 1e9;
        for (const auto& c : candidates)
        {
          if (c.first <= r.recommendedTheta && c.first > below)
            below = c.first;
          if (c.first >= r.recommendedTheta && c.first < above)
            above = c.first;
        }
        double best = below < 0 ? above : above > 1e8 ? below : (err(above) < err(below) ? above : below);
        if (std::abs(below - r.recommendedTheta) <= 1e-9)
          best = below;
        EXPECT_NEAR(r.theta, best, 1e-9) << a << "/" << bb << " stroke " << k;
      }
    }
  }
  // Target length follows epsilon: 0.6 of the parent monopodial, 0.8 sympodial.
  TreeParameters s = StrokeParameters();
  Tree tree;
  ASSERT_EQ(BuildTree(s, SampleStrokes(), tree), "");
  EXPECT_NEAR(tree.strokes[1].targetLength, 0.6 * tree.branches[0].length, 1e-12);
  s.type = TreeType::Sympodial;
  ASSERT_EQ(BuildTree(s, SampleStrokes(), tree), "");
  EXPECT_NEAR(tree.strokes[1].targetLength, 0.8 * tree.branches[0].length, 1e-12);
}

TEST(TreeStrokes, Eq2DistanceAndEq1Angle)
{
  double mu = 0;
  EXPECT_DOUBLE_EQ(PointSegmentDistance({ -3, 4 }, { 0, 0 }, { 10, 0 }, mu), 5.0);
  EXPECT_EQ(mu, 0.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({ 13, 4 }, { 0, 0 }, { 10, 0 }, mu), 5.0);
  EXPECT_EQ(mu, 1.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({ 4, -3 }, { 0, 0 }, { 10, 0 }, mu), 3.0);
  EXPECT_DOUBLE_EQ(mu, 0.4);
  EXPECT_NEAR(SignedSegmentAngle({ 0, 1 }, { 1, 1 }), 45.0, 1e-12); // turning right: (b x a).z > 0
  EXPECT_NEAR(SignedSegmentAngle({ 0, 1 }, { -1, 1 }), -45.0, 1e-12);
}

TEST(TreeStrokes, TemplateSubtreesGrowOnStrokeBranchesAndInsertedPointsSplitParents)
{
  TreeParameters s = StrokeParameters();
  s.strokesOnly = false;
  s.strokeSubtreeDepth = 2;
  s.childCount = 3;
  Tree tree;
  ASSERT_EQ(BuildTree(s, SampleStrokes(), tree), "");
  EXPECT_EQ(tree.branches.size(), SampleStrokes().size() * SubtreeSize(3, 2));
  // Stroke k has id k * 13.
  for (std::size_t k = 0; k < tree.strokes.size(); ++k)
    EXPECT_EQ(tree.strokes[k].branchId, int(k) * 13);
  // The trunk got two attachment points inserted (strokes 1 and 2 attach inside segments).
  const auto byId = ById(tree);
  EXPECT_EQ(byId.at(0)->centre.size(), std::size_t(s.segmentsPerBranch + 1 + 2));
  TubeMesh mesh;
  ASSERT_EQ(BuildTubes(TubesOf(tree), 6, mesh), "");
  EXPECT_EQ(ClosedManifoldFailures(mesh), 0);
}

TEST(TreeStrokes, TiesAreBrokenByTheSeedReproducibly)
{
  // Strokes 1 and 2 start at the trunk's tip: stroke 2 is at distance 0 from both the trunk and stroke 1.
  const std::vector<std::vector<Eigen::Vector3d>> strokes = { Line({ { 0, 0 }, { 0, 10 } }),
    Line({ { 0, 10 }, { 3, 13 } }), Line({ { 0, 10 }, { -3, 12 } }) };
  std::set<int> parents;
  for (std::uint64_t seed = 0; seed < 32; ++seed)
  {
    TreeParameters s = StrokeParameters();
    s.seed = seed;
    Tree a, b;
    ASSERT_EQ(BuildTree(s, strokes, a), "");
    ASSERT_EQ(BuildTree(s, strokes, b), "");
    EXPECT_EQ(a.strokes[2].parentId, b.strokes[2].parentId);
    EXPECT_EQ(a.strokes[2].distance, 0.0);
    parents.insert(a.strokes[2].parentId);
  }
  EXPECT_EQ(parents, (std::set<int>{ 0, 1 }));
}

TEST(TreeStrokes, BadStrokesGiveErrorsNamingTheInput)
{
  TreeParameters s = StrokeParameters();
  Tree tree;
  EXPECT_NE(BuildTree(s, {}, tree).find("Strokes input"), std::string::npos);
  auto strokes = SampleStrokes();
  strokes[2] = Line({ { 1, 1 } });
  std::string error = BuildTree(s, strokes, tree);
  EXPECT_NE(error.find("stroke 2"), std::string::npos) << error;
  EXPECT_TRUE(tree.branches.empty());
  strokes[2] = Line({ { 1, 1 }, { NAN, 2 } });
  error = BuildTree(s, strokes, tree);
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
  strokes[2] = {};
  EXPECT_NE(BuildTree(s, strokes, tree), "");
  strokes[2] = Line({ { 1, 1 }, { 1, 1 } });
  EXPECT_NE(BuildTree(s, strokes, tree).find("zero length"), std::string::npos);
}

TEST(TreeStrokes, ParsesCsvAndSvg)
{
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  ASSERT_EQ(ParseStrokeCsv("stroke_id,x,y\n7,0,0\n7,0,1\n3,0.5,0.5\n7,0.1,2\n3,1,1\n", strokes), "");
  ASSERT_EQ(strokes.size(), 2u);
  EXPECT_EQ(strokes[0].size(), 3u);
  EXPECT_EQ(strokes[0][2], Eigen::Vector3d(0.1, 2, 0));
  EXPECT_EQ(strokes[1][1], Eigen::Vector3d(1, 1, 0));
  EXPECT_NE(ParseStrokeCsv("id,x,y\n1,0,0\n1,abc,2\n", strokes), "");
  ASSERT_EQ(ParseStrokeSvg("<svg><polyline points=\"0,0 1,-2 3,-4\"/><path d=\"M 1 1 L 2 2 l 1 0 M 5 5 h 2\"/>"
                           "</svg>",
              strokes),
    "");
  ASSERT_EQ(strokes.size(), 3u);
  EXPECT_EQ(strokes[0][1], Eigen::Vector3d(1, 2, 0)); // y flipped
  EXPECT_EQ(strokes[1].size(), 3u);
  EXPECT_EQ(strokes[1][2], Eigen::Vector3d(3, -2, 0));
  EXPECT_EQ(strokes[2][1], Eigen::Vector3d(7, -5, 0));
}

TEST(TreeLeaves, LeavesSitOnTwigSurfacesWithPhyllotaxis)
{
  TreeParameters s = Preset(2);
  s.depth = 3;
  s.leaves = true;
  s.leafCount = 5;
  Tree tree;
  ASSERT_EQ(BuildTree(s, {}, tree), "");
  const auto byId = ById(tree);
  long long twigs = 0;
  for (const auto& b : tree.branches)
    twigs += b.level == 0;
  EXPECT_EQ(twigs, 27);
  ASSERT_EQ(static_cast<long long>(tree.leaves.size()), twigs * 5);
  for (std::size_t n = 0; n < tree.leaves.size(); ++n)
  {
    const TreeLeaf& leaf = tree.leaves[n];
    const TreeBranch& twig = *byId.at(leaf.branchId);
    EXPECT_EQ(twig.level, 0);
    const int j = int(n % 5) + 1;
    const double pos = (1.0 - s.leafRatio) + j * s.leafRatio / 5;
    const Eigen::Vector3d axis = twig.centre.front() + pos * (twig.centre.back() - twig.centre.front());
    const Eigen::Vector3d offset = leaf.origin - axis;
    EXPECT_NEAR(offset.dot(twig.frame.col(1)), 0.0, 1e-12);
    EXPECT_NEAR(offset.norm(), twig.radius + pos * (twig.radiusEnd - twig.radius), 1e-12);
    EXPECT_LT((leaf.axes.transpose() * leaf.axes - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(std::acos(leaf.axes.col(1).dot(twig.frame.col(1))) / Degree, s.leafAngle, 1e-9);
  }
  // Willow: every twig becomes the pendulous Bezier curve, scaled by its length.
  s.leafType = LeafType::Willow;
  Tree willow;
  ASSERT_EQ(BuildTree(s, {}, willow), "");
  const auto willowById = ById(willow);
  for (const auto& b : willow.branches)
  {
    if (b.level != 0)
      continue;
    const TreeBranch& straight = *byId.at(b.id);
    EXPECT_EQ(b.centre.front(), straight.centre.front());
    const Eigen::Vector3d drop = b.centre.back() - b.centre.front();
    EXPECT_NEAR(drop.y(), -0.8 * straight.length, 1e-12);
    EXPECT_NEAR(Eigen::Vector2d(drop.x(), drop.z()).norm(), 0.1 * straight.length, 1e-12);
  }
  (void)willowById;
  s.leafType = LeafType::Sympodial;
  Tree whorl;
  ASSERT_EQ(BuildTree(s, {}, whorl), "");
  for (const auto& leaf : whorl.leaves)
  {
    const TreeBranch& twig = *byId.at(leaf.branchId);
    EXPECT_NEAR(((leaf.origin - twig.centre.back()).norm()), twig.radiusEnd, 1e-12);
  }
}

TEST(TreeFromSketch, SameSettingsAndStrokesGiveBitIdenticalTrees)
{
  TreeParameters s = StrokeParameters();
  s.mode = TreeMode::TemplateAndStrokes;
  s.depth = 2;
  s.strokesOnly = false;
  s.leaves = true;
  s.seed = 42;
  Tree a, b;
  ASSERT_EQ(BuildTree(s, SampleStrokes(), a), "");
  ASSERT_EQ(BuildTree(s, SampleStrokes(), b), "");
  ASSERT_EQ(a.branches.size(), b.branches.size());
  for (std::size_t i = 0; i < a.branches.size(); ++i)
  {
    ASSERT_EQ(a.branches[i].centre.size(), b.branches[i].centre.size());
    EXPECT_EQ(0,
      std::memcmp(a.branches[i].centre.data(), b.branches[i].centre.data(),
        a.branches[i].centre.size() * sizeof(Eigen::Vector3d)));
  }
  TubeMesh ma, mb;
  ASSERT_EQ(BuildTubes(TubesOf(a), 6, ma), "");
  // Parallel build (uneven chunks) gives the same bytes as the serial one.
  ASSERT_EQ(BuildTubes(TubesOf(b), 6, mb,
              [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
                for (std::size_t begin = 0; begin < count; begin += 7)
                  body(begin, std::min(count, begin + 7));
              }),
    "");
  EXPECT_EQ(ma.points, mb.points);
  EXPECT_EQ(ma.triangles, mb.triangles);
  EXPECT_EQ(a.leaves.size(), b.leaves.size());
}

TEST(TreeFromSketch, BadSettingsNameTheProperty)
{
  Tree tree;
  TreeParameters s;
  s.length = -1;
  EXPECT_NE(BuildTree(s, {}, tree).find("Length"), std::string::npos);
  s = TreeParameters();
  s.ratio = NAN;
  EXPECT_NE(BuildTree(s, {}, tree).find("Ratio"), std::string::npos);
  s = TreeParameters();
  s.depth = 8; // 8^9 branches
  EXPECT_NE(BuildTree(s, {}, tree).find("MaxSegments"), std::string::npos);
  EXPECT_TRUE(tree.branches.empty());
  s = TreeParameters();
  s.overrides[3].radius = -2;
  EXPECT_NE(BuildTree(s, {}, tree).find("BranchOverrides"), std::string::npos);
}

// ---- Joints: a child's base ring sits on its parent's faceted surface --------------------------------------------

namespace
{
Eigen::Vector3d MeshPoint(const TubeMesh& mesh, std::int64_t i)
{
  const std::size_t k = 3 * std::size_t(i);
  return Eigen::Vector3d(mesh.points[k], mesh.points[k + 1], mesh.points[k + 2]);
}

/// Distance from p to triangle abc (closest point by Voronoi regions, Ericson's Real-Time Collision Detection 5.1.5).
double TriangleDistance(
  const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0)
    return (p - a).norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3)
    return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6)
    return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denominator = 1.0 / (va + vb + vc);
  return (p - (a + ab * vb * denominator + ac * vc * denominator)).norm();
}

/// Distance from p to tube t's surface, and its winding number (1 inside, 0 outside; Van Oosterom-Strackee).
void Locate(const TubeMesh& mesh, std::size_t t, const Eigen::Vector3d& p, double& distance, double& winding)
{
  distance = 1e300;
  winding = 0.0;
  for (auto f = mesh.triangleOffsets[t]; f < mesh.triangleOffsets[t + 1]; ++f)
  {
    const int* v = &mesh.triangles[3 * std::size_t(f)];
    const Eigen::Vector3d a = MeshPoint(mesh, v[0]), b = MeshPoint(mesh, v[1]), c = MeshPoint(mesh, v[2]);
    distance = std::min(distance, TriangleDistance(p, a, b, c));
    const Eigen::Vector3d x = a - p, y = b - p, z = c - p;
    const double nx = x.norm(), ny = y.norm(), nz = z.norm();
    winding += 2.0 * std::atan2(x.dot(y.cross(z)), nx * ny * nz + x.dot(y) * nz + y.dot(z) * nx + z.dot(x) * ny);
  }
  winding /= 4.0 * Pi;
}

struct JointCheck
{
  int ringOnSurface = 0, ringOff = 0, ringInside = 0, insideParent = 0, capInsideOrOn = 0, capOutside = 0;
  double widestLedge = 0.0; ///< largest distance of an unseated ring vertex from the parent, over the child radius
};

/// For every child tube: its base-ring vertices' distance to the parent's surface; every other vertex (rings >= 1,
/// tip) must not be inside the parent (winding > 0.5 and farther than `tolerance` from its surface).
JointCheck CheckJoints(const Tree& tree, const TubeMesh& mesh, int sides, double tolerance)
{
  JointCheck check;
  const std::vector<TubeInput> tubes = TreeTubeInputs(tree);
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    if (tubes[t].parent < 0)
      continue;
    const std::size_t parent = std::size_t(tubes[t].parent);
    for (auto i = mesh.pointOffsets[t]; i < mesh.pointOffsets[t + 1]; ++i)
    {
      double distance = 0.0, winding = 0.0;
      Locate(mesh, parent, MeshPoint(mesh, i), distance, winding);
      const auto local = i - mesh.pointOffsets[t];
      if (local == 0)
      {
        (winding > 0.5 || distance <= tolerance ? check.capInsideOrOn : check.capOutside)++;
      }
      else if (local <= sides)
      {
        (distance <= tolerance ? check.ringOnSurface : check.ringOff)++;
        if (distance > tolerance)
        {
          check.ringInside += winding > 0.5;
          check.widestLedge = std::max(check.widestLedge, distance / tree.branches[t].radius);
        }
      }
      else if (winding > 0.5 && distance > tolerance)
      {
        ++check.insideParent;
      }
    }
  }
  return check;
}
} // namespace

TEST(BranchTubes, ChildBaseRingsSitOnTheParentSurfaceNeitherBuriedNorFloating)
{
  // Table 1's monopodial templates (depth 2 to keep the brute-force checks short) and a stroke tree with subtrees.
  for (int preset : { 1, 3 })
  {
    TreeParameters s = Preset(preset);
    s.depth = 2;
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    TubeMesh mesh;
    JointReport joints;
    ASSERT_EQ(BuildTubes(TubesOf(tree), s.sides, mesh, SerialFor, &joints), "");
    EXPECT_EQ(ClosedManifoldFailures(mesh), 0);
    const std::int64_t children = std::int64_t(tree.branches.size()) - 1;
    EXPECT_EQ(joints.seated + joints.missed, children * s.sides) << preset;
    EXPECT_EQ(joints.clamped + joints.buried, 0) << preset;
    const JointCheck check = CheckJoints(tree, mesh, s.sides, 1e-9);
    // Seated vertices are on the parent's faceted surface; the others (their line misses the parent: these
    // children are wider than the parent there) are outside it, within a child radius of it. Nothing is buried.
    EXPECT_EQ(check.ringOnSurface, joints.seated) << preset;
    EXPECT_EQ(check.ringOff, joints.missed) << preset;
    EXPECT_EQ(check.ringInside, 0) << preset;
    EXPECT_LT(check.widestLedge, 1.0) << preset;
    EXPECT_EQ(check.insideParent, 0) << preset;
    EXPECT_EQ(check.capOutside, 0) << preset;
    EXPECT_GT(joints.seated, children) << preset;
    std::printf("preset %d depth 2: ring vertices seated %lld, missed %lld; widest ledge %.9f child radii\n", preset,
      static_cast<long long>(joints.seated), static_cast<long long>(joints.missed), check.widestLedge);
  }
}

TEST(BranchTubes, JointsThatCannotBeSeatedAreCountedNotHidden)
{
  // Sympodial forks sit at the parent's capped tip: part of each child's base ring hangs past the cap and meets
  // the parent nowhere. Those vertices are counted as missed; every vertex that was seated is on the surface, and
  // still no vertex beyond the base ring is inside the parent.
  TreeParameters s = Preset(2);
  s.depth = 3;
  Tree tree;
  ASSERT_EQ(BuildTree(s, {}, tree), "");
  TubeMesh mesh;
  JointReport joints;
  ASSERT_EQ(BuildTubes(TubesOf(tree), s.sides, mesh, SerialFor, &joints), "");
  EXPECT_EQ(ClosedManifoldFailures(mesh), 0);
  const JointCheck check = CheckJoints(tree, mesh, s.sides, 1e-9);
  EXPECT_EQ(check.ringOnSurface, joints.seated);
  EXPECT_EQ(check.ringInside, joints.clamped + joints.buried);
  EXPECT_EQ(
    joints.seated + joints.missed + joints.clamped + joints.buried, std::int64_t(tree.branches.size() - 1) * s.sides);
  std::printf("sympodial depth 3: ring vertices seated %lld, missed %lld, clamped %lld, buried %lld; "
              "vertices beyond the ring inside the parent %d\n",
    static_cast<long long>(joints.seated), static_cast<long long>(joints.missed),
    static_cast<long long>(joints.clamped), static_cast<long long>(joints.buried), check.insideParent);
  EXPECT_GT(joints.seated, 0);
}

// ---- Merging a second tree (docs/methods/tree-from-sketch.md; paper 004 sec. 3.2, Fig. 11) -----------------------

namespace
{
Tree SecondTree()
{
  TreeParameters s = Preset(2); // sympodial, curved-free but branching at the tips
  s.depth = 2;
  Tree tree;
  EXPECT_EQ(BuildTree(s, {}, tree), "");
  return tree;
}
} // namespace

TEST(TreeMerge, BranchCountIsTheSumAndMergedGeometryIsTheSecondTreeUnderTheStatedSimilarity)
{
  const Tree second = SecondTree();
  const auto skeleton = SkeletonOf(second);
  TreeParameters s = Preset(1);
  s.depth = 2;
  Tree alone;
  ASSERT_EQ(BuildTree(s, {}, alone), "");
  MergeOntoBranch3(s); // a child of the trunk
  Tree merged;
  ASSERT_EQ(BuildTree(s, {}, &skeleton, merged), "");
  ASSERT_EQ(merged.branches.size(), alone.branches.size() + second.branches.size());
  ASSERT_EQ(merged.mergeIdBase, SubtreeSize(8, 2)); // 73: the first id the template never uses
  // This tree's own branches are untouched, bit for bit.
  for (std::size_t i = 0; i < alone.branches.size(); ++i)
  {
    EXPECT_EQ(merged.branches[i].id, alone.branches[i].id);
    EXPECT_TRUE(merged.branches[i].centre == alone.branches[i].centre);
  }
  const auto byId = ById(merged);
  const TreeBranch& host = *byId.at(3);
  // Expected placement, written out from the formulas: the host is straight, its frame constant, its radius linear.
  const Eigen::Matrix3d R = host.frame * RotationY(70.0) * RotationZ(40.0);
  const Eigen::Vector3d axisPoint = host.centre.front() + 0.3 * (host.centre.back() - host.centre.front());
  const double hostRadius = host.radius + 0.3 * (host.radiusEnd - host.radius);
  const Eigen::Vector3d outward = host.frame * Eigen::Vector3d(-std::cos(70 * Degree), 0, std::sin(70 * Degree));
  const Eigen::Vector3d target = axisPoint + hostRadius * outward;
  const Eigen::Vector3d rootBase = second.branches[0].centre[0];
  for (const TreeBranch& original : second.branches)
  {
    const TreeBranch& b = *byId.at(int(merged.mergeIdBase) + original.id);
    EXPECT_EQ(b.mergedId, original.id);
    EXPECT_EQ(b.parentId, original.parentId < 0 ? 3 : int(merged.mergeIdBase) + original.parentId);
    EXPECT_EQ(b.depth, host.depth + 1 + original.depth);
    ASSERT_EQ(b.centre.size(), original.centre.size());
    for (std::size_t k = 0; k < b.centre.size(); ++k)
    {
      const Eigen::Vector3d expected = target + 0.5 * R * (original.centre[k] - rootBase);
      EXPECT_LT((b.centre[k] - expected).norm(), 1e-12) << b.id << " " << k;
      EXPECT_NEAR(b.radii[k], 0.5 * original.radii[k], 1e-15);
    }
  }
  // Oracle independent of R: the merged root starts on the host's surface, diverges 40 degrees from it, turned 70
  // degrees about it; the similarity halves every distance.
  const TreeBranch& root = *byId.at(int(merged.mergeIdBase));
  const Eigen::Vector3d d = (root.centre[1] - root.centre[0]).normalized();
  const Eigen::Vector3d local = host.frame.transpose() * d;
  EXPECT_NEAR(std::acos(local.y()) / Degree, 40.0, 1e-9);
  EXPECT_NEAR(std::atan2(local.z(), -local.x()) / Degree, 70.0, 1e-9);
  const Eigen::Vector3d fromAxis = root.centre[0] - host.centre[0];
  const Eigen::Vector3d along = host.frame.col(1);
  EXPECT_NEAR(fromAxis.dot(along) / host.length, 0.3, 1e-12);
  EXPECT_NEAR((fromAxis - fromAxis.dot(along) * along).norm(), hostRadius, 1e-12);
  const TreeBranch& twig = merged.branches.back();
  const TreeBranch& twigSource = second.branches.back();
  EXPECT_NEAR((twig.centre.back() - root.centre[0]).norm(), 0.5 * (twigSource.centre.back() - rootBase).norm(), 1e-12);
}

TEST(TreeMerge, SecondTrunkStandsAtTheOffsetTurnedAboutY)
{
  const Tree second = SecondTree();
  const auto skeleton = SkeletonOf(second);
  TreeParameters s = Preset(1);
  s.depth = 1;
  s.mergeParent = -1;
  s.mergeOffset = Eigen::Vector3d(5.0, 0.0, 2.0);
  s.mergeRotation = 90.0;
  s.mergeAngle = 0.0;
  Tree merged;
  ASSERT_EQ(BuildTree(s, {}, &skeleton, merged), "");
  const auto byId = ById(merged);
  for (const TreeBranch& original : second.branches)
  {
    const TreeBranch& b = *byId.at(int(merged.mergeIdBase) + original.id);
    if (original.parentId < 0)
    {
      EXPECT_EQ(b.parentId, -1);
      EXPECT_EQ(b.depth, 0);
    }
    for (std::size_t k = 0; k < b.centre.size(); ++k)
    {
      // R_y(90): (x, y, z) -> (z, y, -x).
      const Eigen::Vector3d x = original.centre[k] - second.branches[0].centre[0];
      EXPECT_LT((b.centre[k] - (s.mergeOffset + Eigen::Vector3d(x.z(), x.y(), -x.x()))).norm(), 1e-12);
    }
  }
}

TEST(TreeMerge, MergedIdsAreStableUnderEditsAndAddressableByDeletionsAndOverrides)
{
  const Tree second = SecondTree();
  const auto skeleton = SkeletonOf(second);
  TreeParameters s = Preset(1);
  s.depth = 2;
  s.mergeParent = 0;
  Tree merged;
  ASSERT_EQ(BuildTree(s, {}, &skeleton, merged), "");
  const int base = int(merged.mergeIdBase);
  // Deleting this tree's branches does not renumber merged ones (and vice versa).
  TreeParameters edited = s;
  edited.deletedBranches = { 1, 10, base + 1 }; // two template children, one merged child with its subtree
  Tree after;
  ASSERT_EQ(BuildTree(edited, {}, &skeleton, after), "");
  EXPECT_EQ(after.mergeIdBase, base);
  const auto before = ById(merged), now = ById(after);
  long long removedMerged = 0;
  for (const auto& [id, b] : before)
  {
    if (b->mergedId < 0)
      continue;
    // A merged branch is gone exactly when it or an ancestor was deleted.
    bool deleted = false;
    for (int a = id; a >= base; a = before.at(a)->parentId)
      deleted = deleted || a == base + 1;
    EXPECT_EQ(now.count(id) == 0, deleted) << id;
    removedMerged += deleted;
    if (!deleted)
    {
      EXPECT_TRUE(now.at(id)->centre == b->centre) << id;
    }
  }
  EXPECT_EQ(removedMerged, SubtreeSize(3, 1));
  // Overrides: radius and length of a merged branch; its sub-branches move with its tip.
  edited = s;
  const int root = base;
  edited.overrides[root].radius = 0.9;
  edited.overrides[root].length = 2.0 * before.at(root)->length;
  ASSERT_EQ(BuildTree(edited, {}, &skeleton, after), "");
  const auto grown = ById(after);
  EXPECT_NEAR(grown.at(root)->radius, 0.9, 1e-15);
  EXPECT_NEAR(grown.at(root)->length, 2.0 * before.at(root)->length, 1e-12);
  EXPECT_NEAR(grown.at(root)->radiusEnd / 0.9, before.at(root)->radiusEnd / before.at(root)->radius, 1e-12);
  const TreeBranch& child = *grown.at(base + 1);
  const Eigen::Vector3d shift = child.centre[0] - before.at(base + 1)->centre[0];
  // Scaling the root by 2 about its base moves the child's base (on the root's tip surface) twice as far from it.
  EXPECT_LT((shift - (before.at(base + 1)->centre[0] - before.at(root)->centre[0])).norm(), 1e-12);
  for (std::size_t k = 0; k < child.centre.size(); ++k)
    EXPECT_LT((child.centre[k] - before.at(base + 1)->centre[k] - shift).norm(), 1e-12);
  // u, angle and rotation of the merged root replace MergeU, MergeAngle, MergeRotation.
  edited = s;
  edited.overrides[root].u = 0.8;
  edited.overrides[root].angle = 20.0;
  TreeParameters direct = s;
  direct.mergeU = 0.8;
  direct.mergeAngle = 20.0;
  Tree viaOverride, viaProperties;
  ASSERT_EQ(BuildTree(edited, {}, &skeleton, viaOverride), "");
  ASSERT_EQ(BuildTree(direct, {}, &skeleton, viaProperties), "");
  ASSERT_EQ(viaOverride.branches.size(), viaProperties.branches.size());
  for (std::size_t i = 0; i < viaOverride.branches.size(); ++i)
    EXPECT_TRUE(viaOverride.branches[i].centre == viaProperties.branches[i].centre);
  // On other merged branches they are refused, naming the row and where to edit instead.
  edited = s;
  edited.overrides[base + 2].angle = 10.0;
  EXPECT_NE(BuildTree(edited, {}, &skeleton, after).find("BranchOverrides row of branch " + std::to_string(base + 2)),
    std::string::npos);
  EXPECT_TRUE(after.branches.empty());
}

TEST(TreeMerge, InputThatIsNotATreeIsRefusedWithAClearMessage)
{
  const auto good = SkeletonOf(SecondTree());
  TreeParameters s = Preset(1);
  s.depth = 1;
  const auto refused = [&](std::vector<SkeletonBranch> skeleton, const std::string& why) {
    Tree tree;
    const std::string error = BuildTree(s, {}, &skeleton, tree);
    EXPECT_EQ(error.rfind("Merge input is not a tree: ", 0), 0u) << error;
    EXPECT_NE(error.find(why), std::string::npos) << error;
    EXPECT_TRUE(tree.branches.empty());
  };
  auto bad = good;
  bad[2].id = bad[1].id;
  refused(bad, "appears on more than one polyline");
  bad = good;
  bad[3].parentId = -1;
  refused(bad, "2 branches have ParentId -1");
  bad = good;
  bad[3].parentId = 999;
  refused(bad, "ParentId 999, which is no branch of it");
  bad = good;
  bad[1].parentId = bad[2].id; // 1 -> 2 and 2 -> 1: a cycle cut off from the root
  bad[2].parentId = bad[1].id;
  refused(bad, "not reachable from the root");
  bad = good;
  bad[1].radii[1] = std::nan("");
  refused(bad, "not finite");
  bad = good;
  bad[1].centre.resize(1);
  bad[1].radii.resize(1);
  refused(bad, "fewer than 2 points");
  EXPECT_NE(ValidateSkeletonIsTree({}).find("Merge input is not a tree: it has no branches"), std::string::npos);
  // A parent branch that is not there.
  s.mergeParent = 5000;
  auto fine = good;
  Tree tree;
  EXPECT_NE(BuildTree(s, {}, &fine, tree).find("MergeParentBranch = 5000 names no branch"), std::string::npos);
  s.mergeParent = 0;
  s.mergeScale = 0.0;
  EXPECT_NE(
    BuildTree(s, {}, &fine, tree).find("MergeScale = 0 is outside the accepted range (0, 1e6]"), std::string::npos);
}

// ---- BranchOverrides on stroke branches ---------------------------------------------------------------------------

TEST(TreeStrokes, OverridesApplyToStrokeBranchesAsToTemplateBranches)
{
  TreeParameters s = StrokeParameters();
  const auto strokes = SampleStrokes();
  Tree plain;
  ASSERT_EQ(BuildTree(s, strokes, plain), "");
  const auto original = ById(plain);
  const int id = plain.strokes[2].branchId; // attached to the trunk, goes to -x
  const TreeBranch& b0 = *original.at(id);
  const auto build = [&](const BranchOverride& o, Tree& tree) {
    TreeParameters edited = s;
    edited.overrides[id] = o;
    return BuildTree(edited, strokes, tree);
  };
  Tree tree;
  // All NaN: the same tree, bit for bit.
  ASSERT_EQ(build(BranchOverride(), tree), "");
  for (std::size_t i = 0; i < tree.branches.size(); ++i)
    EXPECT_TRUE(tree.branches[i].centre == plain.branches[i].centre);

  // rotation_angle: the lifting angle phi; the branch still projects onto its stroke, with eq. (3)'s length.
  BranchOverride o;
  o.rotation = 150.0;
  ASSERT_EQ(build(o, tree), "");
  {
    const TreeBranch& b = *ById(tree).at(id);
    EXPECT_EQ(tree.strokes[2].rotation, 150.0);
    EXPECT_NEAR(tree.strokes[2].theta, 30.0, 1e-12);
    std::vector<Eigen::Vector2d> planar;
    for (std::size_t k = 0; k < b.centre.size(); ++k)
    {
      EXPECT_LT((b.centre[k].head<2>() - b0.centre[k].head<2>()).norm(), 1e-12);
      EXPECT_NEAR(
        b.centre[k].z() - b.centre[0].z(), (b.centre[k].x() - b.centre[0].x()) * std::tan(150 * Degree), 1e-12);
      planar.push_back(b.centre[k].head<2>());
    }
    EXPECT_NEAR(b.length, LiftedLength(planar, 30.0 * Degree), 1e-12);
  }
  o = BranchOverride();
  o.rotation = 270.0;
  EXPECT_NE(build(o, tree).find("rotation_angle = 270"), std::string::npos);

  // length: scaled about C.
  o = BranchOverride();
  o.length = 3.0;
  ASSERT_EQ(build(o, tree), "");
  {
    const TreeBranch& b = *ById(tree).at(id);
    EXPECT_NEAR(b.length, 3.0, 1e-12);
    const double f = 3.0 / b0.length;
    for (std::size_t k = 0; k < b.centre.size(); ++k)
      EXPECT_LT((b.centre[k] - b0.centre[0] - f * (b0.centre[k] - b0.centre[0])).norm(), 1e-12);
  }

  // u: moved rigidly along the parent to arc-length fraction u, the base a vertex of the parent's centre line.
  o = BranchOverride();
  o.u = 0.25;
  ASSERT_EQ(build(o, tree), "");
  {
    const auto m = ById(tree);
    const TreeBranch& b = *m.at(id);
    const TreeBranch& parent = *m.at(b.parentId);
    EXPECT_EQ(b.position, 0.25);
    double arc = 0.0, total = 0.0, at = -1.0;
    for (std::size_t k = 0; k + 1 < parent.centre.size(); ++k)
      total += (parent.centre[k + 1] - parent.centre[k]).norm();
    for (std::size_t k = 0; k < parent.centre.size(); ++k)
    {
      if (k > 0)
        arc += (parent.centre[k] - parent.centre[k - 1]).norm();
      if (parent.centre[k] == b.centre[0])
        at = arc / total;
    }
    EXPECT_NEAR(at, 0.25, 1e-12);
    for (std::size_t k = 0; k < b.centre.size(); ++k)
      EXPECT_LT(((b.centre[k] - b.centre[0]) - (b0.centre[k] - b0.centre[0])).norm(), 1e-12);
  }

  // angle: turned about C to that divergence from the parent's tangent; distances from C kept.
  o = BranchOverride();
  o.angle = 75.0;
  ASSERT_EQ(build(o, tree), "");
  {
    const auto m = ById(tree);
    const TreeBranch& b = *m.at(id);
    Eigen::Vector3d point;
    Eigen::Matrix3d frame;
    double radius = 0.0;
    BranchFrameAt(*m.at(b.parentId), b.position, point, frame, radius);
    const Eigen::Vector3d first = (b.centre[1] - b.centre[0]).normalized();
    EXPECT_NEAR(std::acos(first.dot(frame.col(1))) / Degree, 75.0, 1e-9);
    for (std::size_t k = 0; k < b.centre.size(); ++k)
      EXPECT_NEAR((b.centre[k] - b.centre[0]).norm(), (b0.centre[k] - b0.centre[0]).norm(), 1e-12);
  }

  // The trunk stroke has no parent: u, angle and rotation_angle are ignored, as for the template trunk.
  TreeParameters trunk = s;
  trunk.overrides[plain.strokes[0].branchId] = BranchOverride{ std::nan(""), std::nan(""), 0.5, 60.0, 45.0 };
  ASSERT_EQ(BuildTree(trunk, strokes, tree), "");
  for (std::size_t i = 0; i < tree.branches.size(); ++i)
    EXPECT_TRUE(tree.branches[i].centre == plain.branches[i].centre);
}

// ---- Welded joints: one closed surface per tree (BranchJunctions.h) ----------------------------------------------

namespace
{
struct WholeSurface
{
  int edgeFailures = 0; ///< directed edges not used exactly once with their reverse used exactly once
  int components = 0;   ///< connected pieces (through shared edges)
  long long euler = 0;  ///< V - E + F over the referenced points
  double volume = 0.0;  ///< signed, divergence theorem
};

WholeSurface CheckWholeSurface(const TubeMesh& mesh)
{
  WholeSurface w;
  std::map<std::pair<int, int>, int> directed;
  const std::size_t F = mesh.TriangleCount();
  std::vector<std::size_t> root(F);
  for (std::size_t f = 0; f < F; ++f)
    root[f] = f;
  const auto find = [&](std::size_t x) {
    while (root[x] != x)
      x = root[x] = root[root[x]];
    return x;
  };
  std::map<std::pair<int, int>, std::size_t> firstFace;
  std::set<int> used;
  for (std::size_t f = 0; f < F; ++f)
  {
    const int* v = &mesh.triangles[3 * f];
    w.volume += MeshPoint(mesh, v[0]).dot(MeshPoint(mesh, v[1]).cross(MeshPoint(mesh, v[2]))) / 6.0;
    for (int e = 0; e < 3; ++e)
    {
      used.insert(v[e]);
      directed[{ v[e], v[(e + 1) % 3] }]++;
      const std::pair<int, int> key{ std::min(v[e], v[(e + 1) % 3]), std::max(v[e], v[(e + 1) % 3]) };
      const auto [it, inserted] = firstFace.emplace(key, f);
      if (!inserted)
        root[find(f)] = find(it->second);
    }
  }
  for (const auto& [edge, count] : directed)
  {
    const auto reverse = directed.find({ edge.second, edge.first });
    if (count != 1 || reverse == directed.end() || reverse->second != 1)
      ++w.edgeFailures;
  }
  for (std::size_t f = 0; f < F; ++f)
    w.components += find(f) == f;
  w.euler = static_cast<long long>(used.size()) - static_cast<long long>(firstFace.size()) + static_cast<long long>(F);
  return w;
}

/// Pairs of triangles that intersect other than in shared vertices or edges (CGAL, exact predicates).
std::vector<std::pair<std::size_t, std::size_t>> SelfIntersections(const TubeMesh& mesh)
{
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  Mesh sm;
  std::vector<Mesh::Vertex_index> vertex;
  for (std::size_t i = 0; i < mesh.PointCount(); ++i)
    vertex.push_back(
      sm.add_vertex(Kernel::Point_3(mesh.points[3 * i], mesh.points[3 * i + 1], mesh.points[3 * i + 2])));
  for (std::size_t f = 0; f < mesh.TriangleCount(); ++f)
  {
    const int* v = &mesh.triangles[3 * f];
    if (sm.add_face(vertex[std::size_t(v[0])], vertex[std::size_t(v[1])], vertex[std::size_t(v[2])]) ==
      Mesh::null_face())
      ADD_FAILURE() << "triangle " << f << " is not manifold";
  }
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
  std::vector<std::pair<std::size_t, std::size_t>> result;
  for (const auto& [a, b] : pairs)
    result.emplace_back(std::size_t(a), std::size_t(b));
  return result;
}

/// The tube owning triangle f.
std::size_t TubeOfTriangle(const TubeMesh& mesh, std::size_t f)
{
  return std::size_t(std::upper_bound(mesh.triangleOffsets.begin(), mesh.triangleOffsets.end(), std::int64_t(f)) -
           mesh.triangleOffsets.begin()) -
    1;
}

} // namespace

TEST(BranchJunctions, TJointIsOneClosedSurfaceWithTheUnionsVolume)
{
  // A prism of radius 1 along y from -6 to 6 and one of radius 0.5 leaving it at 90 deg from its axis, 6 long
  // (a stroke branch starts on its parent's axis). The union's volume: both prisms minus their intersection,
  // estimated on a 200^3 grid with exact polygon membership; the welded surface must contain both (volume >= the
  // union's) and its hull filler must be small against the overlap that the sum of the tubes counts twice.
  const int sides = 16;
  const double R = 1.0, r = 0.5;
  TubeInput parent{ { { 0, -6, 0 }, { 0, 6, 0 } }, { R, R }, Eigen::Vector3d::UnitX() };
  TubeInput child{ { { 0, 0, 0 }, { 6, 0, 0 } }, { r, r }, Eigen::Vector3d::UnitY(), 0 };
  TubeMesh mesh;
  JunctionReport report;
  ASSERT_EQ(BuildWeldedTubes({ parent, child }, sides, mesh, SerialFor, &report), "");
  EXPECT_EQ(report.junctions, 1);
  EXPECT_EQ(report.welded, 1);
  EXPECT_EQ(report.fallback, 0);
  EXPECT_EQ(report.narrowed, 0);
  const WholeSurface w = CheckWholeSurface(mesh);
  EXPECT_EQ(w.edgeFailures, 0);
  EXPECT_EQ(w.components, 1);
  EXPECT_EQ(w.euler, 2);
  EXPECT_TRUE(SelfIntersections(mesh).empty());
  // Regular polygons with vertex 0 towards the tube's `normal`: inside if within every edge's half-plane.
  std::vector<double> cosines, sines;
  for (int j = 0; j < sides; ++j)
    cosines.push_back(std::cos(2.0 * Pi * (j + 0.5) / sides)), sines.push_back(std::sin(2.0 * Pi * (j + 0.5) / sides));
  const auto inPolygon = [&](double u, double v, double radius) {
    for (std::size_t j = 0; j < cosines.size(); ++j)
    {
      if (u * cosines[j] + v * sines[j] > radius * std::cos(Pi / sides))
        return false;
    }
    return true;
  };
  const int N = 200;
  long long both = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      for (int k = 0; k < N; ++k)
      {
        // The box [0, 1] x [-0.5, 0.5] x [-0.5, 0.5] holds the intersection.
        const double x = (i + 0.5) / N, y = -0.5 + (j + 0.5) / N, z = -0.5 + (k + 0.5) / N;
        // Parent: polygon in (x, z) (vertex 0 along x, then towards z since n x t = x x y = z... sign checked by
        // symmetry: the polygon is symmetric under z -> -z). Child: polygon in (y, z'), likewise symmetric.
        both += inPolygon(x, z, R) && inPolygon(y, z, r);
      }
  const double overlap = double(both) / (double(N) * N * N);
  const double sum = 12.0 * PolygonArea(sides, R) + 6.0 * PolygonArea(sides, r);
  const double unionVolume = sum - overlap;
  std::printf("T joint (%d sides): welded volume %.6f, union %.6f, sum of tubes %.6f (overlap %.6f); filler %.3f "
              "of the overlap\n",
    sides, w.volume, unionVolume, sum, overlap, (w.volume - unionVolume) / overlap);
  EXPECT_GT(w.volume, unionVolume - 1e-3 * overlap);
  EXPECT_LT(w.volume - unionVolume, 0.5 * (sum - unionVolume));
}

namespace
{
struct WeldedResult
{
  WholeSurface surface;
  JunctionReport report;
  long long intersecting = 0; ///< self-intersecting triangle pairs
  long long atJunctions = 0;  ///< of these, pairs whose tubes are a welded parent and child or siblings
  long long atFallbacks = 0;  ///< pairs of a fallback child and its parent (overlapping, as documented)
  std::size_t trees = 0;      ///< roots (tubes without a parent)
};

WeldedResult Weld(const Tree& tree, int sides, const ParallelFor& parallel = SerialFor)
{
  WeldedResult r;
  const std::vector<TubeInput> tubes = TubesOf(tree);
  TubeMesh mesh;
  EXPECT_EQ(BuildWeldedTubes(tubes, sides, mesh, parallel, &r.report), "");
  r.surface = CheckWholeSurface(mesh);
  for (const TubeInput& t : tubes)
    r.trees += t.parent < 0;
  for (const auto& [a, b] : SelfIntersections(mesh))
  {
    const std::size_t ta = TubeOfTriangle(mesh, a), tb = TubeOfTriangle(mesh, b);
    ++r.intersecting;
    const auto parentOf = [&](std::size_t t) { return tubes[t].parent; };
    const auto fallback = [&](std::size_t t) {
      return std::binary_search(r.report.fallbackTubes.begin(), r.report.fallbackTubes.end(), std::int64_t(t));
    };
    if ((fallback(ta) && parentOf(ta) == std::int64_t(tb)) || (fallback(tb) && parentOf(tb) == std::int64_t(ta)))
    {
      ++r.atFallbacks;
      continue;
    }
    r.atJunctions += ta == tb || parentOf(ta) == std::int64_t(tb) || parentOf(tb) == std::int64_t(ta) ||
      (parentOf(ta) >= 0 && parentOf(ta) == parentOf(tb));
  }
  return r;
}

void ExpectOneClosedSurfacePerTree(const WeldedResult& r, const std::string& what)
{
  EXPECT_EQ(r.surface.edgeFailures, 0) << what;
  EXPECT_GT(r.surface.volume, 0.0) << what;
  // Every welded child joins its parent's component; each fallback child is a closed piece of its own.
  EXPECT_EQ(std::size_t(r.surface.components), r.trees + std::size_t(r.report.fallback)) << what;
  EXPECT_EQ(r.surface.euler, 2 * r.surface.components) << what; // every piece a sphere
  std::printf("%s: junctions %lld (merged %lld, at ends %lld), welded %lld, narrowed %lld, fallback %lld; "
              "components %d; self-intersecting pairs %lld (%lld at a junction's own tubes, %lld of fallback children "
              "with their parents)\n",
    what.c_str(), (long long)r.report.junctions, (long long)r.report.merged, (long long)r.report.endJunctions,
    (long long)r.report.welded, (long long)r.report.narrowed, (long long)r.report.fallback, r.surface.components,
    r.intersecting, r.atJunctions, r.atFallbacks);
  for (std::int64_t t : r.report.fallbackTubes)
    std::printf("  fallback: tube %lld\n", (long long)t);
}
} // namespace

TEST(BranchJunctions, PresetTreesAreOneClosedOrientedManifold)
{
  // Table 1's three templates at reduced depth (the brute-force checks stay short).
  for (int preset = 1; preset <= 3; ++preset)
  {
    TreeParameters s = Preset(preset);
    s.depth = preset == 2 ? 3 : 2;
    Tree tree;
    ASSERT_EQ(BuildTree(s, {}, tree), "");
    const WeldedResult r = Weld(tree, s.sides);
    ExpectOneClosedSurfacePerTree(r, std::string("preset ") + TreePresetName(preset));
    // Every child welded, and the junctions themselves never self-intersect. What intersects is branches crossing
    // each other away from any junction: the same pairs of tubes cross in the seated (unwelded) tubes, counted here
    // for comparison.
    EXPECT_EQ(r.report.fallback, 0) << preset;
    EXPECT_EQ(r.atJunctions, 0) << preset;
    const std::vector<TubeInput> tubes = TubesOf(tree);
    TubeMesh seated;
    ASSERT_EQ(BuildTubes(tubes, s.sides, seated), "");
    const auto related = [&](std::size_t a, std::size_t b) {
      const auto parentOf = [&](std::size_t t) { return tubes[t].parent; };
      const auto grand = [&](std::size_t t) { return parentOf(t) < 0 ? -1 : parentOf(std::size_t(parentOf(t))); };
      return a == b || parentOf(a) == std::int64_t(b) || parentOf(b) == std::int64_t(a) ||
        (parentOf(a) >= 0 && parentOf(a) == parentOf(b)) || grand(a) == std::int64_t(b) || grand(b) == std::int64_t(a);
    };
    std::set<std::pair<std::size_t, std::size_t>> crossingSeated, crossingWelded;
    for (const auto& [a, b] : SelfIntersections(seated))
    {
      const std::size_t ta = TubeOfTriangle(seated, a), tb = TubeOfTriangle(seated, b);
      if (!related(ta, tb))
        crossingSeated.insert({ std::min(ta, tb), std::max(ta, tb) });
    }
    TubeMesh welded;
    ASSERT_EQ(BuildWeldedTubes(tubes, s.sides, welded), "");
    for (const auto& [a, b] : SelfIntersections(welded))
    {
      const std::size_t ta = TubeOfTriangle(welded, a), tb = TubeOfTriangle(welded, b);
      if (!related(ta, tb))
        crossingWelded.insert({ std::min(ta, tb), std::max(ta, tb) });
    }
    std::size_t common = 0;
    for (const auto& pair : crossingWelded)
      common += crossingSeated.count(pair);
    std::printf("  tube pairs crossing away from junctions: welded %zu, seated %zu, both %zu\n", crossingWelded.size(),
      crossingSeated.size(), common);
    EXPECT_EQ(common, crossingWelded.size()) << preset; // welding adds no crossing of its own
  }
}

TEST(BranchJunctions, StrokeEditedAndMergedTreesAreClosedAndJunctionsDoNotSelfIntersect)
{
  TreeParameters s = StrokeParameters();
  s.strokesOnly = false;
  s.strokeSubtreeDepth = 1;
  s.childCount = 3;
  Tree strokes;
  ASSERT_EQ(BuildTree(s, SampleStrokes(), strokes), "");
  const WeldedResult a = Weld(strokes, 6);
  ExpectOneClosedSurfacePerTree(a, "stroke tree");
  EXPECT_EQ(a.atJunctions, 0);

  TreeParameters e = Preset(1);
  e.depth = 2;
  e.deletedBranches = { 2, 20 };
  e.overrides[11].length = 3.0;
  e.overrides[11].angle = 70.0;
  e.overrides[29].radius = 0.05;
  Tree edited;
  ASSERT_EQ(BuildTree(e, {}, edited), "");
  const WeldedResult b = Weld(edited, 6);
  ExpectOneClosedSurfacePerTree(b, "edited tree");
  EXPECT_EQ(b.atJunctions, 0);

  const Tree second = SecondTree();
  const auto skeleton = SkeletonOf(second);
  TreeParameters m = Preset(1);
  m.depth = 1;
  MergeOntoBranch3(m); // a child of the trunk
  Tree merged;
  ASSERT_EQ(BuildTree(m, {}, &skeleton, merged), "");
  const WeldedResult c = Weld(merged, 6);
  ExpectOneClosedSurfacePerTree(c, "merged tree");
  EXPECT_EQ(c.atJunctions, 0);
}

TEST(BranchJunctions, BitIdenticalAcrossThreadCuts)
{
  TreeParameters s = Preset(1);
  s.depth = 3;
  Tree tree;
  ASSERT_EQ(BuildTree(s, {}, tree), "");
  TubeMesh serial, chunked;
  ASSERT_EQ(BuildWeldedTubes(TubesOf(tree), 6, serial), "");
  ASSERT_EQ(BuildWeldedTubes(TubesOf(tree), 6, chunked,
              [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
                for (std::size_t begin = 0; begin < count; begin += 3)
                  body(begin, std::min(count, begin + 3));
              }),
    "");
  // And on real threads: 4 threads, each a contiguous quarter of every range.
  TubeMesh threaded;
  ASSERT_EQ(BuildWeldedTubes(TubesOf(tree), 6, threaded,
              [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
                std::vector<std::thread> threads;
                for (std::size_t k = 0; k < 4; ++k)
                  threads.emplace_back(body, count * k / 4, count * (k + 1) / 4);
                for (std::thread& t : threads)
                  t.join();
              }),
    "");
  EXPECT_EQ(serial.triangles, threaded.triangles);
  EXPECT_EQ(0, std::memcmp(serial.points.data(), threaded.points.data(), serial.points.size() * sizeof(double)));
  ASSERT_EQ(serial.points.size(), chunked.points.size());
  ASSERT_EQ(serial.triangles, chunked.triangles);
  EXPECT_EQ(0, std::memcmp(serial.points.data(), chunked.points.data(), serial.points.size() * sizeof(double)));
  EXPECT_EQ(serial.normals, chunked.normals);
  EXPECT_EQ(serial.tcoords, chunked.tcoords);
  EXPECT_EQ(serial.triangleOffsets, chunked.triangleOffsets);
}

TEST(BranchJunctions, AChildAlongItsParentsAxisFallsBackToItsOwnClosedTube)
{
  // A child starting on the parent's axis at mid-length and running along it (angle 0, not at the parent's end): no
  // junction can have its ring as a face. It stays a closed tube of its own (counted), the parent stays whole, and
  // a second, ordinary child is still welded.
  TubeInput parent{ { { 0, 0, 0 }, { 0, 5, 0 }, { 0, 10, 0 } }, { 1, 0.8, 0.6 }, Eigen::Vector3d::UnitX() };
  TubeInput along{ { { 0, 4, 0 }, { 0, 8, 0 } }, { 0.3, 0.2 }, Eigen::Vector3d::UnitX(), 0 };
  TubeInput side{ { { 0.8, 6, 0 }, { 4, 8, 0 } }, { 0.3, 0.2 }, Eigen::Vector3d::UnitY(), 0 };
  TubeMesh mesh;
  JunctionReport report;
  ASSERT_EQ(BuildWeldedTubes({ parent, along, side }, 8, mesh, SerialFor, &report), "");
  EXPECT_EQ(report.fallback, 1);
  ASSERT_EQ(report.fallbackTubes.size(), 1u);
  EXPECT_EQ(report.fallbackTubes[0], 1);
  EXPECT_EQ(report.welded, 1);
  const WholeSurface w = CheckWholeSurface(mesh);
  EXPECT_EQ(w.edgeFailures, 0);
  EXPECT_EQ(w.components, 2);
  EXPECT_EQ(w.euler, 4);
  // The fallback tube is the seated-free tube BuildTubes makes for it alone: same triangle count, closed.
  TubeMesh alone;
  TubeInput lone = along;
  lone.parent = -1;
  ASSERT_EQ(BuildTubes({ lone }, 8, alone), "");
  EXPECT_EQ(mesh.triangleOffsets[2] - mesh.triangleOffsets[1], alone.triangleOffsets[1]);
}
