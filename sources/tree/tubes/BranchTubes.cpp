// SPDX-License-Identifier: GPL-3.0-or-later
#include "BranchTubes.h"
#include "BranchPieces.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>
#include <plantmorph/RotationMinimizingFrames.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{

namespace
{
CleanedTube CleanTube(const TubeInput& input)
{
  CleanedTube c;
  for (std::size_t k = 0; k < input.centre.size(); ++k)
  {
    if (!c.centre.empty() && input.centre[k] == c.centre.back())
    {
      c.radii.back() = input.radii[k]; // keep the later radius (the end's)
      continue;
    }
    c.centre.push_back(input.centre[k]);
    c.radii.push_back(input.radii[k]);
  }
  c.apex = !c.radii.empty() && !(c.radii.back() > 0.0);
  return c;
}
} // namespace

std::string CleanTubes(const std::vector<TubeInput>& tubes, int sides, std::vector<CleanedTube>& cleaned)
{
  cleaned.clear();
  if (sides < 3 || sides > 256)
  {
    return OutOfRange("Sides", sides, "[3, 256]");
  }
  cleaned.assign(tubes.size(), CleanedTube());
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    if (tubes[t].radii.size() != tubes[t].centre.size())
    {
      return "tube " + std::to_string(t) + ": one radius per centre point is needed";
    }
    for (std::size_t k = 0; k < tubes[t].centre.size(); ++k)
    {
      if (!tubes[t].centre[k].allFinite() || !std::isfinite(tubes[t].radii[k]) || tubes[t].radii[k] < 0.0)
      {
        return "tube " + std::to_string(t) + ": point " + std::to_string(k) + " or its radius is not finite";
      }
    }
    if (tubes[t].parent >= static_cast<std::int64_t>(t) || tubes[t].parent < -1)
    {
      return "tube " + std::to_string(t) + ": parent " + std::to_string(tubes[t].parent) +
        " must be -1 or a smaller index";
    }
    cleaned[t] = CleanTube(tubes[t]);
    if (cleaned[t].centre.size() < 2)
    {
      return "tube " + std::to_string(t) + " has fewer than 2 distinct centre points";
    }
    for (std::size_t k = 0; k + 1 < cleaned[t].radii.size(); ++k)
    {
      if (!(cleaned[t].radii[k] > 0.0))
      {
        return "tube " + std::to_string(t) + ": radius 0 before its end";
      }
    }
  }
  return {};
}

void SetMeshPoint(
  TubeMesh& mesh, std::int64_t index, const Eigen::Vector3d& x, const Eigen::Vector3d& normal, double u, double v)
{
  const std::size_t i = static_cast<std::size_t>(index);
  mesh.points[3 * i] = x.x(), mesh.points[3 * i + 1] = x.y(), mesh.points[3 * i + 2] = x.z();
  mesh.normals[3 * i] = static_cast<float>(normal.x());
  mesh.normals[3 * i + 1] = static_cast<float>(normal.y());
  mesh.normals[3 * i + 2] = static_cast<float>(normal.z());
  mesh.tcoords[2 * i] = static_cast<float>(u);
  mesh.tcoords[2 * i + 1] = static_cast<float>(v);
}

namespace
{
} // namespace

RingAngles::RingAngles(int sides)
{
  for (int j = 0; j < sides; ++j)
  {
    const double a = 2.0 * Pi * j / sides;
    this->cosines.push_back(std::cos(a));
    this->sines.push_back(std::sin(a));
    this->around.push_back(1.0 - std::abs(1.0 - 2.0 * j / sides));
  }
}

Eigen::Vector3d MitreOffset(const Eigen::Vector3d& w, const Eigen::Vector3d& d, const Eigen::Vector3d& plane)
{
  static const double minimumCos = std::cos(85.0 * Pi / 180.0);
  const double denominator = std::max(d.dot(plane), minimumCos);
  return w - (w.dot(plane) / denominator) * d;
}

