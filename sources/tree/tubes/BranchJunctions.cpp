// SPDX-License-Identifier: GPL-3.0-or-later
#include "BranchJunctions.h"
#include "BranchPieces.h"
#include "SmallConvexHull.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RotationMinimizingFrames.h>

#include <CGAL/Triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace plantmorph
{

namespace
{
/// A lateral child's junction ring is first cut FirstTilt from its cross-section towards the parent's axis (never
/// more than 90 deg - its angle, the cut parallel to the parent's axis); in a merged junction a ring behind the
/// parent's far ring tilts further in TiltStep steps up to MaxTilt (see PlaceChild and Solve).
constexpr double FirstTilt = 30.0 * Pi / 180.0;
constexpr double MaxTilt = 75.0 * Pi / 180.0;
constexpr double TiltStep = 15.0 * Pi / 180.0;

/// A tube's centre line with its per-segment frames (the rotation-minimising transport of BuildTubes: segment k's
/// ring directions are cos(2 pi j / sides) n[k] + sin(2 pi j / sides) (n[k] x dir[k])).
struct Skeleton
{
  CleanedTube line;
  std::vector<Eigen::Vector3d> tangents; ///< PolylineTangents: mitre plane normals at the centre points
  std::vector<Eigen::Vector3d> dir;      ///< unit segment directions
  std::vector<Eigen::Vector3d> n;        ///< ring vertex 0's direction across each segment
  std::vector<double> arc;               ///< arc length at each centre point
  double Length() const { return this->arc.back(); }
  std::size_t Segment(double s) const
  {
    const auto it = std::upper_bound(this->arc.begin(), this->arc.end(), s);
    const std::size_t k = it == this->arc.begin() ? 0 : static_cast<std::size_t>(it - this->arc.begin()) - 1;
    return std::min(k, this->dir.size() - 1);
  }
  double RadiusAt(double s) const
  {
    const std::size_t k = this->Segment(s);
    const double f = std::clamp((s - this->arc[k]) / (this->arc[k + 1] - this->arc[k]), 0.0, 1.0);
    return this->line.radii[k] + f * (this->line.radii[k + 1] - this->line.radii[k]);
  }
  /// Whether centre point k's ring lies on the frustum between its neighbours' (collinear segments, radius linear in
  /// arc length): then a hull holding rings on both sides of it holds it too, and it is left out of the hull's input
  /// (it would only add points on the hull's boundary and degenerate, exactly evaluated, orientation tests).
  bool Redundant(std::size_t k) const
  {
    if (k == 0 || k + 1 >= this->arc.size())
      return false;
    const double f = (this->arc[k] - this->arc[k - 1]) / (this->arc[k + 1] - this->arc[k - 1]);
    const double linear = this->line.radii[k - 1] + f * (this->line.radii[k + 1] - this->line.radii[k - 1]);
    return this->dir[k - 1].dot(this->dir[k]) >= 1.0 - 1e-14 &&
      std::abs(this->line.radii[k] - linear) <= 1e-12 * std::max(this->line.radii[k], linear);
  }
  Eigen::Vector3d PointAt(double s) const
  {
    const std::size_t k = this->Segment(s);
    return this->line.centre[k] + (s - this->arc[k]) * this->dir[k];
  }
};

Skeleton MakeSkeleton(CleanedTube&& cleaned, const Eigen::Vector3d& normal)
{
  Skeleton s;
  s.line = std::move(cleaned);
  const CleanedTube& line = s.line;
  const std::size_t n = line.centre.size();
  s.tangents = PolylineTangents(line.centre);
  s.arc.assign(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k)
  {
    const Eigen::Vector3d d = line.centre[k + 1] - line.centre[k];
    s.arc[k + 1] = s.arc[k] + d.norm();
    s.dir.push_back(d.normalized());
  }
  s.n.push_back(PerpendicularTo(s.tangents[0], normal));
  for (std::size_t k = 1; k + 1 < n; ++k)
  {
    const Eigen::Vector3d& d = s.dir[k - 1];
    Eigen::Vector3d w = s.n[k - 1] - s.n[k - 1].dot(d) * d;
    w.normalize();
    const Eigen::Vector3d offset = MitreOffset(w, d, s.tangents[k]);
    const Eigen::Vector3d next = offset - offset.dot(s.dir[k]) * s.dir[k];
    s.n.push_back(next.norm() > 0.0 ? Eigen::Vector3d(next.normalized()) : w);
  }
  return s;
}

/// Where a ring sits on its tube: at centre point `point` (a mitre ring; the base ring for 0) or, for point = -1,
/// across segment `segment` at arc length `arc` (a cut ring, perpendicular to the segment).
struct Station
{
  double arc = 0.0;
  long point = -1;
  /// A cut ring's plane normal when the cut is tilted (a welded child's junction ring, see PlaceChild); zero: the cut
  /// is perpendicular to the segment.
  const Eigen::Vector3d* tilt = nullptr; ///< into the child's ChildState (a pointer keeps stations small)
};

struct RingVertex
{
  Eigen::Vector3d x, normal;
  float u = 0.0f, v = 0.0f;
};

/// Ring vertex j of the ring at `station` of tube `s` (BuildTubes' formulas).
RingVertex Vertex(const Skeleton& s, const Station& station, const RingAngles& trig, std::size_t j)
{
  RingVertex r;
  const double total = s.Length();
  r.u = static_cast<float>(trig.around[j]);
  r.v = static_cast<float>(total > 0.0 ? station.arc / total : 0.0);
  if (station.point > 0)
  {
    const std::size_t k = static_cast<std::size_t>(station.point);
    const Eigen::Vector3d& d = s.dir[k - 1];
    const Eigen::Vector3d b = s.n[k - 1].cross(d);
    Eigen::Vector3d w = trig.cosines[j] * s.n[k - 1] + trig.sines[j] * b;
    w -= w.dot(d) * d;
    w.normalize();
    r.x = s.line.centre[k] + s.line.radii[k] * MitreOffset(w, d, s.tangents[k]);
    r.normal = w;
    return r;
  }
  const std::size_t k = station.point == 0 ? 0 : s.Segment(station.arc);
  const Eigen::Vector3d w = trig.cosines[j] * s.n[k] + trig.sines[j] * s.n[k].cross(s.dir[k]);
  const double radius = station.point == 0 ? s.line.radii[0] : s.RadiusAt(station.arc);
  const Eigen::Vector3d centre = station.point == 0 ? s.line.centre[0] : s.PointAt(station.arc);
  const bool tilted = station.point < 0 && station.tilt && station.tilt->squaredNorm() > 0.0;
  r.x = centre + radius * (tilted ? MitreOffset(w, s.dir[k], *station.tilt) : w);
  r.normal = w;
  return r;
}

/// One ring of a junction: on tube `tube` at `station`, its outward normal points away from the junction.
struct JunctionRing
{
  std::size_t tube = 0;
  Station station;
  Eigen::Vector3d centre, outward;
  double radius = 0.0;
};

struct JunctionPoint
{
  RingVertex vertex;
  std::size_t tube = 0;
  long ring = -1; ///< index into the junction's rings, or -1 (a dropped part's point)
  long slot = -1; ///< ring vertex j, or the tube's extra point number once it is a hull corner
};

struct Junction
{
  std::size_t parent = 0;
  std::vector<std::size_t> children; ///< ascending index
  double lo = 0.0, hi = 0.0;         ///< the parent's dropped interval of arc length
  bool end = false;                  ///< hi is the parent's end: no ring after, the end dropped
  bool failed = false;
  std::vector<JunctionRing> rings;
  std::vector<JunctionPoint> points;
  std::vector<std::array<long, 3>> facets; ///< into points, outward
};

struct ChildState
{
  double node = 0.0; ///< arc length of the node on the parent
  Eigen::Vector3d nodePoint, axis;
  double pull = 0.0; ///< arc length of the child's junction ring
  double parentRadius = 0.0;
  Eigen::Vector3d tilt = Eigen::Vector3d::Zero(); ///< the junction ring's plane normal (Station::tilt)
  double tau = 0.0, tauMax = 0.0;                 ///< its tilt from the child's cross-section, and the most it may tilt
  Eigen::Vector3d d, hPerp;                       ///< the child's first direction, and the direction it tilts towards
  void SetTilt(double angle)
  {
    this->tau = angle;
    this->tilt = angle > 1e-6
      ? Eigen::Vector3d((std::cos(angle) * this->d + std::sin(angle) * this->hPerp).normalized())
      : Eigen::Vector3d::Zero();
  }
  bool welded = false;
  bool narrowed = false;
};

/// The points of a junction for the current pulls and interval: rings first (children, then the parent's before
/// and after rings), then the dropped parts' points.
void CollectPoints(
  const std::vector<Skeleton>& skeletons, const std::vector<ChildState>& state, const RingAngles& trig, Junction& J)
{
  J.rings.clear();
  J.points.clear();
  const std::size_t sides = trig.cosines.size();
  const auto addRing = [&](std::size_t tube, const Station& station, const Eigen::Vector3d& outward) {
    const Skeleton& s = skeletons[tube];
    JunctionRing ring{ tube, station, s.PointAt(station.arc), outward, s.RadiusAt(station.arc) };
    J.rings.push_back(ring);
    for (std::size_t j = 0; j < sides; ++j)
    {
      J.points.push_back(
        { Vertex(s, station, trig, j), tube, static_cast<long>(J.rings.size() - 1), static_cast<long>(j) });
    }
  };
  const auto addDropped = [&](std::size_t tube, const Station& station) {
    for (std::size_t j = 0; j < sides; ++j)
    {
      J.points.push_back({ Vertex(skeletons[tube], station, trig, j), tube, -1, static_cast<long>(j) });
    }
  };
  for (std::size_t c : J.children)
  {
    const Skeleton& s = skeletons[c];
    const Eigen::Vector3d& tilt = state[c].tilt;
    addRing(c, Station{ state[c].pull, -1, &tilt },
      tilt.squaredNorm() > 0.0 ? tilt : Eigen::Vector3d(s.dir[s.Segment(state[c].pull)]));
  }
  const Skeleton& p = skeletons[J.parent];
  addRing(J.parent, Station{ J.lo, -1 }, -p.dir[p.Segment(J.lo)]);
  if (!J.end)
  {
    addRing(J.parent, Station{ J.hi, -1 }, p.dir[p.Segment(J.hi)]);
  }
  for (std::size_t c : J.children)
  {
    const Skeleton& s = skeletons[c];
    for (std::size_t k = 0; k < s.arc.size() && s.arc[k] < state[c].pull; ++k)
    {
      if (!s.Redundant(k))
        addDropped(c, Station{ s.arc[k], static_cast<long>(k) });
    }
  }
  const std::size_t last = p.arc.size() - 1;
  // The parent's stations inside (lo, hi): arc lengths ascend, so from the first past lo (not a walk over the
  // whole parent for each of its junctions).
  const auto first =
    last > 1 ? std::upper_bound(p.arc.begin() + 1, p.arc.begin() + static_cast<long>(last), J.lo) : p.arc.end();
  for (auto k = static_cast<std::size_t>(first - p.arc.begin()); k < last && p.arc[k] < J.hi; ++k)
  {
    if (!p.Redundant(k))
      addDropped(J.parent, Station{ p.arc[k], static_cast<long>(k) });
  }
  if (J.end)
  {
    if (p.line.apex)
    {
      RingVertex apex;
      apex.x = p.line.centre[last];
      apex.normal = p.dir.back();
      apex.u = 0.5f, apex.v = 1.0f;
      J.points.push_back({ apex, J.parent, -1, -2 });
    }
    else
    {
      addDropped(J.parent, Station{ p.arc[last], static_cast<long>(last) });
    }
  }
}

/// Index of the first ring that is not a face with margin (every point off the ring at least 0.05 of its radius
/// inside its plane), or -1; `blocker`: the point farthest in front of that ring's plane.
long FirstBadRing(const Junction& J, std::size_t& blocker)
{
  for (std::size_t i = 0; i < J.rings.size(); ++i)
  {
    const JunctionRing& r = J.rings[i];
    double worst = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < J.points.size(); ++k)
    {
      const JunctionPoint& q = J.points[k];
      const double ahead = (q.vertex.x - r.centre).dot(r.outward);
      if (q.ring != static_cast<long>(i) && ahead > worst)
        worst = ahead, blocker = k;
    }
    if (!(worst < -0.05 * r.radius))
      return static_cast<long>(i);
  }
  return -1;
}

/// Crowded siblings (one's junction ring in front of the other's plane) first get thinner bases, down to this
/// fraction of the parent's radius, before their rings are pulled out (see the header's pipe model).
constexpr double CrowdedRadius = 0.35;

/// Grows the junction's pulls and margins until every ring is a face (true) or a limit is hit (false).
bool Solve(std::vector<Skeleton>& skeletons, std::vector<ChildState>& state, const std::vector<double>& baseCut,
  const RingAngles& trig, Junction& J)
{
  const Skeleton& p = skeletons[J.parent];
  double parentRadius = 0.0;
  for (std::size_t c : J.children)
    parentRadius = std::max(parentRadius, state[c].parentRadius);
  double before = 0.3 * parentRadius, after = 0.3 * parentRadius;
  const double L = p.Length();
  for (int round = 0; round < 48; ++round)
  {
    // The interval: the children's rings and dropped parts along the parent's axis at each node, plus margins.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t c : J.children)
    {
      const Skeleton& s = skeletons[c];
      if (state[c].pull > 0.85 * s.Length())
        return false;
      const Station ring{ state[c].pull, -1, &state[c].tilt };
      for (std::size_t j = 0; j < trig.cosines.size(); ++j)
      {
        for (const Station& st : { ring, Station{ 0.0, 0 } })
        {
          const double t = state[c].node + (Vertex(s, st, trig, j).x - state[c].nodePoint).dot(state[c].axis);
          lo = std::min(lo, t), hi = std::max(hi, t);
        }
      }
    }
    // A tilted ring must end before the child's next kept ring (the next centre point's mitre ring, which reaches back
    // r tan(bend / 2) on its inner side), else the band between them folds: pull it past that point.
    bool folded = false;
    for (std::size_t c : J.children)
    {
      const Skeleton& s = skeletons[c];
      if (state[c].tau <= 0.0)
        continue;
      const double pull = state[c].pull;
      const std::size_t k = s.Segment(pull);
      const Eigen::Vector3d centre = s.PointAt(pull);
      double ahead = 0.0;
      for (std::size_t j = 0; j < trig.cosines.size(); ++j)
        ahead = std::max(ahead, (Vertex(s, Station{ pull, -1, &state[c].tilt }, trig, j).x - centre).dot(s.dir[k]));
      double back = 0.0;
      if (k + 2 < s.arc.size())
      {
        const double bend = std::acos(std::clamp(s.dir[k].dot(s.dir[k + 1]), -1.0, 1.0));
        back = s.line.radii[k + 1] * std::tan(0.5 * std::min(bend, 170.0 * Pi / 180.0));
      }
      if (pull + ahead + back + 0.05 * s.RadiusAt(pull) > s.arc[k + 1])
      {
        state[c].pull = std::max(1.1 * pull, s.arc[k + 1] + 1e-3 * s.Length());
        folded = true;
      }
    }
    if (folded)
      continue;
    J.lo = lo - before;
    J.hi = hi + after;
    const double base = baseCut[J.parent] + 0.05 * parentRadius;
    if (!(J.lo > base))
      return false;
    J.end = J.hi >= L - 0.05 * parentRadius || (p.line.apex && p.RadiusAt(J.hi) < 0.2 * parentRadius);
    if (J.end)
      J.hi = L;
    CollectPoints(skeletons, state, trig, J);
    std::size_t blocker = 0;
    const long bad = FirstBadRing(J, blocker);
    if (bad < 0)
      return true;
    const JunctionRing& r = J.rings[static_cast<std::size_t>(bad)];
    const std::size_t other = J.points[blocker].tube;
    if (static_cast<std::size_t>(bad) < J.children.size() && other != J.parent && other != r.tube)
    {
      // Two crowded siblings: thin both bases (the pipe model's narrowing, further) while they can be thinned.
      bool thinned = false;
      for (std::size_t c : { r.tube, other })
      {
        double& r0 = skeletons[c].line.radii[0];
        const double floor = CrowdedRadius * state[c].parentRadius;
        if (r0 > floor * (1.0 + 1e-9))
        {
          r0 = std::max(floor, 0.85 * r0);
          state[c].narrowed = thinned = true;
        }
      }
      if (thinned)
        continue;
    }
    if (static_cast<std::size_t>(bad) < J.children.size() && other == J.parent && J.children.size() > 1 &&
      state[r.tube].tau < state[r.tube].tauMax)
    {
      // A child low in a long merged interval, behind the parent's far ring: turn its ring towards the parent's axis
      // (it then clears the parent by lying beside it) rather than pulling it out along the child.
      state[r.tube].SetTilt(std::min(state[r.tube].tauMax, state[r.tube].tau + TiltStep));
      continue;
    }
    if (static_cast<std::size_t>(bad) < J.children.size())
      state[r.tube].pull *= 1.1;
    else if (r.station.arc == J.lo)
      before *= 1.3;
    else
      after *= 1.3;
  }
  return false;
}

/// The junction's hull facets by CGAL, when SmallConvexHull fails (false: no hull, the junction falls back).
/// The hull is the boundary of the points' tetrahedralisation (CGAL Triangulation_3, exact orientation predicates,
/// points inserted in order: one answer for one input, whatever the thread; CGAL 5.5's convex_hull_3 was seen by
/// valgrind to read freed list nodes on these inputs, and a Delaunay tetrahedralisation spent most of its time in
/// exact in-sphere tests of the cocircular ring points). Its facets are the finite facets of the infinite cells.
bool CgalHullFacets(const Junction& J, std::vector<std::array<long, 3>>& facets)
{
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<long, Kernel>;
  using Tds = CGAL::Triangulation_data_structure_3<Vb>;
  using Triangulation = CGAL::Triangulation_3<Kernel, Tds>;
  Triangulation dt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < J.points.size(); ++i)
  {
    const Eigen::Vector3d& x = J.points[i].vertex.x;
    centroid += x;
    const std::size_t before = dt.number_of_vertices();
    const auto v = dt.insert(Kernel::Point_3(x.x(), x.y(), x.z()));
    if (dt.number_of_vertices() == before)
      return false; // a repeated point
    v->info() = static_cast<long>(i) + 1;
  }
  centroid /= static_cast<double>(J.points.size());
  if (dt.dimension() != 3 || dt.number_of_vertices() != J.points.size())
    return false;
  std::vector<Triangulation::Cell_handle> hullCells;
  dt.incident_cells(dt.infinite_vertex(), std::back_inserter(hullCells));
  for (const Triangulation::Cell_handle& c : hullCells)
  {
    const int infinite = c->index(dt.infinite_vertex());
    std::array<long, 3> v{};
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != infinite)
        v[static_cast<std::size_t>(m++)] = c->vertex(k)->info() - 1;
    // Outward: the centroid (strictly inside) is behind the facet.
    const Eigen::Vector3d& a = J.points[static_cast<std::size_t>(v[0])].vertex.x;
    const Eigen::Vector3d& b = J.points[static_cast<std::size_t>(v[1])].vertex.x;
    const Eigen::Vector3d& d = J.points[static_cast<std::size_t>(v[2])].vertex.x;
    if ((b - a).cross(d - a).dot(centroid - a) > 0.0)
      std::swap(v[1], v[2]);
    // A canonical rotation (smallest index first) and order, so the output does not depend on cell storage.
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    facets.push_back(v);
  }
  std::sort(facets.begin(), facets.end());
  return true;
}

