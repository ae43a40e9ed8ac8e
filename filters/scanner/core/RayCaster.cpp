// SPDX-License-Identifier: GPL-3.0-or-later
#include "RayCaster.h"

#include <plantmorph/RangeError.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <sys/types.h>
#include <utility>

namespace plantmorph
{

struct RayCaster::Embree
{
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<std::int64_t> bytes{ 0 };
  std::atomic<std::int64_t> peak{ 0 };
};

namespace
{
/// Embree's far distance for a beam that starts at `start` (the exact distances t are from the beam's own origin):
/// t's distance from there, rounded up to single precision (the 1e-6 and the slack cover the rounding), and never
/// below Embree's near distance 0, which a ray must keep (tnear <= tfar) even when rounding puts t a hair before
/// the start.
float FarLimit(double t, double start, double slack)
{
  return static_cast<float>(std::max(0.0, (t - start) * (1.0 + 1e-6) + slack));
}

bool CountMemory(void* user, ssize_t bytes, bool /*post*/)
{
  auto* e = static_cast<RayCaster::Embree*>(user);
  const std::int64_t now = e->bytes.fetch_add(static_cast<std::int64_t>(bytes)) + static_cast<std::int64_t>(bytes);
  std::int64_t peak = e->peak.load();
  while (now > peak && !e->peak.compare_exchange_weak(peak, now))
  {
  }
  return true;
}

std::string DeviceError(RTCDevice device, const char* what)
{
  const RTCError code = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  std::ostringstream s;
  s << "Embree: " << what << " failed (error " << static_cast<int>(code)
    << (code == RTC_ERROR_OUT_OF_MEMORY ? ": out of memory for the surface's ray-casting hierarchy" : "") << ")";
  return s.str();
}

/// The beam in Woop et al.'s sheared frame: kz the dominant axis of the direction, the shear taking it to +z.
struct ShearedRay
{
  double origin[3];
  int kx, ky, kz;
  double sx, sy, sz;
};

ShearedRay Shear(const double origin[3], const double direction[3])
{
  ShearedRay r;
  for (int k = 0; k < 3; ++k)
    r.origin[k] = origin[k];
  const double ax = std::abs(direction[0]), ay = std::abs(direction[1]), az = std::abs(direction[2]);
  r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (direction[r.kz] < 0.0)
    std::swap(r.kx, r.ky);
  r.sx = direction[r.kx] / direction[r.kz];
  r.sy = direction[r.ky] / direction[r.kz];
  r.sz = 1.0 / direction[r.kz];
  return r;
}

/// Woop, Benthin and Wald's watertight test (JCGT 2(1), 2013) in double precision on the vertices a, b, c of
/// triangle `index`; on a hit nearer than hit.t (or as near, and `index` the smaller) updates hit and returns true.
/// The tie rule makes the nearest hit independent of the order the triangles are tested in.
bool IntersectTriangle(
  const ShearedRay& r, const double* va, const double* vb, const double* vc, std::int64_t index, TriangleHit& hit)
{
  const double a[3] = { va[0] - r.origin[0], va[1] - r.origin[1], va[2] - r.origin[2] };
  const double b[3] = { vb[0] - r.origin[0], vb[1] - r.origin[1], vb[2] - r.origin[2] };
  const double c[3] = { vc[0] - r.origin[0], vc[1] - r.origin[1], vc[2] - r.origin[2] };
  const double ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const double bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const double cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
  double e0 = cx * by - cy * bx;
  double e1 = ax * cy - ay * cx;
  double e2 = bx * ay - by * ax;
  if (e0 == 0.0 || e1 == 0.0 || e2 == 0.0)
  {
    // On an edge in double precision: decided in long double, as the paper falls back to higher precision.
    using L = long double;
    e0 = static_cast<double>(L(cx) * L(by) - L(cy) * L(bx));
    e1 = static_cast<double>(L(ax) * L(cy) - L(ay) * L(cx));
    e2 = static_cast<double>(L(bx) * L(ay) - L(by) * L(ax));
  }
  if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0))
    return false;
  const double det = e0 + e1 + e2;
  if (det == 0.0)
    return false;
  const double az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const double tScaled = e0 * az + e1 * bz + e2 * cz;
  // A cheap rejection with room for rounding (the exact comparison is on t itself, below).
  const double reach = hit.t * det * (1.0 + 1e-12);
  if (det > 0.0 ? (tScaled <= 0.0 || tScaled > reach) : (tScaled >= 0.0 || tScaled < reach))
    return false;
  const double inverse = 1.0 / det;
  const double t = tScaled * inverse;
  if (!(t < hit.t || (t == hit.t && hit.triangle >= 0 && index < hit.triangle)))
    return false;
  hit.t = t;
  hit.u = e1 * inverse;
  hit.v = e2 * inverse;
  hit.triangle = index;
  const double u[3] = { vb[0] - va[0], vb[1] - va[1], vb[2] - va[2] };
  const double w[3] = { vc[0] - va[0], vc[1] - va[1], vc[2] - va[2] };
  hit.normal[0] = u[1] * w[2] - u[2] * w[1];
  hit.normal[1] = u[2] * w[0] - u[0] * w[2];
  hit.normal[2] = u[0] * w[1] - u[1] * w[0];
  return true;
}