std::size_t TubeTriangles(MeshArray<std::int32_t>& triangles, std::size_t q, std::int64_t firstRing, std::size_t rings,
  int sides, std::int64_t baseCentre, std::int64_t end, bool apex, const std::vector<char>* bandAfter)
{
  const auto tri = [&](std::int64_t a, std::int64_t b, std::int64_t d) {
    triangles[q++] = static_cast<std::int32_t>(a);
    triangles[q++] = static_cast<std::int32_t>(b);
    triangles[q++] = static_cast<std::int32_t>(d);
  };
  const auto ring = [&](
                      std::size_t k, int j) { return firstRing + static_cast<std::int64_t>(k) * sides + (j % sides); };
  if (baseCentre >= 0)
    for (int j = 0; j < sides; ++j)
      tri(baseCentre, ring(0, j), ring(0, j + 1));
  for (std::size_t k = 0; k + 1 < rings; ++k)
  {
    if (bandAfter && !(*bandAfter)[k])
      continue;
    for (int j = 0; j < sides; ++j)
    {
      tri(ring(k, j), ring(k + 1, j), ring(k, j + 1));
      tri(ring(k, j + 1), ring(k + 1, j), ring(k + 1, j + 1));
    }
  }
  if (end >= 0)
  {
    for (int j = 0; j < sides; ++j)
    {
      if (apex)
        tri(ring(rings - 1, j), end, ring(rings - 1, j + 1));
      else
        tri(end, ring(rings - 1, j + 1), ring(rings - 1, j));
    }
  }
  return q;
}

namespace
{
using Cleaned = CleanedTube;

std::int64_t PointCount(const Cleaned& c, int sides)
{
  const std::int64_t rings = static_cast<std::int64_t>(c.centre.size()) - (c.apex ? 1 : 0);
  return 1 + rings * sides + 1; // base centre, rings, end centre or apex
}

std::int64_t TriangleCount(const Cleaned& c, int sides)
{
  const std::int64_t n = static_cast<std::int64_t>(c.centre.size());
  return sides + 2 * sides * (c.apex ? n - 2 : n - 1) + sides;
}
} // namespace

namespace
{
using TriangleRanges = std::vector<std::pair<std::int64_t, std::int64_t>>;

double LastCrossingIn(const TubeMesh& mesh, const TriangleRanges& ranges, const Eigen::Vector3d& p,
  const Eigen::Vector3d& e, double tMin, double tMax, bool* leaving);
} // namespace

double LastCrossing(const TubeMesh& mesh, std::size_t tube, const Eigen::Vector3d& p, const Eigen::Vector3d& e,
  double tMax, bool* leaving)
{
  return LastCrossingIn(mesh, { { mesh.triangleOffsets[tube], mesh.triangleOffsets[tube + 1] } }, p, e,
    -std::numeric_limits<double>::infinity(), tMax, leaving);
}

