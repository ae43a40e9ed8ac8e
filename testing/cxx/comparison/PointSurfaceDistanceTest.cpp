// SPDX-License-Identifier: GPL-3.0-or-later
// PointSurfaceDistance (filters/comparison/core): the BVH's distances equal brute force over every triangle computed by an
// independent oracle (projection + clamped segments); clouds sampled from a surface are at distance 0; points moved
// off a flat leaf blade by t are at distance t with signed distance +t / -t; signs on a closed cube and sphere
// (corners and edges included: pseudo-normals, not the nearest face's normal); nearest neighbours in cloud mode;
// degenerate triangles; bad input refused.
#include "PointSurfaceDistance.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace plantmorph
{
namespace
{
struct Mesh
{
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  std::size_t PointCount() const { return points.size() / 3; }
  std::size_t TriangleCount() const { return triangles.size() / 3; }
};

double Dot3(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Independent oracle: the squared distance from p to segment [a, b] by clamped projection.
double SegmentDistance2(const double* p, const double* a, const double* b)
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  const double len2 = Dot3(ab, ab);
  const double t = len2 > 0 ? std::clamp(Dot3(ap, ab) / len2, 0.0, 1.0) : 0.0;
  const double d[3] = { ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2] };
  return Dot3(d, d);
}

/// Independent oracle: projection onto the plane if it falls inside (barycentric by areas), else the nearest edge.
double OracleTriangleDistance(const double* p, const double* a, const double* b, const double* c)
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ac[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  double n[3] = { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0] };
  const double area2 = std::sqrt(Dot3(n, n));
  double best = std::min({ SegmentDistance2(p, a, b), SegmentDistance2(p, b, c), SegmentDistance2(p, c, a) });
  if (area2 > 0)
  {
    for (double& x : n)
    {
      x /= area2;
    }
    const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
    const double h = Dot3(ap, n);
    const double q[3] = { p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2] };
    // q inside iff the three sub-triangles (q, edge) have normals along n.
    const double* v[3] = { a, b, c };
    bool inside = true;
    for (int e = 0; e < 3; ++e)
    {
      const double* s = v[e];
      const double* t = v[(e + 1) % 3];
      const double st[3] = { t[0] - s[0], t[1] - s[1], t[2] - s[2] };
      const double sq[3] = { q[0] - s[0], q[1] - s[1], q[2] - s[2] };
      const double m[3] = { st[1] * sq[2] - st[2] * sq[1], st[2] * sq[0] - st[0] * sq[2],
        st[0] * sq[1] - st[1] * sq[0] };
      inside = inside && Dot3(m, n) >= 0;
    }
    if (inside)
    {
      best = std::min(best, h * h);
    }
  }
  return std::sqrt(best);
}

double BruteForce(const Mesh& mesh, const double* p)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.TriangleCount(); ++t)
  {
    best = std::min(best,
      OracleTriangleDistance(p, &mesh.points[3 * mesh.triangles[3 * t]], &mesh.points[3 * mesh.triangles[3 * t + 1]],
        &mesh.points[3 * mesh.triangles[3 * t + 2]]));
  }
  return best;
}

Mesh RandomSoup(RandomStream& random, std::size_t triangles)
{
  Mesh mesh;
  for (std::size_t t = 0; t < triangles; ++t)
  {
    const double cx = random.Uniform(-1, 1);
    const double cy = random.Uniform(-1, 1);
    const double cz = random.Uniform(-1, 1);
    for (int corner = 0; corner < 3; ++corner)
    {
      mesh.points.insert(mesh.points.end(),
        { cx + random.Uniform(-0.3, 0.3), cy + random.Uniform(-0.3, 0.3), cz + random.Uniform(-0.3, 0.3) });
      mesh.triangles.push_back(static_cast<std::int64_t>(3 * t + corner));
    }
  }
  return mesh;
}