/// The hull's facets without the rings' caps into J.facets; false if a ring is not a face with each of its edges in
/// exactly one side facet.
bool KeepSideFacets(Junction& J, std::size_t sides, const std::vector<std::array<long, 3>>& facets)
{
  std::vector<int> capFacets(J.rings.size(), 0);
  std::vector<int> ringEdges(J.points.size(), 0); // side facets using ring edge (point, its ring successor)
  J.facets.clear();
  for (const std::array<long, 3>& v : facets)
  {
    const long r0 = J.points[static_cast<std::size_t>(v[0])].ring;
    if (r0 >= 0 && r0 == J.points[static_cast<std::size_t>(v[1])].ring &&
      r0 == J.points[static_cast<std::size_t>(v[2])].ring)
    {
      ++capFacets[static_cast<std::size_t>(r0)];
      continue;
    }
    for (int e = 0; e < 3; ++e)
    {
      const long a = v[static_cast<std::size_t>(e)], b = v[static_cast<std::size_t>((e + 1) % 3)];
      const JunctionPoint& pa = J.points[static_cast<std::size_t>(a)];
      const JunctionPoint& pb = J.points[static_cast<std::size_t>(b)];
      if (pa.ring >= 0 && pa.ring == pb.ring)
      {
        // Ring points are stored j = 0..sides-1 per ring: the edge (j, j + 1 mod sides) is keyed by j's point.
        const long next = (pa.slot + 1) % static_cast<long>(sides);
        if (pb.slot == next)
          ++ringEdges[static_cast<std::size_t>(a)];
        else if ((pb.slot + 1) % static_cast<long>(sides) == pa.slot)
          ++ringEdges[static_cast<std::size_t>(b)];
        else
          return false; // a chord of the ring on the hull's side: the ring is not a face
      }
    }
    J.facets.push_back(v);
  }
  // Every ring: sides - 2 cap facets, and each of its edges in exactly one side facet, running j + 1 -> j (the
  // tube beyond runs j -> j + 1 along its band: see the band triangles).
  for (std::size_t r = 0; r < J.rings.size(); ++r)
  {
    if (capFacets[r] != static_cast<int>(sides) - 2)
      return false;
    const long first = static_cast<long>(r * sides);
    for (std::size_t j = 0; j < sides; ++j)
    {
      if (ringEdges[static_cast<std::size_t>(first) + j] != 1)
        return false;
    }
  }
  return true;
}