namespace
{
double LastCrossingIn(const TubeMesh& mesh, const TriangleRanges& ranges, const Eigen::Vector3d& p,
  const Eigen::Vector3d& e, double tMin, double tMax, bool* leaving)
{
  double best = std::numeric_limits<double>::quiet_NaN();
  bool bestLeaving = false;
  const double eNorm = e.norm();
  if (!(eNorm > 0.0))
  {
    return best;
  }
  const Eigen::Vector3d unit = e / eNorm;
  const auto P = [&](std::int32_t i) {
    const std::size_t k = 3 * static_cast<std::size_t>(i);
    return Eigen::Vector3d(mesh.points[k], mesh.points[k + 1], mesh.points[k + 2]);
  };
  for (const auto& [first, last] : ranges)
    for (std::int64_t f = first; f < last; ++f)
    {
      const std::int32_t* v = &mesh.triangles[3 * static_cast<std::size_t>(f)];
      const Eigen::Vector3d a = P(v[0]), b = P(v[1]), c = P(v[2]);
      // Cull: the line must pass within the triangle's bounding sphere (about its centroid).
      const Eigen::Vector3d centroid = (a + b + c) / 3.0;
      const double reach2 =
        std::max({ (a - centroid).squaredNorm(), (b - centroid).squaredNorm(), (c - centroid).squaredNorm() });
      const Eigen::Vector3d w = centroid - p;
      if ((w - w.dot(unit) * unit).squaredNorm() > reach2 * (1.0 + 1e-9))
      {
        continue;
      }
      // Moller-Trumbore for the whole line.
      const Eigen::Vector3d e1 = b - a, e2 = c - a;
      const Eigen::Vector3d h = e.cross(e2);
      const double det = e1.dot(h);
      if (std::abs(det) <= 1e-300)
      {
        continue; // parallel to the triangle's plane
      }
      const double inv = 1.0 / det;
      const Eigen::Vector3d s = p - a;
      const double u = inv * s.dot(h);
      constexpr double slack = 1e-12;
      if (u < -slack || u > 1.0 + slack)
      {
        continue;
      }
      const Eigen::Vector3d q = s.cross(e1);
      const double vv = inv * e.dot(q);
      if (vv < -slack || u + vv > 1.0 + slack)
      {
        continue;
      }
      const double t = inv * e2.dot(q);
      if (t < tMax && t >= tMin && !(t <= best))
      {
        best = t;
        bestLeaving = e.dot(e1.cross(e2)) > 0.0;
      }
    }
  if (leaving)
  {
    *leaving = bestLeaving;
  }
  return best;
}

/// Tube t's points and triangles at its offsets: base centre, rings (ring 0 around the first segment, vertex 0
/// towards `towards`, the tube's normal; each further ring the previous one's directions carried along the segment
/// onto the bisector plane), end point, and TubeTriangles' caps and bands.
void WriteTube(
  const Cleaned& c, const Eigen::Vector3d& towards, const RingAngles& angles, int sides, std::size_t t, TubeMesh& mesh)
{
  const std::vector<double>& cosines = angles.cosines;
  const std::vector<double>& sines = angles.sines;
  const std::vector<double>& around = angles.around;
  const std::size_t n = c.centre.size();
  const std::vector<Eigen::Vector3d> tangents = PolylineTangents(c.centre);
  std::vector<double> arc(n, 0.0);
  for (std::size_t k = 1; k < n; ++k)
  {
    arc[k] = arc[k - 1] + (c.centre[k] - c.centre[k - 1]).norm();
  }
  const double total = arc.back();
  std::int64_t p = mesh.pointOffsets[t];
  const auto put = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& normal, double u, double v) {
    SetMeshPoint(mesh, p, x, normal, u, v);
    return p++;
  };
  const std::int64_t baseCentre = put(c.centre[0], -tangents[0], 0.5, 0.0);
  const std::size_t rings = c.apex ? n - 1 : n;
  const std::int64_t firstRing = p;
  // Ring 0: a circle around the first segment, vertex 0 towards the given normal.
  std::vector<Eigen::Vector3d> radial(static_cast<std::size_t>(sides)); // unit, across the current segment
  const Eigen::Vector3d n0 = PerpendicularTo(tangents[0], towards);
  const Eigen::Vector3d b0 = n0.cross(tangents[0]);
  for (int j = 0; j < sides; ++j)
  {
    const std::size_t js = static_cast<std::size_t>(j);
    radial[js] = cosines[js] * n0 + sines[js] * b0;
    put(c.centre[0] + c.radii[0] * radial[js], radial[js], around[js], 0.0);
  }
  // Ring k: ring k - 1's cross-section directions carried along segment k - 1 (a translation: no twist, the
  // exact rotation-minimising transport of a polyline) onto the bisector plane at point k, i.e. the
  // intersection of segment k - 1's cylinder with that plane, which is also segment k's cylinder's.
  for (std::size_t k = 1; k < rings; ++k)
  {
    const Eigen::Vector3d d = (c.centre[k] - c.centre[k - 1]).normalized();
    const Eigen::Vector3d& plane = tangents[k];
    const Eigen::Vector3d out = k + 1 < n ? Eigen::Vector3d((c.centre[k + 1] - c.centre[k]).normalized()) : d;
    for (int j = 0; j < sides; ++j)
    {
      const std::size_t js = static_cast<std::size_t>(j);
      Eigen::Vector3d w = radial[js] - radial[js].dot(d) * d;
      w.normalize();
      const Eigen::Vector3d offset = c.radii[k] * MitreOffset(w, d, plane);
      put(c.centre[k] + offset, w, around[js], total > 0.0 ? arc[k] / total : 0.0);
      // Across the next segment: the same offset direction without its component along it.
      Eigen::Vector3d next = offset - offset.dot(out) * out;
      radial[js] = next.norm() > 0.0 ? Eigen::Vector3d(next.normalized()) : w;
    }
  }
  const std::int64_t last = put(c.centre[n - 1], tangents[n - 1], 0.5, 1.0);
  TubeTriangles(mesh.triangles, 3 * static_cast<std::size_t>(mesh.triangleOffsets[t]), firstRing, rings, sides,
    baseCentre, last, c.apex);
}

