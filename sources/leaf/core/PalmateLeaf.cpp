// SPDX-License-Identifier: GPL-3.0-or-later
#include "PalmateLeaf.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>

namespace plantmorph
{
namespace
{
using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactPolygon = CGAL::Polygon_2<ExactKernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<ExactKernel>;

/// One lobe in the leaf's final frame (base at the origin, lobe 1's chord along +Y).
struct Lobe
{
  std::vector<Eigen::Vector2d> margin; ///< the integrated half-margin, start to tip
  std::vector<Eigen::Vector2d> mirror; ///< the other half, start to tip
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> subTips; ///< its sub-lobes' tips on both halves
};

/// What an outline vertex was before the union: a sample, the base, a lobe's start, or a lobe's tip.
struct VertexRole
{
  bool base = false;
  bool start = false;
  int tip = -1;        ///< index of the lobe whose tip this is
  bool subTip = false; ///< a sub-lobe's tip
};

using Key = std::pair<double, double>;
Key KeyOf(const Eigen::Vector2d& x)
{
  return { x.x(), x.y() };
}

Eigen::Vector2d MirrorInAxis(const Eigen::Vector2d& x)
{
  return { -x.x(), x.y() };
}

/// The point at `fraction` of the length of the polyline `path`.
Eigen::Vector2d AlongPath(const std::vector<Eigen::Vector2d>& path, double fraction)
{
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    total += (path[i + 1] - path[i]).norm();
  double target = std::clamp(fraction, 0.0, 1.0) * total;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
  {
    const double piece = (path[i + 1] - path[i]).norm();
    if (target <= piece || i + 2 == path.size())
      return piece > 0.0 ? Eigen::Vector2d(path[i] + std::min(1.0, target / piece) * (path[i + 1] - path[i]))
                         : path[i + 1];
    target -= piece;
  }
  return path.back();
}

std::string LobeName(int level)
{
  return "lobe " + std::to_string(level + 1);
}

/// An outline vertex of the lobes' union: its position, its role before the union, or a crossing of lobe margins.
struct OutlineVertex
{
  Eigen::Vector2d x;
  VertexRole role;
  bool crossing = false;
};

/// Where the lobes' tips are along the outline.
struct TipLayout
{
  std::vector<int> position; ///< outline index of each lobe's tip
  std::vector<int> order;    ///< lobes by the position of their tips, right to left
  std::vector<double> u;     ///< each lobe's LeafUV u
};

/// A sector between neighbouring midveins (or between a midvein and the margin down to the base): its polygon and
/// boundary LeafUV, for the interior points' mean-value interpolation.
struct Sector
{
  std::vector<Eigen::Vector2d> polygon, uv;
  double uLow = 0.0, uHigh = 0.0;
};

/// Sub-lobes (a pinnately lobed lobe) on one half-margin `half` of a lobe running from `start` to `tip`: every
/// sample at arc-length fraction t beyond `from` is pulled towards the lobe's axis (its chord from start to tip) to
/// 1 - depth*sin^4(pi*phi) of its distance from it, phi = (count + 1)(t - from)/(1 - from): `count` sub-lobes whose
/// tips (phi = 1..count, the samples nearest their t, kept where they were) go to `tips`, with rounded sinuses
/// between them and one below the lobe's own tip.
void SubLobeHalf(const SpaceCurveParameters& p, double from, const Eigen::Vector2d& start, const Eigen::Vector2d& tip,
  std::vector<Eigen::Vector2d>& half, std::vector<Eigen::Vector2d>& tips)
{
  const Eigen::Vector2d axis = (tip - start).normalized();
  std::vector<double> t(half.size(), 0.0);
  for (std::size_t i = 1; i < half.size(); ++i)
    t[i] = t[i - 1] + (half[i] - half[i - 1]).norm();
  for (double& value : t)
    value /= t.back();
  const double periods = p.subLobes + 1.0;
  std::vector<std::size_t> tipSamples;
  for (int j = 1; j <= p.subLobes; ++j)
  {
    const double target = from + j * (1.0 - from) / periods;
    std::size_t nearest = 1;
    for (std::size_t i = 1; i + 1 < half.size(); ++i)
    {
      if (std::abs(t[i] - target) < std::abs(t[nearest] - target))
        nearest = i;
    }
    if (t[nearest] > from)
      tipSamples.push_back(nearest);
  }
  for (std::size_t i = 1; i + 1 < half.size(); ++i)
  {
    if (t[i] <= from)
      continue;
    const double phi = periods * (t[i] - from) / (1.0 - from);
    const double bump = std::pow(std::sin(Pi * phi), 4);
    const Eigen::Vector2d foot = start + (half[i] - start).dot(axis) * axis;
    half[i] = foot + (1.0 - p.subLobeDepth * bump) * (half[i] - foot);
  }
  for (std::size_t i : tipSamples)
    tips.push_back(half[i]);
}

/// Sub-lobes on both halves of every lobe (subLobes > 0), each half from where it leaves the other lobes (the
/// entire lobes' polygons, both copies; at least LobeStart) to its tip: only margin that is outline is cut, so the
/// sinuses open no holes where lobes overlap.
void ApplySubLobes(const SpaceCurveParameters& p, std::vector<Lobe>& lobes)
{
  if (p.subLobes <= 0)
    return;
  std::vector<std::vector<Eigen::Vector2d>> polygons;
  std::vector<std::size_t> owner;
  for (std::size_t k = 0; k < lobes.size(); ++k)
  {
    for (int copy = 0; copy < (k == 0 ? 1 : 2); ++copy)
    {
      std::vector<Eigen::Vector2d> loop(lobes[k].margin.begin(), lobes[k].margin.end());
      for (std::size_t i = lobes[k].mirror.size() - 2; i >= 1; --i)
        loop.push_back(lobes[k].mirror[i]);
      for (Eigen::Vector2d& x : loop)
        x = copy == 0 ? x : MirrorInAxis(x);
      polygons.push_back(loop);
      owner.push_back(k);
    }
  }
  for (std::size_t k = 0; k < lobes.size(); ++k)
  {
    for (std::vector<Eigen::Vector2d>* half : { &lobes[k].margin, &lobes[k].mirror })
    {
      double from = p.lobeStart, along = 0.0, total = 0.0;
      for (std::size_t i = 1; i < half->size(); ++i)
        total += ((*half)[i] - (*half)[i - 1]).norm();
      for (std::size_t i = 1; i + 1 < half->size(); ++i)
      {
        along += ((*half)[i] - (*half)[i - 1]).norm();
        for (std::size_t j = 0; j < polygons.size(); ++j)
        {
          if (owner[j] != k && InsidePolygon(polygons[j], (*half)[i]))
            from = std::max(from, along / total);
        }
      }
      if (from < 0.95)
        SubLobeHalf(p, from, lobes[k].start, lobes[k].tip, *half, lobes[k].subTips);
    }
  }
}

/// Lobe 1 in the paper's frame, turned so that its chord runs along +Y, and each further lobe's half-margin from its
/// start on the previous lobe's (`levels` lobes in all).
std::string IntegrateLobes(const SpaceCurveParameters& p, int n, int levels, std::vector<Lobe>& lobes)
{
  // Lobe 1 in the paper's frame, then the rotation that takes its chord to +Y.
  std::vector<FrenetFrame> frames;
  std::string error = IntegrateHalfMargin(p, n, frames);
  if (!error.empty())
    return "Curvature: " + error;
  const Eigen::Vector3d base = frames.front().position;
  const Eigen::Vector3d chord = frames.back().position - base;
  const double chordLength = chord.norm();
  if (!(chordLength > 1e-9 * p.length))
    return "Curvature: the half-margin closes on itself (its end is its start); lower CurvatureMu";
  const Eigen::Matrix3d rotation =
    Eigen::Quaterniond::FromTwoVectors(chord / chordLength, Eigen::Vector3d::UnitY()).toRotationMatrix();
  auto flat = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d y = rotation * x;
    return Eigen::Vector2d(y.x(), y.y());
  };