/// What a packet of beams (or one) carries through Embree's traversal: Embree hands the context to the callbacks
/// (it comes first); each single-precision ray's id is its lane here, whichever way Embree regroups the rays.
/// `best` is the exact nearest hit so far, in either geometry.
struct BeamContext
{
  RTCIntersectContext context;
  ShearedRay ray[RayCaster::PacketSize];
  TriangleHit best[RayCaster::PacketSize];
  double start[RayCaster::PacketSize]; // the single-precision ray starts at origin + start * direction
  double slack[RayCaster::PacketSize]; // added to its far distance (covers its rounding and the padding)
};

/// The data the callbacks see, in the Morton order of the triangles' centroids (Embree's primitive i is input
/// triangle order[i]), so the triangles of one box of the hierarchy lie close together in memory. ExactUser: the
/// triangles' vertices in double precision, nine per triangle (CopyMortonOrdered). Triangles: the points in double
/// precision, renumbered in the order of first use, and the triangles' indices into them (CopyIndexed).
struct Surface
{
  std::vector<double> vertices;
  std::vector<std::uint32_t> order;
  const double* centre;
  double pad;
  std::vector<double> points;
  std::vector<std::uint32_t> indices;
};

void TriangleBounds(const RTCBoundsFunctionArguments* args)
{
  const auto* s = static_cast<const Surface*>(args->geometryUserPtr);
  const double* v = &s->vertices[9 * static_cast<std::size_t>(args->primID)];
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k)
  {
    lo[k] = std::min({ v[k], v[3 + k], v[6 + k] }) - s->centre[k];
    hi[k] = std::max({ v[k], v[3 + k], v[6 + k] }) - s->centre[k];
  }
  // Padded outwards: the single-precision beam strays from the exact one by less than the padding, so no box the
  // exact beam enters is culled.
  RTCBounds* b = args->bounds_o;
  b->lower_x = static_cast<float>(lo[0] - s->pad);
  b->lower_y = static_cast<float>(lo[1] - s->pad);
  b->lower_z = static_cast<float>(lo[2] - s->pad);
  b->upper_x = static_cast<float>(hi[0] + s->pad);
  b->upper_y = static_cast<float>(hi[1] + s->pad);
  b->upper_z = static_cast<float>(hi[2] + s->pad);
}

/// 10-bit spread of a coordinate in [0, 1] for a 30-bit Morton code.
std::uint32_t Spread(double x)
{
  std::uint32_t v = static_cast<std::uint32_t>(std::min(1023.0, std::max(0.0, x * 1024.0)));
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

void TriangleIntersect(const RTCIntersectFunctionNArguments* args)
{
  const auto* s = static_cast<const Surface*>(args->geometryUserPtr);
  auto* beams = reinterpret_cast<BeamContext*>(args->context);
  const double* a = &s->vertices[9 * static_cast<std::size_t>(args->primID)];
  const double *b = a + 3, *c = a + 6;
  const auto triangle = static_cast<std::int64_t>(s->order[args->primID]);
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i)
  {
    if (!args->valid[i])
      continue;
    const unsigned lane = RTCRayN_id(rays, args->N, i);
    TriangleHit& best = beams->best[lane];
    if (!IntersectTriangle(beams->ray[lane], a, b, c, triangle, best))
      continue;
    // Boxes the beam enters beyond the hit need no visit: the single-precision far distance, rounded up.
    // (Rounding to single precision loses less than the 1e-6 added.)
    RTCRayN_tfar(rays, args->N, i) = FarLimit(best.t, beams->start[lane], beams->slack[lane]);
    RTCHitN_geomID(hits, args->N, i) = args->geomID;
    RTCHitN_primID(hits, args->N, i) = args->primID;
  }
}

