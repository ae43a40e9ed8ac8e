// The virtual scanner's ray caster: Embree 3 (Debian's libembree-dev; Wald et al., "Embree: a kernel framework for
// efficient CPU ray tracing", ACM TOG 33(4), 2014) builds the hierarchy once per surface and traverses it, beams in
// packets of PacketSize (rtcIntersect8), from any number of threads at once. It measured 1.2-1.8 times the project's
// own BVH per CPU second on the same beams (benchmarks/README.md "virtual_scanner_benchmark"; issue 24: "whichever
// measures faster, the other kept out"), which is now in benchmarks/ only.
//
// Exactness (docs/methods/virtual-scanner.md):
// - The triangle test is ours, run by Embree as a user geometry: Woop, Benthin and Wald's watertight test (JCGT
//   2(1), 2013) in double precision on the input's vertices, so no beam slips between two triangles of a closed
//   surface and the hit lies on its triangle to double precision. Embree's own single-precision triangles, even with
//   RTC_SCENE_FLAG_ROBUST, let 4-9 of 71,688 beams aimed at an icosphere's shared vertices and edges through.
// - Embree's single-precision boxes are padded outwards (1e-5 of the surface's size) and relative to the surface's
//   bounding-box centre, and each beam starts at its entry into the box, so Embree never culls a triangle the exact
//   test would hit, wherever the surface and the scanner stand.
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
  bool Hit() const { return this->triangle >= 0; }
};

class RayCaster
{
public:
  RayCaster();
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Builds over `triangles` (three point indices each) of `points` (x, y, z each), copying what it needs (their
  /// vertices, in double precision, 72 bytes a triangle). Degenerate triangles are never hit. An empty string on
  /// success, else Embree's error (the caster is then empty: every beam misses). Indices out of range are the
  /// caller's error (ValidateSurface). `buildThreads`: Embree's build threads (0: all of the machine's).
  std::string Build(
    const std::vector<double>& points, const std::vector<std::int64_t>& triangles, int buildThreads = 0);

  /// The nearest hit with 0 < t < tMax of the ray origin + t * direction; no hit: triangle = -1. Of hits at the
  /// same distance (a beam through a shared edge), the smaller triangle index.
  TriangleHit Intersect(const double origin[3], const double direction[3], double tMax) const;

  /// Beams per Embree packet (rtcIntersect8 / rtcIntersect16).
  static constexpr unsigned PacketSize = 8;
  /// The first `count` (at most PacketSize) beams (x, y, z each in `origins`, `directions`) as one packet:
  /// `hits[i]` is exactly what Intersect gives for beam i, whatever the other beams are.
  void Intersect(
    std::size_t count, const double* origins, const double* directions, double tMax, TriangleHit* hits) const;

  std::size_t TriangleCount() const { return this->Count; }
  /// Bytes Embree allocated for the hierarchy at the peak of the build; bytes the caster holds (the hierarchy and the
  /// copied vertices).
  std::size_t PeakBytes() const;
  std::size_t MemoryBytes() const;

  struct Embree;    // the device, the scene and its memory count (RayCaster.cpp)
  struct Callbacks; // what Embree's bounds and intersection callbacks see

private:
  void Release();
  Embree* Impl = nullptr;
  Callbacks* User = nullptr;
  std::size_t Count = 0; // triangles
  double Centre[3] = { 0.0, 0.0, 0.0 };
  double Box[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 }; // padded bounds relative to Centre
  double Margin = 0.0;                              // how far before the box a beam starts
  double Pad = 0.0;                                 // the single-precision boxes' padding
};

} // namespace plantmorph