  lobes.assign(levels, Lobe());
  for (const FrenetFrame& f : frames)
    lobes[0].margin.push_back(flat(f.position - base));
  lobes[0].margin.front() = Eigen::Vector2d::Zero();
  lobes[0].tip = Eigen::Vector2d(0.0, chordLength);
  lobes[0].margin.back() = lobes[0].tip;

  double angle = p.initialAngle;
  for (int k = 1; k < levels; ++k)
  {
    // The start: on the previous lobe's half-margin at the arc-length fraction lobeStart (its samples are at equal
    // arc length), a sample if one is within 0.3 of the spacing, else a new sample of that margin.
    std::vector<Eigen::Vector2d>& previous = lobes[k - 1].margin;
    const int pieces = static_cast<int>(previous.size()) - 1;
    const double position = p.lobeStart * pieces;
    const long nearest = std::lround(position);
    Eigen::Vector2d start;
    if (std::abs(position - static_cast<double>(nearest)) <= 0.3 && nearest >= 1 && nearest < pieces)
      start = previous[static_cast<std::size_t>(nearest)];
    else
    {
      const int i = std::min(pieces - 1, static_cast<int>(std::floor(position)));
      const double t = position - i;
      start = (1.0 - t) * previous[i] + t * previous[i + 1];
      previous.insert(previous.begin() + i + 1, start);
    }

    angle -= p.lobeAngle;
    const double scale = std::pow(p.lobeScale, k);
    SpaceCurveParameters q = p;
    q.length = p.length * scale;
    q.initialAngle = angle;
    q.lobes = 1;
    const int lobePieces = std::max(4, static_cast<int>(std::lround(n * scale)));
    error = IntegrateHalfMargin(q, lobePieces, frames);
    if (!error.empty())
      return "Curvature (" + LobeName(k) + "): " + error;
    Lobe& lobe = lobes[k];
    lobe.start = start;
    for (const FrenetFrame& f : frames)
      lobe.margin.push_back(start + flat(f.position - frames.front().position));
    lobe.margin.front() = start;
    lobe.tip = lobe.margin.back();
  }
  return {};
}

/// Second halves: lobe 1's mirrored in the leaf's axis (x = 0), the others in their own chords.
std::string MirrorLobes(const SpaceCurveParameters& p, std::vector<Lobe>& lobes)
{
  for (std::size_t k = 0; k < lobes.size(); ++k)
  {
    Lobe& lobe = lobes[k];
    const Eigen::Vector2d axis = lobe.tip - lobe.start;
    if (!(axis.norm() > 1e-9 * p.length))
      return "Curvature (" + LobeName(static_cast<int>(k)) + "): the half-margin closes on itself; lower CurvatureMu";
    const Eigen::Vector2d direction = axis.normalized();
    for (const Eigen::Vector2d& x : lobe.margin)
    {
      const Eigen::Vector2d d = x - lobe.start;
      lobe.mirror.push_back(
        k == 0 ? MirrorInAxis(x) : Eigen::Vector2d(lobe.start + 2.0 * d.dot(direction) * direction - d));
    }
    lobe.mirror.front() = lobe.start;
    lobe.mirror.back() = lobe.tip;
  }
  return {};
}

/// Lobe polygons: lobe 1, then each further lobe on its own side and mirrored on the other. Roles of their vertices.
std::string LobePolygons(const std::vector<Lobe>& lobes, std::map<Key, VertexRole>& roles,
  std::vector<ExactPolygon>& polygons, std::vector<Eigen::Vector2d>& tips)
{
  roles[KeyOf(Eigen::Vector2d::Zero())].base = true;
  for (std::size_t k = 0; k < lobes.size(); ++k)
  {
    for (int copy = 0; copy < (k == 0 ? 1 : 2); ++copy)
    {
      const Lobe& lobe = lobes[k];
      auto place = [&](const Eigen::Vector2d& x) { return copy == 0 ? x : MirrorInAxis(x); };
      std::vector<Eigen::Vector2d> loop;
      for (const Eigen::Vector2d& x : lobe.margin)
        loop.push_back(place(x));
      for (std::size_t i = lobe.mirror.size() - 2; i >= 1; --i)
        loop.push_back(place(lobe.mirror[i]));
      ExactPolygon polygon;
      for (const Eigen::Vector2d& x : loop)
      {
        polygon.push_back(ExactKernel::Point_2(x.x(), x.y()));
        roles[KeyOf(x)];
      }
      if (!polygon.is_simple())
        return "Curvature (" + LobeName(static_cast<int>(k)) + "): the lobe's two halves cross; lower CurvatureMu";
      if (polygon.orientation() == CGAL::CLOCKWISE)
        polygon.reverse_orientation();
      polygons.push_back(polygon);
      const int tipIndex = static_cast<int>(tips.size());
      tips.push_back(place(lobe.tip));
      roles[KeyOf(tips.back())].tip = tipIndex;
      if (k > 0)
        roles[KeyOf(place(lobe.start))].start = true;
      for (const Eigen::Vector2d& x : lobe.subTips)
        roles[KeyOf(place(x))].subTip = true;
    }
  }
  return {};
}

Eigen::Vector2d ToVector(const ExactKernel::Point_2& x)
{
  return { CGAL::to_double(CGAL::exact(x.x())), CGAL::to_double(CGAL::exact(x.y())) };
}

/// SinusDepth d > 0: every sinus between two lobes whose tips follow each other along the outline (its bottom: the
/// outline vertex nearest the base between them) that is farther from the base than (1 - d) times the nearer of
/// the two tips is cut towards the base by a thin wedge along the ray from the base through it, to that distance
/// (the sinus reaches (1 - d) of the shorter lobe's length from the base; deeper sinuses stay). The wedge is half as wide at the old bottom as that
/// bottom's distance from the nearer of the two lines from the base to the lobes' tips, and closes to a point at the
/// new bottom, so it stays between the two lobes' midveins. The lobes stay joined at the base.
std::string CarveSinuses(double depth, const std::map<Key, VertexRole>& roles, ExactPolygonWithHoles& blade)
{
  if (!(depth > 0.0))
    return {};
  std::vector<Eigen::Vector2d> outline;
  std::vector<int> tip;
  std::size_t base = 0;
  for (auto v = blade.outer_boundary().vertices_begin(); v != blade.outer_boundary().vertices_end(); ++v)
  {
    outline.push_back(ToVector(*v));
    const auto known = roles.find(KeyOf(outline.back()));
    tip.push_back(known != roles.end() ? known->second.tip : -1);
    if (known != roles.end() && known->second.base)
      base = outline.size() - 1;
  }
  const std::size_t n = outline.size();
  std::vector<ExactPolygon> wedges;
  int previous = -1; // outline position (from the base) of the last tip met
  for (std::size_t k = 1; k < n; ++k)
  {
    const std::size_t i = (base + k) % n;
    if (tip[i] < 0)
      continue;
    if (previous >= 0)
    {
      std::size_t bottom = (base + previous + 1) % n;
      for (std::size_t m = previous + 1; m < k; ++m)
      {
        if (outline[(base + m) % n].norm() < outline[bottom].norm())
          bottom = (base + m) % n;
      }
      const Eigen::Vector2d s = outline[bottom];
      const Eigen::Vector2d a = outline[(base + previous) % n].normalized(), b = outline[i].normalized();
      const double target = (1.0 - depth) * std::min(outline[(base + previous) % n].norm(), outline[i].norm());
      const auto off = [&](const Eigen::Vector2d& unit) { return std::abs(unit.x() * s.y() - unit.y() * s.x()); };
      const double half = 0.5 * std::min(off(a), off(b));
      if (s.norm() > target && half > 0.0)
      {
        const Eigen::Vector2d along = s.normalized(), across(-along.y(), along.x());
        const Eigen::Vector2d corners[3] = { target * along, s + half * (across + along),
          s + half * (-across + along) };
        ExactPolygon wedge;
        for (const Eigen::Vector2d& x : corners)
          wedge.push_back(ExactKernel::Point_2(x.x(), x.y()));
        if (wedge.orientation() == CGAL::CLOCKWISE)
          wedge.reverse_orientation();
        wedges.push_back(wedge);
      }
    }
    previous = static_cast<int>(k);
  }
  for (const ExactPolygon& wedge : wedges)
  {
    std::vector<ExactPolygonWithHoles> pieces;
    CGAL::difference(blade, wedge, std::back_inserter(pieces));
    if (pieces.size() != 1 || pieces.front().number_of_holes() > 0)
      return "SinusDepth: a sinus cut the blade apart; lower SinusDepth";
    blade = pieces.front();
  }
  return {};
}

/// The union's outline, counter-clockwise, from the base; crossings of lobe margins (and the corners of sinuses cut
/// deeper, SinusDepth) are new vertices.
std::string UnionOutline(const std::vector<ExactPolygon>& polygons, const std::map<Key, VertexRole>& roles,
  double sinusDepth, std::vector<OutlineVertex>& vertices)
{
  std::vector<ExactPolygonWithHoles> unions;
  CGAL::join(polygons.begin(), polygons.end(), std::back_inserter(unions));
  if (unions.size() != 1)
    return "LobeStart/LobeAngle: the lobes do not join into one blade";
  if (unions.front().number_of_holes() > 0)
    return "LobeAngle/LobeScale: the lobes enclose a hole; lower LobeAngle";
  if (const std::string error = CarveSinuses(sinusDepth, roles, unions.front()); !error.empty())
    return error;

  for (auto v = unions.front().outer_boundary().vertices_begin(); v != unions.front().outer_boundary().vertices_end();
       ++v)
  {
    OutlineVertex vertex;
    // From the exact value (rounded towards zero, so mirror-image crossings round to mirror-image doubles; the
    // lazy kernel's approximation need not).
    vertex.x = Eigen::Vector2d(CGAL::to_double(CGAL::exact(v->x())), CGAL::to_double(CGAL::exact(v->y())));
    const auto known = roles.find(KeyOf(vertex.x));
    if (known != roles.end())
      vertex.role = known->second;
    else
      vertex.crossing = true;
    vertices.push_back(vertex);
  }
  {
    std::map<Key, int> seen;
    for (const OutlineVertex& v : vertices)
    {
      if (++seen[KeyOf(v.x)] > 1)
        return "LobeAngle: a lobe meets the previous one at its start point only; lower LobeAngle or raise LobeStart";
    }
  }
  const auto baseIt =
    std::find_if(vertices.begin(), vertices.end(), [](const OutlineVertex& v) { return v.role.base; });
  if (baseIt == vertices.end())
    return "LobeAngle/LobeStart: a lobe covers the leaf's base; lower LobeAngle or raise LobeStart";
  std::rotate(vertices.begin(), baseIt, vertices.end());
  return {};
}

/// No slivers: drop plain samples closer than 0.3 of the spacing to a neighbouring crossing or lobe start.
void DropSlivers(double spacing, std::vector<OutlineVertex>& vertices)
{
  std::vector<OutlineVertex> kept;
  const std::size_t count = vertices.size();
  for (std::size_t i = 0; i < count; ++i)
  {
    const OutlineVertex& v = vertices[i];
    const bool plain = !v.crossing && !v.role.base && !v.role.start && v.role.tip < 0 && !v.role.subTip;
    bool crowded = false;
    for (const std::size_t j : { (i + count - 1) % count, (i + 1) % count })
    {
      const OutlineVertex& w = vertices[j];
      crowded = crowded || ((w.crossing || w.role.start) && (w.x - v.x).norm() < 0.3 * spacing);
    }
    if (!(plain && crowded))
      kept.push_back(v);
  }
  vertices.swap(kept);
}

/// Where the lobes' tips are along the outline: from the base counter-clockwise, the rightmost first.
std::string LayOutTips(const std::vector<OutlineVertex>& vertices, int lobeCount, TipLayout& tips)
{
  std::vector<int>& tipPosition = tips.position;
  tipPosition.assign(lobeCount, -1);
  for (std::size_t i = 0; i < vertices.size(); ++i)
  {
    if (vertices[i].role.tip >= 0)
      tipPosition[vertices[i].role.tip] = static_cast<int>(i);
  }
  for (int k = 0; k < lobeCount; ++k)
  {
    if (tipPosition[k] < 0)
      return "LobeAngle/LobeScale: the tip of a lobe lies inside another lobe; lower LobeScale or raise LobeAngle";
  }
  std::vector<int>& order = tips.order;
  order.resize(lobeCount);
  for (int k = 0; k < lobeCount; ++k)
    order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return tipPosition[a] < tipPosition[b]; });
  tips.u.resize(lobeCount);
  for (int j = 0; j < lobeCount; ++j)
    tips.u[order[j]] = (0.5 * (lobeCount - 1) - j) / lobeCount;
  return {};
}