/// Convex hull of the junction's points (SmallConvexHull; CGAL's Triangulation_3 when that fails its check or a ring
/// check); false if a ring is not a face of it (then the junction falls back).
bool Hull(Junction& J, std::size_t sides)
{
  std::vector<Eigen::Vector3d> points(J.points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = J.points[i].vertex.x;
  std::vector<std::array<long, 3>> facets;
  if (SmallConvexHull(points, facets) && KeepSideFacets(J, sides, facets))
    return true;
  return CgalHullFacets(J, facets) && KeepSideFacets(J, sides, facets);
}

/// What the junctions decide for every tube: its skeleton (a welded child's first radius may be narrowed), its
/// children, its state as a child, the arc length of its welded base ring, and the junctions on it as a parent.
struct Welding
{
  std::vector<Skeleton> skeletons;
  std::vector<std::vector<std::size_t>> children;
  std::vector<ChildState> state;
  std::vector<double> baseCut; ///< arc length of a welded child's ring (0: its base)
  std::vector<std::vector<Junction>> junctionsOf;
};

/// What a build restricted to some tubes (a piece, BranchPieces.h) computes of each tube: all of them are set for a
/// whole build. write: its points are written (the selected tubes, and their parents, siblings and children, whose
/// rings the selected tubes' junction facets may use); decide: its children's junctions are decided (the written
/// tubes and their ancestors: a junction depends on its parent's own welding); skeleton: its skeleton is made (the
/// decided tubes and their children); hull: the hulls of the junctions on it are built (the written tubes and their
/// parents); triangles: its triangles are written (the selected tubes).
struct TubeRoles
{
  std::vector<char> write, decide, skeleton, hull, triangles;
};

TubeRoles RolesFor(const std::vector<TubeInput>& tubes, const std::vector<std::vector<std::size_t>>& children,
  const std::vector<char>* selected)
{
  const std::size_t count = tubes.size();
  TubeRoles roles;
  if (!selected)
  {
    roles.write.assign(count, 1);
    roles.decide = roles.skeleton = roles.hull = roles.triangles = roles.write;
    return roles;
  }
  roles.triangles = *selected;
  roles.write = *selected;
  const auto parentOf = [&](std::size_t t) { return tubes[t].parent; };
  for (std::size_t t = 0; t < count; ++t)
  {
    if (!(*selected)[t])
      continue;
    for (std::size_t c : children[t])
      roles.write[c] = 1;
    if (parentOf(t) >= 0)
    {
      const std::size_t p = static_cast<std::size_t>(parentOf(t));
      roles.write[p] = 1;
      for (std::size_t c : children[p])
        roles.write[c] = 1;
    }
  }
  roles.decide.assign(count, 0);
  roles.hull.assign(count, 0);
  for (std::size_t t = 0; t < count; ++t)
  {
    if (!roles.write[t])
      continue;
    roles.hull[t] = 1;
    if (parentOf(t) >= 0)
      roles.hull[static_cast<std::size_t>(parentOf(t))] = 1;
    for (std::int64_t a = static_cast<std::int64_t>(t); a >= 0 && !roles.decide[static_cast<std::size_t>(a)];
         a = parentOf(static_cast<std::size_t>(a)))
      roles.decide[static_cast<std::size_t>(a)] = 1;
  }
  roles.skeleton = roles.decide;
  for (std::size_t t = 0; t < count; ++t)
    if (roles.decide[t])
      for (std::size_t c : children[t])
        roles.skeleton[c] = 1;
  return roles;
}

/// Children per parent (into `children`), and the parents level by level.
std::vector<std::vector<std::size_t>> ParentsByLevel(
  const std::vector<TubeInput>& tubes, std::vector<std::vector<std::size_t>>& children)
{
  const std::size_t count = tubes.size();
  children.assign(count, {});
  std::vector<int> level(count, 0);
  int levels = 0;
  for (std::size_t t = 0; t < count; ++t)
  {
    if (tubes[t].parent >= 0)
    {
      const std::size_t p = static_cast<std::size_t>(tubes[t].parent);
      children[p].push_back(t);
      level[t] = level[p] + 1;
      levels = std::max(levels, level[t]);
    }
  }
  std::vector<std::vector<std::size_t>> byLevel(static_cast<std::size_t>(levels) + 1);
  for (std::size_t t = 0; t < count; ++t)
  {
    if (!children[t].empty())
      byLevel[static_cast<std::size_t>(level[t])].push_back(t);
  }
  return byLevel;
}

/// A child's node on its parent `p` (the parent's centre-line point nearest the child's first point), the parent's
/// radius there, and the child's first pull; narrows the child's first radius to the pipe model's. False when the
/// child runs along the parent's axis (it falls back).

bool PlaceChild(const Skeleton& p, Skeleton& s, ChildState& cs)
{
  const double smallAngle = std::sin(5.0 * Pi / 180.0);
  // Node: the parent's centre-line point nearest the child's first point.
  const Eigen::Vector3d B = s.line.centre[0];
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.dir.size(); ++k)
  {
    const double len = p.arc[k + 1] - p.arc[k];
    const double f = std::clamp((B - p.line.centre[k]).dot(p.dir[k]), 0.0, len);
    const Eigen::Vector3d x = p.line.centre[k] + f * p.dir[k];
    if ((x - B).squaredNorm() < best)
    {
      best = (x - B).squaredNorm();
      cs.node = p.arc[k] + f, cs.nodePoint = x, cs.axis = p.dir[k];
    }
  }
  const bool atEnd = cs.node >= p.Length() * (1.0 - 1e-9);
  cs.parentRadius = std::max(p.RadiusAt(cs.node), atEnd ? p.line.radii[p.line.radii.size() - 2] : 0.0);
  const Eigen::Vector3d d = s.dir[0];
  const double cosine = d.dot(cs.axis);
  const double sine = std::sqrt(std::max(0.0, 1.0 - cosine * cosine));
  if (sine < smallAngle && !atEnd)
    return false; // along the parent's axis: falls back
  if (!atEnd && s.line.radii[0] > 0.9 * cs.parentRadius)
  {
    s.line.radii[0] = 0.9 * cs.parentRadius; // the pipe model (see the header)
    cs.narrowed = true;
  }
  const Eigen::Vector3d across = d - cosine * cs.axis;
  const double h = sine > 0.0 ? (B - cs.nodePoint).dot(across) / across.norm() : 0.0;
  const double rc = s.line.radii[0];
  // The junction ring of a lateral child is cut in a plane turned from the child's cross-section towards the
  // parent's axis (by 90 deg - the angle, at most MaxTilt): its normal is then (nearly) `across`, so the ring clears
  // the parent and its siblings by lying beside the parent, not by being pulled out along a steep child (which made
  // the hull of neighbouring children balloon into the crook between them).
  cs.d = d;
  cs.tauMax = 0.0;
  if (!atEnd && sine > 0.0 && std::abs(cosine) > 1e-9)
  {
    const Eigen::Vector3d h = across.normalized();
    cs.hPerp = (h - h.dot(d) * d).normalized();
    cs.tauMax = std::min(std::abs(0.5 * Pi - std::acos(std::clamp(cosine, -1.0, 1.0))), MaxTilt);
  }
  cs.SetTilt(std::min(cs.tauMax, FirstTilt));
  // At a parent's end the child need not clear a parent continuing beside it: start short and let the face
  // test grow it (a short pull leaves room for the child's own first junctions).
  cs.pull =
    atEnd ? 0.3 * rc : std::max(0.3 * rc, (1.2 * cs.parentRadius - h + rc * std::abs(cosine)) / std::max(sine, 0.2));
  return true;
}