/// Embree's primitive `primitive` of the Triangles surface (input triangle order[primitive]) through the exact test.
bool TestIndexed(const Surface& s, const ShearedRay& r, std::uint32_t primitive, TriangleHit& best)
{
  const std::uint32_t* t = &s.indices[3 * static_cast<std::size_t>(primitive)];
  return IntersectTriangle(r, &s.points[3 * static_cast<std::size_t>(t[0])],
    &s.points[3 * static_cast<std::size_t>(t[1])], &s.points[3 * static_cast<std::size_t>(t[2])],
    static_cast<std::int64_t>(s.order[primitive]), best);
}

/// Embree's intersection filter on the single-precision (enlarged) triangles: a candidate is kept only when the
/// exact test on the input's triangle improved the beam's nearest hit, and then the far distance is the exact
/// one's, rounded up (as the user geometry does), so nothing the exact test could prefer is culled by
/// single-precision rounding; a rejected candidate lets Embree go on to the triangles behind it.
void TriangleFilter(const RTCFilterFunctionNArguments* args)
{
  const auto* s = static_cast<const Surface*>(args->geometryUserPtr);
  auto* beams = reinterpret_cast<BeamContext*>(const_cast<RTCIntersectContext*>(args->context));
  for (unsigned i = 0; i < args->N; ++i)
  {
    if (args->valid[i] == 0)
      continue;
    const unsigned lane = RTCRayN_id(args->ray, args->N, i);
    const std::uint32_t index = RTCHitN_primID(args->hit, args->N, i);
    if (!TestIndexed(*s, beams->ray[lane], index, beams->best[lane]))
    {
      args->valid[i] = 0;
      continue;
    }
    RTCRayN_tfar(args->ray, args->N, i) = FarLimit(beams->best[lane].t, beams->start[lane], beams->slack[lane]);
  }
}
} // namespace

struct RayCaster::Callbacks
{
  Surface surface;
};

RayCaster::RayCaster() = default;

RayCaster::~RayCaster()
{
  this->Release();
}

void RayCaster::Clear()
{
  this->Release();
  this->Count = 0;
}

void RayCaster::Release()
{
  if (this->Impl)
  {
    if (this->Impl->scene)
      rtcReleaseScene(this->Impl->scene);
    if (this->Impl->device)
      rtcReleaseDevice(this->Impl->device);
    delete this->Impl;
    this->Impl = nullptr;
  }
  delete this->User;
  this->User = nullptr;
}

std::size_t RayCaster::PeakBytes() const
{
  return this->Impl ? static_cast<std::size_t>(std::max<std::int64_t>(0, this->Impl->peak.load())) : 0;
}

std::size_t RayCaster::MemoryBytes() const
{
  std::size_t own = 0;
  if (this->User)
  {
    const Surface& s = this->User->surface;
    own = (s.vertices.size() + s.points.size()) * sizeof(double) + (s.order.size() + s.indices.size()) * 4;
  }
  return own + (this->Impl ? static_cast<std::size_t>(std::max<std::int64_t>(0, this->Impl->bytes.load())) : 0);
}

std::string ValidateRayCasterParameters(const RayCasterParameters& p)
{
  std::string error = CheckRange(
    p.buildQuality >= 0 && p.buildQuality <= 2, "buildQuality", p.buildQuality, "{0, 1, 2}", "0 low, 1 medium, 2 high");
  if (error.empty())
    error = CheckRange(p.packetWidth == 1 || p.packetWidth == 4 || p.packetWidth == 8 || p.packetWidth == 16,
      "packetWidth", p.packetWidth, "{1, 4, 8, 16}");
  if (error.empty())
    error = CheckRange(p.buildThreads >= 0, "buildThreads", p.buildThreads, "[0, inf)", "0: all");
  return error;
}

std::string RayCaster::Build(
  const std::vector<double>& points, const std::vector<std::int64_t>& triangles, int buildThreads)
{
  RayCasterParameters parameters;
  parameters.buildThreads = buildThreads;
  return this->Build(points, triangles, parameters);
}