/// A closed, outward-wound cube [-1, 1]^3, each face split into 2 n^2 triangles.
Mesh Cube(int n)
{
  Mesh mesh;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = -1; side <= 1; side += 2)
    {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      const std::int64_t base = static_cast<std::int64_t>(mesh.PointCount());
      for (int j = 0; j <= n; ++j)
      {
        for (int i = 0; i <= n; ++i)
        {
          double p[3];
          p[axis] = side;
          p[u] = -1.0 + 2.0 * i / n;
          p[v] = -1.0 + 2.0 * j / n;
          mesh.points.insert(mesh.points.end(), { p[0], p[1], p[2] });
        }
      }
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const std::int64_t q00 = base + j * (n + 1) + i;
          const std::int64_t q10 = q00 + 1;
          const std::int64_t q01 = q00 + n + 1;
          const std::int64_t q11 = q01 + 1;
          // (u, v, axis) is right-handed, so (q00, q10, q11) winds about +axis.
          if (side > 0)
          {
            mesh.triangles.insert(mesh.triangles.end(), { q00, q10, q11, q00, q11, q01 });
          }
          else
          {
            mesh.triangles.insert(mesh.triangles.end(), { q00, q11, q10, q00, q01, q11 });
          }
        }
      }
    }
  }
  // Weld the duplicated edge points so edges are shared (pseudo-normals need the topology).
  std::vector<std::int64_t> map(mesh.PointCount());
  std::vector<double> welded;
  for (std::size_t i = 0; i < mesh.PointCount(); ++i)
  {
    std::int64_t found = -1;
    for (std::size_t j = 0; j < welded.size() / 3 && found < 0; ++j)
    {
      if (welded[3 * j] == mesh.points[3 * i] && welded[3 * j + 1] == mesh.points[3 * i + 1] &&
        welded[3 * j + 2] == mesh.points[3 * i + 2])
      {
        found = static_cast<std::int64_t>(j);
      }
    }
    if (found < 0)
    {
      found = static_cast<std::int64_t>(welded.size() / 3);
      welded.insert(welded.end(), mesh.points.begin() + 3 * i, mesh.points.begin() + 3 * i + 3);
    }
    map[i] = found;
  }
  for (auto& t : mesh.triangles)
  {
    t = map[static_cast<std::size_t>(t)];
  }
  mesh.points = welded;
  return mesh;
}

/// A UV sphere of radius r, outward-wound, poles shared.
Mesh Sphere(double r, int rings, int segments)
{
  constexpr double Pi = 3.14159265358979323846;
  Mesh mesh;
  mesh.points.insert(mesh.points.end(), { 0.0, 0.0, r });
  for (int i = 1; i < rings; ++i)
  {
    const double theta = Pi * i / rings;
    for (int j = 0; j < segments; ++j)
    {
      const double phi = 2 * Pi * j / segments;
      mesh.points.insert(mesh.points.end(),
        { r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta) });
    }
  }
  mesh.points.insert(mesh.points.end(), { 0.0, 0.0, -r });
  const std::int64_t south = static_cast<std::int64_t>(mesh.PointCount() - 1);
  auto ring = [&](int i, int j) { return static_cast<std::int64_t>(1 + (i - 1) * segments + (j % segments)); };
  for (int j = 0; j < segments; ++j)
  {
    mesh.triangles.insert(mesh.triangles.end(), { 0, ring(1, j), ring(1, j + 1) });
    mesh.triangles.insert(mesh.triangles.end(), { south, ring(rings - 1, j + 1), ring(rings - 1, j) });
  }
  for (int i = 1; i + 1 < rings; ++i)
  {
    for (int j = 0; j < segments; ++j)
    {
      mesh.triangles.insert(mesh.triangles.end(), { ring(i, j), ring(i + 1, j), ring(i + 1, j + 1) });
      mesh.triangles.insert(mesh.triangles.end(), { ring(i, j), ring(i + 1, j + 1), ring(i, j + 1) });
    }
  }
  return mesh;
}

Mesh GinkgoBlade(int resolution)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  LeafGeometry leaf;
  EXPECT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf), "");
  Mesh mesh;
  for (const auto& p : leaf.blade.points)
  {
    mesh.points.insert(mesh.points.end(), { p.x(), p.y(), 0.0 });
  }
  for (const auto& t : leaf.blade.triangles)
  {
    mesh.triangles.insert(mesh.triangles.end(), { t[0], t[1], t[2] });
  }
  return mesh;
}

/// Uniform random points on the mesh's triangles (area-agnostic: a random triangle, then random barycentrics).
std::vector<double> SampleOnMesh(const Mesh& mesh, RandomStream& random, std::size_t count)
{
  std::vector<double> samples;
  for (std::size_t i = 0; i < count; ++i)
  {
    const auto t = static_cast<std::size_t>(random.Integer(0, static_cast<std::int64_t>(mesh.TriangleCount()) - 1));
    double u = random.Uniform();
    double v = random.Uniform();
    if (u + v > 1)
    {
      u = 1 - u;
      v = 1 - v;
    }
    const double* a = &mesh.points[3 * mesh.triangles[3 * t]];
    const double* b = &mesh.points[3 * mesh.triangles[3 * t + 1]];
    const double* c = &mesh.points[3 * mesh.triangles[3 * t + 2]];
    for (int k = 0; k < 3; ++k)
    {
      samples.push_back(a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]));
    }
  }
  return samples;
}

PointSurfaceDistance Build(const Mesh& mesh)
{
  PointSurfaceDistance distance;
  EXPECT_EQ(
    distance.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount()), "");
  return distance;
}

