// SPDX-License-Identifier: GPL-3.0-or-later
// The virtual scanner's algorithm layer (filters/scanner/core): the BVH against brute force, watertightness, the sphere's
// visible cap and its solid angle, an exact shadow, determinism per seed and thread count, bad input, the budget.
#include "ScanPattern.h"
#include "RayCaster.h"
#include "VirtualScan.h"

#include <gtest/gtest.h>

#include <plantmorph/RandomStream.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>
#include <utility>

using namespace plantmorph;

namespace
{
constexpr double Pi = 3.14159265358979323846;

struct Mesh
{
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
  std::size_t Points() const { return points.size() / 3; }
  void Append(const Mesh& other)
  {
    const auto offset = static_cast<std::int64_t>(Points());
    points.insert(points.end(), other.points.begin(), other.points.end());
    for (std::int64_t t : other.triangles)
      triangles.push_back(t + offset);
  }
};

/// An icosphere of radius `radius` about `centre`, `levels` times subdivided (20 * 4^levels triangles, outward).
Mesh Icosphere(int levels, double radius = 1.0, const Vec3& centre = { 0.0, 0.0, 0.0 })
{
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = { { -1, g, 0 }, { 1, g, 0 }, { -1, -g, 0 }, { 1, -g, 0 }, { 0, -1, g }, { 0, 1, g },
    { 0, -1, -g }, { 0, 1, -g }, { g, 0, -1 }, { g, 0, 1 }, { -g, 0, -1 }, { -g, 0, 1 } };
  std::vector<std::array<std::int64_t, 3>> f = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 },
    { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 },
    { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  auto unit = [](Vec3 a) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return Vec3{ a[0] / l, a[1] / l, a[2] / l };
  };
  for (auto& x : v)
    x = unit(x);
  for (int level = 0; level < levels; ++level)
  {
    std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> middle;
    auto mid = [&](std::int64_t a, std::int64_t b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end())
        return it->second;
      v.push_back(unit({ v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2] }));
      return middle[key] = static_cast<std::int64_t>(v.size() - 1);
    };
    std::vector<std::array<std::int64_t, 3>> next;
    for (const auto& t : f)
    {
      const std::int64_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      next.push_back({ t[0], ab, ca });
      next.push_back({ t[1], bc, ab });
      next.push_back({ t[2], ca, bc });
      next.push_back({ ab, bc, ca });
    }
    f = std::move(next);
  }
  Mesh m;
  for (const auto& x : v)
    for (int k = 0; k < 3; ++k)
      m.points.push_back(centre[k] + radius * x[k]);
  for (const auto& t : f)
    m.triangles.insert(m.triangles.end(), t.begin(), t.end());
  return m;
}

/// The smallest distance from the origin to a triangle's plane: the inscribed ball of a convex mesh about the origin.
double InscribedRadius(const Mesh& m)
{
  double r = 1e300;
  for (std::size_t t = 0; t < m.triangles.size() / 3; ++t)
  {
    const double* a = &m.points[3 * m.triangles[3 * t]];
    const double* b = &m.points[3 * m.triangles[3 * t + 1]];
    const double* c = &m.points[3 * m.triangles[3 * t + 2]];
    const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    r = std::min(r, std::abs(n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) / l);
  }
  return r;
}

/// An axis-aligned square in the plane z = `z`, [x0, x1] x [y0, y1], `n` x `n` cells of two triangles.
Mesh Square(double x0, double x1, double y0, double y1, double z, int n)
{
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.points.insert(m.points.end(), { x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z });
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const std::int64_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.triangles.insert(m.triangles.end(), { a, b, d, a, d, c });
    }
  return m;
}

/// The nearest hit by brute force, Moller-Trumbore (an independent test from the BVH's).
double BruteForce(const Mesh& m, const double o[3], const double d[3])
{
  double best = 1e300;
  for (std::size_t t = 0; t < m.triangles.size() / 3; ++t)
  {
    const double* a = &m.points[3 * m.triangles[3 * t]];
    const double* b = &m.points[3 * m.triangles[3 * t + 1]];
    const double* c = &m.points[3 * m.triangles[3 * t + 2]];
    const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double p[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0] };
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (std::abs(det) < 1e-300)
      continue;
    const double s[3] = { o[0] - a[0], o[1] - a[1], o[2] - a[2] };
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    const double q[3] = { s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0] };
    const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && tt > 0)
      best = std::min(best, tt);
  }
  return best;
}

/// A parallel-for over `threads` threads with uneven pieces (piece p is p + 1 shares long).
ParallelFor Threads(std::size_t threads)
{
  return [threads](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    std::vector<std::thread> pool;
    const std::size_t shares = threads * (threads + 1) / 2;
    std::size_t begin = 0, done = 0;
    for (std::size_t p = 0; p < threads; ++p)
    {
      done += p + 1;
      const std::size_t end = n * done / shares;
      pool.emplace_back([&body, begin, end] {
        if (begin < end)
          body(begin, end);
      });
      begin = end;
    }
    for (auto& t : pool)
      t.join();
  };
}

double Dot3(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

template <class Array>
bool SameBits(const Array& a, const Array& b)
{
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(*a.data())) == 0);
}
} // namespace

TEST(RayCaster, NearestHitEqualsBruteForce)
{
  Mesh scene = Icosphere(3, 1.0);
  scene.Append(Icosphere(2, 0.4, { 1.5, 0.2, -0.3 }));
  scene.Append(Square(-2, 2, -2, 2, -1.2, 7));
  RayCaster caster;
  ASSERT_EQ(caster.Build(scene.points, scene.triangles), "");
  EXPECT_EQ(caster.TriangleCount(), scene.triangles.size() / 3);
  RandomStream random(7);
  int hits = 0;
  for (int i = 0; i < 3000; ++i)
  {
    const double o[3] = { random.Uniform(-3, 3), random.Uniform(-3, 3), random.Uniform(-3, 3) };
    double d[3] = { random.Normal(), random.Normal(), random.Normal() };
    if (i % 2 == 0) // aimed at the scene
    {
      for (int k = 0; k < 3; ++k)
        d[k] = random.Uniform(-1.2, 1.2) - o[k];
    }
    const TriangleHit hit = caster.Intersect(o, d, 1e30);
    const double expected = BruteForce(scene, o, d);
    if (expected == 1e300)
    {
      EXPECT_FALSE(hit.Hit()) << "ray " << i;
      continue;
    }
    ++hits;
    ASSERT_TRUE(hit.Hit()) << "ray " << i;
    EXPECT_NEAR(hit.t, expected, 1e-9 * (1.0 + expected)) << "ray " << i;
    // The reported triangle and barycentrics give the hit point.
    const std::int64_t* t = &scene.triangles[3 * hit.triangle];
    for (int k = 0; k < 3; ++k)
    {
      const double x = (1 - hit.u - hit.v) * scene.points[3 * t[0] + k] + hit.u * scene.points[3 * t[1] + k] +
        hit.v * scene.points[3 * t[2] + k];
      EXPECT_NEAR(x, o[k] + hit.t * d[k], 1e-9);
    }
    // Its normal is that triangle's (v1 - v0) x (v2 - v0) from the input's own numbers, exactly.
    const double* a = &scene.points[3 * t[0]];
    const double* b = &scene.points[3 * t[1]];
    const double* c = &scene.points[3 * t[2]];
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    EXPECT_EQ(hit.normal[0], u[1] * w[2] - u[2] * w[1]) << "ray " << i;
    EXPECT_EQ(hit.normal[1], u[2] * w[0] - u[0] * w[2]) << "ray " << i;
    EXPECT_EQ(hit.normal[2], u[0] * w[1] - u[1] * w[0]) << "ray " << i;
  }
  EXPECT_GT(hits, 1000);
}