/// The child tubes level by level (level 1 first; the roots, level 0, are left out).
std::vector<std::vector<std::size_t>> ChildrenByLevel(const std::vector<TubeInput>& tubes)
{
  std::vector<int> level(tubes.size(), 0);
  int levels = 0;
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    level[t] = tubes[t].parent < 0 ? 0 : level[static_cast<std::size_t>(tubes[t].parent)] + 1;
    levels = std::max(levels, level[t]);
  }
  std::vector<std::vector<std::size_t>> byLevel(static_cast<std::size_t>(levels) + 1);
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    if (level[t] > 0)
      byLevel[static_cast<std::size_t>(level[t])].push_back(t);
  }
  return byLevel;
}

Eigen::Vector3d MeshPoint(const TubeMesh& mesh, std::int64_t i)
{
  const std::size_t k = 3 * static_cast<std::size_t>(i);
  return Eigen::Vector3d(mesh.points[k], mesh.points[k + 1], mesh.points[k + 2]);
}

void MovePoint(TubeMesh& mesh, std::int64_t i, const Eigen::Vector3d& x)
{
  const std::size_t k = 3 * static_cast<std::size_t>(i);
  mesh.points[k] = x.x(), mesh.points[k + 1] = x.y(), mesh.points[k + 2] = x.z();
}