/// Merges junctions whose intervals overlap (the children sorted along the parent), re-solves, repeats.
void MergeOverlapping(std::size_t P, const RingAngles& trig, Welding& w, std::vector<Junction>& single)
{
  std::stable_sort(single.begin(), single.end(), [](const Junction& a, const Junction& b) { return a.lo < b.lo; });
  for (bool changed = true; changed;)
  {
    changed = false;
    for (std::size_t k = 0; k + 1 < single.size(); ++k)
    {
      if (single[k].hi < single[k + 1].lo)
        continue;
      Junction J;
      J.parent = P;
      J.children = single[k].children;
      J.children.insert(J.children.end(), single[k + 1].children.begin(), single[k + 1].children.end());
      std::sort(J.children.begin(), J.children.end());
      single.erase(single.begin() + static_cast<long>(k), single.begin() + static_cast<long>(k) + 2);
      if (Solve(w.skeletons, w.state, w.baseCut, trig, J))
      {
        single.insert(single.begin() + static_cast<long>(k), std::move(J));
        std::stable_sort(
          single.begin(), single.end(), [](const Junction& a, const Junction& b) { return a.lo < b.lo; });
      }
      changed = true;
      break;
    }
  }
}

/// The junctions of parent P: one per child that can weld, merged where they overlap; marks the welded children
/// and gives the unwelded ones back their template radius (before their own children are decided).
void WeldChildrenOf(std::size_t P, const std::vector<double>& firstRadius, const RingAngles& trig, Welding& w)
{
  const Skeleton& p = w.skeletons[P];
  std::vector<Junction> single;
  for (std::size_t c : w.children[P])
  {
    if (!PlaceChild(p, w.skeletons[c], w.state[c]))
      continue;
    Junction J;
    J.parent = P;
    J.children = { c };
    if (Solve(w.skeletons, w.state, w.baseCut, trig, J))
      single.push_back(std::move(J));
  }
  MergeOverlapping(P, trig, w, single);
  for (Junction& J : single)
  {
    for (std::size_t c : J.children)
    {
      w.state[c].welded = true;
      w.baseCut[c] = w.state[c].pull;
    }
  }
  // Children left unwelded keep their template radius (before their own children are decided).
  for (std::size_t c : w.children[P])
  {
    if (w.state[c].narrowed && !w.state[c].welded)
    {
      w.skeletons[c].line.radii[0] = firstRadius[c];
      w.state[c].narrowed = false;
    }
  }
  w.junctionsOf[P] = std::move(single);
}