/// Outline vertices with their LeafUV, piece by piece along the canonical rectangle's edges.
BladeOutline OutlineWithLeafUV(const std::vector<OutlineVertex>& vertices, const TipLayout& tips)
{
  const std::vector<int>& tipPosition = tips.position;
  const std::vector<int>& order = tips.order;
  const std::vector<double>& tipU = tips.u;
  const int lobeCount = static_cast<int>(tipPosition.size());
  BladeOutline outline;
  const int count = static_cast<int>(vertices.size());
  outline.points.resize(count);
  outline.uv.resize(count);
  outline.region.resize(count);
  for (int i = 0; i < count; ++i)
  {
    outline.points[i] = vertices[i].x;
    outline.region[i] = vertices[i].role.base || vertices[i].role.tip >= 0 ? RegionMidvein : RegionMargin;
    outline.boundary.push_back(i);
  }
  outline.uv[0] = Eigen::Vector2d::Zero();
  for (int j = 0; j <= lobeCount; ++j)
  {
    const int from = j == 0 ? 0 : tipPosition[order[j - 1]];
    const int to = j == lobeCount ? count : tipPosition[order[j]];
    std::vector<Eigen::Vector2d> path;
    if (j == 0)
      path = { { 0.5, 0.0 }, { 0.5, 1.0 }, { tipU[order[0]], 1.0 } };
    else if (j == lobeCount)
      path = { { tipU[order[j - 1]], 1.0 }, { -0.5, 1.0 }, { -0.5, 0.0 } };
    else
      path = { { tipU[order[j - 1]], 1.0 }, { tipU[order[j]], 1.0 } };
    std::vector<double> length(1, 0.0);
    for (int i = from; i < to; ++i)
      length.push_back(length.back() + (outline.points[(i + 1) % count] - outline.points[i]).norm());
    for (int i = from + 1; i < to; ++i)
      outline.uv[i] = AlongPath(path, length[i - from] / length.back());
    if (j < lobeCount)
      outline.uv[to] = Eigen::Vector2d(tipU[order[j]], 1.0);
  }
  return outline;
}