/// The parent's triangles a child's crossing window can reach: those of the parent's segments passing within
/// (`reach` + the segment's ring reach) of the child's base centre. A segment's triangles lie within
/// max radius / cos(85 / 2 deg) < 1.36 radii of it (mitre clamp).
TriangleRanges ParentTrianglesNear(
  const Cleaned& host, std::int64_t hostTriangles, const Eigen::Vector3d& baseCentre, double reach, int sides)
{
  const std::size_t hostRings = host.centre.size() - (host.apex ? 1 : 0);
  TriangleRanges ranges;
  for (std::size_t k = 0; k + 1 < host.centre.size(); ++k)
  {
    const Eigen::Vector3d a = host.centre[k], d = host.centre[k + 1] - host.centre[k];
    const double along = std::clamp((baseCentre - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double distance = (baseCentre - a - along * d).norm();
    // (+ the first segment's length for k = 0: the parent's own base ring may have slid back that far.)
    const double slid = k == 0 ? d.norm() : 0.0;
    if (distance > reach + slid + 1.36 * std::max(host.radii[k], host.radii[k + 1]) + 1e-9 * (1.0 + reach))
    {
      continue;
    }
    if (k == 0)
      ranges.emplace_back(hostTriangles, hostTriangles + sides); // base cap
    if (k + 1 < hostRings)
    {
      const std::int64_t first = hostTriangles + sides + 2 * sides * static_cast<std::int64_t>(k);
      ranges.emplace_back(first, first + 2 * sides);
    }
    if (k + 2 == host.centre.size()) // end cap or apex fan
    {
      const std::int64_t first = hostTriangles + sides + 2 * sides * static_cast<std::int64_t>(hostRings - 1);
      ranges.emplace_back(first, first + sides);
    }
  }
  return ranges;
}

/// The parameter t of the line v + t e where it comes closest to the host's centre line.
double ClosestToCentreLine(const Cleaned& host, const Eigen::Vector3d& v, const Eigen::Vector3d& e)
{
  double along = 0.0, closest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < host.centre.size(); ++k)
  {
    // Closest points of the line v + t e and the segment a + s (b - a), s in [0, 1].
    const Eigen::Vector3d a = host.centre[k], d = host.centre[k + 1] - host.centre[k], r = v - a;
    const double ee = e.dot(e), dd = d.dot(d), ed = e.dot(d), er = e.dot(r), dr = d.dot(r);
    const double det = ee * dd - ed * ed;
    double sParam = det > 1e-300 * ee * dd ? std::clamp((ee * dr - ed * er) / det, 0.0, 1.0) : 0.0;
    const double tParam = (ed * sParam - er) / ee;
    const double gap = (v + tParam * e - a - sParam * d).norm();
    if (gap < closest)
    {
      closest = gap, along = tParam;
    }
  }
  return along;
}

/// Seats child tube t's base ring on its parent's surface (each ring vertex slides along its first band edge to
/// where that line last leaves the parent) and its base cap's centre along the axis; counts seated, missed,
/// clamped and buried vertices.
void SeatJoint(const std::vector<TubeInput>& tubes, const std::vector<Cleaned>& cleaned, std::size_t t, int sides,
  TubeMesh& mesh, std::array<std::int64_t, 4>& count)
{
  const auto P = [&](std::int64_t i) { return MeshPoint(mesh, i); };
  const auto Set = [&](std::int64_t i, const Eigen::Vector3d& x) { MovePoint(mesh, i, x); };
  const std::size_t parent = static_cast<std::size_t>(tubes[t].parent);
  const std::int64_t baseCentre = mesh.pointOffsets[t], firstRing = baseCentre + 1;
  const bool apex = cleaned[t].apex;
  const std::size_t rings = cleaned[t].centre.size() - (apex ? 1 : 0);
  const std::int64_t apexPoint = mesh.pointOffsets[t + 1] - 1;
  // Crossings are looked for from `back` behind the base ring (4 (child + parent radius): past the parent's
  // far side) to ring 1, among the parent's triangles that window can reach.
  const Cleaned& host = cleaned[parent];
  const double back = 4.0 * (cleaned[t].radii[0] + *std::max_element(host.radii.begin(), host.radii.end()));
  double reach = 0.0;
  for (int j = 0; j < sides; ++j)
  {
    const Eigen::Vector3d next = rings >= 2 ? P(firstRing + sides + j) : P(apexPoint);
    reach =
      std::max(reach, std::max(back, (next - P(firstRing + j)).norm()) + (P(firstRing + j) - P(baseCentre)).norm());
  }
  const TriangleRanges ranges = ParentTrianglesNear(host, mesh.triangleOffsets[parent], P(baseCentre), reach, sides);
  for (int j = 0; j < sides; ++j)
  {
    const Eigen::Vector3d v = P(firstRing + j);
    const Eigen::Vector3d next = rings >= 2 ? P(firstRing + sides + j) : P(apexPoint);
    const Eigen::Vector3d e = next - v;
    bool leaving = false;
    const double crossing = LastCrossingIn(mesh, ranges, v, e, -back / e.norm(), 1.0, &leaving);
    if (std::isnan(crossing))
    {
      // The line misses the parent (a child wider than its parent there): slide to where the line comes
      // closest to the parent's centre line (within the window), so the child's wall reaches back beside the parent, not past it.
      const double along = ClosestToCentreLine(host, v, e);
      Set(firstRing + j, v + std::clamp(along, -back / e.norm(), 0.95) * e);
      ++count[1];
    }
    else if (!leaving)
    {
      ++count[3];
    }
    else if (crossing > 0.95)
    {
      Set(firstRing + j, v + 0.95 * e);
      ++count[2];
    }
    else
    {
      Set(firstRing + j, v + crossing * e);
      ++count[0];
    }
  }
  // The base cap's centre along the axis: where the axis leaves the parent before the next centre point.
  const Eigen::Vector3d centre = P(baseCentre);
  const Eigen::Vector3d axis = cleaned[t].centre[1] - cleaned[t].centre[0];
  bool leaving = false;
  const double crossing = LastCrossingIn(mesh, ranges, centre, axis, -back / axis.norm(), 0.95, &leaving);
  if (!std::isnan(crossing) && leaving)
  {
    Set(baseCentre, centre + crossing * axis);
  }
}
} // namespace