namespace
{
/// The input indices of the triangles in the Morton order of their centroids (30-bit codes over the box `lo`,
/// `size`; ties by index).
template <class Index>
std::vector<std::uint32_t> MortonOrder(
  const double* points, const Index* triangles, std::size_t nt, const double lo[3], double size)
{
  std::vector<std::uint64_t> keys(nt);
  for (std::size_t i = 0; i < nt; ++i)
  {
    double x[3] = { 0.0, 0.0, 0.0 };
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        x[k] += points[3 * static_cast<std::size_t>(triangles[3 * i + j]) + k] / 3.0;
    std::uint32_t code = 0;
    for (int k = 0; k < 3; ++k)
      code |= Spread(size > 0.0 ? (x[k] - lo[k]) / size : 0.0) << k;
    keys[i] = (static_cast<std::uint64_t>(code) << 32) | i;
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(nt);
  for (std::size_t i = 0; i < nt; ++i)
    order[i] = static_cast<std::uint32_t>(keys[i] & 0xFFFFFFFFu);
  return order;
}

/// ExactUser: the triangles' vertices in double precision, nine per triangle, in the Morton order of their centroids.
template <class Index>
void CopyMortonOrdered(
  const double* points, const Index* triangles, std::size_t nt, const double lo[3], double size, Surface& surface)
{
  surface.order = MortonOrder(points, triangles, nt, lo, size);
  surface.vertices.resize(9 * nt);
  for (std::size_t i = 0; i < nt; ++i)
  {
    const std::uint32_t t = surface.order[i];
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        surface.vertices[9 * i + 3 * j + k] = points[3 * static_cast<std::size_t>(triangles[3 * t + j]) + k];
  }
}

/// Triangles: the triangles in the Morton order of their centroids (Embree's primitive i is input triangle
/// order[i]) and their points renumbered in the order of first use, so that triangles near in space are near in
/// memory: the intersection filter reads them in the order the beams meet them (at 10^7 triangles its cache misses
/// on the input's order were a fifth of the scan's time). The vertices' values and order in each triangle are the
/// input's.
template <class Index>
void CopyIndexed(const double* points, std::size_t pointCount, const Index* triangles, std::size_t nt,
  const double lo[3], double size, Surface& surface)
{
  surface.order = MortonOrder(points, triangles, nt, lo, size);
  constexpr std::uint32_t Unused = ~std::uint32_t(0);
  std::vector<std::uint32_t> renumbered(pointCount, Unused);
  surface.indices.resize(3 * nt);
  surface.points.clear();
  surface.points.reserve(3 * pointCount);
  for (std::size_t i = 0; i < nt; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      const auto v = static_cast<std::size_t>(triangles[3 * static_cast<std::size_t>(surface.order[i]) + j]);
      if (renumbered[v] == Unused)
      {
        renumbered[v] = static_cast<std::uint32_t>(surface.points.size() / 3);
        surface.points.insert(surface.points.end(), points + 3 * v, points + 3 * v + 3);
      }
      surface.indices[3 * i + j] = renumbered[v];
    }
  }
}

/// Triangle `t` relative to `centre`, its edges moved outwards in its plane by `grow` (each vertex along its angle's
/// bisector by grow / sin(angle / 2), at most 1000 grow), in single precision: nine floats.
void EnlargedTriangle(const double* points, const std::uint32_t* t, const double* centre, double grow, float* out)
{
  double v[3][3];
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      v[j][k] = points[3 * static_cast<std::size_t>(t[j]) + k] - centre[k];
  for (int j = 0; j < 3; ++j)
  {
    double u[2][3], length[2];
    for (int e = 0; e < 2; ++e)
    {
      const double* q = v[(j + 1 + e) % 3];
      for (int k = 0; k < 3; ++k)
        u[e][k] = q[k] - v[j][k];
      length[e] = std::sqrt(u[e][0] * u[e][0] + u[e][1] * u[e][1] + u[e][2] * u[e][2]);
    }
    double sum[3], difference = 0.0, along = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const double a = length[0] > 0.0 ? u[0][k] / length[0] : 0.0, b = length[1] > 0.0 ? u[1][k] / length[1] : 0.0;
      sum[k] = a + b; // along the bisector, into the triangle
      difference += (a - b) * (a - b);
      along += sum[k] * sum[k];
    }
    along = std::sqrt(along);
    // |a - b| = 2 sin(angle / 2): the vertex moves grow / sin(angle / 2) (degenerate corners: not moved; such
    // triangles are never hit by the exact test).
    const double move =
      along > 0.0 && difference > 0.0 ? std::min(1000.0 * grow, 2.0 * grow / std::sqrt(difference)) : 0.0;
    for (int k = 0; k < 3; ++k)
      out[3 * j + k] = static_cast<float>(v[j][k] - (along > 0.0 ? move * sum[k] / along : 0.0));
  }
}
} // namespace