/// Keeps only the hull's corners (ring points, which come first, keep their indices), so the junctions held until
/// the mesh is written take less memory beside it.
void DropInteriorPoints(Junction& J)
{
  std::vector<long> index(J.points.size(), -1);
  for (const std::array<long, 3>& f : J.facets)
    for (long v : f)
      index[static_cast<std::size_t>(v)] = 0;
  for (std::size_t k = 0; k < J.points.size(); ++k)
    if (J.points[k].ring >= 0)
      index[k] = 0;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < J.points.size(); ++k)
  {
    if (index[k] < 0)
      continue;
    index[k] = static_cast<long>(kept);
    J.points[kept++] = J.points[k];
  }
  J.points.resize(kept);
  J.points.shrink_to_fit();
  for (std::array<long, 3>& f : J.facets)
    for (long& v : f)
      v = index[static_cast<std::size_t>(v)];
  J.facets.shrink_to_fit();
}

/// Hulls, in parallel; a junction whose hull lacks a ring face falls back: its children stay closed tubes from
/// their base (they keep the narrowed first radius their own junctions were built with). All junctions, in order.
std::vector<Junction*> BuildHulls(std::size_t S, const ParallelFor& parallel, const TubeRoles& roles, Welding& w)
{
  std::vector<Junction*> all;
  for (std::size_t t = 0; t < w.junctionsOf.size(); ++t)
    if (roles.hull[t])
      for (Junction& J : w.junctionsOf[t])
        all.push_back(&J);
  parallel(all.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      all[i]->failed = !Hull(*all[i], S);
      if (!all[i]->failed)
        DropInteriorPoints(*all[i]);
    }
  });
  for (Junction* J : all)
  {
    if (!J->failed)
      continue;
    for (std::size_t c : J->children)
    {
      w.state[c].welded = false;
      w.baseCut[c] = 0.0;
    }
  }
  return all;
}

