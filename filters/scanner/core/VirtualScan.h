// SPDX-License-Identifier: GPL-3.0-or-later
// The virtual scan (docs/methods/virtual-scanner.md): every beam of a BeamPattern cast through a RayCaster (Embree)
// of the surface, the nearest hit within MaximumRange kept, then dropout, range noise and angular jitter drawn from
// a counter-based stream keyed by (Seed, beam index), so the cloud is bit-identical for a seed whatever the number
// of threads or how the beams are shared out. Points come out in beam order.
#pragma once

#include "ScanPattern.h"
#include "RayCaster.h"
#include <plantmorph/memory/CloudArray.h>

#include <plantmorph/ParallelFor.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

/// The cloud, one entry per returned beam.
struct ScanPoints
{
  // The types are those of the VTK wrapper's output arrays, which adopt these (CloudArray::Release) uncopied:
  // long long is the type of VTK's ids.
  CloudArray<double> points;      ///< x, y, z: origin + measured range * beam direction
  CloudArray<float> normals;      ///< unit normal of the triangle hit, facing the scanner
  CloudArray<double> range;       ///< measured range (the true one plus noise, never below 0)
  CloudArray<double> intensity;   ///< cos(incidence), over the true range squared when intensityFalloff
  CloudArray<std::int32_t> pose;  ///< the scanner pose (ScanPattern.h: position, fan or turntable step)
  CloudArray<long long> triangle; ///< index of the input triangle hit
  CloudArray<double> barycentric; ///< u, v of the hit in that triangle (its own vertex order), if withBarycentric
  CloudArray<long long> beam;     ///< index of the beam in the pattern (BeamPattern::Beam)
  std::uint64_t beams = 0;        ///< beams cast (this share's)
  std::uint64_t dropped = 0;      ///< beams that hit but were dropped (DropoutProbability)

  /// Set before CastBeams: false leaves `barycentric` empty (16 bytes a point less, when nothing is interpolated).
  bool withBarycentric = true;

  std::size_t Size() const { return this->range.size(); }
  void Clear(); ///< empties the cloud (withBarycentric kept)
  /// Room for `n` points in every array (address space; barycentric only withBarycentric).
  void Reserve(std::size_t n)
  {
    this->ForEachArray([n](auto& array, std::size_t components) { array.reserve(components * n); });
  }
  /// `n` points in every array, those beyond the old size unset (barycentric only withBarycentric).
  void Resize(std::size_t n)
  {
    this->ForEachArray([n](auto& array, std::size_t components) { array.resize(components * n); });
  }

private:
  /// f(array, numbers per point) for each array of the cloud.
  template <class F>
  void ForEachArray(const F& f)
  {
    f(this->points, 3);
    f(this->normals, 3);
    f(this->range, 1);
    f(this->intensity, 1);
    f(this->pose, 1);
    f(this->triangle, 1);
    f(this->barycentric, this->withBarycentric ? 2 : 0);
    f(this->beam, 1);
  }
};

/// Checks a surface: finite points, triangle indices in range. An empty string when it can be scanned.
std::string ValidateSurface(const std::vector<double>& points, const std::vector<std::int64_t>& triangles);
/// The same over raw arrays (`pointCount` points, `triangleCount` triangles of 32-bit indices: the VTK wrapper's).
std::string ValidateSurface(
  const double* points, std::size_t pointCount, const std::uint32_t* triangles, std::size_t triangleCount);

/// Casts the beams [firstBeam, endBeam) (clamped to the pattern's count; default all) of `pattern` (Setup already
/// succeeded) against `caster` (built on the surface): a share of the beams gives exactly the points the whole scan
/// gives for them, so ranks casting consecutive shares concatenate to the whole cloud.
/// `progress(fraction)` is called between blocks of beams; returning false stops the scan (the cloud is cleared and
/// "aborted" returned). Memory that cannot be had for the cloud (std::bad_alloc, on this thread or a worker of
/// `parallel`, which must hand it back: SMPFor does) empties the cloud and returns an error naming MaximumBeams, the
/// properties that set the beam count and the memory asked for.
std::string CastBeams(const ScannerParameters& parameters, const BeamPattern& pattern, const RayCaster& caster,
  ScanPoints& out, const ParallelFor& parallel = SerialFor, const std::function<bool(double)>& progress = {},
  std::uint64_t firstBeam = 0, std::uint64_t endBeam = ~std::uint64_t(0));

/// The numbers a returned point takes in the cloud (ScanPoints' arrays; 88 with barycentric, 72 without).
std::size_t CloudBytesPerPoint(bool withBarycentric);

/// The properties that set the beam count of `parameters`' scanner type, for messages ("AngularStep,
/// HorizontalFieldOfView, VerticalFieldOfView, Positions" for a terrestrial scanner; MaximumBeams caps them all).
std::string BeamCountProperties(const ScannerParameters& parameters);

/// The bytes this process can still allocate: the address-space limit (RLIMIT_AS, `ulimit -v`) less what it maps
/// now, and at most the machine's memory and swap. The largest size_t where neither is known.
std::size_t AvailableMemory();

/// Refuses a scan whose cloud clearly cannot fit before casting it: the return rate of up to 4096 beams spread
/// evenly over [firstBeam, endBeam) (their hits, less the dropout) times the share's beams is the expected number
/// of points, each taking CloudBytesPerPoint + `extraBytesPerPoint` (what the caller adds per point: the output's
/// vertices, carried arrays). "" when that fits in `available` bytes, else the error naming MaximumBeams, the
/// properties that set the beam count, the memory needed and the memory available.
std::string CheckCloudMemory(const ScannerParameters& parameters, const BeamPattern& pattern, const RayCaster& caster,
  bool withBarycentric, std::size_t extraBytesPerPoint, std::size_t available, std::uint64_t firstBeam = 0,
  std::uint64_t endBeam = ~std::uint64_t(0));

/// The whole scan: parameters and the beam budget checked first (nothing built or cast when they fail), then the
/// surface checked, the hierarchy built and the beams cast.
std::string VirtualScan(const ScannerParameters& parameters, const std::vector<double>& points,
  const std::vector<std::int64_t>& triangles, ScanPoints& out, const ParallelFor& parallel = SerialFor,
  const std::function<bool(double)>& progress = {});

/// The counter-based random numbers of beam `beam`: uniform in [0, 1) from (seed, beam, slot) alone.
double BeamUniform(std::uint64_t seed, std::uint64_t beam, std::uint64_t slot);

} // namespace plantmorph