TEST(RayCaster, ClosedSurfaceLetsNoBeamThrough)
{
  // Beams aimed exactly at the vertices and edge midpoints of a closed icosphere, where two or more triangles meet,
  // from inside and from outside: each must hit (a crack between triangles would let it through).
  const Mesh sphere = Icosphere(4, 1.0);
  RayCaster caster;
  ASSERT_EQ(caster.Build(sphere.points, sphere.triangles), "");
  std::vector<Vec3> targets;
  for (std::size_t i = 0; i < sphere.Points(); ++i)
    targets.push_back({ sphere.points[3 * i], sphere.points[3 * i + 1], sphere.points[3 * i + 2] });
  for (std::size_t t = 0; t < sphere.triangles.size() / 3; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const double* a = &sphere.points[3 * sphere.triangles[3 * t + k]];
      const double* b = &sphere.points[3 * sphere.triangles[3 * t + (k + 1) % 3]];
      targets.push_back({ 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]) });
    }
  const double inside[3][3] = { { 0, 0, 0 }, { 0.1, -0.2, 0.05 }, { -0.3, 0.3, 0.3 } };
  std::size_t missed = 0;
  for (const Vec3& x : targets)
  {
    for (const auto& o : inside)
    {
      const double d[3] = { x[0] - o[0], x[1] - o[1], x[2] - o[2] };
      missed += caster.Intersect(o, d, 1e30).Hit() ? 0 : 1;
    }
    const double outside[3] = { 3 * x[0], 3 * x[1], 3 * x[2] };
    const double d[3] = { -x[0], -x[1], -x[2] };
    const TriangleHit hit = caster.Intersect(outside, d, 1e30);
    missed += hit.Hit() ? 0 : 1;
    if (hit.Hit())
    {
      EXPECT_NEAR(hit.t, 2.0, 1e-12);
    }
  }
  EXPECT_EQ(missed, 0u) << "of " << 4 * targets.size() << " beams through vertices and edges";
  // And a dense terrestrial scan from inside: every beam of the full sphere of directions returns.
  ScannerParameters p;
  p.positions = { Vec3{ 0.05, -0.1, 0.02 } };
  p.lookAt = { 1, 0, 0 };
  p.horizontalFieldOfView = 360;
  p.verticalFieldOfView = 180;
  p.angularStep = 0.5;
  ScanPoints out;
  ASSERT_EQ(VirtualScan(p, sphere.points, sphere.triangles, out), "");
  EXPECT_EQ(out.beams, 720u * 361u);
  EXPECT_EQ(out.Size(), out.beams);
}

TEST(RayCaster, PacketsGiveEachBeamItsOwnHitAndTiesGoToTheSmallerTriangle)
{
  // A flat grid (every interior edge shared by two coplanar triangles: beams through an edge hit both at exactly the
  // same distance) and a sphere; beams aimed at vertices, edge midpoints and random points, cast alone and in
  // packets with different companions: the same hit, bit for bit, and on a tie the smaller triangle index.
  Mesh scene = Square(-1, 1, -1, 1, 0.0, 8);
  const std::size_t gridTriangles = scene.triangles.size() / 3;
  scene.Append(Icosphere(2, 0.3, { 0.2, 0.1, 1.0 }));
  RayCaster caster;
  ASSERT_EQ(caster.Build(scene.points, scene.triangles, 1), "");
  RayCaster threaded; // built on all threads: the same hits
  ASSERT_EQ(threaded.Build(scene.points, scene.triangles, 0), "");
  std::vector<double> origins, directions;
  RandomStream random(3);
  for (std::size_t i = 0; i < scene.Points(); ++i)
  {
    const double o[3] = { random.Uniform(-0.5, 0.5), random.Uniform(-0.5, 0.5), 2.5 };
    origins.insert(origins.end(), o, o + 3);
    for (int k = 0; k < 3; ++k)
      directions.push_back(scene.points[3 * i + k] - o[k]);
  }
  for (std::size_t t = 0; t < gridTriangles; ++t) // edge midpoints of the grid, from straight above
  {
    const double* a = &scene.points[3 * scene.triangles[3 * t]];
    const double* b = &scene.points[3 * scene.triangles[3 * t + 1]];
    origins.insert(origins.end(), { 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 2.0 });
    directions.insert(directions.end(), { 0.0, 0.0, -1.0 });
  }
  const std::size_t beams = origins.size() / 3;
  std::vector<TriangleHit> single(beams);
  int ties = 0;
  for (std::size_t i = 0; i < beams; ++i)
  {
    single[i] = caster.Intersect(&origins[3 * i], &directions[3 * i], 10.0);
    const TriangleHit other = threaded.Intersect(&origins[3 * i], &directions[3 * i], 10.0);
    EXPECT_EQ(other.triangle, single[i].triangle) << "beam " << i;
    EXPECT_EQ(std::memcmp(&other.t, &single[i].t, sizeof(double)), 0) << "beam " << i;
    const bool onGrid = single[i].Hit() && single[i].triangle < static_cast<std::int64_t>(gridTriangles);
    if (i < scene.Points() || !onGrid) // the sphere hides some of the grid
      continue;
    // A vertical beam through an edge midpoint meets both triangles at exactly t = 2 (every product a power of two
    // apart): it reports the smaller index of the grid triangles whose closed inside holds the point.
    EXPECT_EQ(single[i].t, 2.0);
    for (std::size_t t = 0; t < gridTriangles; ++t)
    {
      const double* o = &origins[3 * i];
      const double* d = &directions[3 * i];
      const double tt = -o[2] / d[2];
      const double x = o[0] + tt * d[0], y = o[1] + tt * d[1];
      // Inside test of the grid triangle t (closed), in the plane z = 0.
      const double* a = &scene.points[3 * scene.triangles[3 * t]];
      const double* b = &scene.points[3 * scene.triangles[3 * t + 1]];
      const double* c = &scene.points[3 * scene.triangles[3 * t + 2]];
      auto edge = [](const double* p, const double* q, double X, double Y) {
        return (q[0] - p[0]) * (Y - p[1]) - (q[1] - p[1]) * (X - p[0]);
      };
      const double e0 = edge(a, b, x, y), e1 = edge(b, c, x, y), e2 = edge(c, a, x, y);
      if (e0 >= 0 && e1 >= 0 && e2 >= 0 && (e0 == 0 || e1 == 0 || e2 == 0))
      {
        EXPECT_LE(single[i].triangle, static_cast<std::int64_t>(t)) << "beam " << i;
        ties += static_cast<std::int64_t>(t) != single[i].triangle ? 1 : 0;
      }
    }
  }
  EXPECT_GT(ties, 100); // the grid's shared edges were really hit
  // Packets: consecutive beams, then every third beam with an odd count, so each beam has other companions.
  for (std::size_t stride : { 1, 3 })
  {
    for (std::size_t first = 0; first < beams; first += RayCaster::PacketSize * stride)
    {
      std::vector<double> o, d;
      std::vector<std::size_t> which;
      const std::size_t size = RayCaster::PacketSize - (stride == 3 ? 1 : 0);
      for (std::size_t j = first; j < beams && which.size() < size; j += stride)
      {
        o.insert(o.end(), &origins[3 * j], &origins[3 * j] + 3);
        d.insert(d.end(), &directions[3 * j], &directions[3 * j] + 3);
        which.push_back(j);
      }
      std::vector<TriangleHit> hits(which.size());
      caster.Intersect(which.size(), o.data(), d.data(), 10.0, hits.data());
      for (std::size_t j = 0; j < which.size(); ++j)
      {
        const TriangleHit& h = single[which[j]];
        EXPECT_EQ(hits[j].triangle, h.triangle) << "beam " << which[j];
        EXPECT_EQ(std::memcmp(&hits[j].t, &h.t, sizeof(double)), 0) << "beam " << which[j];
        EXPECT_EQ(std::memcmp(&hits[j].u, &h.u, sizeof(double)), 0) << "beam " << which[j];
      }
    }
  }
}