/// Stations of a tube: centre points and cut rings, kept or dropped; bands between kept neighbours; the hull
/// corners and facets the tube owns.
struct Layout
{
  std::vector<Station> stations;
  std::vector<char> bandAfter; ///< band from station i to i + 1
  bool baseCap = true, endKept = true;
  std::vector<std::pair<const Junction*, long>> extras;        ///< (junction, point) hull corners owned by the tube
  std::vector<std::pair<const Junction*, std::size_t>> facets; ///< (junction, facet) owned by the tube
};

/// Each hull facet goes to the lowest-numbered child tube with a ring in it (else the parent), each used corner of
/// a dropped part to its tube.
void AssignHullParts(const std::vector<Junction*>& all, std::vector<Layout>& layout)
{
  for (Junction* J : all)
  {
    if (J->failed)
      continue;
    std::vector<char> used(J->points.size(), 0);
    for (std::size_t f = 0; f < J->facets.size(); ++f)
    {
      std::size_t owner = J->parent;
      for (long v : J->facets[f])
      {
        used[static_cast<std::size_t>(v)] = 1;
        const JunctionPoint& q = J->points[static_cast<std::size_t>(v)];
        if (q.tube != J->parent && q.ring >= 0 && (owner == J->parent || q.tube < owner))
          owner = q.tube;
      }
      layout[owner].facets.emplace_back(J, f);
    }
    for (std::size_t v = 0; v < J->points.size(); ++v)
    {
      if (used[v] && J->points[v].ring < 0)
        layout[J->points[v].tube].extras.emplace_back(J, static_cast<long>(v));
    }
  }
}