std::string RayCaster::Build(
  const std::vector<double>& points, const std::vector<std::int64_t>& triangles, const RayCasterParameters& parameters)
{
  return this->BuildFrom(points.data(), points.size() / 3, triangles.data(), triangles.size() / 3, parameters);
}

std::string RayCaster::Build(const double* points, std::size_t pointCount, const std::uint32_t* triangles,
  std::size_t triangleCount, const RayCasterParameters& parameters)
{
  return this->BuildFrom(points, pointCount, triangles, triangleCount, parameters);
}

template <class Index>
std::string RayCaster::BuildFrom(const double* points, std::size_t pointCount, const Index* triangles, std::size_t nt,
  const RayCasterParameters& parameters)
{
  this->Release();
  this->Impl = new Embree;
  this->User = new Callbacks;
  this->Count = 0;
  this->Settings = parameters;
  std::string error = ValidateRayCasterParameters(parameters);
  if (!error.empty())
    return error;
  if (3 * nt >= (std::size_t(1) << 32) || pointCount >= (std::size_t(1) << 32))
    return "Input: more than 2^32 / 3 triangles or 2^32 points";
  // The bounding box of the triangles' vertices; the single-precision boxes are relative to its centre.
  double lo[3] = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  for (std::size_t c = 0; c < 3 * nt; ++c)
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], points[3 * static_cast<std::size_t>(triangles[c]) + k]);
      hi[k] = std::max(hi[k], points[3 * static_cast<std::size_t>(triangles[c]) + k]);
    }
  double size = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    if (nt == 0)
      lo[k] = hi[k] = 0.0;
    this->Centre[k] = 0.5 * (lo[k] + hi[k]);
    size = std::max(size, hi[k] - lo[k]);
  }
  // Single precision (relative 6e-8) of coordinates up to the box's size: a padding of 1e-5 of it covers the
  // rounding of the boxes and of the single-precision beam (which starts near the box, see Intersect).
  const double pad = 1e-5 * size + 1e-30;
  for (int k = 0; k < 3; ++k)
  {
    this->Box[k] = lo[k] - this->Centre[k] - 2.0 * pad;
    this->Box[k + 3] = hi[k] - this->Centre[k] + 2.0 * pad;
  }
  this->Margin = 1e-2 * size + pad;
  this->Pad = pad;
  Surface& surface = this->User->surface;
  surface.centre = this->Centre;
  surface.pad = pad;
  // The caster's own copy first: the scene is built from it alone, so a caller may drop its arrays before
  // Embree's build, the peak of the memory.
  if (parameters.geometry == RayCasterParameters::Geometry::ExactUser)
    CopyMortonOrdered(points, triangles, nt, lo, size, surface);
  else
    CopyIndexed(points, pointCount, triangles, nt, lo, size, surface);
  error = this->BuildScene(nt);
  if (error.empty())
    this->Count = nt;
  return error;
}