TEST(PointSurfaceDistance, AgreesWithBruteForceOnRandomTriangleSoups)
{
  RandomStream random(7);
  for (std::size_t triangles : { 1u, 2u, 5u, 37u, 300u })
  {
    const Mesh mesh = RandomSoup(random, triangles);
    const PointSurfaceDistance distance = Build(mesh);
    for (int q = 0; q < 400; ++q)
    {
      const double scale = q % 4 == 0 ? 5.0 : 1.5; // some queries far outside
      const double p[3] = { random.Uniform(-scale, scale), random.Uniform(-scale, scale),
        random.Uniform(-scale, scale) };
      const DistanceQueryResult r = distance.Query(p);
      const double expected = BruteForce(mesh, p);
      ASSERT_NEAR(r.distance, expected, 1e-12 * (1 + expected)) << triangles << " triangles, query " << q;
      EXPECT_DOUBLE_EQ(std::fabs(r.signedDistance), r.distance);
      // The closest point is on the reported triangle and at the reported distance.
      const double d[3] = { p[0] - r.closest[0], p[1] - r.closest[1], p[2] - r.closest[2] };
      EXPECT_NEAR(std::sqrt(Dot3(d, d)), r.distance, 1e-12 * (1 + expected));
      const auto t = static_cast<std::size_t>(r.primitive);
      EXPECT_NEAR(OracleTriangleDistance(r.closest, &mesh.points[3 * mesh.triangles[3 * t]],
                    &mesh.points[3 * mesh.triangles[3 * t + 1]], &mesh.points[3 * mesh.triangles[3 * t + 2]]),
        0.0, 1e-12);
    }
  }
}

// A surface big enough that the structure's arrays (triangles, leaf packs, tree nodes, Morton keys) are allocated on
// huge pages and left unset until written: a 160 x 160 sphere (50,880 triangles) with a duplicated and a degenerate
// triangle and points no triangle uses. Distances equal brute force, signs the side of the sphere, and the Morton-
// ordered QueryMany equals one query at a time bit for bit, at random points, far points, vertices and edge midpoints
// (exact ties between the triangles around them).
TEST(PointSurfaceDistance, LargeSurfaceOnHugePagesAgreesWithBruteForce)
{
  Mesh mesh = Sphere(1.0, 160, 160);
  const std::int64_t unused = static_cast<std::int64_t>(mesh.PointCount());
  mesh.points.insert(mesh.points.end(), { 5.0, 5.0, 5.0, -5.0, 0.0, 0.0 }); // used by no triangle
  mesh.triangles.insert(mesh.triangles.end(), { mesh.triangles[300], mesh.triangles[301], mesh.triangles[302] });
  mesh.triangles.insert(mesh.triangles.end(), { 7, 7, 8 });   // degenerate: a segment
  ASSERT_GT(mesh.TriangleCount() * 96, std::size_t(4) << 20); // the triangles in leaf order take 96 bytes each
  const PointSurfaceDistance distance = Build(mesh);
  RandomStream random(2026);
  std::vector<double> queries;
  for (int q = 0; q < 3000; ++q)
  {
    const double scale = q % 10 == 0 ? 4.0 : 1.3;
    queries.insert(
      queries.end(), { random.Uniform(-scale, scale), random.Uniform(-scale, scale), random.Uniform(-scale, scale) });
  }
  for (std::size_t t = 0; t < mesh.TriangleCount(); t += 17)
  {
    const double* a = &mesh.points[3 * mesh.triangles[3 * t]];
    const double* b = &mesh.points[3 * mesh.triangles[3 * t + 1]];
    queries.insert(queries.end(), { a[0], a[1], a[2], 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]) });
  }
  queries.insert(queries.end(), { mesh.points[3 * unused], mesh.points[3 * unused + 1], mesh.points[3 * unused + 2] });
  const std::size_t n = queries.size() / 3;
  std::vector<double> d(n), signedDistance(n), closest(3 * n);
  std::vector<std::int64_t> primitive(n);
  distance.QueryMany(queries.data(), n, d.data(), signedDistance.data(), closest.data(), primitive.data());
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* p = &queries[3 * i];
    const DistanceQueryResult one = distance.Query(p);
    ASSERT_EQ(one.primitive, primitive[i]) << "query " << i;
    EXPECT_EQ(one.distance, d[i]);
    EXPECT_EQ(one.signedDistance, signedDistance[i]);
    EXPECT_EQ(one.closest[0], closest[3 * i]);
    EXPECT_EQ(one.closest[1], closest[3 * i + 1]);
    EXPECT_EQ(one.closest[2], closest[3 * i + 2]);
    if (i % 11 == 0) // brute force over every triangle for every eleventh query
    {
      const double expected = BruteForce(mesh, p);
      ASSERT_NEAR(d[i], expected, 1e-12 * (1 + expected)) << "query " << i;
    }
    const double radius = std::sqrt(Dot3(p, p));
    if (std::fabs(radius - 1.0) > 1e-2) // clear of the tessellation's sagitta
    {
      EXPECT_EQ(signedDistance[i] > 0.0, radius > 1.0) << "query " << i;
    }
  }
}