/// The bend of each further lobe's midvein (own side; mirror it for the other): two spacings into the lobe from its
/// start along the bisector of the lobe's axis and its inner (mirrored) half-margin, i.e. on the side of the
/// previous lobe, where the straight line from the base can reach the lobe.
std::vector<Eigen::Vector2d> MidveinBends(const std::vector<Lobe>& lobes, double spacing)
{
  const int levels = static_cast<int>(lobes.size());
  std::vector<Eigen::Vector2d> bends(levels, Eigen::Vector2d::Zero());
  for (int level = 1; level < levels; ++level)
  {
    const Lobe& lobe = lobes[level];
    const Eigen::Vector2d axis = (lobe.tip - lobe.start).normalized();
    const Eigen::Vector2d inner = (lobe.mirror[1] - lobe.start).normalized();
    const double depth = std::min(2.0 * spacing, 0.1 * (lobe.tip - lobe.start).norm());
    bends[level] = lobe.start + depth * (axis + inner).normalized();
  }
  return bends;
}

/// The midvein of `level` (own side) from the base through the bends firstBend..level to the tip.
std::vector<Eigen::Vector2d> MidveinPath(
  const std::vector<Eigen::Vector2d>& bends, int level, int firstBend, const Eigen::Vector2d& tip)
{
  std::vector<Eigen::Vector2d> path = { Eigen::Vector2d::Zero() };
  for (int l = firstBend; l <= level; ++l)
    path.push_back(bends[l]);
  path.push_back(tip);
  return path;
}