TEST(RayCaster, FarFromTheOriginStaysExactAndWatertight)
{
  // Single precision inside Embree is relative to the surface's own box: a sphere 10^5 away from the origin,
  // scanned from 10^3 away from it, gives points on the sphere to double precision and no beam through a crack.
  const Vec3 centre{ 1.0e5, -2.0e5, 3.0e4 };
  const Mesh sphere = Icosphere(4, 1.0, centre);
  RayCaster caster;
  ASSERT_EQ(caster.Build(sphere.points, sphere.triangles), "");
  std::size_t missed = 0;
  for (std::size_t i = 0; i < sphere.Points(); ++i)
  {
    const double* x = &sphere.points[3 * i];
    const double u[3] = { x[0] - centre[0], x[1] - centre[1], x[2] - centre[2] };
    const double o[3] = { centre[0] + 1000 * u[0], centre[1] + 1000 * u[1], centre[2] + 1000 * u[2] };
    const double d[3] = { -u[0], -u[1], -u[2] };
    const TriangleHit hit = caster.Intersect(o, d, 1e30);
    missed += hit.Hit() ? 0 : 1;
    if (hit.Hit())
    {
      EXPECT_NEAR(hit.t, 999.0, 1e-9);
    }
    const double inside[3] = { centre[0] + 0.1, centre[1] - 0.2, centre[2] + 0.05 };
    const double e[3] = { x[0] - inside[0], x[1] - inside[1], x[2] - inside[2] };
    missed += caster.Intersect(inside, e, 1e30).Hit() ? 0 : 1;
  }
  EXPECT_EQ(missed, 0u);
}

TEST(RayCaster, EveryGeometryQualityAndPacketWidthGivesTheSameExactHits)
{
  // The exact user geometry cast one beam at a time is the reference; Embree's enlarged single-precision triangles
  // with the double-precision filter, every build quality and every packet width must give the same triangle,
  // distance and barycentrics bit for bit: beams through an icosphere's shared vertices and edge midpoints (from
  // inside and outside), through a grid's shared edges (ties), and random beams (some missing everything).
  Mesh scene = Icosphere(3, 1.0);
  scene.Append(Square(-2, 2, -2, 2, -1.5, 6));
  scene.Append(Icosphere(2, 0.3, { 1.4, 0.3, 0.2 }));
  std::vector<double> origins, directions;
  for (std::size_t i = 0; i < 642; ++i) // the level-3 icosphere's vertices
  {
    const double* x = &scene.points[3 * i];
    origins.insert(origins.end(), { 0.1, -0.2, 0.05 });
    directions.insert(directions.end(), { x[0] - 0.1, x[1] + 0.2, x[2] - 0.05 });
    origins.insert(origins.end(), { 3 * x[0], 3 * x[1], 3 * x[2] });
    directions.insert(directions.end(), { -x[0], -x[1], -x[2] });
  }
  for (std::size_t t = 0; t < 1280; t += 3) // edge midpoints of the icosphere, from inside
  {
    const double* a = &scene.points[3 * scene.triangles[3 * t]];
    const double* b = &scene.points[3 * scene.triangles[3 * t + 1]];
    origins.insert(origins.end(), { -0.3, 0.3, 0.3 });
    directions.insert(
      directions.end(), { 0.5 * (a[0] + b[0]) + 0.3, 0.5 * (a[1] + b[1]) - 0.3, 0.5 * (a[2] + b[2]) - 0.3 });
  }
  for (int i = 0; i <= 12; ++i) // the grid's shared edges, from straight above (beside the sphere)
    for (int j = 0; j <= 12; ++j)
    {
      origins.insert(origins.end(), { -2.0 + i / 3.0, -2.0 + j / 6.0, 3.0 });
      directions.insert(directions.end(), { 0.0, 0.0, -1.0 });
    }
  RandomStream random(11);
  for (int i = 0; i < 1500; ++i)
  {
    origins.insert(origins.end(), { random.Uniform(-3, 3), random.Uniform(-3, 3), random.Uniform(-3, 3) });
    directions.insert(directions.end(), { random.Normal(), random.Normal(), random.Normal() });
  }
  const std::size_t beams = origins.size() / 3;
  RayCasterParameters exact;
  exact.geometry = RayCasterParameters::Geometry::ExactUser;
  exact.buildQuality = 2;
  RayCaster reference;
  ASSERT_EQ(reference.Build(scene.points, scene.triangles, exact), "");
  std::vector<TriangleHit> expected(beams);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < beams; ++i)
  {
    expected[i] = reference.Intersect(&origins[3 * i], &directions[3 * i], 100.0);
    hits += expected[i].Hit() ? 1 : 0;
  }
  EXPECT_GT(hits, beams / 2);
  EXPECT_LT(hits, beams);
  for (auto geometry : { RayCasterParameters::Geometry::Triangles, RayCasterParameters::Geometry::ExactUser })
    for (int quality : { 0, 1, 2 })
    {
      RayCasterParameters parameters;
      parameters.geometry = geometry;
      parameters.buildQuality = quality;
      RayCaster caster;
      ASSERT_EQ(caster.Build(scene.points, scene.triangles, parameters), "");
      for (unsigned width : { 1u, 4u, 8u, 16u })
      {
        ASSERT_TRUE(caster.SetPacketWidth(width));
        std::size_t different = 0;
        for (std::size_t first = 0; first < beams; first += RayCaster::PacketSize)
        {
          TriangleHit got[RayCaster::PacketSize];
          const std::size_t n = std::min<std::size_t>(RayCaster::PacketSize, beams - first);
          caster.Intersect(n, &origins[3 * first], &directions[3 * first], 100.0, got);
          for (std::size_t j = 0; j < n; ++j)
          {
            const TriangleHit& e = expected[first + j];
            different += got[j].triangle != e.triangle || std::memcmp(&got[j].t, &e.t, sizeof(double)) != 0 ||
                std::memcmp(&got[j].u, &e.u, sizeof(double)) != 0 || std::memcmp(&got[j].v, &e.v, sizeof(double)) != 0
              ? 1
              : 0;
          }
        }
        EXPECT_EQ(different, 0u) << "of " << beams << " beams, geometry " << static_cast<int>(geometry) << " quality "
                                 << quality << " width " << width;
      }
    }
}