/// Tube t's stations and bands: its centre points outside the dropped intervals (its welded base, the junctions
/// on it) and the cut rings at their ends.
void LayOutStations(std::size_t t, const Welding& w, Layout& L)
{
  const Skeleton& s = w.skeletons[t];
  std::vector<std::pair<double, double>> dropped; // open intervals
  std::vector<Station> cuts;
  if (w.state[t].welded)
  {
    dropped.emplace_back(-1.0, w.baseCut[t]);
    cuts.push_back({ w.baseCut[t], -1, &w.state[t].tilt });
    L.baseCap = false;
  }
  for (const Junction& J : w.junctionsOf[t])
  {
    if (J.failed)
      continue;
    dropped.emplace_back(J.lo, J.end ? std::numeric_limits<double>::infinity() : J.hi);
    cuts.push_back({ J.lo, -1 });
    if (J.end)
      L.endKept = false;
    else
      cuts.push_back({ J.hi, -1 });
  }
  const auto inside = [&](double a) {
    for (const auto& [lo, hi] : dropped)
      if (a > lo && a < hi)
        return true;
    return false;
  };
  const std::size_t n = s.arc.size();
  const std::size_t ringPoints = s.line.apex ? n - 1 : n;
  for (std::size_t k = 0; k < ringPoints; ++k)
  {
    bool nearCut = false;
    for (const Station& c : cuts)
      nearCut = nearCut || std::abs(c.arc - s.arc[k]) <= 1e-9 * s.Length();
    if (!inside(s.arc[k]) && !nearCut)
      L.stations.push_back({ s.arc[k], static_cast<long>(k) });
  }
  for (const Station& c : cuts)
    L.stations.push_back(c);
  std::sort(L.stations.begin(), L.stations.end(), [](const Station& a, const Station& b) { return a.arc < b.arc; });
  for (std::size_t i = 0; i + 1 < L.stations.size(); ++i)
    L.bandAfter.push_back(!inside(0.5 * (L.stations[i].arc + L.stations[i + 1].arc)));
}

/// Point and triangle offsets of every tube, and the mesh's arrays sized; "" or the 32-bit id error.
std::string AllocateWeldedMesh(const std::vector<Layout>& layout, int sides, const TubeRoles& roles, TubeMesh& mesh)
{
  const std::size_t count = layout.size();
  const std::size_t S = static_cast<std::size_t>(sides);
  mesh.pointOffsets.assign(count + 1, 0);
  mesh.triangleOffsets.assign(count + 1, 0);
  for (std::size_t t = 0; t < count; ++t)
  {
    const Layout& L = layout[t];
    std::int64_t bands = 0;
    for (char b : L.bandAfter)
      bands += b;
    mesh.pointOffsets[t + 1] = mesh.pointOffsets[t] +
      (roles.write[t] ? (L.baseCap ? 1 : 0) + static_cast<std::int64_t>(L.stations.size() * S) + (L.endKept ? 1 : 0) +
            static_cast<std::int64_t>(L.extras.size())
                      : 0);
    mesh.triangleOffsets[t + 1] = mesh.triangleOffsets[t] +
      (roles.triangles[t] ? (L.baseCap ? sides : 0) + 2 * sides * bands + (L.endKept ? sides : 0) +
            static_cast<std::int64_t>(L.facets.size())
                          : 0);
  }
  if (mesh.pointOffsets.back() > std::numeric_limits<std::int32_t>::max())
  {
    mesh = TubeMesh();
    return "the tubes would have more than 2^31 - 1 points";
  }
  mesh.points.resize(3 * static_cast<std::size_t>(mesh.pointOffsets.back()));
  mesh.normals.resize(mesh.points.size());
  mesh.tcoords.resize(2 * static_cast<std::size_t>(mesh.pointOffsets.back()));
  mesh.triangles.resize(3 * static_cast<std::size_t>(mesh.triangleOffsets.back()));
  return {};
}

