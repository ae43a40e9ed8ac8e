// The virtual scanner's ray caster: Embree 3 (Debian's libembree-dev; Wald et al., "Embree: a kernel framework for
// efficient CPU ray tracing", ACM TOG 33(4), 2014), which measured 2-3 times faster per thread than the project's
// own BVH on the same beams (benchmarks/README.md "virtual_scanner_benchmark"; issue 24: "whichever measures
// faster, the other kept out"). Built once per surface, then cast from any number of threads at once.
//
// Exactness:
// - Watertight: the scene is committed with RTC_SCENE_FLAG_ROBUST (Embree's watertight triangle test and
//   conservative box tests), and every vertex is converted to single precision once, whichever triangles share it,
//   so a beam through a closed surface hits at least one triangle at a shared edge or vertex.
// - Single precision chooses the triangle only: the hit's distance and barycentric coordinates are then recomputed
//   in double precision on that triangle (the ray meets its plane), so points lie on the surface to double
//   precision. Vertices are stored relative to the surface's bounding-box centre, and each beam starts at its entry
//   into the (padded) bounding box, so single precision is relative to the surface's size, not to where it or the
//   scanner stands. Two surfaces closer than about 1e-7 of the surface's size along a beam may be told apart in the
//   wrong order.
// - Deterministic: a beam's hit depends only on the beam and the surface, never on the thread that casts it or on
//   the other beams (single rays, rtcIntersect1: packets measured no faster on the scanner's beams, see the
//   benchmark), and Embree's build of a given surface is the same on every run and rank.
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
  /// vertices, in double precision, 72 bytes a triangle). Degenerate triangles are never hit. An empty string on success, else Embree's error
  /// (the caster is then empty: every beam misses). Indices out of range are the caller's error (ValidateSurface).
  /// `buildThreads`: Embree's build threads (0: all of the machine's).
  std::string Build(const std::vector<double>& points, const std::vector<std::int64_t>& triangles, int buildThreads = 0);

  /// The nearest hit with 0 < t < tMax of the ray origin + t * direction; no hit: triangle = -1. Of hits at the
  /// same distance (a beam through a shared edge), the smaller triangle index.
  TriangleHit Intersect(const double origin[3], const double direction[3], double tMax) const;

  /// Beams per Embree packet (rtcIntersect8 / rtcIntersect16).
  static constexpr unsigned PacketSize = 8;
  /// The first `count` (at most PacketSize) beams (x, y, z each in `origins`, `directions`) as one packet:
  /// `hits[i]` is exactly what Intersect gives for beam i, whatever the other beams are.
  void Intersect(std::size_t count, const double* origins, const double* directions, double tMax,
    TriangleHit* hits) const;

  std::size_t TriangleCount() const { return this->Count; }
  /// Bytes Embree allocated for the hierarchy at the peak of the build; bytes the caster holds (the hierarchy and the
  /// copied vertices).
  std::size_t PeakBytes() const;
  std::size_t MemoryBytes() const;

  struct Embree; // the device, the scene and its memory count (RayCaster.cpp)
  struct Callbacks; // what Embree's bounds and intersection callbacks see

private:
  void Release();
  Embree* Impl = nullptr;
  Callbacks* User = nullptr;
  std::size_t Count = 0; // triangles
  double Centre[3] = { 0.0, 0.0, 0.0 };
  double Box[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 }; // padded bounds relative to Centre
  double Margin = 0.0; // how far before the box a beam starts
  double Pad = 0.0; // the single-precision boxes' padding
};

} // namespace plantmorph