TEST(RayCaster, NearlyCoplanarSurfacesGiveTheNearerOne)
{
  // Two separate squares 1e-9 apart (single precision cannot tell them apart at this scale) with different
  // triangulations: every beam from above must report the upper one at its exact distance.
  Mesh scene = Square(-1, 1, -1, 1, 0.0, 5);
  const auto lower = static_cast<std::int64_t>(scene.triangles.size() / 3);
  scene.Append(Square(-1, 1, -1, 1, 1e-9, 3));
  for (auto geometry : { RayCasterParameters::Geometry::Triangles, RayCasterParameters::Geometry::ExactUser })
  {
    RayCasterParameters parameters;
    parameters.geometry = geometry;
    RayCaster caster;
    ASSERT_EQ(caster.Build(scene.points, scene.triangles, parameters), "");
    RandomStream random(5);
    int wrong = 0;
    for (int i = 0; i < 4000; ++i)
    {
      const double o[3] = { random.Uniform(-0.5, 0.5), random.Uniform(-0.5, 0.5), 2.0 };
      const double d[3] = { random.Uniform(-0.7, 0.7) - o[0], random.Uniform(-0.7, 0.7) - o[1], -2.0 };
      const TriangleHit hit = caster.Intersect(o, d, 10.0);
      const double t = (1e-9 - o[2]) / d[2];
      wrong += hit.triangle >= lower && std::abs(hit.t - t) <= 1e-15 ? 0 : 1;
    }
    EXPECT_EQ(wrong, 0) << "geometry " << static_cast<int>(geometry);
  }
}

TEST(RayCaster, BadParametersAreRefusedWithTheirNames)
{
  const Mesh scene = Icosphere(1, 1.0);
  RayCasterParameters parameters;
  parameters.packetWidth = 3;
  RayCaster caster;
  EXPECT_EQ(caster.Build(scene.points, scene.triangles, parameters),
    "packetWidth = 3 is outside the accepted range {1, 4, 8, 16}");
  const double o[3] = { 0, 0, 5 }, d[3] = { 0, 0, -1 };
  EXPECT_FALSE(caster.Intersect(o, d, 10).Hit()); // empty: every beam misses
  parameters.packetWidth = 8;
  parameters.buildQuality = 3;
  EXPECT_EQ(caster.Build(scene.points, scene.triangles, parameters),
    "buildQuality = 3 is outside the accepted range {0, 1, 2} (0 low, 1 medium, 2 high)");
  parameters.buildQuality = 1;
  ASSERT_EQ(caster.Build(scene.points, scene.triangles, parameters), "");
  EXPECT_TRUE(caster.Intersect(o, d, 10).Hit());
  EXPECT_FALSE(caster.SetPacketWidth(5));
  EXPECT_EQ(caster.Parameters().packetWidth, 8u);
}

TEST(VirtualScan, SphereFromOutsideGivesTheVisibleCapAndItsSolidAngle)
{
  const double R = 1.0, D = 5.0;
  const Mesh sphere = Icosphere(5, R);
  const double rIn = InscribedRadius(sphere);
  ScannerParameters p;
  p.positions = { Vec3{ 0.0, -D, 0.0 } };
  p.lookAt = { 0, 0, 0 };
  p.horizontalFieldOfView = 30;
  p.verticalFieldOfView = 30;
  p.angularStep = 0.2;
  ScanPoints out;
  ASSERT_EQ(VirtualScan(p, sphere.points, sphere.triangles, out), "");
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  ASSERT_EQ(out.beams, 151u * 151u);
  const double s[3] = { 0.0, -D, 0.0 };
  // Per beam: inside the cone of the inscribed ball it must hit, outside the circumscribed one it must not.
  std::vector<char> hit(out.beams, 0);
  for (std::uint64_t b : out.beam)
    hit[b] = 1;
  for (std::uint64_t b = 0; b < out.beams; ++b)
  {
    double o[3], d[3];
    std::int64_t pose;
    pattern.Beam(b, o, d, pose);
    const double angle = std::acos(std::min(1.0, d[1]));
    if (angle < std::asin(rIn / D) - 1e-12)
    {
      EXPECT_TRUE(hit[b]) << "beam " << b << " at " << angle;
    }
    if (angle > std::asin(R / D) + 1e-12)
    {
      EXPECT_FALSE(hit[b]) << "beam " << b << " at " << angle;
    }
  }
  // The count: the cap's solid angle over the grid's solid angle per beam (step^2 cos(elevation), ~1% here).
  const double alpha = std::asin(R / D);
  const double expected = 2 * Pi * (1 - std::cos(alpha)) / std::pow(p.angularStep * Pi / 180, 2);
  EXPECT_NEAR(static_cast<double>(out.Size()), expected, 0.02 * expected);
  const double visibleCos = std::acos(rIn / D); // half-angle of the visible cap, seen from the centre
  for (std::size_t i = 0; i < out.Size(); ++i)
  {
    const double* x = &out.points[3 * i];
    const double n[3] = { out.normals[3 * i], out.normals[3 * i + 1], out.normals[3 * i + 2] };
    const double r = std::sqrt(Dot3(x, x));
    EXPECT_GE(r, rIn - 1e-12);
    EXPECT_LE(r, R + 1e-12);
    // The outer face was hit (the normal, flipped towards the scanner, points outwards) and on the near side.
    EXPECT_GT(Dot3(n, x), 0.0) << "point " << i << " on a face seen from behind";
    EXPECT_LE(std::acos(-x[1] / r), visibleCos + 0.02) << "point " << i << " beyond the visible cap";
    const double toScanner[3] = { s[0] - x[0], s[1] - x[1], s[2] - x[2] };
    EXPECT_GT(Dot3(n, toScanner), 0.0);
    EXPECT_NEAR(out.range[i], std::sqrt(Dot3(toScanner, toScanner)), 1e-9);
    EXPECT_EQ(out.pose[i], 0);
  }
}