TEST(PointSurfaceDistance, QueryManyEqualsSingleQueriesWhateverTheOrder)
{
  RandomStream random(11);
  const Mesh mesh = GinkgoBlade(40);
  const PointSurfaceDistance distance = Build(mesh);
  std::vector<double> points;
  for (int i = 0; i < 2000; ++i)
  {
    points.insert(points.end(), { random.Uniform(-3, 3), random.Uniform(-1, 6), random.Uniform(-1, 1) });
  }
  std::vector<double> d(2000), s(2000), c(6000);
  std::vector<std::int64_t> prim(2000);
  // A ParallelFor that cuts the range into uneven pieces (the hint restarts in each).
  const ParallelFor pieces = [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    for (std::size_t begin = 0; begin < count; begin += 333)
    {
      body(begin, std::min(count, begin + 333));
    }
  };
  distance.QueryMany(points.data(), 2000, d.data(), s.data(), c.data(), prim.data(), pieces);
  for (std::size_t i = 0; i < 2000; ++i)
  {
    const DistanceQueryResult r = distance.Query(&points[3 * i]);
    EXPECT_EQ(d[i], r.distance);
    EXPECT_EQ(s[i], r.signedDistance);
    EXPECT_NEAR(d[i], BruteForce(mesh, &points[3 * i]), 1e-12);
  }
}

/// An open, strongly bent sheet: 3/4 of a cylinder of radius 1 about the z axis, z in [-1, 1], n x m quads split in
/// two (points near the axis are almost equally far from most of it, like the centre of a sphere).
Mesh BentSheet(int n, int m)
{
  constexpr double Pi = 3.14159265358979323846;
  Mesh mesh;
  for (int j = 0; j <= m; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      const double angle = 1.5 * Pi * i / n;
      mesh.points.insert(mesh.points.end(), { std::cos(angle), std::sin(angle), -1.0 + 2.0 * j / m });
    }
  }
  for (int j = 0; j < m; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const std::int64_t q00 = j * (n + 1) + i;
      mesh.triangles.insert(mesh.triangles.end(), { q00, q00 + 1, q00 + n + 2, q00, q00 + n + 2, q00 + n + 1 });
    }
  }
  return mesh;
}

/// Random points: half uniform in the cube [-1.5, 1.5]^3 (inside and outside, some near the centre), half within
/// about 0.01 of the unit sphere / cylinder (what a scan looks like).
std::vector<double> InsideAndOutside(RandomStream& random, std::size_t count)
{
  std::vector<double> points;
  for (std::size_t i = 0; i < count; ++i)
  {
    double p[3] = { random.Uniform(-1.5, 1.5), random.Uniform(-1.5, 1.5), random.Uniform(-1.5, 1.5) };
    if (i % 2 == 1)
    {
      const double r = std::sqrt(Dot3(p, p));
      const double scale = (1.0 + random.Normal(0.0, 0.01)) / std::max(r, 1e-9);
      p[0] *= scale;
      p[1] *= scale;
      p[2] *= scale;
    }
    points.insert(points.end(), { p[0], p[1], p[2] });
  }
  // And the centre itself, where every triangle of the sphere is nearly equally far.
  points.insert(points.end(), { 0.0, 0.0, 0.0, 1e-3, -2e-3, 5e-4 });
  return points;
}

/// Two results of the same query by different search paths. The same triangle: bit for bit equal. Triangles tied
/// at the minimum (the closest point on their shared edge or vertex, common outside a convex mesh): the same distance
/// and sign to round-off, the same closest point.
::testing::AssertionResult SameResult(const DistanceQueryResult& a, const DistanceQueryResult& b)
{
  if (a.primitive == b.primitive)
  {
    if (a.distance == b.distance && a.signedDistance == b.signedDistance && a.closest[0] == b.closest[0] &&
      a.closest[1] == b.closest[1] && a.closest[2] == b.closest[2])
    {
      return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << "same triangle " << a.primitive << ", different results";
  }
  const double tolerance = 1e-14 * (1.0 + a.distance);
  const double gap[3] = { a.closest[0] - b.closest[0], a.closest[1] - b.closest[1], a.closest[2] - b.closest[2] };
  if (std::fabs(a.distance - b.distance) <= tolerance && std::fabs(a.signedDistance - b.signedDistance) <= tolerance &&
    std::sqrt(Dot3(gap, gap)) <= 1e-12)
  {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "triangles " << a.primitive << " and " << b.primitive << ": distances "
                                       << a.distance << " and " << b.distance << ", signed " << a.signedDistance
                                       << " and " << b.signedDistance;
}

TEST(PointSurfaceDistance, SlabBoundsGiveTheBruteForceResultOnASphereAndABentSheet)
{
  RandomStream random(2026);
  for (const bool sphere : { true, false })
  {
    const Mesh mesh = sphere ? Sphere(1.0, 40, 80) : BentSheet(90, 40);
    PointSurfaceDistance slabs;
    ASSERT_EQ(
      slabs.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount()), "");
    PointSurfaceDistance boxes;
    boxes.SetSlabBounds(false);
    ASSERT_EQ(
      boxes.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount()), "");
    ASSERT_TRUE(slabs.GetSlabBounds());
    ASSERT_FALSE(boxes.GetSlabBounds());
    const std::vector<double> points = InsideAndOutside(random, 3000);
    for (std::size_t i = 0; i < points.size() / 3; ++i)
    {
      const double* p = &points[3 * i];
      const DistanceQueryResult a = slabs.Query(p);
      const DistanceQueryResult b = boxes.Query(p);
      // The same nearest triangle (bit for bit the same unsigned and signed distance and closest point), or one
      // tied with it.
      ASSERT_TRUE(SameResult(a, b)) << "point " << i;
      // And the minimum over all triangles by the independent oracle (to its round-off).
      ASSERT_NEAR(a.distance, BruteForce(mesh, p), 1e-13) << "point " << i;
      if (sphere) // the sign says inside / outside (chord error < 0.004)
      {
        const double r = std::sqrt(Dot3(p, p));
        if (std::fabs(r - 1.0) > 0.004)
        {
          ASSERT_EQ(a.signedDistance < 0, r < 1.0) << r;
        }
      }
      ASSERT_EQ(std::fabs(a.signedDistance), a.distance);
    }
  }
}