/// Every tube's points (base centre, rings, end point, owned hull corners) and triangles (TubeTriangles' caps and
/// kept bands, then its hull facets).
void WriteWeldedTubes(const Welding& w, const std::vector<Layout>& layout, int sides, const RingAngles& trig,
  const ParallelFor& parallel, const TubeRoles& roles, TubeMesh& mesh)
{
  const std::size_t count = layout.size();
  const std::size_t S = static_cast<std::size_t>(sides);
  // Global id of ring vertex j of the ring at arc `a` of tube t (its station), and of a junction's extra points.
  const auto ringId = [&](std::size_t t, double a, std::size_t j) {
    const Layout& L = layout[t];
    const auto it =
      std::lower_bound(L.stations.begin(), L.stations.end(), a, [](const Station& st, double x) { return st.arc < x; });
    const std::size_t index = static_cast<std::size_t>(it - L.stations.begin());
    return mesh.pointOffsets[t] + (L.baseCap ? 1 : 0) + static_cast<std::int64_t>(index * S + j);
  };
  // An extra point's id: its place among its tube's extras (a few per junction: a linear search, no map).
  const auto pointId = [&](const Junction* J, long v) {
    const JunctionPoint& q = J->points[static_cast<std::size_t>(v)];
    if (q.ring >= 0)
      return ringId(q.tube, J->rings[static_cast<std::size_t>(q.ring)].station.arc, static_cast<std::size_t>(q.slot));
    const Layout& L = layout[q.tube];
    const auto it = std::find(L.extras.begin(), L.extras.end(), std::make_pair(J, v));
    return mesh.pointOffsets[q.tube + 1] - static_cast<std::int64_t>(L.extras.end() - it);
  };
  parallel(count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      if (!roles.write[t])
        continue;
      const Skeleton& s = w.skeletons[t];
      const Layout& L = layout[t];
      std::int64_t p = mesh.pointOffsets[t];
      const auto put = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& normal, double u, double v) {
        SetMeshPoint(mesh, p, x, normal, u, v);
        return p++;
      };
      const std::int64_t baseCentre = L.baseCap ? put(s.line.centre[0], -s.tangents[0], 0.5, 0.0) : -1;
      const std::int64_t firstRing = p;
      for (const Station& st : L.stations)
      {
        for (std::size_t j = 0; j < S; ++j)
        {
          const RingVertex r = Vertex(s, st, trig, j);
          put(r.x, r.normal, r.u, r.v);
        }
      }
      const std::size_t rings = L.stations.size();
      const std::int64_t last = L.endKept ? put(s.line.centre.back(), s.tangents.back(), 0.5, 1.0) : -1;
      for (const auto& e : L.extras)
      {
        const RingVertex& r = e.first->points[static_cast<std::size_t>(e.second)].vertex;
        put(r.x, r.normal, r.u, r.v);
      }
      if (!roles.triangles[t])
        continue;
      std::size_t q = TubeTriangles(mesh.triangles, 3 * static_cast<std::size_t>(mesh.triangleOffsets[t]), firstRing,
        rings, sides, baseCentre, last, s.line.apex, &L.bandAfter);
      for (const auto& [J, f] : L.facets)
      {
        for (long v : J->facets[f])
          mesh.triangles[q++] = static_cast<std::int32_t>(pointId(J, v));
      }
    }
  });
}

/// The junction counts and the tubes that fell back.
void FillJunctionReport(const std::vector<TubeInput>& tubes, const std::vector<Junction*>& all, const Welding& w,
  const TubeRoles& roles, JunctionReport& report)
{
  for (const Junction* J : all)
  {
    if (J->failed || !roles.triangles[J->parent])
      continue;
    ++report.junctions;
    report.welded += static_cast<std::int64_t>(J->children.size());
    report.merged += J->children.size() > 1 ? 1 : 0;
    report.endJunctions += J->end ? 1 : 0;
  }
  for (std::size_t t = 0; t < tubes.size(); ++t)
  {
    if (!roles.triangles[t])
      continue;
    report.narrowed += w.state[t].narrowed ? 1 : 0;
    if (tubes[t].parent >= 0 && !w.state[t].welded)
    {
      ++report.fallback;
      report.fallbackTubes.push_back(static_cast<std::int64_t>(t));
    }
  }
}
} // namespace

std::string BuildWeldedTubes(const std::vector<TubeInput>& tubes, int sides, TubeMesh& mesh,
  const ParallelFor& parallel, JunctionReport* report, const std::vector<char>* selected)
{
  if (report)
    *report = JunctionReport();
  mesh = TubeMesh();
  std::vector<CleanedTube> cleaned;
  if (std::string error = CleanTubes(tubes, sides, cleaned); !error.empty())
  {
    return error;
  }
  if (selected && selected->size() != tubes.size())
    return "the tube selection has " + std::to_string(selected->size()) + " entries for " +
      std::to_string(tubes.size()) + " tubes";
  const std::size_t count = tubes.size();
  const std::size_t S = static_cast<std::size_t>(sides);
  const RingAngles trig(sides);
  Welding w;
  // Children per parent, parents level by level: each level's junctions in parallel (a parent is final before its
  // children's junctions are decided). A piece decides, hulls and writes only what its tubes need (TubeRoles).
  const std::vector<std::vector<std::size_t>> byLevel = ParentsByLevel(tubes, w.children);
  const TubeRoles roles = RolesFor(tubes, w.children, selected);
  w.skeletons.resize(count);
  std::vector<double> firstRadius(count); // before the pipe model narrows it
  parallel(count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      firstRadius[t] = cleaned[t].radii[0];
      if (roles.skeleton[t])
        w.skeletons[t] = MakeSkeleton(std::move(cleaned[t]), tubes[t].normal);
    }
  });
  std::vector<CleanedTube>().swap(cleaned); // moved into the skeletons: not kept beside the mesh

  w.state.assign(count, ChildState());
  w.baseCut.assign(count, 0.0);
  w.junctionsOf.assign(count, {});
  for (const std::vector<std::size_t>& level : byLevel)
  {
    std::vector<std::size_t> parents;
    for (std::size_t P : level)
      if (roles.decide[P])
        parents.push_back(P);
    parallel(parents.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        WeldChildrenOf(parents[i], firstRadius, trig, w);
    });
  }
  const std::vector<Junction*> all = BuildHulls(S, parallel, roles, w);

  // Stations of each tube, then points and triangles.
  std::vector<Layout> layout(count);
  AssignHullParts(all, layout);
  parallel(count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      if (roles.write[t])
        LayOutStations(t, w, layout[t]);
  });
  if (std::string error = AllocateWeldedMesh(layout, sides, roles, mesh); !error.empty())
    return error;
  WriteWeldedTubes(w, layout, sides, trig, parallel, roles, mesh);
  if (selected)
    KeepTubes(mesh, *selected);

  if (report)
    FillJunctionReport(tubes, all, w, roles, *report);
  return {};
}

} // namespace plantmorph