TEST(VirtualScan, SmallSquareCastsAnExactShadow)
{
  // A depth camera 3 above a large square (z = 0) with a small one at z = 1.5 in front: per beam, the analytic
  // answer (small square, large square, or nothing) by plane intersections.
  Mesh scene = Square(-1, 1, -1, 1, 0.0, 4); // triangles 0..31
  const std::size_t largeTriangles = scene.triangles.size() / 3;
  scene.Append(Square(-0.2, 0.3, -0.25, 0.15, 1.5, 1));
  ScannerParameters p;
  p.type = ScannerType::DepthCamera;
  p.positions = { Vec3{ 0.05, 0.02, 3.0 } };
  p.lookAt = { 0.05, 0.02, 0.0 };
  p.up = { 0, 1, 0 };
  p.horizontalFieldOfView = 50;
  p.verticalFieldOfView = 50;
  p.resolution[0] = 200;
  p.resolution[1] = 200;
  ScanPoints out;
  ASSERT_EQ(VirtualScan(p, scene.points, scene.triangles, out), "");
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  std::vector<std::int64_t> got(out.beams, -1);
  for (std::size_t i = 0; i < out.Size(); ++i)
    got[out.beam[i]] = out.triangle[i] < static_cast<std::int64_t>(largeTriangles) ? 0 : 1;
  int shadowed = 0, checked = 0;
  for (std::uint64_t b = 0; b < out.beams; ++b)
  {
    double o[3], d[3];
    std::int64_t pose;
    pattern.Beam(b, o, d, pose);
    const double ts = (1.5 - o[2]) / d[2], tl = -o[2] / d[2];
    const double xs = o[0] + ts * d[0], ys = o[1] + ts * d[1], xl = o[0] + tl * d[0], yl = o[1] + tl * d[1];
    auto inside = [](double x, double y, double x0, double x1, double y0, double y1, double& margin) {
      margin = std::min({ x - x0, x1 - x, y - y0, y1 - y });
      return margin > 0;
    };
    double ms, ml;
    const bool small = inside(xs, ys, -0.2, 0.3, -0.25, 0.15, ms);
    const bool large = inside(xl, yl, -1, 1, -1, 1, ml);
    if (std::abs(ms) < 1e-9 || std::abs(ml) < 1e-9)
      continue; // grazing an edge: either answer is right
    ++checked;
    const std::int64_t expected = small ? 1 : (large ? 0 : -1);
    EXPECT_EQ(got[b], expected) << "beam " << b;
    shadowed += (!small || !large) ? 0 : 1;
  }
  EXPECT_GT(shadowed, 500); // the shadow is there and covered by beams
  EXPECT_GT(checked, 39000);
  // No point of the large square inside the shadow's outline (the small square projected from the scanner).
  for (std::size_t i = 0; i < out.Size(); ++i)
  {
    if (out.triangle[i] >= static_cast<std::int64_t>(largeTriangles))
    {
      EXPECT_NEAR(out.points[3 * i + 2], 1.5, 1e-12);
      continue;
    }
    const double x = out.points[3 * i], y = out.points[3 * i + 1];
    // Project towards the scanner onto z = 1.5: halfway up (3 - 1.5) / 3.
    const double px = x + 0.5 * (0.05 - x), py = y + 0.5 * (0.02 - y);
    const bool inShadow = px > -0.2 + 1e-9 && px < 0.3 - 1e-9 && py > -0.25 + 1e-9 && py < 0.15 - 1e-9;
    EXPECT_FALSE(inShadow) << "point " << i << " (" << x << ", " << y << ") of the large square is in the shadow";
  }
}

TEST(VirtualScan, NoiseAndDropoutAreSeededAndThreadIndependent)
{
  const Mesh plane = Square(-2, 2, -2, 2, 0.0, 3);
  ScannerParameters p;
  p.positions = { Vec3{ 0, 0, 2 }, Vec3{ 0.5, 0.3, 2.5 } };
  p.lookAt = { 0, 0, 0 };
  p.horizontalFieldOfView = 60;
  p.verticalFieldOfView = 60;
  p.angularStep = 0.25;
  p.rangeNoise = 0.01;
  p.dropoutProbability = 0.3;
  p.angularJitter = 0.05;
  p.seed = 42;
  ScanPoints serial;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, serial), "");
  for (std::size_t threads : { 2, 3, 7 })
  {
    ScanPoints parallel;
    ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, parallel, Threads(threads)), "");
    EXPECT_TRUE(SameBits(serial.points, parallel.points)) << threads << " threads";
    EXPECT_TRUE(SameBits(serial.range, parallel.range));
    EXPECT_TRUE(SameBits(serial.normals, parallel.normals));
    EXPECT_EQ(serial.beam, parallel.beam);
    EXPECT_TRUE(SameBits(serial.barycentric, parallel.barycentric));
  }
  ScanPoints again;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, again), "");
  EXPECT_TRUE(SameBits(serial.points, again.points));
  p.seed = 43;
  ScanPoints other;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, other), "");
  EXPECT_FALSE(SameBits(serial.range, other.range));
  // Dropout: each hitting beam dropped with probability 0.3 (binomial, 5 sigma).
  const double hitting = static_cast<double>(serial.Size() + serial.dropped);
  EXPECT_NEAR(static_cast<double>(serial.dropped) / hitting, 0.3, 5 * std::sqrt(0.3 * 0.7 / hitting));
  // Range noise without jitter: measured - true ~ N(0, 0.01); the true range to the plane z = 0 along the beam.
  p.angularJitter = 0.0;
  p.dropoutProbability = 0.0;
  ScanPoints noisy;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, noisy), "");
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < noisy.Size(); ++i)
  {
    double o[3], d[3];
    std::int64_t pose;
    pattern.Beam(noisy.beam[i], o, d, pose);
    const double e = noisy.range[i] - (-o[2] / d[2]);
    sum += e;
    sum2 += e * e;
    // The point lies on its beam at the measured range.
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(noisy.points[3 * i + k], o[k] + noisy.range[i] * d[k], 1e-12);
  }
  const double n = static_cast<double>(noisy.Size());
  EXPECT_NEAR(sum / n, 0.0, 5 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.01, 0.01 * 5 / std::sqrt(2 * n));
}

TEST(VirtualScan, WithoutBarycentricsTheCloudIsTheSame)
{
  // A scan that keeps no barycentric coordinates (nothing to interpolate) gives the same points, bit for bit.
  const Mesh sphere = Icosphere(3, 1.0);
  ScannerParameters p;
  p.positions = { Vec3{ 0, -3, 0.2 } };
  p.angularStep = 0.5;
  p.rangeNoise = 0.01;
  ScanPoints with, without;
  without.withBarycentric = false;
  ASSERT_EQ(VirtualScan(p, sphere.points, sphere.triangles, with, Threads(2)), "");
  ASSERT_EQ(VirtualScan(p, sphere.points, sphere.triangles, without, Threads(2)), "");
  ASSERT_GT(with.Size(), 100u);
  EXPECT_EQ(with.barycentric.size(), 2 * with.Size());
  EXPECT_TRUE(without.barycentric.empty());
  EXPECT_FALSE(without.withBarycentric); // kept through the scan's Clear
  EXPECT_TRUE(SameBits(with.points, without.points));
  EXPECT_TRUE(SameBits(with.normals, without.normals));
  EXPECT_EQ(with.triangle, without.triangle);
  EXPECT_EQ(with.beam, without.beam);
}