TEST(PointSurfaceDistance, AvxAndSse2TraversalsGiveTheSameResultsBitForBit)
{
  // The traversal is compiled twice (AVX, four children's bounds an instruction; SSE2, two): the same arithmetic in
  // the same order, so the same nodes are visited and every output is bit-identical. (On a processor without AVX
  // both runs take the SSE2 path and the test is trivially true.)
  RandomStream random(31);
  for (const bool sphere : { true, false })
  {
    const Mesh mesh = sphere ? Sphere(1.0, 40, 80) : BentSheet(90, 40);
    const std::vector<double> points = InsideAndOutside(random, 6000); // QueryMany sorts them (>= 4096)
    const std::size_t n = points.size() / 3;
    std::vector<double> d[2], s[2], c[2];
    std::vector<std::int64_t> prim[2];
    for (const bool avx : { true, false })
    {
      PointSurfaceDistance distance;
      distance.SetAvx(avx);
      ASSERT_EQ(
        distance.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount()), "");
      ASSERT_EQ(distance.GetAvx(), avx); // kept by BuildSurface
      d[avx].resize(n);
      s[avx].resize(n);
      c[avx].resize(3 * n);
      prim[avx].resize(n);
      distance.QueryMany(points.data(), n, d[avx].data(), s[avx].data(), c[avx].data(), prim[avx].data());
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      ASSERT_EQ(prim[0][i], prim[1][i]) << "point " << i;
      ASSERT_EQ(d[0][i], d[1][i]) << "point " << i;
      ASSERT_EQ(s[0][i], s[1][i]) << "point " << i;
      ASSERT_EQ(c[0][3 * i], c[1][3 * i]) << "point " << i;
      ASSERT_EQ(c[0][3 * i + 1], c[1][3 * i + 1]) << "point " << i;
      ASSERT_EQ(c[0][3 * i + 2], c[1][3 * i + 2]) << "point " << i;
      ASSERT_NEAR(d[0][i], BruteForce(mesh, &points[3 * i]), 1e-13) << "point " << i;
    }
  }
}

TEST(PointSurfaceDistance, ThreadedBuildAndMortonQueriesEqualSerialOnes)
{
  RandomStream random(5);
  const Mesh mesh = Sphere(1.0, 30, 60);
  const ParallelFor pieces = [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    for (std::size_t begin = 0; begin < count; begin += 97) // uneven pieces, last one first
    {
      const std::size_t first = (count - 1) / 97 * 97 - begin;
      body(first, std::min(count, first + 97));
    }
  };
  PointSurfaceDistance serial;
  ASSERT_EQ(
    serial.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount()), "");
  PointSurfaceDistance threaded;
  ASSERT_EQ(
    threaded.BuildSurface(mesh.points.data(), mesh.PointCount(), mesh.triangles.data(), mesh.TriangleCount(), pieces),
    "");
  EXPECT_EQ(serial.MemoryBytes(), threaded.MemoryBytes());
  // 5000 points: QueryMany sorts them along the Z-curve; with a progress callback it works in blocks.
  const std::vector<double> points = InsideAndOutside(random, 5000);
  const std::size_t n = points.size() / 3;
  std::vector<double> d(n), s(n), c(3 * n);
  std::vector<std::int64_t> prim(n);
  std::vector<double> reported;
  threaded.QueryMany(points.data(), n, d.data(), s.data(), c.data(), prim.data(), pieces, [&](double done) {
    reported.push_back(done);
    return true;
  });
  ASSERT_FALSE(reported.empty());
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  for (std::size_t i = 0; i < n; ++i)
  {
    // Single queries on the serial build, without the Morton order's starting hint: the same nearest triangle,
    // or one tied with it.
    const DistanceQueryResult r = serial.Query(&points[3 * i]);
    DistanceQueryResult q;
    q.distance = d[i];
    q.signedDistance = s[i];
    q.primitive = prim[i];
    std::copy(&c[3 * i], &c[3 * i] + 3, q.closest);
    ASSERT_TRUE(SameResult(q, r)) << "point " << i;
  }
  // A progress callback that says stop: QueryMany returns after the first block (70000 points: two blocks).
  const std::vector<double> many = InsideAndOutside(random, 70000);
  std::vector<double> far(many.size() / 3, -1.0);
  int calls = 0;
  threaded.QueryMany(many.data(), far.size(), far.data(), nullptr, nullptr, nullptr, SerialFor, [&](double done) {
    ++calls;
    EXPECT_LT(done, 1.0);
    return false;
  });
  EXPECT_EQ(calls, 1);
  EXPECT_GT(std::count(far.begin(), far.end(), -1.0), 0); // some points were never queried
}