std::string RayCaster::BuildScene(std::size_t nt)
{
  const std::string config = "threads=" + std::to_string(std::max(0, this->Settings.buildThreads));
  RTCDevice device = rtcNewDevice(config.c_str());
  if (!device)
    return DeviceError(nullptr, "rtcNewDevice (is the CPU supported?)");
  this->Impl->device = device;
  rtcSetDeviceMemoryMonitorFunction(device, CountMemory, this->Impl);
  RTCScene scene = rtcNewScene(device);
  this->Impl->scene = scene;
  // Compact: Embree's leaves refer to the vertex buffer instead of copying the triangles, 330 MB less at the build's
  // peak at 10^7 triangles (1.96 -> 1.63 GB for the filter's first run) at the same speed within this machine's
  // noise (benchmarks/README.md run 5).
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_COMPACT);
  const RTCBuildQuality quality[3] = { RTC_BUILD_QUALITY_LOW, RTC_BUILD_QUALITY_MEDIUM, RTC_BUILD_QUALITY_HIGH };
  rtcSetSceneBuildQuality(scene, quality[this->Settings.buildQuality]);
  Surface& surface = this->User->surface;
  if (nt > 0 && this->Settings.geometry == RayCasterParameters::Geometry::ExactUser)
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryBuildQuality(geometry, quality[this->Settings.buildQuality]);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(nt));
    rtcSetGeometryUserData(geometry, &surface);
    rtcSetGeometryBoundsFunction(geometry, TriangleBounds, nullptr);
    rtcSetGeometryIntersectFunction(geometry, TriangleIntersect);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  else if (nt > 0)
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, quality[this->Settings.buildQuality]);
    auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * nt));
    auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    if (!vertices || !indices)
    {
      rtcReleaseGeometry(geometry);
      return DeviceError(device, "allocating the triangle buffers");
    }
    // Each triangle its own three vertices, relative to the box's centre (single precision relative to the
    // surface's size) and enlarged by the padding: a beam the exact test finds on a triangle passes well inside its
    // single-precision candidate, so Embree's test proposes it (no slip at shared vertices and edges).
    for (std::size_t i = 0; i < nt; ++i)
    {
      EnlargedTriangle(surface.points.data(), &surface.indices[3 * i], this->Centre, this->Pad, vertices + 9 * i);
      for (unsigned j = 0; j < 3; ++j)
        indices[3 * i + j] = static_cast<unsigned>(3 * i + j);
    }
    rtcSetGeometryUserData(geometry, &surface);
    rtcSetGeometryIntersectFilterFunction(geometry, TriangleFilter);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
    return DeviceError(device, "building the scene");
  return {};
}

namespace
{
/// Lane `lane` of a packet of W single-precision rays: the beam clipped to the padded box `box` (relative to
/// `centre`), started `margin` before it. False (and the ray inactive) when the beam misses the box.
template <typename Rays>
bool PrepareLane(const double* origin, const double* direction, double tMax, const double* centre, const double* box,
  double margin, double pad, BeamContext& beams, unsigned lane, Rays& r)
{
  double o[3], enter = 0.0, leave = tMax;
  for (int k = 0; k < 3; ++k)
  {
    o[k] = origin[k] - centre[k];
    if (direction[k] == 0.0)
    {
      if (!(o[k] >= box[k] && o[k] <= box[k + 3]))
        return false;
      continue;
    }
    double a = (box[k] - o[k]) / direction[k], b = (box[k + 3] - o[k]) / direction[k];
    if (a > b)
      std::swap(a, b);
    enter = std::max(enter, a);
    leave = std::min(leave, b);
  }
  if (!(enter <= leave))
    return false;
  const double length =
    std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
  beams.ray[lane] = Shear(origin, direction);
  beams.best[lane] = TriangleHit{};
  beams.best[lane].t = tMax;
  const double start = std::max(0.0, enter - margin / length);
  beams.start[lane] = start;
  beams.slack[lane] = 2.0 * pad / length;
  r.org_x[lane] = static_cast<float>(o[0] + start * direction[0]);
  r.org_y[lane] = static_cast<float>(o[1] + start * direction[1]);
  r.org_z[lane] = static_cast<float>(o[2] + start * direction[2]);
  r.dir_x[lane] = static_cast<float>(direction[0]);
  r.dir_y[lane] = static_cast<float>(direction[1]);
  r.dir_z[lane] = static_cast<float>(direction[2]);
  r.tnear[lane] = 0.0f;
  r.tfar[lane] = FarLimit(leave, start, beams.slack[lane]);
  r.time[lane] = 0.0f;
  r.mask[lane] = 0xFFFFFFFFu;
  r.id[lane] = lane;
  r.flags[lane] = 0;
  return true;
}

/// One lane's view of a single RTCRay, so PrepareLane serves rtcIntersect1 too.
struct SingleRay
{
  RTCRay& ray;
  struct Field
  {
    float* f;
    float& operator[](unsigned) { return *f; }
  };
  struct UField
  {
    unsigned* u;
    unsigned& operator[](unsigned) { return *u; }
  };
  Field org_x{ &ray.org_x }, org_y{ &ray.org_y }, org_z{ &ray.org_z }, dir_x{ &ray.dir_x }, dir_y{ &ray.dir_y },
    dir_z{ &ray.dir_z }, tnear{ &ray.tnear }, tfar{ &ray.tfar }, time{ &ray.time };
  UField mask{ &ray.mask }, id{ &ray.id }, flags{ &ray.flags };
};
} // namespace