TEST(VirtualScan, BadInputIsRefusedWithThePropertyNamed)
{
  const Mesh plane = Square(-1, 1, -1, 1, 0.0, 2);
  auto expectError = [&](const ScannerParameters& p, const std::string& property, const Mesh& mesh) {
    ScanPoints out;
    out.range = { 1.0 };
    const std::string error = VirtualScan(p, mesh.points, mesh.triangles, out);
    EXPECT_NE(error.find(property), std::string::npos) << "got: " << error;
    EXPECT_EQ(out.Size(), 0u);
  };
  ScannerParameters p;
  p.angularStep = 0;
  expectError(p, "AngularStep", plane);
  p = ScannerParameters{};
  p.horizontalFieldOfView = 361;
  expectError(p, "HorizontalFieldOfView", plane);
  p = ScannerParameters{};
  p.positions = { Vec3{ 0, 0, 1 }, Vec3{ std::nan(""), 0, 1 } };
  expectError(p, "Positions", plane);
  p = ScannerParameters{};
  p.positions.clear();
  expectError(p, "Positions", plane);
  p = ScannerParameters{};
  p.lookAt = p.positions[0];
  expectError(p, "LookAt", plane);
  p = ScannerParameters{};
  p.dropoutProbability = 1.5;
  expectError(p, "DropoutProbability", plane);
  p = ScannerParameters{};
  p.rangeNoise = -1;
  expectError(p, "RangeNoise", plane);
  p = ScannerParameters{};
  p.maximumRange = std::nan("");
  expectError(p, "MaximumRange", plane);
  p = ScannerParameters{};
  p.type = ScannerType::DepthCamera;
  p.resolution[1] = 0;
  expectError(p, "Resolution", plane);
  p.resolution[1] = 10;
  p.horizontalFieldOfView = 180;
  expectError(p, "HorizontalFieldOfView", plane);
  p = ScannerParameters{};
  p.type = ScannerType::Line;
  p.lineSpacing = 0;
  expectError(p, "LineSpacing", plane);
  p.lineMotion = LineMotion::Turntable;
  p.turntableSteps = 0;
  expectError(p, "TurntableSteps", plane);
  expectError(ScannerParameters{}, "no polygons", Mesh{});
  Mesh broken = plane;
  broken.points[4] = std::nan("");
  expectError(ScannerParameters{}, "not finite", broken);
  broken = plane;
  broken.triangles[5] = 99;
  expectError(ScannerParameters{}, "outside", broken);
}

TEST(VirtualScan, BeamBudgetIsRefusedBeforeAnyWork)
{
  const Mesh plane = Square(-1, 1, -1, 1, 0.0, 2);
  ScannerParameters p;
  p.horizontalFieldOfView = 360;
  p.verticalFieldOfView = 180;
  p.angularStep = 0.01; // 36000 x 18001 beams
  p.maximumBeams = 100000000;
  ScanPoints out;
  bool called = false;
  const std::string error = VirtualScan(p, plane.points, plane.triangles, out, SerialFor, [&](double) {
    called = true;
    return true;
  });
  EXPECT_NE(error.find("MaximumBeams"), std::string::npos) << error;
  EXPECT_NE(error.find("648036000 beams"), std::string::npos) << error;
  EXPECT_FALSE(called);
  EXPECT_EQ(out.Size(), 0u);
  // A count past 2^64 is refused as well (no overflow into a small number).
  p.angularStep = 1e-4;
  p.positions.assign(100000, Vec3{ 0, 0, 2 });
  p.maximumBeams = AbsoluteMaximumBeams;
  EXPECT_NE(VirtualScan(p, plane.points, plane.triangles, out).find("MaximumBeams"), std::string::npos);
  // Exactly at the budget is accepted.
  p = ScannerParameters{};
  p.positions = { Vec3{ 0, 0, 2 } };
  p.horizontalFieldOfView = 10;
  p.verticalFieldOfView = 10;
  p.angularStep = 1;
  p.maximumBeams = 121;
  EXPECT_EQ(VirtualScan(p, plane.points, plane.triangles, out), "");
  EXPECT_EQ(out.beams, 121u);
  p.maximumBeams = 120;
  EXPECT_NE(VirtualScan(p, plane.points, plane.triangles, out), "");
}

TEST(VirtualScan, MaximumRangeAndIntensity)
{
  const Mesh plane = Square(-10, 10, -10, 10, 0.0, 2);
  ScannerParameters p;
  p.positions = { Vec3{ 0, 0, 2 } };
  p.lookAt = { 0, 0, 0 };
  p.up = { 0, 1, 0 };
  p.horizontalFieldOfView = 120;
  p.verticalFieldOfView = 120;
  p.angularStep = 1;
  p.maximumRange = 3.0;
  ScanPoints out;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, out), "");
  ASSERT_GT(out.Size(), 100u);
  for (std::size_t i = 0; i < out.Size(); ++i)
  {
    EXPECT_LT(out.range[i], 3.0);
    const double cosine = 2.0 / out.range[i]; // the plane's normal is z; the scanner 2 above it
    EXPECT_NEAR(out.intensity[i], cosine / (out.range[i] * out.range[i]), 1e-12);
    EXPECT_NEAR(out.normals[3 * i + 2], 1.0, 1e-12);
  }
  // Beams reaching the plane within range: those within acos(2/3) of straight down, and no other.
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  std::size_t expected = 0;
  for (std::uint64_t b = 0; b < pattern.BeamCount(); ++b)
  {
    double o[3], d[3];
    std::int64_t pose;
    pattern.Beam(b, o, d, pose);
    const double t = -2.0 / d[2];
    expected += d[2] < 0 && t < 3.0 - 1e-9 ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(out.Size()), static_cast<double>(expected), 2.0);
}

TEST(BeamPattern, RunsOfBeamsEqualSingleBeamsAcrossRowsAndPoses)
{
  // Beams() steps row, column and pose from its first beam; Beam() divides them out of each index.
  ScannerParameters terrestrial;
  terrestrial.positions = { Vec3{ 0, -3, 0 }, Vec3{ 3, 0, 0.5 } };
  terrestrial.horizontalFieldOfView = 7;
  terrestrial.verticalFieldOfView = 5;
  terrestrial.angularStep = 1;
  ScannerParameters camera = terrestrial;
  camera.type = ScannerType::DepthCamera;
  camera.resolution[0] = 5;
  camera.resolution[1] = 3;
  ScannerParameters turntable = terrestrial;
  turntable.type = ScannerType::Line;
  turntable.lineMotion = LineMotion::Turntable;
  turntable.turntableSteps = 4;
  for (const ScannerParameters& p : { terrestrial, camera, turntable })
  {
    BeamPattern pattern;
    ASSERT_EQ(pattern.Setup(p), "");
    const std::uint64_t beams = pattern.BeamCount();
    ASSERT_GT(pattern.PoseCount(), 1u);
    for (std::uint64_t first : { std::uint64_t(0), std::uint64_t(3), pattern.BeamsPerPose() - 2 })
    {
      const auto count = static_cast<std::size_t>(beams - first);
      std::vector<double> origins(3 * count), directions(3 * count);
      std::vector<std::int64_t> poses(count);
      pattern.Beams(first, count, origins.data(), directions.data(), poses.data());
      for (std::size_t i = 0; i < count; ++i)
      {
        double o[3], d[3];
        std::int64_t pose;
        pattern.Beam(first + i, o, d, pose);
        EXPECT_EQ(pose, poses[i]) << "beam " << first + i;
        EXPECT_EQ(std::memcmp(o, &origins[3 * i], sizeof o), 0) << "beam " << first + i;
        EXPECT_EQ(std::memcmp(d, &directions[3 * i], sizeof d), 0) << "beam " << first + i;
      }
    }
  }
}