TEST(PointSurfaceDistance, PointsSampledFromTheSurfaceAreAtDistanceZero)
{
  RandomStream random(3);
  for (const Mesh& mesh : { GinkgoBlade(30), Sphere(2.0, 20, 40), Cube(4) })
  {
    const PointSurfaceDistance distance = Build(mesh);
    const std::vector<double> samples = SampleOnMesh(mesh, random, 3000);
    std::vector<double> d(1000 * 3);
    distance.QueryMany(samples.data(), 3000, d.data(), nullptr, nullptr, nullptr);
    EXPECT_LT(*std::max_element(d.begin(), d.end()), 1e-9);
    // The vertices themselves too.
    std::vector<double> dv(mesh.PointCount());
    distance.QueryMany(mesh.points.data(), mesh.PointCount(), dv.data(), nullptr, nullptr, nullptr);
    EXPECT_LT(*std::max_element(dv.begin(), dv.end()), 1e-12);
  }
}

TEST(PointSurfaceDistance, OffsetOfAFlatBladeGivesPlusAndMinusT)
{
  RandomStream random(5);
  const Mesh blade = GinkgoBlade(30); // z = 0, counter-clockwise triangles: the upper side faces +Z
  const PointSurfaceDistance distance = Build(blade);
  const std::vector<double> samples = SampleOnMesh(blade, random, 2000);
  for (double t : { 1e-6, 0.01, 0.37, 2.5 })
  {
    for (int side : { 1, -1 })
    {
      std::vector<double> moved = samples;
      for (std::size_t i = 2; i < moved.size(); i += 3)
      {
        moved[i] += side * t;
      }
      std::vector<double> d(2000), s(2000), c(6000);
      distance.QueryMany(moved.data(), 2000, d.data(), s.data(), c.data(), nullptr);
      for (std::size_t i = 0; i < 2000; ++i)
      {
        ASSERT_NEAR(d[i], t, 1e-12 * (1 + t));
        ASSERT_NEAR(s[i], side * t, 1e-12 * (1 + t));
        // The closest point is the sample itself.
        ASSERT_NEAR(c[3 * i], samples[3 * i], 1e-12);
        ASSERT_NEAR(c[3 * i + 1], samples[3 * i + 1], 1e-12);
        ASSERT_NEAR(c[3 * i + 2], 0.0, 1e-12);
      }
    }
  }
}

TEST(PointSurfaceDistance, ClosedCubeSignsAtFacesEdgesAndCorners)
{
  const Mesh cube = Cube(3);
  const PointSurfaceDistance distance = Build(cube);
  RandomStream random(9);
  for (int q = 0; q < 3000; ++q)
  {
    const double p[3] = { random.Uniform(-2.5, 2.5), random.Uniform(-2.5, 2.5), random.Uniform(-2.5, 2.5) };
    const DistanceQueryResult r = distance.Query(p);
    // Closed form: outside, the distance to the box; inside, the distance to the nearest face.
    double outside2 = 0.0;
    double inside = std::numeric_limits<double>::infinity();
    for (double x : p)
    {
      const double excess = std::max(0.0, std::fabs(x) - 1.0);
      outside2 += excess * excess;
      inside = std::min(inside, 1.0 - std::fabs(x));
    }
    const double expected = outside2 > 0 ? std::sqrt(outside2) : inside;
    ASSERT_NEAR(r.distance, expected, 1e-12);
    ASSERT_EQ(r.signedDistance > 0, outside2 > 0) << p[0] << " " << p[1] << " " << p[2];
  }
  // Exactly diagonal from a corner and from an edge: the nearest feature is a vertex / edge.
  const double corner[3] = { 1.5, 1.5, 1.5 };
  EXPECT_NEAR(distance.Query(corner).signedDistance, std::sqrt(0.75), 1e-12);
  const double edge[3] = { 1.2, 1.2, 0.1 };
  EXPECT_NEAR(distance.Query(edge).signedDistance, std::sqrt(0.08), 1e-12);
}

