// SPDX-License-Identifier: GPL-3.0-or-later
#include "VirtualScan.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RandomStream.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <new>
#include <sstream>

#ifdef __linux__
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace plantmorph
{

namespace
{
constexpr std::uint64_t Block = 1u << 16; // beams per progress step and compaction block
// The random slots of a beam.
constexpr std::uint64_t SlotDropout = 0, SlotRange = 1, SlotJitter = 3;

/// Box-Muller from two of the beam's slots: two independent standard normals.
void BeamNormals(std::uint64_t seed, std::uint64_t beam, std::uint64_t slot, double& n0, double& n1)
{
  const double u0 = BeamUniform(seed, beam, slot), u1 = BeamUniform(seed, beam, slot + 1);
  const double r = std::sqrt(-2.0 * std::log(1.0 - u0));
  n0 = r * std::cos(2.0 * Pi * u1);
  n1 = r * std::sin(2.0 * Pi * u1);
}

/// What one beam returned (filled in parallel, compacted in beam order).
struct BeamResult
{
  double point[3];
  double normal[3];
  double range;
  double intensity;
  double u, v;
  std::int64_t triangle; // -1: nothing returned
  std::int64_t pose;
  bool dropped;
};

/// Beam `beam`'s direction `d` (unit) as cast: the pattern's, turned by the angular jitter drawn.
void Jitter(const ScannerParameters& p, std::uint64_t beam, double d[3])
{
  // Two normal deviations about two axes orthogonal to the beam (Duff et al. 2017's branchless basis).
  const double sign = std::copysign(1.0, d[2]);
  const double a = -1.0 / (sign + d[2]), b = d[0] * d[1] * a;
  const double e1[3] = { 1.0 + sign * d[0] * d[0] * a, sign * b, -sign * d[0] };
  const double e2[3] = { b, sign + d[1] * d[1] * a, -d[1] };
  double n0, n1;
  BeamNormals(p.seed, beam, SlotJitter, n0, n1);
  const double s = p.angularJitter * Pi / 180.0;
  double length = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    d[k] += s * (n0 * e1[k] + n1 * e2[k]);
    length += d[k] * d[k];
  }
  length = std::sqrt(length);
  for (int k = 0; k < 3; ++k)
    d[k] /= length;
}

/// What beam `beam` returns given its nearest hit: dropout, the normal facing the scanner, noise, intensity.
void Finish(const ScannerParameters& p, std::uint64_t beam, const double origin[3], const double d[3],
  const TriangleHit& hit, BeamResult& r)
{
  r.triangle = -1;
  r.dropped = false;
  if (!hit.Hit())
    return;
  if (p.dropoutProbability > 0.0 && BeamUniform(p.seed, beam, SlotDropout) < p.dropoutProbability)
  {
    r.dropped = true;
    return;
  }
  const double* n = hit.normal;
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  double cosine = -(n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / length;
  const double flip = cosine < 0.0 ? -1.0 : 1.0;
  cosine *= flip;
  for (int k = 0; k < 3; ++k)
    r.normal[k] = flip * n[k] / length;
  double measured = hit.t;
  if (p.rangeNoise > 0.0)
  {
    double n0, n1;
    BeamNormals(p.seed, beam, SlotRange, n0, n1);
    measured = std::max(0.0, hit.t + p.rangeNoise * n0);
  }
  for (int k = 0; k < 3; ++k)
    r.point[k] = origin[k] + measured * d[k];
  r.range = measured;
  r.intensity = p.intensityFalloff ? cosine / (hit.t * hit.t) : cosine;
  r.u = hit.u;
  r.v = hit.v;
  r.triangle = hit.triangle;
}

/// Beams first + [begin, end) into block[begin, end), RayCaster::PacketSize at a time (each beam's hit does not
/// depend on its packet, so neither does the cloud).
void CastRange(const ScannerParameters& p, const BeamPattern& pattern, const RayCaster& caster, std::uint64_t first,
  std::size_t begin, std::size_t end, BeamResult* block)
{
  constexpr std::size_t W = RayCaster::PacketSize;
  double origins[3 * W], directions[3 * W];
  std::int64_t poses[W];
  TriangleHit hits[W];
  for (std::size_t i = begin; i < end; i += W)
  {
    const std::size_t n = std::min(W, end - i);
    pattern.Beams(first + i, n, origins, directions, poses);
    for (std::size_t j = 0; j < n; ++j)
    {
      block[i + j].pose = poses[j];
      if (p.angularJitter > 0.0)
        Jitter(p, first + i + j, directions + 3 * j);
    }
    caster.Intersect(n, origins, directions, p.maximumRange, hits);
    for (std::size_t j = 0; j < n; ++j)
      Finish(p, first + i + j, origins + 3 * j, directions + 3 * j, hits[j], block[i + j]);
  }
}
} // namespace

double BeamUniform(std::uint64_t seed, std::uint64_t beam, std::uint64_t slot)
{
  // SplitMix64 of a counter: (seed, beam, slot) -> 53 bits, the same on every thread and machine.
  const std::uint64_t key = SplitMix64(seed ^ 0x5CA77E12B3A1D0C5ull);
  const std::uint64_t x = SplitMix64(key + SplitMix64(beam * 8u + slot));
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

void ScanPoints::Clear()
{
  const bool uv = this->withBarycentric;
  *this = ScanPoints{};
  this->withBarycentric = uv;
}

namespace
{
template <class Index>
std::string CheckSurface(
  const double* points, std::size_t pointCount, const Index* triangles, std::size_t triangleCount)
{
  for (std::size_t i = 0; i < 3 * pointCount; ++i)
  {
    if (!std::isfinite(points[i]))
    {
      std::ostringstream s;
      s << "Input: point " << i / 3 << " is not finite";
      return s.str();
    }
  }
  const auto count = static_cast<std::int64_t>(pointCount);
  for (std::size_t i = 0; i < 3 * triangleCount; ++i)
  {
    const auto index = static_cast<std::int64_t>(triangles[i]);
    if (index < 0 || index >= count)
    {
      std::ostringstream s;
      s << "Input: triangle " << i / 3 << " refers to point " << index << ", outside [0, " << count - 1 << "]";
      return s.str();
    }
  }
  if (triangleCount == 0)
    return "Input: the surface has no polygons to scan (give a surface: triangles, polygons or strips)";
  if (triangleCount >= (std::uint64_t(1) << 32))
    return "Input: more than 2^32 triangles";
  return {};
}
} // namespace

std::string ValidateSurface(const std::vector<double>& points, const std::vector<std::int64_t>& triangles)
{
  return CheckSurface(points.data(), points.size() / 3, triangles.data(), triangles.size() / 3);
}

std::string ValidateSurface(
  const double* points, std::size_t pointCount, const std::uint32_t* triangles, std::size_t triangleCount)
{
  return CheckSurface(points, pointCount, triangles, triangleCount);
}

std::size_t CloudBytesPerPoint(bool withBarycentric)
{
  // points, normals (float), range, intensity, pose (int32), triangle, beam; u, v
  return 3 * sizeof(double) + 3 * sizeof(float) + 2 * sizeof(double) + sizeof(std::int32_t) + 2 * sizeof(long long) +
    (withBarycentric ? 2 * sizeof(double) : 0);
}

std::string BeamCountProperties(const ScannerParameters& p)
{
  switch (p.type)
  {
    case ScannerType::Terrestrial:
      return "AngularStep, HorizontalFieldOfView, VerticalFieldOfView, Positions";
    case ScannerType::DepthCamera:
      return "Resolution, Positions";
    case ScannerType::Line:
      return p.lineMotion == LineMotion::Path ? "AngularStep, VerticalFieldOfView, LineSpacing, Positions"
                                              : "AngularStep, VerticalFieldOfView, TurntableSteps, Positions";
  }
  return "AngularStep";
}

namespace
{
/// A field of /proc/meminfo in bytes (0 when absent).
std::size_t MemInfo(const char* field)
{
  std::ifstream file("/proc/meminfo");
  std::string name;
  double kilobytes = 0.0;
  std::string unit;
  while (file >> name >> kilobytes)
  {
    std::getline(file, unit);
    if (name == field)
      return static_cast<std::size_t>(kilobytes * 1024.0);
  }
  return 0;
}

std::string Gigabytes(double bytes)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(bytes < 1e9 ? 3 : 1) << bytes / 1e9 << " GB";
  return s.str();
}

/// The error of a cloud that does not fit: `points` points of `bytesPerPoint` bytes against `available` (0:
/// unknown, an allocation failed).
std::string MemoryError(const ScannerParameters& p, std::uint64_t beams, double points, std::size_t bytesPerPoint,
  std::size_t available, const char* how)
{
  std::ostringstream s;
  s << std::setprecision(3) << "MaximumBeams / " << BeamCountProperties(p) << ": the scan casts " << double(beams)
    << " beams and its cloud of " << how << " " << points << " points needs "
    << Gigabytes(points * static_cast<double>(bytesPerPoint)) << " (" << bytesPerPoint << " bytes a point)";
  if (available > 0)
    s << ", more than the " << Gigabytes(static_cast<double>(available))
      << " this process can still allocate (its address-space limit, ulimit -v, or the machine's memory and swap)";
  else
    s << ": out of memory";
  s << "; cast fewer beams (a coarser AngularStep or Resolution, a narrower field of view, fewer Positions) or lower "
       "MaximumBeams to refuse such a set-up";
  return s.str();
}
} // namespace

std::size_t AvailableMemory()
{
  std::size_t available = std::numeric_limits<std::size_t>::max();
#ifdef __linux__
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const long pages = sysconf(_SC_PHYS_PAGES);
  if (pages > 0)
    available = static_cast<std::size_t>(pages) * page + MemInfo("SwapTotal:");
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
  {
    std::size_t mapped = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r"))
    {
      unsigned long size = 0;
      if (std::fscanf(statm, "%lu", &size) == 1)
        mapped = static_cast<std::size_t>(size) * page;
      std::fclose(statm);
    }
    const auto cap = static_cast<std::size_t>(limit.rlim_cur);
    available = std::min(available, cap > mapped ? cap - mapped : 0);
  }
#endif
  return available;
}

std::string CheckCloudMemory(const ScannerParameters& p, const BeamPattern& pattern, const RayCaster& caster,
  bool withBarycentric, std::size_t extraBytesPerPoint, std::size_t available, std::uint64_t firstBeam,
  std::uint64_t endBeam)
{
  const std::uint64_t end = std::min(endBeam, pattern.BeamCount());
  const std::uint64_t start = std::min(firstBeam, end);
  const std::uint64_t beams = end - start;
  const std::size_t bytes = CloudBytesPerPoint(withBarycentric) + extraBytesPerPoint;
  if (beams == 0 || static_cast<double>(beams) * static_cast<double>(bytes) <= static_cast<double>(available))
    return {}; // fits even if every beam returns: nothing to estimate
  const std::uint64_t samples = std::min<std::uint64_t>(beams, 4096);
  std::uint64_t hits = 0;
  for (std::uint64_t k = 0; k < samples; ++k)
  {
    double origin[3], direction[3];
    std::int64_t pose;
    pattern.Beams(start + k * beams / samples, 1, origin, direction, &pose);
    hits += caster.Intersect(origin, direction, p.maximumRange).Hit() ? 1 : 0;
  }
  const double points = (1.0 - p.dropoutProbability) * static_cast<double>(hits) / static_cast<double>(samples) *
    static_cast<double>(beams);
  if (points * static_cast<double>(bytes) <= static_cast<double>(available))
    return {};
  return MemoryError(p, beams, points, bytes, available, "about");
}

std::string CastBeams(const ScannerParameters& p, const BeamPattern& pattern, const RayCaster& caster, ScanPoints& out,
  const ParallelFor& parallel, const std::function<bool(double)>& progress, std::uint64_t firstBeam,
  std::uint64_t endBeam)
{
  out.Clear();
  const std::uint64_t end = std::min(endBeam, pattern.BeamCount());
  const std::uint64_t start = std::min(firstBeam, end);
  const std::uint64_t beams = end - start;
  std::size_t wanted = 0; // the points the cloud was asked to hold, for the out-of-memory error
  try
  {
    std::vector<BeamResult> block(static_cast<std::size_t>(std::min(beams, Block)));
    // Each block in pieces of Piece beams: a piece is cast and counts its returns in parallel, the pieces' places in
    // the cloud follow (a short serial sum), then the pieces copy their returns in parallel.
    constexpr std::size_t Piece = 1024;
    std::vector<std::size_t> place(static_cast<std::size_t>(Block / Piece) + 1);
    for (std::uint64_t first = start; first < end; first += Block)
    {
      if (progress && !progress(static_cast<double>(first - start) / static_cast<double>(beams)))
      {
        out.Clear();
        return "aborted";
      }
      const std::size_t count = static_cast<std::size_t>(std::min(Block, end - first));
      const std::size_t pieces = (count + Piece - 1) / Piece;
      std::vector<std::size_t> returned(pieces, 0), dropped(pieces, 0);
      parallel(pieces, [&](std::size_t begin, std::size_t end) {
        for (std::size_t piece = begin; piece < end; ++piece)
        {
          const std::size_t b = piece * Piece, e = std::min(count, b + Piece);
          CastRange(p, pattern, caster, first, b, e, block.data());
          for (std::size_t i = b; i < e; ++i)
          {
            returned[piece] += block[i].triangle >= 0 ? 1 : 0;
            dropped[piece] += block[i].dropped ? 1 : 0;
          }
        }
      });
      std::size_t n = out.Size();
      for (std::size_t piece = 0; piece < pieces; ++piece)
      {
        place[piece] = n;
        n += returned[piece];
        out.dropped += dropped[piece];
      }
      if (n > out.range.capacity())
      {
        // Room for every beam of the share up to 2^26 (address space only: pages are touched as points arrive), so a
        // cloud of that size is never copied to a larger allocation (serial work: run 3 of the benchmark); beyond,
        // room for the rest of the scan at the return rate so far.
        const double rate = static_cast<double>(n) / static_cast<double>(first + count - start);
        const auto expected = static_cast<std::size_t>(1.05 * rate * static_cast<double>(end - start)) + 1024;
        const auto share = static_cast<std::size_t>(end - start);
        wanted = std::max(n, share <= (std::size_t(1) << 26) ? share : std::min(expected, share));
        try
        {
          out.Reserve(wanted);
        }
        catch (const std::bad_alloc&)
        {
          // The room for the whole share is address space only, but under an address-space limit (ulimit -v) even
          // that may not be had: then room at the return rate, as for a larger share.
          wanted = std::max(n, std::min(expected, share));
          out.Reserve(wanted);
        }
      }
      wanted = std::max(wanted, n);
      out.Resize(n);
      const bool uv = out.withBarycentric;
      parallel(pieces, [&](std::size_t begin, std::size_t end) {
        for (std::size_t piece = begin; piece < end; ++piece)
        {
          std::size_t j = place[piece];
          for (std::size_t i = piece * Piece; i < std::min(count, (piece + 1) * Piece); ++i)
          {
            const BeamResult& r = block[i];
            if (r.triangle < 0)
              continue;
            std::copy(r.point, r.point + 3, &out.points[3 * j]);
            for (std::size_t k = 0; k < 3; ++k)
              out.normals[3 * j + k] = static_cast<float>(r.normal[k]);
            out.range[j] = r.range;
            out.intensity[j] = r.intensity;
            out.pose[j] = static_cast<std::int32_t>(r.pose); // poses are held in memory: far fewer than 2^31
            out.triangle[j] = r.triangle;
            if (uv)
            {
              out.barycentric[2 * j] = r.u;
              out.barycentric[2 * j + 1] = r.v;
            }
            out.beam[j] = static_cast<long long>(first + i);
            ++j;
          }
        }
      });
    }
  }
  catch (const std::bad_alloc&)
  {
    out.Clear();
    return MemoryError(p, beams, static_cast<double>(wanted), CloudBytesPerPoint(out.withBarycentric), 0, "up to");
  }
  out.beams = beams;
  if (progress)
    progress(1.0);
  return {};
}

std::string VirtualScan(const ScannerParameters& p, const std::vector<double>& points,
  const std::vector<std::int64_t>& triangles, ScanPoints& out, const ParallelFor& parallel,
  const std::function<bool(double)>& progress)
{
  out.Clear();
  BeamPattern pattern;
  std::string error = pattern.Setup(p);
  if (error.empty())
    error = ValidateSurface(points, triangles);
  if (!error.empty())
    return error;
  RayCaster caster;
  error = caster.Build(points, triangles);
  if (!error.empty())
    return error;
  return CastBeams(p, pattern, caster, out, parallel, progress);
}

} // namespace plantmorph