TEST(VirtualScan, LineScannerOnAPathAndOnATurntable)
{
  // A fan moving along x over the plane z = 0, looking straight down: fans every 0.1 over a path of 1.
  const Mesh plane = Square(-2, 2, -2, 2, 0.0, 2);
  ScannerParameters p;
  p.type = ScannerType::Line;
  p.positions = { Vec3{ -0.5, 0, 1 }, Vec3{ 0.0, 0, 1 }, Vec3{ 0.5, 0, 1 } };
  p.lookAt = { 0, 0, 0 }; // below the middle of the path
  p.up = { 0, 1, 0 };
  p.verticalFieldOfView = 40;
  p.angularStep = 1;
  p.lineSpacing = 0.1;
  ScanPoints out;
  ASSERT_EQ(VirtualScan(p, plane.points, plane.triangles, out), "");
  EXPECT_EQ(out.beams, 11u * 41u);
  ASSERT_EQ(out.Size(), out.beams);
  for (std::size_t i = 0; i < out.Size(); ++i)
  {
    EXPECT_NEAR(out.points[3 * i], -0.5 + 0.1 * static_cast<double>(out.pose[i]), 1e-12); // the fan's x
    EXPECT_NEAR(out.points[3 * i + 2], 0.0, 1e-12);
    EXPECT_LE(std::abs(out.points[3 * i + 1]), std::tan(20.0 * Pi / 180) + 1e-12);
  }
  // The set-up: the path's two segments, and per fan shown its central beam and the fan's two ends.
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  std::vector<double> segments;
  std::vector<std::int64_t> shown;
  pattern.SetupLines(1.0, 4, segments, shown);
  EXPECT_EQ(shown.size(), 2u + 4u * 3u);
  EXPECT_EQ(std::count(shown.begin(), shown.end(), -1), 2);
  EXPECT_EQ(std::count(shown.begin(), shown.end(), 10), 3); // the last fan is among those shown
  // LookAt on a path (docs/methods/virtual-scanner.md, "What LookAt means"): every fan looks in the direction from
  // the middle of the path to LookAt, here obliquely; so the middle fan's central beam lands on LookAt and the
  // others side by side on the plane, 0.1 apart like the fans, not all on the line through LookAt along Up.
  {
    ScannerParameters oblique = p;
    oblique.lookAt = { 0.3, 0.3, 0.0 };
    BeamPattern path;
    ASSERT_EQ(path.Setup(oblique), "");
    ASSERT_EQ(path.PoseCount(), 11u);
    for (std::uint64_t k = 0; k < path.PoseCount(); ++k)
    {
      double origin[3], direction[3];
      std::int64_t pose;
      path.Beam(k * path.BeamsPerPose() + path.BeamsPerPose() / 2, origin, direction, pose); // the central beam
      ASSERT_EQ(pose, static_cast<std::int64_t>(k));
      const double t = -origin[2] / direction[2]; // to z = 0
      EXPECT_NEAR(origin[0] + t * direction[0], 0.3 + 0.1 * (static_cast<double>(k) - 5.0), 1e-12) << k;
      EXPECT_NEAR(origin[1] + t * direction[1], 0.3, 1e-12) << k;
    }
    // A LookAt at the middle of the path gives no direction: an error that says so, not a scan.
    oblique.lookAt = { 0.0, 0.0, 1.0 };
    EXPECT_NE(path.Setup(oblique).find("LookAt: it coincides with the middle of the path"), std::string::npos);
    // A path whose middle lies inside a segment other than the first: a bent path of arc length 3, middle at
    // (1, 0.5, 1); LookAt straight below it gives a vertical middle fan.
    oblique.positions = { Vec3{ 0, 0, 1 }, Vec3{ 1, 0, 1 }, Vec3{ 1, 2, 1 } };
    oblique.lookAt = { 1.0, 0.5, 0.0 };
    oblique.lineSpacing = 0.5;
    ASSERT_EQ(path.Setup(oblique), "");
    double origin[3], direction[3];
    std::int64_t pose;
    path.Beam(3 * path.BeamsPerPose() + path.BeamsPerPose() / 2, origin, direction, pose); // fan 3, at s = 1.5
    EXPECT_NEAR(origin[0], 1.0, 1e-12);
    EXPECT_NEAR(origin[1], 0.5, 1e-12);
    EXPECT_NEAR(direction[2], -1.0, 1e-12);
  }
  // Turntable: a sphere turned 8 times a full turn in front of a fan sees every side of it.
  const Mesh sphere = Icosphere(3, 0.5);
  p.lineMotion = LineMotion::Turntable;
  p.positions = { Vec3{ 0, -3, 0 } };
  p.lookAt = { 0, 0, 0 };
  p.up = { 0, 0, 1 };
  p.turntableSteps = 8;
  ASSERT_EQ(VirtualScan(p, sphere.points, sphere.triangles, out), "");
  EXPECT_EQ(out.beams, 8u * 41u);
  std::vector<int> sides(8, 0);
  for (std::size_t i = 0; i < out.Size(); ++i)
  {
    const double azimuth = std::atan2(out.points[3 * i + 1], out.points[3 * i]);
    sides[static_cast<std::size_t>(std::floor((azimuth + Pi) / (2 * Pi) * 8 + 0.5)) % 8] += 1;
    EXPECT_NEAR(std::sqrt(Dot3(&out.points[3 * i], &out.points[3 * i])), 0.5, 0.01);
  }
  for (int s = 0; s < 8; ++s)
    EXPECT_GT(sides[s], 0) << "side " << s;
}

TEST(VirtualScan, FullTurnDoesNotRepeatItsFirstColumn)
{
  ScannerParameters p;
  p.horizontalFieldOfView = 360;
  p.verticalFieldOfView = 10;
  p.angularStep = 1;
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  EXPECT_EQ(pattern.BeamCount(), 360u * 11u);
  double o[3], first[3], last[3];
  std::int64_t pose;
  pattern.Beam(0, o, first, pose);
  pattern.Beam(359, o, last, pose);
  // Neighbours on the lowest row, one step of azimuth apart (sin(elevation) is the beam's z, Up being z).
  EXPECT_NEAR(first[2], last[2], 1e-15);
  EXPECT_NEAR(Dot3(first, last), (1 - first[2] * first[2]) * std::cos(Pi / 180) + first[2] * first[2], 1e-12);
}