TEST(PointSurfaceDistance, SphereSignsInsideAndOutside)
{
  const double r = 2.0;
  const Mesh sphere = Sphere(r, 24, 48);
  const PointSurfaceDistance distance = Build(sphere);
  RandomStream random(13);
  for (int q = 0; q < 3000; ++q)
  {
    const double p[3] = { random.Uniform(-3, 3), random.Uniform(-3, 3), random.Uniform(-3, 3) };
    const double radius = std::sqrt(Dot3(p, p));
    if (std::fabs(radius - r) < 0.02) // the chord error of this tessellation is below 0.02
    {
      continue;
    }
    const DistanceQueryResult result = distance.Query(p);
    ASSERT_EQ(result.signedDistance > 0, radius > r) << radius;
    ASSERT_NEAR(result.distance, BruteForce(sphere, p), 1e-12);
  }
}

/// Inside a closed mesh iff a ray from p crosses it an odd number of times (Moeller-Trumbore, a skew direction).
bool InsideByRayParity(const Mesh& mesh, const double* p)
{
  const double dir[3] = { 0.5773, 0.5874, 0.5672 };
  int crossings = 0;
  for (std::size_t t = 0; t < mesh.TriangleCount(); ++t)
  {
    const double* a = &mesh.points[3 * mesh.triangles[3 * t]];
    const double* b = &mesh.points[3 * mesh.triangles[3 * t + 1]];
    const double* c = &mesh.points[3 * mesh.triangles[3 * t + 2]];
    const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double h[3] = { dir[1] * e2[2] - dir[2] * e2[1], dir[2] * e2[0] - dir[0] * e2[2],
      dir[0] * e2[1] - dir[1] * e2[0] };
    const double det = Dot3(e1, h);
    if (std::fabs(det) < 1e-15)
    {
      continue;
    }
    const double s[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
    const double u = Dot3(s, h) / det;
    const double q[3] = { s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0] };
    const double v = Dot3(dir, q) / det;
    const double along = Dot3(e2, q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && along > 0)
    {
      ++crossings;
    }
  }
  return crossings % 2 == 1;
}

TEST(PointSurfaceDistance, NonConvexClosedSurfaceSignsMatchRayParity)
{
  // A bumpy sphere: concave valleys between the bumps, where the nearest triangle's own normal gives wrong signs
  // outside concave edges and vertices; the angle-weighted pseudo-normals must not.
  Mesh mesh = Sphere(1.0, 16, 32);
  for (std::size_t i = 0; i < mesh.PointCount(); ++i)
  {
    double* x = &mesh.points[3 * i];
    const double theta = std::acos(std::clamp(x[2], -1.0, 1.0));
    const double phi = std::atan2(x[1], x[0]);
    const double r = 1.0 + 0.35 * std::sin(3 * theta) * std::cos(4 * phi);
    for (int k = 0; k < 3; ++k)
    {
      x[k] *= r;
    }
  }
  const PointSurfaceDistance distance = Build(mesh);
  RandomStream random(21);
  const std::vector<double> onSurface = SampleOnMesh(mesh, random, 1500);
  std::vector<double> queries;
  for (std::size_t i = 0; i < 1500; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      queries.push_back(onSurface[3 * i + k] + random.Uniform(-0.08, 0.08));
    }
  }
  // The mesh's vertices pushed straight out and in: their nearest feature is often that vertex or an edge.
  for (std::size_t i = 0; i < mesh.PointCount(); ++i)
  {
    for (double f : { 1.03, 0.97 })
    {
      queries.insert(queries.end(), { f * mesh.points[3 * i], f * mesh.points[3 * i + 1], f * mesh.points[3 * i + 2] });
    }
  }
  std::size_t checked = 0;
  for (std::size_t i = 0; i < queries.size() / 3; ++i)
  {
    const DistanceQueryResult r = distance.Query(&queries[3 * i]);
    if (r.distance < 1e-9)
    {
      continue;
    }
    ++checked;
    ASSERT_EQ(r.signedDistance < 0, InsideByRayParity(mesh, &queries[3 * i])) << "query " << i;
  }
  EXPECT_GT(checked, 2000u);
}