/// Each further level's midvein (own side; the mirrored side is its mirror image): straight from the base to the
/// tip if that stays inside the blade; else bent at this lobe's bend, or also at the previous lobes' bends (a
/// lobe that starts on another lobe takes its midvein through that lobe's base). first[level] is the first bend
/// used, level + 1 for none. Lobes whose midveins share bends share the stretch up to them, so no two cross.
std::vector<int> FirstBends(const std::vector<Eigen::Vector2d>& bends, const BladeOutline& outline,
  const std::vector<int>& tipPosition, double spacing)
{
  const int levels = static_cast<int>(bends.size());
  std::vector<Eigen::Vector2d> boundaryPolygon(outline.points.begin(), outline.points.end());
  auto staysInside = [&](const std::vector<Eigen::Vector2d>& path) {
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
    {
      const int steps = std::max(2, static_cast<int>(std::ceil(4.0 * (path[i + 1] - path[i]).norm() / spacing)));
      for (int s = (i == 0 ? 1 : 0); s < steps; ++s)
      {
        if (!InsidePolygon(boundaryPolygon, path[i] + (static_cast<double>(s) / steps) * (path[i + 1] - path[i])))
          return false;
      }
    }
    return true;
  };
  std::vector<int> first(levels, 1);
  for (int level = levels - 1; level >= 1; --level)
  {
    const Eigen::Vector2d tip = outline.points[tipPosition[2 * level - 1]];
    first[level] = level + 1;
    while (first[level] > 1 && !staysInside(MidveinPath(bends, level, first[level], tip)))
      --first[level];
  }
  for (int level = 1; level < levels; ++level)
  {
    for (int outer = level + 1; outer < levels; ++outer)
    {
      if (first[outer] <= level)
        first[level] = std::min(first[level], first[outer]);
    }
  }
  return first;
}