TriangleHit RayCaster::Intersect(const double origin[3], const double direction[3], double tMax) const
{
  if (this->Count == 0)
    return TriangleHit{};
  BeamContext beams;
  RTCRayHit ray;
  SingleRay single{ ray.ray };
  if (!PrepareLane(origin, direction, tMax, this->Centre, this->Box, this->Margin, this->Pad, beams, 0, single))
    return TriangleHit{};
  rtcInitIntersectContext(&beams.context);
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(this->Impl->scene, &beams.context, &ray);
  return beams.best[0].Hit() ? beams.best[0] : TriangleHit{};
}

namespace
{
/// Beams [0, count) of `origins`, `directions` cast as Embree packets of W lanes (`Packet` RTCRayHitNt<W>).
template <unsigned W, typename Intersector>
void CastPackets(RTCScene scene, const double* centre, const double* box, double margin, double pad, std::size_t count,
  const double* origins, const double* directions, double tMax, TriangleHit* hits, Intersector intersect)
{
  for (std::size_t first = 0; first < count; first += W)
  {
    BeamContext beams;
    alignas(64) RTCRayHitNt<W> packet{}; // inactive lanes zero, never stale
    alignas(64) int valid[W];
    int active = 0;
    for (unsigned i = 0; i < W; ++i)
    {
      const std::size_t b = first + i;
      valid[i] = b < count &&
          PrepareLane(origins + 3 * b, directions + 3 * b, tMax, centre, box, margin, pad, beams, i, packet.ray)
        ? -1
        : 0;
      packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
      active += valid[i] ? 1 : 0;
    }
    if (active == 0)
      continue;
    rtcInitIntersectContext(&beams.context);
    beams.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    intersect(valid, scene, &beams.context, &packet);
    for (unsigned i = 0; i < W && first + i < count; ++i)
      if (valid[i] && beams.best[i].Hit())
        hits[first + i] = beams.best[i];
  }
}
} // namespace

bool RayCaster::SetPacketWidth(unsigned width)
{
  RayCasterParameters p = this->Settings;
  p.packetWidth = width;
  if (!ValidateRayCasterParameters(p).empty())
    return false;
  this->Settings.packetWidth = width;
  return true;
}

void RayCaster::Intersect(
  std::size_t count, const double* origins, const double* directions, double tMax, TriangleHit* hits) const
{
  count = std::min<std::size_t>(count, PacketSize);
  for (std::size_t i = 0; i < count; ++i)
    hits[i] = TriangleHit{};
  if (this->Count == 0 || count == 0)
    return;
  RTCScene scene = this->Impl->scene;
  const double *c = this->Centre, *box = this->Box;
  switch (this->Settings.packetWidth)
  {
    case 16:
      CastPackets<16>(scene, c, box, this->Margin, this->Pad, count, origins, directions, tMax, hits,
        [](const int* v, RTCScene s, RTCIntersectContext* x, RTCRayHitNt<16>* r) {
          rtcIntersect16(v, s, x, reinterpret_cast<RTCRayHit16*>(r));
        });
      break;
    case 8:
      CastPackets<8>(scene, c, box, this->Margin, this->Pad, count, origins, directions, tMax, hits,
        [](const int* v, RTCScene s, RTCIntersectContext* x, RTCRayHitNt<8>* r) {
          rtcIntersect8(v, s, x, reinterpret_cast<RTCRayHit8*>(r));
        });
      break;
    case 4:
      CastPackets<4>(scene, c, box, this->Margin, this->Pad, count, origins, directions, tMax, hits,
        [](const int* v, RTCScene s, RTCIntersectContext* x, RTCRayHitNt<4>* r) {
          rtcIntersect4(v, s, x, reinterpret_cast<RTCRayHit4*>(r));
        });
      break;
    default:
      for (std::size_t i = 0; i < count; ++i)
        hits[i] = this->Intersect(origins + 3 * i, directions + 3 * i, tMax);
  }
}

} // namespace plantmorph
