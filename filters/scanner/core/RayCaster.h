// SPDX-License-Identifier: GPL-3.0-or-later
// The virtual scanner's ray caster: Embree 3 (Debian's libembree-dev; Wald et al., "Embree: a kernel framework for
// efficient CPU ray tracing", ACM TOG 33(4), 2014) builds the hierarchy once per surface and traverses it, beams in
// packets (rtcIntersect4/8/16, RayCasterParameters::packetWidth), from any number of threads at once. It measured
// 1.2-1.8 times the project's own BVH per CPU second on the same beams (benchmarks/README.md
// "virtual_scanner_benchmark"; whichever measures faster is kept in the plugin), which is now in benchmarks/
// only.
//
// Two ways of running the triangle test (RayCasterParameters::geometry; benchmarks/README.md measures both):
// - Triangles (the default): Embree's own single-precision triangles (RTC_GEOMETRY_TYPE_TRIANGLE, robust mode, SIMD
//   leaves) propose the candidates, relative to the surface's bounding-box centre (so far-away scenes keep their
//   precision) and each enlarged in its plane by 1e-5 of the surface's size, so that every triangle the exact test
//   would hit is proposed (Embree's robust single-precision test alone lets 4-9 of 71,688 beams aimed at an
//   icosphere's shared vertices slip through). An intersection filter re-tests every candidate with our
//   double-precision watertight test (Woop, Benthin and Wald, JCGT 2(1), 2013) on the input's triangle, rejects
//   what it rejects (Embree then goes on to the triangles behind) and keeps Embree's far distance just above the
//   exact nearest hit, so the result is the exact nearest hit, as with ExactUser. The one tolerance: a beam within
//   about a degree of grazing a triangle, near one of its edges, may not have that triangle proposed (the enlargement
//   in the plane covers single-precision rounding across the plane only at steeper incidence); and a corner sharper
//   than about 0.1 degree is enlarged by at most 1e-2 of the size (docs/methods/virtual-scanner.md).
// - ExactUser: the same double-precision test run by Embree as a user geometry on every triangle whose padded
//   single-precision box the beam enters: no tolerance at all, but slower (no SIMD leaves; benchmarks/README.md).
// Both:
// - Embree's single-precision boxes are relative to the surface's bounding-box centre, and each beam starts shortly
//   before its entry into the (padded) box, so single precision is relative to the surface, wherever it stands.
// - Deterministic: of hits at the same distance the smaller triangle index wins, so a beam's hit depends on the beam
//   and the surface only, not on the traversal order, the packet's other beams, the build threads or the thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

/// The nearest hit of a beam: distance along the (unit or not) direction, the triangle, and its barycentric
/// coordinates (the point is (1 - u - v) v0 + u v1 + v v2 in the triangle's own vertex order).
struct TriangleHit
{
  double t = 0.0;
  std::int64_t triangle = -1;
  double u = 0.0;
  double v = 0.0;
  /// (v1 - v0) x (v2 - v0) of the triangle hit, in its own vertex order and double precision (not unit length):
  /// RayCaster fills it from its copy of the vertices, already in cache, so callers need not read the surface again.
  double normal[3] = { 0.0, 0.0, 0.0 };
  bool Hit() const { return this->triangle >= 0; }
};

/// How the caster is built and traverses (RayCaster.h's header comment; the defaults measured fastest).
struct RayCasterParameters
{
  enum class Geometry
  {
    Triangles, ///< Embree's single-precision triangles + the double-precision filter
    ExactUser  ///< our double-precision test as an Embree user geometry
  };
  Geometry geometry = Geometry::Triangles;
  int buildQuality = 1;      ///< Embree's RTC_BUILD_QUALITY: 0 low, 1 medium, 2 high (spatial splits)
  unsigned packetWidth = 16; ///< beams per Embree call: 1 (rtcIntersect1), 4, 8 or 16
  int buildThreads = 0;      ///< Embree's build threads (0: all of the machine's)
};

/// Checks a RayCasterParameters: "" when valid.
std::string ValidateRayCasterParameters(const RayCasterParameters& parameters);

class RayCaster
{
public:
  RayCaster();
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Builds over `triangles` (three point indices each) of `points` (x, y, z each), copying what it needs (the
  /// vertices in double precision; Triangles also in single precision, both in the Morton order of the triangles).
  /// Degenerate triangles are never hit. An empty string on success, else the parameters' or Embree's error (the
  /// caster is then empty: every beam misses). Indices out of range are the caller's error (ValidateSurface).
  std::string Build(const std::vector<double>& points, const std::vector<std::int64_t>& triangles,
    const RayCasterParameters& parameters);
  /// The same over raw arrays: `pointCount` points (x, y, z each) and `triangleCount` triangles of 32-bit point
  /// indices (the VTK wrapper's, half the memory of 64-bit ones); nothing points at them once Build returns.
  std::string Build(const double* points, std::size_t pointCount, const std::uint32_t* triangles,
    std::size_t triangleCount, const RayCasterParameters& parameters);
  /// The default parameters with `buildThreads` build threads.
  std::string Build(
    const std::vector<double>& points, const std::vector<std::int64_t>& triangles, int buildThreads = 0);

  /// The nearest hit with 0 < t < tMax of the ray origin + t * direction; no hit: triangle = -1. Of hits at the
  /// same distance (a beam through a shared edge), the smaller triangle index.
  TriangleHit Intersect(const double origin[3], const double direction[3], double tMax) const;

  /// Most beams per call of the packet Intersect (cast in Embree packets of RayCasterParameters::packetWidth).
  static constexpr unsigned PacketSize = 16;
  /// The first `count` (at most PacketSize) beams (x, y, z each in `origins`, `directions`), in Embree packets:
  /// `hits[i]` is exactly what Intersect gives for beam i, whatever the other beams are.
  void Intersect(
    std::size_t count, const double* origins, const double* directions, double tMax, TriangleHit* hits) const;

  /// Releases the hierarchy and Embree's device now (the caster is then empty: every beam misses).
  void Clear();

  std::size_t TriangleCount() const { return this->Count; }
  const RayCasterParameters& Parameters() const { return this->Settings; }
  /// The packet width may change after Build (it is read at cast time); false (unchanged) unless 1, 4, 8 or 16.
  bool SetPacketWidth(unsigned width);
  /// Bytes Embree allocated for the hierarchy at the peak of the build; bytes the caster holds (the hierarchy and the
  /// copied vertices).
  std::size_t PeakBytes() const;
  std::size_t MemoryBytes() const;

  struct Embree;    // the device, the scene and its memory count (RayCaster.cpp)
  struct Callbacks; // what Embree's bounds and intersection callbacks see

private:
  void Release();
  template <class Index>
  std::string BuildFrom(const double* points, std::size_t pointCount, const Index* triangles, std::size_t nt,
    const RayCasterParameters& parameters);
  std::string BuildScene(std::size_t triangleCount); // from the caster's own copy of the surface
  Embree* Impl = nullptr;
  Callbacks* User = nullptr;
  std::size_t Count = 0; // triangles
  double Centre[3] = { 0.0, 0.0, 0.0 };
  double Box[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 }; // padded bounds relative to Centre
  double Margin = 0.0;                              // how far before the box a beam starts
  double Pad = 0.0;                                 // the single-precision boxes' padding
  RayCasterParameters Settings;
};

} // namespace plantmorph