/// Midveins from the base to each tip, at the margin spacing (lobe 1's in n pieces), added to the outline as
/// interior points with their LeafUV (u of the lobe, v the arc-length fraction); shared stretches share samples.
std::vector<std::vector<int>> SampleMidveins(const std::vector<Eigen::Vector2d>& bends, const std::vector<int>& first,
  const TipLayout& tips, int n, double spacing, BladeOutline& outline)
{
  const std::vector<int>& tipPosition = tips.position;
  const int lobeCount = static_cast<int>(tipPosition.size());
  std::map<Key, int> midveinPointIds; // shared stretches share their samples
  std::vector<std::vector<int>> midveins(lobeCount);
  for (int k = 0; k < lobeCount; ++k)
  {
    const Eigen::Vector2d tip = outline.points[tipPosition[k]];
    const int level = (k + 1) / 2;
    const bool mirrored = k > 0 && k % 2 == 0; // lobes are listed as: lobe 1, then each level's own side and mirror
    std::vector<Eigen::Vector2d> path = k == 0 ? std::vector<Eigen::Vector2d>{ Eigen::Vector2d::Zero(), tip }
                                               : MidveinPath(bends, level, first[level], tip);
    if (mirrored)
    {
      for (std::size_t i = 1; i + 1 < path.size(); ++i)
        path[i] = MirrorInAxis(path[i]);
    }
    const std::size_t firstNewPoint = outline.points.size();
    midveins[k].push_back(0);
    for (std::size_t piece = 0; piece + 1 < path.size(); ++piece)
    {
      const Eigen::Vector2d a = path[piece], b = path[piece + 1];
      const int pieces = k == 0 ? n : std::max(1, static_cast<int>(std::lround((b - a).norm() / spacing)));
      for (int i = 1; i <= pieces; ++i)
      {
        if (piece + 2 == path.size() && i == pieces)
          break; // the tip is an outline vertex already
        const Eigen::Vector2d x = a + (static_cast<double>(i) / pieces) * (b - a);
        const auto known = midveinPointIds.find(KeyOf(x));
        if (known != midveinPointIds.end())
        {
          midveins[k].push_back(known->second);
          continue;
        }
        midveins[k].push_back(static_cast<int>(outline.points.size()));
        midveinPointIds[KeyOf(x)] = midveins[k].back();
        outline.points.push_back(x);
        outline.uv.emplace_back(tips.u[k], 0.0);
        outline.region.push_back(RegionMidvein);
      }
    }
    midveins[k].push_back(tipPosition[k]);
    // v: arc-length fraction along the midvein.
    double total = 0.0;
    for (std::size_t i = 1; i < midveins[k].size(); ++i)
      total += (outline.points[midveins[k][i]] - outline.points[midveins[k][i - 1]]).norm();
    double along = 0.0;
    for (std::size_t i = 1; i + 1 < midveins[k].size(); ++i)
    {
      along += (outline.points[midveins[k][i]] - outline.points[midveins[k][i - 1]]).norm();
      if (static_cast<std::size_t>(midveins[k][i]) >= firstNewPoint) // shared samples keep the first lobe's LeafUV
        outline.uv[midveins[k][i]].y() = along / total;
    }
  }
  return midveins;
}