TEST(VirtualScan, SharesOfTheBeamsConcatenateToTheWholeScan)
{
  // What each MPI rank does: consecutive shares of the beams, with noise and dropout, give the whole cloud in order.
  const Mesh sphere = Icosphere(3, 1.0);
  ScannerParameters p;
  p.positions = { Vec3{ 0, -4, 0.3 }, Vec3{ 3, 1, 0 } };
  p.angularStep = 0.3;
  p.rangeNoise = 0.01;
  p.dropoutProbability = 0.2;
  p.seed = 5;
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  RayCaster caster;
  ASSERT_EQ(caster.Build(sphere.points, sphere.triangles), "");
  ScanPoints whole;
  ASSERT_EQ(CastBeams(p, pattern, caster, whole), "");
  ASSERT_GT(whole.Size(), 1000u);
  for (std::uint64_t ranks : { 2u, 3u, 4u })
  {
    ScanPoints joined;
    for (std::uint64_t r = 0; r < ranks; ++r)
    {
      ScanPoints piece;
      const std::uint64_t b = pattern.BeamCount();
      ASSERT_EQ(CastBeams(p, pattern, caster, piece, SerialFor, {}, b * r / ranks, b * (r + 1) / ranks), "");
      EXPECT_EQ(piece.beams, b * (r + 1) / ranks - b * r / ranks);
      joined.points.append(piece.points.begin(), piece.points.end());
      joined.range.append(piece.range.begin(), piece.range.end());
      joined.beam.append(piece.beam.begin(), piece.beam.end());
    }
    EXPECT_TRUE(SameBits(whole.points, joined.points)) << ranks << " shares";
    EXPECT_TRUE(SameBits(whole.range, joined.range));
    EXPECT_EQ(whole.beam, joined.beam);
  }
}

namespace
{
/// A terrestrial scanner at the centre of a unit icosphere seeing all of it, `step` degrees apart: every beam hits.
ScannerParameters InsideSphere(double step)
{
  ScannerParameters p;
  p.positions = { Vec3{ 0.0, 0.0, 0.0 } };
  p.lookAt = { 1.0, 0.0, 0.0 };
  p.horizontalFieldOfView = 360.0;
  p.verticalFieldOfView = 180.0;
  p.angularStep = step;
  p.maximumBeams = AbsoluteMaximumBeams;
  return p;
}
/// In a child process: limits the address space to what it maps plus `headroom`, scans on two threads and exits
/// with 0 when the scan returned the out-of-memory error naming its properties and an empty cloud (1 otherwise).
void CastUnderALimit(
  const ScannerParameters& p, const BeamPattern& pattern, const RayCaster& caster, std::size_t headroom)
{
  long pages = 0;
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r"))
  {
    if (std::fscanf(statm, "%ld", &pages) != 1)
      pages = 0;
    std::fclose(statm);
  }
  const rlim_t mapped = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE));
  const rlimit limit{ mapped + static_cast<rlim_t>(headroom), RLIM_INFINITY };
  setrlimit(RLIMIT_AS, &limit);
  const auto threads = [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::thread other([&] { body(count / 2, count); });
    body(0, count / 2);
    other.join();
  };
  ScanPoints scan;
  scan.withBarycentric = false;
  const std::string error = CastBeams(p, pattern, caster, scan, threads);
  std::fprintf(stderr, "%s\n", error.c_str());
  const bool named = error.find("MaximumBeams") != std::string::npos &&
    error.find("AngularStep") != std::string::npos && error.find("out of memory") != std::string::npos;
  std::_Exit(named && scan.Size() == 0 ? 0 : 1);
}
} // namespace

// Before casting, a cloud that clearly cannot fit is refused naming MaximumBeams, the properties that set the beam
// count and the memory needed; what fits (even only because few beams return) is not refused.
TEST(VirtualScan, CheckCloudMemoryRefusesOnlyWhatCannotFit)
{
  const Mesh sphere = Icosphere(3);
  RayCaster caster;
  ASSERT_EQ(caster.Build(sphere.points, sphere.triangles), "");
  BeamPattern inside;
  ASSERT_EQ(inside.Setup(InsideSphere(1.0)), "");
  const auto beams = static_cast<std::size_t>(inside.BeamCount());
  const std::size_t bytes = CloudBytesPerPoint(false) + 8;
  EXPECT_EQ(CloudBytesPerPoint(false), 72u);
  EXPECT_EQ(CloudBytesPerPoint(true), 88u);
  EXPECT_EQ(CheckCloudMemory(InsideSphere(1.0), inside, caster, false, 8, beams * bytes), "");
  const std::string refused = CheckCloudMemory(InsideSphere(1.0), inside, caster, false, 8, beams * bytes / 2);
  for (const char* word : { "MaximumBeams", "AngularStep", "HorizontalFieldOfView", "VerticalFieldOfView", "needs",
         " GB", "80 bytes a point" })
    EXPECT_NE(refused.find(word), std::string::npos) << word << ": " << refused;
  // From outside, a quarter or so of the beams hit: room for the hits is enough, though not for every beam.
  ScannerParameters outside = InsideSphere(1.0);
  outside.positions = { Vec3{ 0.0, -3.0, 0.0 } };
  outside.lookAt = { 0.0, 0.0, 0.0 };
  BeamPattern far;
  ASSERT_EQ(far.Setup(outside), "");
  ScanPoints scan;
  scan.withBarycentric = false;
  ASSERT_EQ(CastBeams(outside, far, caster, scan), "");
  ASSERT_LT(2 * scan.Size(), beams);
  EXPECT_EQ(CheckCloudMemory(outside, far, caster, false, 8, (scan.Size() * 11 / 10) * bytes), "");
  EXPECT_NE(CheckCloudMemory(outside, far, caster, false, 8, (scan.Size() * 9 / 10) * bytes), "");
  ScannerParameters camera = outside;
  camera.type = ScannerType::DepthCamera;
  EXPECT_EQ(BeamCountProperties(camera), "Resolution, Positions");
}

// Memory that runs out while casting (here an address-space limit below the cloud's size, in a child process) is an
// error naming MaximumBeams and the properties that set the beam count, with an empty cloud: not std::terminate.
// AddressSanitizer's allocator does not throw std::bad_alloc when memory runs out: it reports and aborts the process
// (its allocator_may_return_null is off), so under the sanitizer build there is no failure path to test here.
#if defined(__SANITIZE_ADDRESS__)
#define PLANTMORPH_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PLANTMORPH_ADDRESS_SANITIZER 1
#endif
#endif
TEST(VirtualScan, RunningOutOfMemoryWhileCastingIsAnErrorNotAnAbort)
{
#ifdef PLANTMORPH_ADDRESS_SANITIZER
  GTEST_SKIP() << "AddressSanitizer aborts on an allocation it cannot serve instead of throwing std::bad_alloc";
#endif
  const Mesh sphere = Icosphere(2);
  RayCaster caster;
  ASSERT_EQ(caster.Build(sphere.points, sphere.triangles), "");
  const ScannerParameters p = InsideSphere(0.05); // 7200 x 3601 beams, a cloud of 1.9 GB
  BeamPattern pattern;
  ASSERT_EQ(pattern.Setup(p), "");
  ::testing::GTEST_FLAG(death_test_style) = "threadsafe"; // the caster's build started threads
  EXPECT_EXIT(CastUnderALimit(p, pattern, caster, std::size_t(512) << 20), ::testing::ExitedWithCode(0),
    "MaximumBeams / AngularStep");
}