TEST(PointSurfaceDistance, CloudModeIsTheNearestNeighbour)
{
  RandomStream random(17);
  std::vector<double> cloud;
  for (int i = 0; i < 1500; ++i)
  {
    cloud.insert(cloud.end(), { random.Uniform(0, 1), random.Uniform(0, 2), random.Normal(0, 0.1) });
  }
  PointSurfaceDistance distance;
  ASSERT_EQ(distance.BuildCloud(cloud.data(), 1500), "");
  EXPECT_FALSE(distance.IsSurface());
  for (int q = 0; q < 500; ++q)
  {
    const double p[3] = { random.Uniform(-1, 2), random.Uniform(-1, 3), random.Uniform(-1, 1) };
    double best = std::numeric_limits<double>::infinity();
    std::size_t bestIndex = 0;
    for (std::size_t i = 0; i < 1500; ++i)
    {
      const double d[3] = { p[0] - cloud[3 * i], p[1] - cloud[3 * i + 1], p[2] - cloud[3 * i + 2] };
      if (Dot3(d, d) < best)
      {
        best = Dot3(d, d);
        bestIndex = i;
      }
    }
    const DistanceQueryResult r = distance.Query(p);
    ASSERT_EQ(static_cast<std::size_t>(r.primitive), bestIndex);
    ASSERT_EQ(r.distance, std::sqrt(best));
    ASSERT_EQ(r.closest[0], cloud[3 * bestIndex]);
  }
}

TEST(PointSurfaceDistance, DegenerateTrianglesAreSegments)
{
  const Mesh line{ { 0, 0, 0, 1, 0, 0, 2, 0, 0 }, { 0, 1, 2 } }; // collinear: the segment [0, 2] on x
  const PointSurfaceDistance distance = Build(line);
  const double beside[3] = { 1.5, 3.0, 4.0 };
  EXPECT_NEAR(distance.Query(beside).distance, 5.0, 1e-12);
  const double beyond[3] = { 5.0, 0.0, 4.0 };
  EXPECT_NEAR(distance.Query(beyond).distance, 5.0, 1e-12);
  const Mesh point{ { 1, 1, 1, 1, 1, 1, 1, 1, 1 }, { 0, 1, 2 } };
  const PointSurfaceDistance distance2 = Build(point);
  const double p[3] = { 1, 4, 5 };
  EXPECT_NEAR(distance2.Query(p).distance, 5.0, 1e-12);
}

TEST(PointSurfaceDistance, ExactTiesGoToTheLowestIndexWhateverTheHint)
{
  // Two mirrored triangles at exactly the same distance (1) from the origin, and a grid of mirrored pairs: the
  // result must not depend on the starting hint (the previous query's primitive, which an MPI rank's other points
  // set differently), so the closest point is the same bit for bit.
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  for (int k = 0; k < 40; ++k)
  {
    const double y = 3.0 * k;
    const std::int64_t base = static_cast<std::int64_t>(points.size() / 3);
    points.insert(points.end(), { 1, y - 1, 0, 2, y + 1, 0, 1, y + 1, 0, -1, y - 1, 0, -1, y + 1, 0, -2, y + 1, 0 });
    triangles.insert(triangles.end(), { base, base + 1, base + 2, base + 3, base + 4, base + 5 });
  }
  PointSurfaceDistance distance;
  ASSERT_EQ(distance.BuildSurface(points.data(), points.size() / 3, triangles.data(), triangles.size() / 3), "");
  for (int k = 0; k < 40; ++k)
  {
    const double p[3] = { 0.0, 3.0 * k, 0.0 };
    const DistanceQueryResult a = distance.Query(p, 2 * k);
    const DistanceQueryResult b = distance.Query(p, 2 * k + 1);
    const DistanceQueryResult none = distance.Query(p);
    EXPECT_EQ(a.distance, 1.0);
    EXPECT_EQ(a.primitive, b.primitive);
    EXPECT_EQ(a.primitive, none.primitive);
    EXPECT_EQ(a.closest[0], b.closest[0]);
    EXPECT_EQ(a.signedDistance, b.signedDistance);
  }
}

TEST(PointSurfaceDistance, BadInputIsRefused)
{
  PointSurfaceDistance distance;
  const std::vector<double> points = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  const std::vector<std::int64_t> bad = { 0, 1, 3 };
  EXPECT_NE(distance.BuildSurface(points.data(), 3, bad.data(), 1).find("outside [0, 3)"), std::string::npos);
  EXPECT_TRUE(distance.IsEmpty());
  EXPECT_NE(distance.BuildSurface(points.data(), 3, bad.data(), 0), "");
  std::vector<double> nan = points;
  nan[4] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::int64_t> good = { 0, 1, 2 };
  EXPECT_NE(distance.BuildSurface(nan.data(), 3, good.data(), 1).find("non-finite"), std::string::npos);
  EXPECT_NE(distance.BuildCloud(nan.data(), 3).find("non-finite"), std::string::npos);
  EXPECT_NE(distance.BuildCloud(points.data(), 0), "");
  // A NaN query gives NaN, not a crash or a bogus distance.
  ASSERT_EQ(distance.BuildSurface(points.data(), 3, good.data(), 1), "");
  const double q[3] = { 0.2, std::numeric_limits<double>::quiet_NaN(), 0.0 };
  EXPECT_TRUE(std::isnan(distance.Query(q).distance));
}

} // namespace
} // namespace plantmorph