/// Sectors between neighbouring midveins (and the outer two, between a midvein and the margin down to the base),
/// `count` being the number of outline vertices.
std::vector<Sector> MakeSectors(
  const BladeOutline& outline, const std::vector<std::vector<int>>& midveins, const TipLayout& tips, int count)
{
  const std::vector<int>& tipPosition = tips.position;
  const std::vector<int>& order = tips.order;
  const int lobeCount = static_cast<int>(tipPosition.size());
  std::vector<Sector> sectors(lobeCount + 1);
  for (int j = 0; j <= lobeCount; ++j)
  {
    std::vector<int> loop;
    if (j > 0)
      loop.assign(midveins[order[j - 1]].begin(), midveins[order[j - 1]].end() - 1);
    const int from = j == 0 ? 0 : tipPosition[order[j - 1]];
    const int to = j == lobeCount ? count : tipPosition[order[j]];
    for (int i = from; i < to; ++i)
      loop.push_back(i);
    if (j < lobeCount)
      loop.insert(loop.end(), midveins[order[j]].rbegin(), midveins[order[j]].rend() - 1);
    Sector& sector = sectors[j];
    sector.uLow = j == lobeCount ? -0.5 : tips.u[order[j]];
    sector.uHigh = j == 0 ? 0.5 : tips.u[order[j - 1]];
    for (int id : loop)
    {
      sector.polygon.push_back(outline.points[id]);
      sector.uv.push_back(outline.uv[id]);
    }
  }
  return sectors;
}