std::string BuildTubes(const std::vector<TubeInput>& tubes, int sides, TubeMesh& mesh, const ParallelFor& parallel,
  JointReport* joints, const std::vector<char>* selected)
{
  if (joints)
  {
    *joints = JointReport();
  }
  mesh = TubeMesh();
  std::vector<Cleaned> cleaned;
  if (std::string error = CleanTubes(tubes, sides, cleaned); !error.empty())
  {
    return error;
  }
  if (selected && selected->size() != tubes.size())
  {
    return "the tube selection has " + std::to_string(selected->size()) + " entries for " +
      std::to_string(tubes.size()) + " tubes";
  }
  // Built: the selected tubes and their ancestors (all tubes without a selection).
  std::vector<char> built(tubes.size(), selected ? 0 : 1);
  for (std::size_t t = 0; selected && t < tubes.size(); ++t)
  {
    for (std::int64_t a = (*selected)[t] ? static_cast<std::int64_t>(t) : -1; a >= 0 && !built[std::size_t(a)];
         a = tubes[std::size_t(a)].parent)
      built[static_cast<std::size_t>(a)] = 1;
  }
  mesh.pointOffsets.assign(tubes.size() + 1, 0);
  mesh.triangleOffsets.assign(tubes.size() + 1, 0);
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    mesh.pointOffsets[t + 1] = mesh.pointOffsets[t] + (built[t] ? PointCount(cleaned[t], sides) : 0);
    mesh.triangleOffsets[t + 1] = mesh.triangleOffsets[t] + (built[t] ? TriangleCount(cleaned[t], sides) : 0);
  }
  if (mesh.pointOffsets.back() > std::numeric_limits<std::int32_t>::max())
  {
    return "the tubes would have more than 2^31 - 1 points";
  }
  const std::size_t points = static_cast<std::size_t>(mesh.pointOffsets.back());
  mesh.points.resize(3 * points);
  mesh.normals.resize(3 * points);
  mesh.tcoords.resize(2 * points);
  mesh.triangles.resize(3 * static_cast<std::size_t>(mesh.triangleOffsets.back()));

  const RingAngles angles(sides);
  parallel(tubes.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      if (built[t])
        WriteTube(cleaned[t], tubes[t].normal, angles, sides, t, mesh);
  });

  // Joints: seat each child's base ring on its parent's surface, level by level (a parent is final before its
  // children read it; children of one level only write their own points).
  std::vector<std::array<std::int64_t, 4>> counts(tubes.size(), { 0, 0, 0, 0 });
  for (std::vector<std::size_t> children : ChildrenByLevel(tubes))
  {
    children.erase(
      std::remove_if(children.begin(), children.end(), [&](std::size_t t) { return !built[t]; }), children.end());
    parallel(children.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        SeatJoint(tubes, cleaned, children[i], sides, mesh, counts[children[i]]);
    });
  }
  if (joints)
  {
    for (std::size_t t = 0; t < tubes.size(); ++t)
    {
      if (selected && !(*selected)[t])
        continue;
      const auto& c = counts[t];
      joints->seated += c[0], joints->missed += c[1], joints->clamped += c[2], joints->buried += c[3];
    }
  }
  if (selected)
  {
    KeepTubes(mesh, *selected);
  }
  return {};
}

} // namespace plantmorph