/// An interior point's LeafUV: the mean-value interpolation over the sector holding it (clamped to the sector's u
/// range and to [0, 1]), else `guess`.
Eigen::Vector2d SectorUV(const std::vector<Sector>& sectors, const Eigen::Vector2d& x, const Eigen::Vector2d& guess)
{
  for (const Sector& sector : sectors)
  {
    if (InsidePolygon(sector.polygon, x))
    {
      Eigen::Vector2d uv = MeanValueInterpolate(sector.polygon, sector.uv, x);
      return Eigen::Vector2d(std::clamp(uv.x(), sector.uLow, sector.uHigh), std::clamp(uv.y(), 0.0, 1.0));
    }
  }
  return guess;
}

std::string Build(const SpaceCurveParameters& p, const SpaceCurveMeshParameters& m, LeafGeometry& leaf)
{
  std::string error = ValidateSpaceCurveParameters(p, m);
  if (!error.empty())
    return error;
  if (p.lobes != 3 && p.lobes != 5)
    return OutOfRange("Lobes", p.lobes, "{3, 5}", "for a palmate leaf");
  const int n = m.resolution;
  const double spacing = p.length / n;
  const int levels = (p.lobes + 1) / 2;

  std::vector<Lobe> lobes;
  if (error = IntegrateLobes(p, n, levels, lobes); !error.empty())
    return error;
  if (error = MirrorLobes(p, lobes); !error.empty())
    return error;
  ApplySubLobes(p, lobes);
  std::map<Key, VertexRole> roles;
  std::vector<ExactPolygon> polygons;
  std::vector<Eigen::Vector2d> tipPoints;
  if (error = LobePolygons(lobes, roles, polygons, tipPoints); !error.empty())
    return error;
  std::vector<OutlineVertex> vertices;
  if (error = UnionOutline(polygons, roles, p.sinusDepth, vertices); !error.empty())
    return error;
  DropSlivers(spacing, vertices);
  TipLayout tips;
  if (error = LayOutTips(vertices, static_cast<int>(tipPoints.size()), tips); !error.empty())
    return error;

  BladeOutline outline = OutlineWithLeafUV(vertices, tips);
  const int count = static_cast<int>(vertices.size());
  const std::vector<Eigen::Vector2d> bends = MidveinBends(lobes, spacing);
  const std::vector<int> first = FirstBends(bends, outline, tips.position, spacing);
  const std::vector<std::vector<int>> midveins = SampleMidveins(bends, first, tips, n, spacing, outline);
  outline.midvein = midveins[0];
  outline.veins.assign(midveins.begin() + 1, midveins.end());
  const std::vector<Sector> sectors = MakeSectors(outline, midveins, tips, count);
  auto solveUV = [&](const Eigen::Vector2d& x, const Eigen::Vector2d& guess) { return SectorUV(sectors, x, guess); };

  LeafMeshParameters meshSettings;
  meshSettings.resolution = n;
  meshSettings.quality = m.quality;
  meshSettings.maxVertices = m.maxVertices;
  meshSettings.progress = m.progress;
  const BladeMeshParameters options = MeshParametersFor(meshSettings, spacing);
  if (m.progress && !m.progress(0.05))
    return "aborted";
  error = MeshBlade(outline, options, solveUV, leaf.blade);
  if (!error.empty())
  {
    if (error.rfind("outline:", 0) == 0)
      return "LobeStart/LobeAngle/LobeScale: " + error +
        " (every lobe's midvein must run inside the blade from the base to its tip; lower LobeAngle or raise "
        "Resolution)";
    return error;
  }

  leaf.midvein = midveins[0];
  leaf.lobeMidveins.assign(midveins.begin() + 1, midveins.end());
  const int apex = tips.position[0];
  leaf.rightMargin.assign(outline.boundary.begin(), outline.boundary.begin() + apex + 1);
  leaf.leftMargin.push_back(0);
  for (int i = count - 1; i >= apex; --i)
    leaf.leftMargin.push_back(i);
  for (int i = 0; i < count; ++i)
  {
    if (vertices[i].role.subTip)
      leaf.subLobeTips.push_back(i);
  }
  leaf.tcoords = BoundingBoxTextureCoordinates(leaf.blade.points);
  return {};
}
} // namespace

std::string BuildPalmateLeaf(
  const SpaceCurveParameters& parameters, const SpaceCurveMeshParameters& settings, LeafGeometry& leaf)
{
  return BuildAllOrNothing(leaf, [&] { return Build(parameters, settings, leaf); });
}

} // namespace plantmorph
