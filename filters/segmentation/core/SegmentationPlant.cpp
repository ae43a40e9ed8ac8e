// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 3 to 5 of the segmentation (PlantSegmentation.h): each region judged leaf or wood, the points of small
// regions labelled from their neighbours, the leaf instances with their base, branch and area, the plant's row.
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <plantmorph/graph/DisjointSets.h>
#include <plantmorph/MathConstants.h>
#include <plantmorph/PlaneFit.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

namespace plantmorph
{
namespace segmentation
{
Eigen::Matrix3d Scatter(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, Eigen::Vector3d& mean)
{
  mean = Eigen::Vector3d::Zero();
  for (int j : ids)
    mean += points[static_cast<std::size_t>(j)];
  mean /= static_cast<double>(ids.size());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (int j : ids)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
    c += d * d.transpose();
  }
  return c;
}

double ExtentAlong(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const Eigen::Vector3d& mean,
  const Eigen::Vector3d& axis)
{
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (int j : ids)
  {
    const double t = (points[static_cast<std::size_t>(j)] - mean).dot(axis);
    low = std::min(low, t);
    high = std::max(high, t);
  }
  return high - low;
}

namespace
{
/// Regions with fewer points are not judged on their own shape.
constexpr std::size_t JudgedRegionPoints = 12;
/// A piece's thickness (its smallest principal spread) under this share of its width (the middle one) is flat
/// (FlatPiecesAwayFromWood): a tube's arc is this flat only over about 40 degrees.
constexpr double FlatPieceThickness = 0.1;

/// A leaf is flat at the features' scale r: about its points, its own points within r lie off their plane by the
/// range noise (the median root mean square off it, over the leaves of the 48 scans of the segmentation benchmark:
/// 1.0 noise, at most 1.8 on any leaf), or by a curl whose radius is well above r. The side of a twig thinner than r,
/// seen from one side, is curved across within r: two such sides forking in one plane grow into one flat-looking
/// region as wide as a leaf (on those scans 3.5 to 9.4 noises off the plane on the 0.1 % noise scans; at 1 % noise
/// the widened r makes the twigs flat: 1.3 to 1.9). CurvedAcross: the lower quartile over about CurvatureSamples of
/// a piece's points, of those whose ball holds CurvatureNeighbours of its points spread over a patch (their middle
/// principal spread at least CurvatureSheetWidth r: not a row of a sparse scan, whose off-plane spread is the rows'),
/// at least CurvedNoises noises and CurvedFloor r (a curl of radius 4r; on a scan without noise). The lower quartile,
/// not the median: a region of small leaves meeting at angles (a brush at a twig's end) is thick at its creases only.
constexpr std::size_t CurvatureSamples = 150, CurvatureNeighbours = 8;
constexpr double CurvatureSheetWidth = 0.25, CurvedNoises = 3.0, CurvedFloor = 1.0 / 32.0;

/// What a region is, from its points' covariance and normals.
struct RegionVerdict
{
  bool judged = false;
  bool leaf = false;
  bool mixed = false;     ///< incoherent yet no cylinder: several sheets grown into one (SplitMixedRegions)
  bool strip = false;     ///< a flat sheet (coherent, no cylinder) judged wood only for being narrow or long
  bool flatStrip = false; ///< such a strip with flat surroundings: leaf, but no leaf instance on its own
  double confidence = 0.0;
};

/// The second moments of the normals of points[ids]: for the surface of a cylinder (a branch) the normals lie in
/// the plane across its axis, so the moments' smallest eigenvector is the axis, along the points' own long axis,
/// and their middle eigenvalue is the spread of the normals around it; a flat leaf has one normal (middle
/// eigenvalue near 0); several leaves grown into one have normals with no common axis along their length. How the
/// normals are spread around the axis tells a branch from a blade folded along its midrib (a V): the kurtosis of
/// their angle around it (its fourth moment over the square of its second) is 1.8 for normals spread evenly over an
/// arc (a tube's surface), 1 for normals in two tight groups (the V's two flat halves).
struct NormalSpread
{
  double axisAlongLength = 0.0; ///< |cos| between the normals' common axis and the points' long axis
  double middle = 0.0;          ///< the middle eigenvalue (the spread of the normals around that axis)
  double kurtosis = 0.0;        ///< of the normals' angle around that axis
  /// The fewest of the normals' angles around that axis in any arc as wide as the `window` given to SpreadOfNormals
  /// within their range (2 % to 98 % of them), over the share an even spread over that range would put in it: near
  /// 1 or more for a tube's normals (they turn steadily across it), near 0 in the empty arc between the normals of
  /// two flat blades; 1 when no window is given or the range is no wider than it.
  double emptiestArc = 1.0;
};

/// The fewest of `angle` (sorted in place) in any arc `window` wide within their 2 % to 98 % range, over the share an
/// even spread over that range would put in it (NormalSpread::emptiestArc).
double EmptiestArc(std::vector<double>& angle, double window)
{
  if (!(window > 0.0) || angle.empty())
    return 1.0;
  std::sort(angle.begin(), angle.end());
  const std::size_t last = angle.size() - 1;
  const double low = angle[last / 50], high = angle[last * 49 / 50];
  if (high - low <= window)
    return 1.0;
  const auto first = std::lower_bound(angle.begin(), angle.end(), low);
  const auto end = std::upper_bound(angle.begin(), angle.end(), high);
  const double even = static_cast<double>(end - first) * window / (high - low);
  // the count in an arc (t, t + window] changes only where t passes an angle: the arc from the range's low end and
  // those just past each angle are the emptiest candidates
  auto fewest = static_cast<double>(std::upper_bound(first, end, low + window) - first);
  for (auto a = first; a != end && *a <= high - window; ++a)
    fewest =
      std::min(fewest, static_cast<double>(std::upper_bound(a, end, *a + window) - std::upper_bound(a, end, *a)));
  return fewest / even;
}

/// SpreadOfNormals with `window` > 0 also measures how evenly the normals fill their arc (NormalSpread::emptiestArc).
NormalSpread SpreadOfNormals(
  const PointFeatures& f, const std::vector<int>& ids, const Eigen::Vector3d& longAxis, double window = 0.0)
{
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int j : ids)
    m += f.normal[static_cast<std::size_t>(j)] * f.normal[static_cast<std::size_t>(j)].transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m / static_cast<double>(ids.size()));
  NormalSpread s;
  s.axisAlongLength = std::abs(solver.eigenvectors().col(0).dot(longAxis));
  s.middle = solver.eigenvalues()[1];
  // each normal's angle around the axis from the main normal (normals have no sign: each turned to face it)
  const Eigen::Vector3d main = solver.eigenvectors().col(2), side = solver.eigenvectors().col(1);
  std::vector<double> angle;
  angle.reserve(ids.size());
  double mean = 0.0;
  for (int j : ids)
  {
    const Eigen::Vector3d& n = f.normal[static_cast<std::size_t>(j)];
    const double sign = n.dot(main) < 0.0 ? -1.0 : 1.0;
    angle.push_back(std::atan2(sign * n.dot(side), sign * n.dot(main)));
    mean += angle.back();
  }
  mean /= static_cast<double>(ids.size());
  double second = 0.0, fourth = 0.0;
  for (double a : angle)
  {
    const double d2 = (a - mean) * (a - mean);
    second += d2;
    fourth += d2 * d2;
  }
  second /= static_cast<double>(ids.size());
  fourth /= static_cast<double>(ids.size());
  s.kurtosis = second > 0.0 ? fourth / (second * second) : 0.0;
  s.emptiestArc = EmptiestArc(angle, window);
  return s;
}

/// A cylinder's piece: its normals share an axis along its length (within about 25 degrees) and turn around it by
/// more than a folded leaf's (mean squared sine of their angle to the mean normal above 0.15: an arc of about 80
/// degrees or more of a tube), spread over the arc (their angle's kurtosis at least CylinderKurtosis), not in two
/// groups: a blade folded along its midrib into a V whose halves' normals are 60 degrees apart spreads as far (0.16)
/// but its normals sit on the two halves' (kurtosis 1.35 on the synthetic V, the features' normals smoothed across
/// the midrib; 1 for two exact planes). On the 18 simulated scans of the accuracy benchmark every region with the
/// axis and spread of a cylinder has a kurtosis of 1.53 or more (a tube's facets, smoothed, 1.5 to 1.8 and more).
constexpr double CylinderAxisCosine = 0.9, CylinderNormalSpread = 0.15, CylinderKurtosis = 1.45;
/// A cylinder's normals fill the arc they turn over: its surface turns steadily across it, so every arc of
/// NormalAngle within the range of their angles around its axis (2 % to 98 % of them) holds at least this fraction of
/// the share an even spread would put there (NormalSpread::emptiestArc; a tube seen from one side thins towards its
/// grazing edges as the cosine of the incidence). Flat blades fanned around a
/// twig like vanes, each blade's plane holding the twig's axis, turn about it as a tube does once the twig's surface,
/// thinner than the features' radius, takes their normals and grows them into one region; but their normals sit in
/// one tight group per blade with empty arcs between (on the benchmark's shrub of elliptic blades at 1 % noise, 30-35
/// degrees holding 0.01-0.02 of an even share; there the two regions of the trunk with a branch grown on at a fork
/// hold 0.28 or more of it in every 5 degrees).
constexpr double CylinderArcFill = 0.1;
/// A narrower arc is a tube's piece too when its normals turn about its length by more than the features' error
/// (mean squared sine above TubeNormalSpread: an rms turn of 10 degrees) and its points lie on a circle across its
/// length of radius at most TubeRadius r (OnThinTube).
constexpr double TubeRadius = 2.0, TubeNormalSpread = 0.03;

/// Whether points[ids] (mean `mean`, covariance eigenvectors `axes`, the last the long axis) lie on a circle across
/// their long axis (the algebraic circle fit of the points projected on the plane across it) of radius at most
/// TubeRadius r: a twig or branch of radius up to 2r seen from one side or between two shadows, whose normals,
/// smoothed over the features' radius, turn too little for a cylinder's spread (an arc under 80 degrees); a leaf
/// rolled across its width to that radius (8 spacings at the default scale) is a tube too.
bool OnThinTube(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const Eigen::Vector3d& mean,
  const Eigen::Matrix3d& axes, double radius)
{
  std::vector<Eigen::Vector2d> q;
  q.reserve(ids.size());
  for (int j : ids)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
    q.emplace_back(d.dot(axes.col(0)), d.dot(axes.col(1)));
  }
  Eigen::Vector3d circle;
  return plantmorph::FitCircle(q, circle) && circle[2] <= TubeRadius * radius;
}

/// Whether the piece points[ids] is curved across at the features' radius: the lower quartile, over about
/// CurvatureSamples of its points whose ball of radius `radius` holds a patch of its own points, of their spread off
/// the ball's plane, at least CurvedNoises range noises `noise` and CurvedFloor radii.
bool CurvedAcross(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, double radius, double noise)
{
  std::vector<Eigen::Vector3d> own;
  own.reserve(ids.size());
  for (int j : ids)
    own.push_back(points[static_cast<std::size_t>(j)]);
  const PointGrid grid(own, radius);
  const std::size_t stride = std::max<std::size_t>(1, own.size() / CurvatureSamples);
  std::vector<double> thickness;
  std::vector<int> near;
  std::size_t samples = 0;
  for (std::size_t k = 0; k < own.size(); k += stride)
  {
    ++samples;
    grid.Within(own[k], radius, near);
    if (near.size() < CurvatureNeighbours)
      continue;
    const Eigen::Vector3d spread = PartMoments::Of(own, near).Spreads();
    if (spread[1] >= CurvatureSheetWidth * radius) // a patch of sheet, not a row or a line of points
      thickness.push_back(spread[0]);
  }
  if (thickness.empty() || 2 * thickness.size() < samples)
    return false;
  auto quartile = thickness.begin() + static_cast<std::ptrdiff_t>(thickness.size() / 4);
  std::nth_element(thickness.begin(), quartile, thickness.end());
  return *quartile >= std::max(CurvedNoises * noise, CurvedFloor * radius);
}

std::vector<RegionVerdict> JudgeRegions(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const std::vector<int>& region, int count, const SegmentationParameters& p, bool allowMixed)
{
  // A sheet narrower than the features' neighbourhood (2r across) cannot be told from a strip of a tube's surface.
  const double minimumWidth = 2.0 * f.radius;
  std::vector<std::vector<int>> members(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0)
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
  std::vector<RegionVerdict> verdicts(static_cast<std::size_t>(count));
  for (std::size_t r = 0; r < members.size(); ++r)
  {
    const std::vector<int>& ids = members[r];
    if (ids.size() < JudgedRegionPoints)
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
      Scatter(points, ids, mean) / static_cast<double>(ids.size()));
    const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
    const Eigen::Vector3d normal = solver.eigenvectors().col(0);
    double coherence = 0.0;
    for (int j : ids)
      coherence += std::abs(f.normal[static_cast<std::size_t>(j)].dot(normal));
    coherence /= static_cast<double>(ids.size());
    const double elongation = l[1] > 0.0 ? std::sqrt(l[2] / l[1]) : std::numeric_limits<double>::infinity();
    RegionVerdict& v = verdicts[r];
    v.judged = true;
    const double width = 2.0 * std::sqrt(3.0 * l[1]); // a uniform rectangle's width from its variance
    const NormalSpread spread = SpreadOfNormals(f, ids, solver.eigenvectors().col(2), p.normalAngle * Pi / 180.0);
    const bool turning = spread.axisAlongLength >= CylinderAxisCosine && spread.kurtosis >= CylinderKurtosis;
    const bool cylinder = turning &&
      ((spread.middle >= CylinderNormalSpread && spread.emptiestArc >= CylinderArcFill) ||
        (spread.middle >= TubeNormalSpread && OnThinTube(points, ids, mean, solver.eigenvectors(), f.radius)));
    // a sheet curved across at r is twigs' sides: one seen from one side, a fork of them in one plane (as wide as a
    // leaf), or a leaf grown into a twig's side (grown again as a mixed region, then judged again)
    const bool sheet = !cylinder && coherence > p.sheetCoherence;
    const bool curved = sheet && CurvedAcross(points, ids, f.radius, f.noise);
    const bool leafShaped = elongation < p.maximumLeafElongation && width >= minimumWidth;
    v.leaf = sheet && !curved && leafShaped;
    v.strip = sheet && !curved && !v.leaf;
    v.mixed = allowMixed && leafShaped && (curved || (!cylinder && coherence <= p.sheetCoherence));
    const double margin = v.leaf ? (coherence - p.sheetCoherence) / (1.0 - p.sheetCoherence)
                                 : std::max({ elongation >= p.maximumLeafElongation ? 1.0 : 0.0,
                                     (p.sheetCoherence - coherence) / p.sheetCoherence, 1.0 - width / minimumWidth });
    v.confidence = std::clamp(0.5 + 0.5 * margin, 0.0, 1.0);
  }
  return verdicts;
}

/// Regions judged mixed (incoherent, wide, not a cylinder: leaves grown into each other through a smooth contact,
/// or one leaf into the next over a crease too gentle to stop it) are grown again inside themselves, each piece's
/// normals now within NormalAngle of its seed's (the flattest point not yet taken), not only of their neighbour's:
/// the normals can no longer drift from one leaf to the next. New region numbers from `count` on; returns the count.
int SplitMixedRegions(const PointFeatures& f, const LinkGraph& graph, const SegmentationParameters& p,
  const std::vector<RegionVerdict>& verdicts, std::vector<int>& region, int count)
{
  const std::size_t n = region.size();
  const double cosine = std::cos(p.normalAngle * Pi / 180.0);
  std::vector<int> order;
  for (std::size_t i = 0; i < n; ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].mixed)
    {
      order.push_back(static_cast<int>(i));
      region[i] = -2 - region[i]; // not yet regrown: -2 - its old region
    }
  std::stable_sort(order.begin(), order.end(),
    [&](int a, int b) { return f.variation[static_cast<std::size_t>(a)] < f.variation[static_cast<std::size_t>(b)]; });
  std::deque<int> queue;
  for (int seed : order)
  {
    const int old = region[static_cast<std::size_t>(seed)];
    if (old >= 0)
      continue;
    const Eigen::Vector3d& axis = f.normal[static_cast<std::size_t>(seed)];
    region[static_cast<std::size_t>(seed)] = count;
    queue.push_back(seed);
    while (!queue.empty())
    {
      const auto q = static_cast<std::size_t>(queue.front());
      queue.pop_front();
      for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
      {
        const auto j = static_cast<std::size_t>(graph.neighbours[e]);
        if (region[j] == old && std::abs(f.normal[q].dot(f.normal[j])) >= cosine &&
          std::abs(axis.dot(f.normal[j])) >= cosine)
        {
          region[j] = count;
          queue.push_back(static_cast<int>(j));
        }
      }
    }
    ++count;
  }
  return count;
}

/// Links around a strip within which its surroundings are looked at (StripIsFlatSheet): 3 links of LinkScale (2.5)
/// spacings reach about 2r at the default FeatureScale, across a twig's next facets.
constexpr int StripRingLinks = 3;
/// A strip's surroundings lie in its plane when their root mean square distance off it is under this fraction of
/// the features' radius r (r is at least 12 times the range noise, so a flat ring's noise stays under it).
constexpr double StripRingFlatness = 0.1;

/// The points within StripRingLinks links around points[ids] (outside them). `mark` is scratch (all -1 in and out).
std::vector<int> RingAround(const LinkGraph& graph, const std::vector<int>& ids, std::vector<int>& mark)
{
  for (int j : ids)
    mark[static_cast<std::size_t>(j)] = 1;
  std::vector<int> front = ids, next, ring;
  for (int k = 0; k < StripRingLinks; ++k)
  {
    next.clear();
    for (int q : front)
      for (std::size_t e = graph.offsets[static_cast<std::size_t>(q)];
           e < graph.offsets[static_cast<std::size_t>(q) + 1]; ++e)
      {
        const int j = graph.neighbours[e];
        if (mark[static_cast<std::size_t>(j)] < 0)
        {
          mark[static_cast<std::size_t>(j)] = 1;
          next.push_back(j);
          ring.push_back(j);
        }
      }
    front.swap(next);
  }
  for (int j : ids)
    mark[static_cast<std::size_t>(j)] = -1;
  for (int j : ring)
    mark[static_cast<std::size_t>(j)] = -1;
  return ring;
}

/// Whether a flat strip is a sheet and not a facet of wood: the points within StripRingLinks links around it
/// (outside it) lie in its plane (root mean square off it under StripRingFlatness r), or there are none. Wood is
/// curved around an axis: around a facet of a tube the next facets turn away from its plane (on the simulated tree
/// their points are 0.3 r to 1 r off it); around a leaf seen at a grazing angle in a few rows, or alone, the
/// surroundings are the leaf's own plane or nothing. `mark` is scratch (all -1 in and out).
bool StripIsFlatSheet(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const std::vector<int>& ids,
  const PartMoments& moments, double radius, std::vector<int>& mark)
{
  double spread = 0.0;
  const Eigen::Vector3d normal = moments.Normal(spread);
  const std::vector<int> ring = RingAround(graph, ids, mark);
  double off = 0.0;
  for (int j : ring)
  {
    const double d = (points[static_cast<std::size_t>(j)] - moments.mean).dot(normal);
    off += d * d;
  }
  return ring.empty() || std::sqrt(off / static_cast<double>(ring.size())) < StripRingFlatness * radius;
}

/// A blade folded along its midrib by more than about 60 degrees grows into two regions, one per half, each
/// narrower than 2r and its surroundings (the other half) turning away: two strips. Two strips that lie within
/// StripRingLinks links of each other are the halves of one folded blade when together they are a V along their
/// length (their normals share an axis along the pair's long axis and turn around it as far as a cylinder's, but
/// in two groups: kurtosis under CylinderKurtosis), as wide as a leaf and no long strip, and the points around the
/// pair (the crease between the halves among them) lie in one half's plane or the other's (root mean square off the
/// nearer under StripRingFlatness r). A branch's facets fail it: the facet between two facets that far apart lies
/// in neither plane. The pair becomes one leaf region (the first's number), with the points around it in either
/// plane that no leaf region holds (the crease along the midrib). Returns the pairs joined.
int JoinFoldedStrips(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  const SegmentationParameters& p, std::vector<RegionVerdict>& verdicts, std::vector<int>& region)
{
  std::vector<std::vector<int>> members(verdicts.size());
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].strip)
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
  std::vector<int> mark(points.size(), -1);
  int joined = 0;
  for (std::size_t a = 0; a < verdicts.size(); ++a)
  {
    if (!verdicts[a].strip)
      continue;
    const auto moved = [&](std::size_t r) { // points an earlier pair took as its crease
      members[r].erase(std::remove_if(members[r].begin(), members[r].end(),
                         [&](int j) { return region[static_cast<std::size_t>(j)] != static_cast<int>(r); }),
        members[r].end());
    };
    moved(a);
    if (members[a].size() < JudgedRegionPoints)
      continue;
    std::map<int, int> near; // the other strips around it, with their points there
    for (int j : RingAround(graph, members[a], mark))
    {
      const int r = region[static_cast<std::size_t>(j)];
      if (r >= 0 && static_cast<std::size_t>(r) != a && verdicts[static_cast<std::size_t>(r)].strip)
        ++near[r];
    }
    if (near.empty())
      continue;
    const auto b =
      static_cast<std::size_t>(std::max_element(near.begin(), near.end(), [](const auto& x, const auto& y) {
        return x.second < y.second;
      })->first);
    moved(b);
    std::vector<int> pair = members[a];
    pair.insert(pair.end(), members[b].begin(), members[b].end());
    const PartMoments halves[2] = { PartMoments::Of(points, members[a]), PartMoments::Of(points, members[b]) };
    const PartMoments both = halves[0].Merged(halves[1]);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(both.scatter / both.count);
    const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
    const NormalSpread spread = SpreadOfNormals(f, pair, solver.eigenvectors().col(2));
    if (spread.axisAlongLength < CylinderAxisCosine || spread.middle < CylinderNormalSpread ||
      spread.kurtosis >= CylinderKurtosis || 2.0 * std::sqrt(3.0 * l[1]) < 2.0 * f.radius ||
      !(l[1] > 0.0 && std::sqrt(l[2] / l[1]) < p.maximumLeafElongation))
      continue;
    double unused = 0.0, off = 0.0;
    const Eigen::Vector3d normals[2] = { halves[0].Normal(unused), halves[1].Normal(unused) };
    const std::vector<int> ring = RingAround(graph, pair, mark);
    std::vector<int> crease; // the ring's points of other strips or of regions too small to judge, in the V
    for (int j : ring)
    {
      const Eigen::Vector3d& q = points[static_cast<std::size_t>(j)];
      const double d =
        std::min(std::abs((q - halves[0].mean).dot(normals[0])), std::abs((q - halves[1].mean).dot(normals[1])));
      off += d * d;
      const int r = region[static_cast<std::size_t>(j)];
      if (r >= 0 && !verdicts[static_cast<std::size_t>(r)].leaf && d < StripRingFlatness * f.radius)
        crease.push_back(j);
    }
    if (!ring.empty() && std::sqrt(off / static_cast<double>(ring.size())) >= StripRingFlatness * f.radius)
      continue;
    for (int j : members[b])
      region[static_cast<std::size_t>(j)] = static_cast<int>(a);
    for (int j : crease)
      region[static_cast<std::size_t>(j)] = static_cast<int>(a);
    pair.insert(pair.end(), crease.begin(), crease.end());
    members[a] = std::move(pair);
    members[b].clear();
    verdicts[b].strip = false;
    verdicts[b].judged = false;
    verdicts[a].strip = false;
    verdicts[a].leaf = true;
    ++joined;
  }
  return joined;
}

/// Flat strips are leaf unless they are a piece of a curved surface: a region judged wood only for being narrower
/// than 2r or longer than MaximumLeafElongation widths, yet a flat sheet (coherent, no cylinder), is a leaf when
/// its surroundings are flat (StripIsFlatSheet). Returns the points that became leaf.
std::size_t FlatStripsAreLeaves(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, double radius,
  std::vector<RegionVerdict>& verdicts, const std::vector<int>& region)
{
  std::vector<std::vector<int>> members(verdicts.size());
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].strip)
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
  std::vector<int> mark(points.size(), -1);
  std::size_t leaves = 0;
  for (std::size_t r = 0; r < verdicts.size(); ++r)
  {
    if (!verdicts[r].strip)
      continue;
    const PartMoments m = PartMoments::Of(points, members[r]);
    if (!StripIsFlatSheet(points, graph, members[r], m, radius, mark))
      continue;
    verdicts[r].strip = false;
    verdicts[r].leaf = true;
    verdicts[r].flatStrip = true;
    leaves += members[r].size();
  }
  return leaves;
}

/// A leaf region's spread reaches its unjudged points within this many features' radii r of the judged point the
/// spread started from: the features see r around a point, so a point reached over more than 2r of unjudged points
/// (a twig's surface beyond the leaf's base, its normals turning through creases and small regions) is no part of
/// the leaf's sheet.
constexpr double LeafSpreadReach = 2.0;

/// Breadth-first from the judged points over the unjudged, non-linear ones: each takes the region (and so the
/// organ) of the judged point it is reached from first, a leaf region's within LeafSpreadReach r of that point.
/// Sources in index order: deterministic.
void SpreadRegions(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  const std::vector<RegionVerdict>& verdicts, std::vector<int>& region, std::vector<char>& judged)
{
  const std::size_t n = region.size();
  const double reach = LeafSpreadReach * f.radius;
  judged.assign(n, 0);
  std::vector<int> source(n, -1);
  std::deque<int> queue;
  for (std::size_t i = 0; i < n; ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].judged)
    {
      judged[i] = 1;
      source[i] = static_cast<int>(i);
      queue.push_back(static_cast<int>(i));
    }
  std::vector<char> reached(judged);
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    const auto from = static_cast<std::size_t>(source[q]);
    const bool leaf = verdicts[static_cast<std::size_t>(region[q])].leaf;
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (reached[j] || IsLinear(f, j) || (leaf && (points[j] - points[from]).norm() > reach))
        continue;
      reached[j] = 1;
      region[j] = region[q];
      source[j] = source[q];
      queue.push_back(static_cast<int>(j));
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!reached[i])
      region[i] = -1; // linear points, points cut off from every judged region or beyond a leaf region's reach
}

/// A flat strip's normals turn about its length by under this: the middle eigenvalue of their second moments (the
/// mean squared sine of their turn), an rms turn of about 6 degrees, an arc of 20 degrees spread evenly. On the
/// simulated tree from one position at 1 % noise the strips left wood that are truly leaf turn by 0.001-0.022 (5 % to
/// 95 %; median 0.006), those truly wood (strips of a twig's surface, its facets smoothed across their edges by the
/// features) by 0.003-0.073 (median 0.022).
constexpr double LoneStripNormalSpread = 0.01;
/// A lone strip has no wood within this fraction of the features' radius r of its points.
constexpr double LoneStripReach = 0.5;

/// The points of each strip region (`members`) and those of them grown into it in step 3 (`own`, the points judged;
/// the rest were reached by the breadth-first spread), indexed by region.
void StripMembers(const std::vector<char>& judged, const std::vector<RegionVerdict>& verdicts,
  const std::vector<int>& region, std::vector<std::vector<int>>& members, std::vector<std::vector<int>>& own)
{
  members.assign(verdicts.size(), {});
  own.assign(verdicts.size(), {});
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].strip)
    {
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
      if (judged[i])
        own[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
    }
}

/// The strip regions `chosen` become flat leaf regions, their points leaf. Returns the points made leaf.
std::size_t StripsMadeLeaf(const std::vector<std::size_t>& chosen, const std::vector<std::vector<int>>& members,
  std::vector<RegionVerdict>& verdicts, std::vector<int>& organ)
{
  std::size_t count = 0;
  for (std::size_t r : chosen)
  {
    verdicts[r].strip = false;
    verdicts[r].leaf = true;
    verdicts[r].flatStrip = true;
    for (int j : members[r])
      organ[static_cast<std::size_t>(j)] = OrganLeaf;
    count += members[r].size();
  }
  return count;
}

/// The strip regions with enough points of their own (JudgedRegionPoints) whose own points' normals do not turn
/// about the strip's length (LoneStripNormalSpread): flat strips, in region order.
std::vector<std::size_t> FlatStrips(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const std::vector<RegionVerdict>& verdicts, const std::vector<std::vector<int>>& own)
{
  std::vector<std::size_t> flat;
  for (std::size_t r = 0; r < verdicts.size(); ++r)
  {
    if (!verdicts[r].strip || own[r].size() < JudgedRegionPoints)
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, own[r], mean));
    if (!(SpreadOfNormals(f, own[r], solver.eigenvectors().col(2)).middle >= LoneStripNormalSpread))
      flat.push_back(r);
  }
  return flat;
}

/// Whether no other wood point (`wood`, a flag per point, set on the piece's own points `ids`) lies within `reach` of
/// a point of the piece; `grid` indexes every point, in cells of at least `reach`. The piece's flags are cleared for
/// the query and set again.
bool ApartFromOtherWood(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const std::vector<int>& ids,
  double reach, std::vector<unsigned char>& wood)
{
  for (int j : ids)
    wood[static_cast<std::size_t>(j)] = 0;
  const bool apart = std::none_of(
    ids.begin(), ids.end(), [&](int j) { return grid.AnyWithin(points[static_cast<std::size_t>(j)], reach, wood); });
  for (int j : ids)
    wood[static_cast<std::size_t>(j)] = 1;
  return apart;
}

/// Strips (flat, coherent, no cylinder, wood only for being narrower than 2r or long) that no flat surroundings made
/// leaf are leaf when no wood lies within LoneStripReach r of them and the normals of their own points (those grown,
/// not spread into them) do not turn about their length (LoneStripNormalSpread). Wood is a tube: its strips lie
/// beside the tube's other strips, or turn with its surface; a leaf seen narrow (a few rows at a grazing angle, a
/// piece beyond a crease, in a brush of other leaves that make its surroundings uneven) is flat and lies among
/// leaves or alone. Judged on the organs as the regions left them, all at once. Returns the points made leaf.
std::size_t LoneFlatStripsAreLeaves(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const std::vector<char>& judged, std::vector<RegionVerdict>& verdicts, const std::vector<int>& region,
  std::vector<int>& organ)
{
  const std::size_t n = region.size();
  std::vector<std::vector<int>> members, own;
  StripMembers(judged, verdicts, region, members, own);
  const double reach = LoneStripReach * f.radius;
  std::vector<unsigned char> wood(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    wood[i] = organ[i] == OrganWood ? 1 : 0;
  const PointGrid grid(points, reach);
  std::vector<std::size_t> lone;
  for (std::size_t r : FlatStrips(points, f, verdicts, own))
  {
    if (ApartFromOtherWood(points, grid, members[r], reach, wood))
      lone.push_back(r);
  }
  return StripsMadeLeaf(lone, members, verdicts, organ);
}

/// A flat strip's wood neighbours lie in its plane when within this many range noises of it (at least half a
/// spacing): the features' radius r is widened to 12 noises on a noisy scan, so this is a quarter of r there.
constexpr double CoplanarStripOffPlane = 3.0;
/// Such a strip is at least as wide (a uniform rectangle's width from its variance) as the features' radius r and
/// as their neighbourhood before the widening for noise (2 FeatureScale spacings): at low noise 2r, so the rule
/// only takes strips narrower than 2r because r was widened (a twig's facet seen flat is narrower than the twig).
constexpr double CoplanarStripWidth = 1.0;
/// The strip's points that touch other wood lie in one spot: their extent along both of the strip's axes is at
/// most this many r (a leaf held at its base by its twig; a twig's strip touches its other facets along its length).
constexpr double CoplanarStripContact = 1.0;

/// Strips left wood by LoneFlatStripsAreLeaves whose own points' normals do not turn (LoneStripNormalSpread), as
/// wide as CoplanarStripWidth on their own points and no long strip (MaximumLeafElongation), are leaf when the wood
/// within LoneStripReach r of them is, but for one spot (CoplanarStripContact), such strips, thin lines (IsLinear)
/// or points cut off from every region, all in their plane (CoplanarStripOffPlane noises). A small or edge-on leaf
/// on a noisy scan, narrower than the widened 2r, is two or three such strips with its margin's lines and cut-off
/// points beside them, and its twig at its base; a twig's flat strips lie beside its other facets, turned off their
/// plane, along their whole length. Judged all at once. Returns the points made leaf.
std::size_t CoplanarFlatStripsAreLeaves(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  double spacing, const SegmentationParameters& p, const std::vector<char>& judged,
  std::vector<RegionVerdict>& verdicts, const std::vector<int>& region, std::vector<int>& organ)
{
  std::vector<std::vector<int>> members, own;
  StripMembers(judged, verdicts, region, members, own);
  std::vector<char> flat(points.size(), 0);
  const std::vector<std::size_t> candidates = FlatStrips(points, f, verdicts, own);
  for (std::size_t r : candidates)
  {
    for (int j : members[r])
      flat[static_cast<std::size_t>(j)] = 1;
  }
  const double reach = LoneStripReach * f.radius;
  const double offPlane = std::max(CoplanarStripOffPlane * f.noise, 0.5 * spacing);
  const double minimumWidth = std::max(CoplanarStripWidth * f.radius, 2.0 * p.featureScale * spacing);
  const PointGrid grid(points, reach);
  std::vector<std::size_t> chosen;
  std::vector<int> near;
  for (std::size_t r : candidates)
  {
    // Its size as JudgeRegions saw it (its own points): no long strip, and wide enough.
    Eigen::Vector3d mean;
    const Eigen::Vector3d l =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Scatter(points, own[r], mean) / static_cast<double>(own[r].size()))
        .eigenvalues()
        .cwiseMax(0.0);
    if (2.0 * std::sqrt(3.0 * l[1]) < minimumWidth || !(std::sqrt(l[2]) < p.maximumLeafElongation * std::sqrt(l[1])))
      continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
      Scatter(points, members[r], mean) / static_cast<double>(members[r].size()));
    const Eigen::Vector3d normal = solver.eigenvectors().col(0);
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (int m : members[r])
    {
      grid.Within(points[static_cast<std::size_t>(m)], reach, near);
      const bool touches = std::any_of(near.begin(), near.end(), [&](int j) {
        const auto q = static_cast<std::size_t>(j);
        return organ[q] == OrganWood && region[q] != static_cast<int>(r) &&
          ((!flat[q] && !IsLinear(f, q) && region[q] >= 0) || std::abs((points[q] - mean).dot(normal)) > offPlane);
      });
      if (!touches)
        continue;
      const Eigen::Vector3d d = points[static_cast<std::size_t>(m)] - mean;
      const Eigen::Vector2d at(d.dot(solver.eigenvectors().col(1)), d.dot(solver.eigenvectors().col(2)));
      low = low.cwiseMin(at);
      high = high.cwiseMax(at);
    }
    if (!(low[0] <= high[0]) || (high - low).maxCoeff() <= CoplanarStripContact * f.radius)
      chosen.push_back(r);
  }
  return StripsMadeLeaf(chosen, members, verdicts, organ);
}

/// A strip among leaves has under this fraction of wood among the points within StripRingLinks links around it. On the
/// 18 simulated scans of the accuracy benchmark the strips left wood that are truly wood lie beside wood (the points
/// around 95 % of them over 45 % wood, around three quarters of them all wood); around half of those truly leaf under
/// a third is wood.
constexpr double StripAmongLeavesWood = 0.4;
/// A strip among leaves was judged on at least this fraction of the points it holds (its own, grown points; the rest
/// reached by the breadth-first spread from it): a small strip that took many unjudged points around it says little
/// of them.
constexpr double StripAmongLeavesOwnFraction = 0.25;

/// A strip among leaves longer than this many features' radii r can be a branch's side, not a leaf seen narrow: on
/// the 18 simulated scans of the accuracy benchmark the strips the rule made leaf that are no single row are at most
/// 11 r long (95 % under 8.5 r), while on a sympodial tree with 1-m leaves (the tree-fit benchmark's sym-small) nine
/// of the thin branches' strips it made leaf run 12-87 r along the branches (2,377 wood points, no leaf).
constexpr double StripAmongLeavesLength = 12.0;

/// Whether a strip (`members`, its own points' mean and axes, the last the long axis; `turn` the middle eigenvalue
/// of its own points' normals) is a branch's side: longer than StripAmongLeavesLength r between 2 % and 98 % of its
/// points along its axis, wider than a row (more points than spacings along that length), and either narrower than
/// the features' neighbourhood 2r across (a thin branch's visible side) or with normals turning about its length as
/// an arc's do (at least LoneStripNormalSpread, the bound of a flat strip). A row of one leaf seen at a grazing angle
/// is one scan line, about a point a spacing; leaves along a twig grown into one strip (the tree-fit benchmark's
/// 0.15-m leaves: 27-42 r long, 2-4 r wide, normals turning by under 0.005) are wide and flat.
bool StripIsABranchsSide(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& members,
  const Eigen::Vector3d& mean, const Eigen::Matrix3d& axes, double turn, double radius, double spacing)
{
  const auto extent = [&](const Eigen::Vector3d& axis) {
    std::vector<double> t;
    t.reserve(members.size());
    for (int j : members)
      t.push_back((points[static_cast<std::size_t>(j)] - mean).dot(axis));
    const auto at = [&t](std::size_t k) {
      std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(k), t.end());
      return t[k];
    };
    const std::size_t last = t.size() - 1;
    return at(last * 49 / 50) - at(last / 50);
  };
  const double length = extent(axes.col(2));
  if (length <= StripAmongLeavesLength * radius || static_cast<double>(members.size()) * spacing <= length)
    return false;
  return turn >= LoneStripNormalSpread || extent(axes.col(1)) < 2.0 * radius;
}

/// Strips (flat, coherent, no cylinder, wood only for being narrower than 2r or long) left wood by the other strip
/// rules are leaf when the points within StripRingLinks links around them are mostly leaf (under
/// StripAmongLeavesWood wood), their own points' normals turn about their length by under the features' error
/// (TubeNormalSpread, an rms turn of 10 degrees: more is a tube's arc, as in JudgeRegions) and those own points are at
/// least StripAmongLeavesOwnFraction of their points, unless they are a branch's side (StripIsABranchsSide). A strip
/// of the wood's surface lies beside the tube's other strips, wood; a leaf's strip in a brush of leaves, or at its
/// base within reach of its twig, lies among leaf points, and so does a thin branch among large leaves, told by its
/// length. Judged on the organs as the earlier rules left them, all at once. Returns the points made leaf.
std::size_t StripsAmongLeavesAreLeaves(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const LinkGraph& graph, const std::vector<char>& judged, double spacing, std::vector<RegionVerdict>& verdicts,
  const std::vector<int>& region, std::vector<int>& organ)
{
  std::vector<std::vector<int>> members, own;
  StripMembers(judged, verdicts, region, members, own);
  std::vector<int> mark(points.size(), -1);
  std::vector<std::size_t> among;
  for (std::size_t r = 0; r < verdicts.size(); ++r)
  {
    if (!verdicts[r].strip || own[r].size() < JudgedRegionPoints ||
      static_cast<double>(own[r].size()) < StripAmongLeavesOwnFraction * static_cast<double>(members[r].size()))
      continue;
    const std::vector<int> ring = RingAround(graph, members[r], mark);
    const auto wood =
      std::count_if(ring.begin(), ring.end(), [&](int j) { return organ[static_cast<std::size_t>(j)] == OrganWood; });
    if (ring.empty() || static_cast<double>(wood) >= StripAmongLeavesWood * static_cast<double>(ring.size()))
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, own[r], mean));
    const double turn = SpreadOfNormals(f, own[r], solver.eigenvectors().col(2)).middle;
    if (turn < TubeNormalSpread &&
      !StripIsABranchsSide(points, members[r], mean, solver.eigenvectors(), turn, f.radius, spacing))
      among.push_back(r);
  }
  return StripsMadeLeaf(among, members, verdicts, organ);
}

/// A thick cylinder's pieces of wood are fitted over lengths of ThickWoodSlice r along their region's axis.
constexpr double ThickWoodSlice = 8.0;
/// Points kept on a thick cylinder's surface lie within this many times the range noise of it (or a spacing).
constexpr double ThickWoodBand = 3.0;

/// A circle through points given in a plane (u, v): centre and radius by the algebraic fit (FitCircle); false when
/// the points determine none.
bool FitCircle(const std::vector<Eigen::Vector2d>& q, Eigen::Vector2d& centre, double& radius)
{
  Eigen::Vector3d circle;
  if (!plantmorph::FitCircle(q, circle))
    return false;
  centre = circle.head<2>();
  radius = circle[2];
  return true;
}

/// A wood region's slice that is a piece of a thick cylinder (a trunk or a wide branch): its axis, centre, radius
/// and the span along the axis its fit holds over.
struct CylinderSlice
{
  Eigen::Vector3d axis, u, v, origin; ///< the region's axis (unit), two directions across it, a point on the axis
  Eigen::Vector2d centre;             ///< the circle's centre in (u, v) from origin
  double radius = 0.0, from = 0.0, to = 0.0;
};

/// The slices of every judged wood region that are pieces of a thick cylinder: its points in a slice of
/// ThickWoodSlice r along the region's main axis (the region at least its diameter long) lie on a circle across
/// the axis of radius at least r (thinner wood is judged a cylinder whole), within `band` in root mean square / 2,
/// over an arc whose sagitta is at least 2 `band` (the curvature resolved: a flat strip of a leaf fits no circle).
std::vector<CylinderSlice> ThickCylinderSlices(const std::vector<Eigen::Vector3d>& points,
  const std::vector<RegionVerdict>& verdicts, const std::vector<int>& region, double radius, double band)
{
  std::vector<std::vector<int>> members(verdicts.size());
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].judged &&
      !verdicts[static_cast<std::size_t>(region[i])].leaf)
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
  std::vector<CylinderSlice> slices;
  const double length = ThickWoodSlice * radius;
  for (const std::vector<int>& ids : members)
  {
    if (ids.size() < JudgedRegionPoints)
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, ids, mean));
    CylinderSlice c;
    c.axis = solver.eigenvectors().col(2);
    c.u = solver.eigenvectors().col(1);
    c.v = solver.eigenvectors().col(0);
    c.origin = mean;
    std::map<long, std::vector<Eigen::Vector2d>> cut; // the points across the axis, slice by slice
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (int j : ids)
    {
      const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
      const double t = d.dot(c.axis);
      low = std::min(low, t);
      high = std::max(high, t);
      cut[std::lround(std::floor(t / length))].emplace_back(d.dot(c.u), d.dot(c.v));
    }
    for (const auto& [k, q] : cut)
    {
      if (q.size() < JudgedRegionPoints || !FitCircle(q, c.centre, c.radius) || c.radius < radius ||
        high - low < 2.0 * c.radius)
        continue;
      double squares = 0.0, least = c.radius;
      for (const Eigen::Vector2d& x : q)
      {
        const double d = (x - c.centre).norm();
        squares += (d - c.radius) * (d - c.radius);
      }
      // the sagitta: how far the chord between the arc's ends lies inside the circle
      std::vector<double> angle;
      const Eigen::Vector2d mid =
        std::accumulate(q.begin(), q.end(), Eigen::Vector2d(Eigen::Vector2d::Zero())) / static_cast<double>(q.size());
      const Eigen::Vector2d out = (mid - c.centre).normalized(), side(-out[1], out[0]);
      for (const Eigen::Vector2d& x : q)
        angle.push_back(std::atan2((x - c.centre).dot(side), (x - c.centre).dot(out)));
      std::sort(angle.begin(), angle.end());
      const double spanned = angle[angle.size() * 49 / 50] - angle[angle.size() / 50];
      least = c.radius * (1.0 - std::cos(std::min(Pi, 0.5 * spanned)));
      if (std::sqrt(squares / static_cast<double>(q.size())) > 0.5 * band || least < 2.0 * band)
        continue;
      c.from = static_cast<double>(k) * length;
      c.to = c.from + length;
      slices.push_back(c);
    }
  }
  return slices;
}

/// The circle of a thick cylinder's slice fitted again to all the wood in the slice near it (`organ` wood,
/// within `shell` of the circle), two rounds, the shell narrowing to 2 `band`: a region is one strip of the trunk's
/// surface, whose arc alone puts the circle off by a tenth of its radius 60 degrees around it; the wood on every side
/// fixes it. False when the wood there then fits no circle within `band` / 2 in root mean square.
bool RefitSlice(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& organ, const PointGrid& grid,
  double band, CylinderSlice& c, std::vector<int>& near)
{
  double shell = 0.15 * c.radius;
  std::vector<Eigen::Vector2d> q;
  for (int round = 0; round < 3; ++round)
  {
    const double half = 0.5 * (c.to - c.from);
    const Eigen::Vector3d middle = c.origin + (c.from + half) * c.axis + c.centre[0] * c.u + c.centre[1] * c.v;
    grid.Within(middle, std::hypot(half, c.radius + shell), near);
    q.clear();
    double squares = 0.0;
    for (int j : near)
    {
      const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - c.origin;
      const double t = d.dot(c.axis);
      const Eigen::Vector2d x(d.dot(c.u), d.dot(c.v));
      const double off = (x - c.centre).norm() - c.radius;
      if (organ[static_cast<std::size_t>(j)] != OrganWood || t < c.from || t > c.to || std::abs(off) > shell)
        continue;
      q.push_back(x);
      squares += off * off;
    }
    if (q.size() < JudgedRegionPoints)
      return false;
    if (round == 2)
      return std::sqrt(squares / static_cast<double>(q.size())) <= 0.5 * band;
    if (!FitCircle(q, c.centre, c.radius))
      return false;
    shell = std::max(2.0 * band, 0.5 * shell);
  }
  return false;
}

/// A thick cylinder keeps its whole surface: a trunk or wide branch is locally flat to the features, and a region
/// grown over an arc of it too narrow for a cylinder's spread of normals (under about 80 degrees), and not long
/// enough for a strip (a trunk's face grown on up a branch that leaves in its plane), was judged a leaf. Every leaf
/// point within `band` of a thick cylinder fitted to the judged wood (ThickCylinderSlices, RefitSlice), inside the
/// slice and facing out of it (its normal within NormalAngle of the radius through it), is wood when at least a
/// quarter of its region's points are: a leaf beside the trunk, even touching it, crosses that shell in a line or a narrow
/// band at most. Returns the points made wood.
std::size_t ThickWoodKeepsItsSurface(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const std::vector<RegionVerdict>& verdicts, const std::vector<int>& region, const SegmentationParameters& p,
  double band, std::vector<int>& organ)
{
  std::vector<CylinderSlice> slices = ThickCylinderSlices(points, verdicts, region, f.radius, band);
  if (slices.empty())
    return 0;
  const double cosine = std::cos(p.normalAngle * Pi / 180.0);
  const PointGrid grid(points, f.radius);
  std::vector<int> near, made;
  for (CylinderSlice& c : slices)
  {
    if (!RefitSlice(points, organ, grid, band, c, near))
      continue;
    const double half = 0.5 * (c.to - c.from);
    const Eigen::Vector3d middle = c.origin + (c.from + half) * c.axis + c.centre[0] * c.u + c.centre[1] * c.v;
    grid.Within(middle, std::hypot(half, c.radius + band), near);
    for (int j : near)
    {
      const auto i = static_cast<std::size_t>(j);
      if (organ[i] != OrganLeaf)
        continue;
      const Eigen::Vector3d d = points[i] - c.origin;
      const double t = d.dot(c.axis);
      const Eigen::Vector2d across = Eigen::Vector2d(d.dot(c.u), d.dot(c.v)) - c.centre;
      const double off = across.norm();
      if (t < c.from || t > c.to || std::abs(off - c.radius) > band || off <= 0.0)
        continue;
      const Eigen::Vector3d radial = (across[0] * c.u + across[1] * c.v) / off;
      if (std::abs(f.normal[i].dot(radial)) >= cosine)
        made.push_back(j); // made wood after every slice is fitted: the fits see the labels as judged
    }
  }
  // a region is bark when a quarter of its points lie on the shells; a leaf touching the trunk meets them in a line
  // (on the simulated sym-large tree: leaf regions 9 % at most, bark regions 8-100 %, most above a quarter)
  std::sort(made.begin(), made.end());
  made.erase(std::unique(made.begin(), made.end()), made.end());
  std::map<int, std::size_t> onShell, size;
  for (int j : made)
    ++onShell[region[static_cast<std::size_t>(j)]];
  for (std::size_t i = 0; i < region.size(); ++i)
    if (onShell.count(region[i]))
      ++size[region[i]];
  std::size_t count = 0;
  for (int j : made)
  {
    const int r = region[static_cast<std::size_t>(j)];
    if (4 * onShell[r] < size[r])
      continue;
    organ[static_cast<std::size_t>(j)] = OrganWood;
    ++count;
  }
  return count;
}

/// Points linked to fewer than JudgedRegionPoints others in all (their whole component of the link graph is that
/// small) were wood, cut off from every judged region: a surface seen at a grazing angle, its scan rows farther apart
/// than the links (a leaf turned edge on, the flanks of a stem), or a stray. Such a piece takes the organ most of the
/// other points within the features' radius r around it have (a stem's flank lies next to the stem's face, judged
/// wood), leaf when there are none (a leaf turned edge on is hit in scattered points; a branch, even a twig thinner
/// than the spacing, is scanned along its length in a line of linked points). On the simulated tree from four
/// positions (0.1 % noise) 11,118 leaf points (43 % of the leaf called wood) and 652 wood points become leaf; made
/// leaf whatever their surroundings, the herb's stem flanks cost its wood IoU 0.895 -> 0.853. Returns the points
/// made leaf.
std::size_t IsolatedPiecesByTheirSurroundings(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  double radius, std::vector<int>& organ, std::vector<double>& confidence)
{
  const std::size_t n = organ.size();
  std::vector<char> seen(n, 0), tiny(n, 0);
  std::vector<std::vector<int>> pieces;
  std::vector<int> piece;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (seen[i])
      continue;
    // the whole component (marked seen), kept only when tiny
    LinkComponent(
      graph, i, [](std::size_t) { return true; }, seen, piece);
    if (piece.size() >= JudgedRegionPoints)
      continue;
    for (int j : piece)
      tiny[static_cast<std::size_t>(j)] = 1;
    pieces.push_back(piece);
  }
  if (pieces.empty())
    return 0;
  // the other points within r of each piece's points (a grid of every point; the tiny pieces' own do not vote)
  const PointGrid grid(points, radius);
  std::vector<int> near;
  std::size_t count = 0;
  for (const std::vector<int>& ids : pieces)
  {
    std::size_t leaf = 0, wood = 0;
    for (int j : ids)
    {
      grid.Within(points[static_cast<std::size_t>(j)], radius, near);
      for (int q : near)
        if (!tiny[static_cast<std::size_t>(q)])
          (organ[static_cast<std::size_t>(q)] == OrganWood ? wood : leaf) += 1;
    }
    if (wood > leaf)
      continue;
    for (int j : ids)
    {
      organ[static_cast<std::size_t>(j)] = OrganLeaf;
      confidence[static_cast<std::size_t>(j)] = 0.25;
    }
    count += ids.size();
  }
  return count;
}

/// The occupied cells of side `cell` in the leaf's principal plane, times the cell's area.
double PlaneArea(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, double cell)
{
  Eigen::Vector3d mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, ids, mean));
  const Eigen::Vector3d u = solver.eigenvectors().col(2), v = solver.eigenvectors().col(1);
  std::set<std::pair<long long, long long>> cells;
  for (int j : ids)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
    cells.emplace(
      static_cast<long long>(std::floor(d.dot(u) / cell)), static_cast<long long>(std::floor(d.dot(v) / cell)));
  }
  return static_cast<double>(cells.size()) * cell * cell;
}

/// Hops from the wood over the link graph (multi-source breadth-first, sources in index order) and, per point,
/// the wood point it is reached from (-1: not connected to the wood).
void DistanceFromWood(
  const LinkGraph& graph, const std::vector<int>& organ, std::vector<int>& hops, std::vector<int>& source)
{
  const std::size_t n = organ.size();
  hops.assign(n, std::numeric_limits<int>::max());
  source.assign(n, -1);
  std::deque<int> queue;
  for (std::size_t i = 0; i < n; ++i)
    if (organ[i] == OrganWood)
    {
      hops[i] = 0;
      source[i] = static_cast<int>(i);
      queue.push_back(static_cast<int>(i));
    }
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (hops[j] == std::numeric_limits<int>::max())
      {
        hops[j] = hops[q] + 1;
        source[j] = source[q];
        queue.push_back(static_cast<int>(j));
      }
    }
  }
}

/// The regions of the points that are not wood linked to the wood piece `ids` (-1: a point in no region).
std::set<int> RegionsAround(
  const LinkGraph& graph, const std::vector<int>& ids, const std::vector<int>& region, const std::vector<int>& organ)
{
  std::set<int> touched;
  for (int q : ids)
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(q)]; e < graph.offsets[static_cast<std::size_t>(q) + 1];
         ++e)
      if (organ[static_cast<std::size_t>(graph.neighbours[e])] != OrganWood)
        touched.insert(region[static_cast<std::size_t>(graph.neighbours[e])]);
  return touched;
}

/// Small wood pieces (connected wood points fewer than MinimumLeafPoints) touching one leaf region and no other
/// region are that leaf's margins, tips or folds (linear at the features' scale): they join the leaf.
void AbsorbWoodFragments(const LinkGraph& graph, const std::vector<RegionVerdict>& verdicts,
  const SegmentationParameters& p, std::vector<int>& region, std::vector<int>& organ)
{
  const std::size_t n = organ.size();
  std::vector<char> seen(n, 0);
  std::vector<int> piece;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (organ[seed] != OrganWood || seen[seed])
      continue;
    LinkComponent(
      graph, seed, [&](std::size_t j) { return organ[j] == OrganWood; }, seen, piece);
    const std::set<int> touched = RegionsAround(graph, piece, region, organ);
    if (piece.size() >= static_cast<std::size_t>(p.minimumLeafPoints) || touched.size() != 1 || *touched.begin() < 0 ||
      !verdicts[static_cast<std::size_t>(*touched.begin())].leaf)
      continue;
    for (int j : piece)
    {
      organ[static_cast<std::size_t>(j)] = OrganLeaf;
      region[static_cast<std::size_t>(j)] = *touched.begin();
    }
  }
}

/// A wood piece lies in the planes of the leaves it touches when the root mean square of its points' distances to the
/// nearest of their local planes, each over that plane's own spread (the leaf's points near the piece off it), is at
/// most this: no farther off the leaves than the leaves' own points.
constexpr double ContactPlaneSpread = 1.0;

/// The local planes, around the piece `ids`, of the leaf regions it touches: each region's points within 2r of the
/// piece's bounding sphere (at least JudgedRegionPoints of them), their best plane and spread off it.
struct LocalPlane
{
  int region = -1;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double spread = 0.0;
};

std::vector<LocalPlane> LocalPlanesAround(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
  const std::set<int>& touched, const std::vector<std::vector<int>>& members, double radius)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int j : ids)
    centre += points[static_cast<std::size_t>(j)];
  centre /= static_cast<double>(ids.size());
  double reach = 0.0;
  for (int j : ids)
    reach = std::max(reach, (points[static_cast<std::size_t>(j)] - centre).norm());
  reach += 2.0 * radius;
  std::vector<LocalPlane> planes;
  std::vector<int> local;
  for (int t : touched)
  {
    local.clear();
    for (int j : members[static_cast<std::size_t>(t)])
      if ((points[static_cast<std::size_t>(j)] - centre).squaredNorm() <= reach * reach)
        local.push_back(j);
    if (local.size() < JudgedRegionPoints)
      continue;
    const PartMoments m = PartMoments::Of(points, local);
    LocalPlane plane;
    plane.region = t;
    plane.mean = m.mean;
    plane.normal = m.Normal(plane.spread);
    plane.spread = std::max(plane.spread, 1e-6 * radius); // exact synthetic planes
    planes.push_back(plane);
  }
  return planes;
}

/// Wood pieces at the contact of leaves are leaf: where two leaves touch or cross, the noisy normals of the contact
/// break it into regions too small to tell from a twig's facets, and their spread carries wood over the contact. A
/// piece of wood (connected wood points) touching two leaf regions or more and no other wood, whose points lie in
/// those regions' local planes (ContactPlaneSpread), is leaf. A twig is round, off the leaves' planes by its radius.
/// The points stay out of every region, so the joins and cuts of the leaf parts see the leaves as before; returned
/// with the region whose plane is nearest to each, they join that region's instance once the instances are made
/// (ContactPointsOfParts). Judged over all pieces first, then applied (no piece's verdict depends on another's).
std::vector<std::pair<int, int>> ContactPiecesAreLeaves(const std::vector<Eigen::Vector3d>& points,
  const LinkGraph& graph, double radius, const std::vector<RegionVerdict>& verdicts, const std::vector<int>& region,
  std::vector<int>& organ)
{
  const std::size_t n = organ.size();
  std::vector<std::vector<int>> members(verdicts.size());
  for (std::size_t i = 0; i < n; ++i)
    if (organ[i] == OrganLeaf && region[i] >= 0 && verdicts[static_cast<std::size_t>(region[i])].leaf)
      members[static_cast<std::size_t>(region[i])].push_back(static_cast<int>(i));
  std::vector<char> seen(n, 0);
  std::vector<int> piece;
  std::vector<std::pair<int, int>> joins; // (point, region)
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (organ[seed] != OrganWood || seen[seed])
      continue;
    LinkComponent(
      graph, seed, [&](std::size_t j) { return organ[j] == OrganWood; }, seen, piece);
    std::set<int> touched = RegionsAround(graph, piece, region, organ);
    for (auto it = touched.begin(); it != touched.end();)
      it = *it >= 0 && verdicts[static_cast<std::size_t>(*it)].leaf ? std::next(it) : touched.erase(it);
    if (touched.size() < 2)
      continue;
    const std::vector<LocalPlane> planes = LocalPlanesAround(points, piece, touched, members, radius);
    if (planes.empty())
      continue;
    const double bound = ContactPlaneSpread * ContactPlaneSpread * static_cast<double>(piece.size());
    double sum = 0.0;
    std::vector<int> nearest(piece.size(), -1);
    for (std::size_t k = 0; k < piece.size() && sum <= bound; ++k)
    {
      const Eigen::Vector3d& x = points[static_cast<std::size_t>(piece[k])];
      double best = std::numeric_limits<double>::infinity(), relative = 0.0;
      for (const LocalPlane& plane : planes)
      {
        const double d = std::abs((x - plane.mean).dot(plane.normal));
        if (d < best)
        {
          best = d;
          relative = d / plane.spread;
          nearest[k] = plane.region;
        }
      }
      sum += relative * relative;
    }
    if (sum > bound)
      continue;
    for (std::size_t k = 0; k < piece.size(); ++k)
      joins.emplace_back(piece[k], nearest[k]);
  }
  for (const auto& join : joins)
    organ[static_cast<std::size_t>(join.first)] = OrganLeaf;
  return joins;
}

/// The contact points (ContactPiecesAreLeaves: point, region) of each leaf part: a point joins the part holding the
/// most points of its region (none when no part holds any: the region was left without an instance).
std::vector<std::vector<int>> ContactPointsOfParts(const std::vector<std::vector<int>>& parts,
  const std::vector<int>& region, const std::vector<std::pair<int, int>>& contacts)
{
  std::map<int, std::map<std::size_t, std::size_t>> count; // region -> part -> points
  for (const auto& contact : contacts)
    count[contact.second];
  for (std::size_t k = 0; k < parts.size(); ++k)
    for (int j : parts[k])
    {
      const auto it = count.find(region[static_cast<std::size_t>(j)]);
      if (it != count.end())
        ++it->second[k];
    }
  std::map<int, std::size_t> holder; // region -> the part holding most of it (the first of equals)
  for (const auto& [r, holders] : count)
    if (!holders.empty())
      holder[r] = std::max_element(holders.begin(), holders.end(), [](const auto& a, const auto& b) {
        return a.second < b.second || (a.second == b.second && a.first > b.first);
      })->first;
  std::vector<std::vector<int>> extra(parts.size());
  for (const auto& contact : contacts)
    if (const auto it = holder.find(contact.second); it != holder.end())
      extra[it->second].push_back(contact.first);
  return extra;
}

/// Wood segments: each judged wood region its own, then the connected components of the other wood points.
std::vector<int> WoodSegments(const LinkGraph& graph, const std::vector<int>& organ, const std::vector<int>& region)
{
  const std::size_t n = organ.size();
  std::vector<int> segment(n, -1), number(n, -1);
  int next = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (organ[i] != OrganWood || region[i] < 0)
      continue;
    int& r = number[static_cast<std::size_t>(region[i])];
    if (r < 0)
      r = next++;
    segment[i] = r;
  }
  std::vector<char> seen(n, 0);
  std::vector<int> piece;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (organ[seed] != OrganWood || segment[seed] >= 0)
      continue;
    LinkComponent(
      graph, seed, [&](std::size_t j) { return organ[j] == OrganWood && region[j] < 0; }, seen, piece);
    for (int j : piece)
      segment[static_cast<std::size_t>(j)] = next;
    ++next;
  }
  return segment;
}

/// A leaf region touching the wood at several places is several leaves touching each other: its points near the
/// wood (within ContactHops links) fall in connected groups (those closer than `reach` merged: one base broken by a
/// gap), and each point goes to the group it is nearest to along the region (breadth-first from every group at
/// once). One group or none: the region as it is.
/// Contact groups whose centres are closer than `reach` (single linkage) are one base: a leaf's base broken by a gap.
std::vector<std::vector<int>> MergeNearGroups(
  const std::vector<Eigen::Vector3d>& points, std::vector<std::vector<int>> groups, double reach)
{
  bool merged = true;
  while (merged && groups.size() > 1)
  {
    merged = false;
    std::vector<Eigen::Vector3d> centres;
    for (const std::vector<int>& g : groups)
    {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int j : g)
        c += points[static_cast<std::size_t>(j)];
      centres.push_back(c / static_cast<double>(g.size()));
    }
    for (std::size_t a = 0; a < groups.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < groups.size() && !merged; ++b)
        if ((centres[a] - centres[b]).norm() < reach)
        {
          groups[a].insert(groups[a].end(), groups[b].begin(), groups[b].end());
          groups.erase(groups.begin() + static_cast<std::ptrdiff_t>(b));
          merged = true;
        }
  }
  return groups;
}

std::vector<std::vector<int>> SplitAtBases(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  const std::vector<int>& ids, const std::vector<int>& hops, double reach, std::vector<int>& owner)
{
  constexpr int ContactHops = 2;
  constexpr std::size_t ContactPoints = 3; // fewer: a stray touch, not a leaf's base
  for (int j : ids)
    owner[static_cast<std::size_t>(j)] = hops[static_cast<std::size_t>(j)] <= ContactHops ? -2 : -3;
  std::deque<int> queue;
  std::vector<std::vector<int>> groups;
  for (int seed : ids)
  {
    if (owner[static_cast<std::size_t>(seed)] != -2)
      continue;
    std::vector<int> group = { seed };
    owner[static_cast<std::size_t>(seed)] = -4;
    for (std::size_t k = 0; k < group.size(); ++k)
    {
      const auto q = static_cast<std::size_t>(group[k]);
      for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
        if (owner[static_cast<std::size_t>(graph.neighbours[e])] == -2)
        {
          owner[static_cast<std::size_t>(graph.neighbours[e])] = -4;
          group.push_back(graph.neighbours[e]);
        }
    }
    if (group.size() >= ContactPoints)
      groups.push_back(std::move(group));
  }
  groups = MergeNearGroups(points, std::move(groups), reach);
  std::vector<std::vector<int>> parts;
  if (groups.size() < 2)
  {
    for (int j : ids)
      owner[static_cast<std::size_t>(j)] = -1;
    parts.push_back(ids);
    return parts;
  }
  for (int j : ids)
    owner[static_cast<std::size_t>(j)] = -3; // in the region, not reached yet
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (int j : groups[g])
    {
      owner[static_cast<std::size_t>(j)] = static_cast<int>(g);
      queue.push_back(j);
    }
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (owner[j] == -3)
      {
        owner[j] = owner[q];
        queue.push_back(static_cast<int>(j));
      }
    }
  }
  parts.assign(groups.size() + 1, {});
  for (int j : ids) // points the groups do not reach (cut off inside the region) stay together
    parts[owner[static_cast<std::size_t>(j)] >= 0 ? static_cast<std::size_t>(owner[static_cast<std::size_t>(j)])
                                                  : groups.size()]
      .push_back(j);
  for (int j : ids)
    owner[static_cast<std::size_t>(j)] = -1;
  parts.erase(
    std::remove_if(parts.begin(), parts.end(), [](const std::vector<int>& x) { return x.empty(); }), parts.end());
  std::sort(parts.begin(), parts.end()); // by lowest point index: deterministic numbering
  return parts;
}

/// A leaf part under this fraction of the plant's median leaf part is a piece of a leaf (JoinPieces).
constexpr double PieceFraction = 0.25;
/// A small part spread over at least this fraction of the plant's typical leaf part, along and across, is a leaf
/// seen sparsely, not a piece (SpreadLikeALeaf).
constexpr double LeafSpreadFraction = 1.0 / 3.0;

/// Whether two touching leaf parts continue one sheet: their planes within `cosine` of each other (NormalAngle) and
/// the points of both together off their common plane by under `thickness` (the features' radius). On the
/// simulated tree (four positions) 73 of 80 touching pairs cut from one leaf pass, 3 of 231 pairs of two leaves do:
/// parts of one leaf cut apart by a crease or a gap in the scan lie in one plane; leaves that touch cross at an
/// angle (45 degrees typically) or lie one on the other.
bool OneSheet(const PartMoments& a, const PartMoments& b, double cosine, double thickness)
{
  double spreadA = 0.0, spreadB = 0.0, spread = 0.0;
  const Eigen::Vector3d na = a.Normal(spreadA), nb = b.Normal(spreadB);
  a.Merged(b).Normal(spread);
  return std::abs(na.dot(nb)) >= cosine && spread < thickness;
}

/// Whether the points of part `piece` lie in the best plane of part `leaf`: their root mean square distance off it
/// under `thickness` (from the moments alone; a narrow piece's own plane is ill-defined about its length).
bool InPlaneOf(const PartMoments& piece, const PartMoments& leaf, double thickness)
{
  double spread = 0.0;
  const Eigen::Vector3d n = leaf.Normal(spread);
  const double offset = (piece.mean - leaf.mean).dot(n);
  return offset * offset + n.dot(piece.scatter * n) / piece.count < thickness * thickness;
}

/// Whether a small part `k` may join the touching part `part` as a piece of it: the crease or gap that cut it off
/// runs across it (the seam between them not short, ShortSeamBetween), or it lies in that part's plane, or the two
/// continue one sheet. A part that touches another over a short seam at an angle is a leaf of its own, seen small.
bool PieceOf(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const std::vector<int>& partOf,
  const std::vector<std::vector<int>>& parts, const std::vector<PartMoments>& moments, std::size_t k, int part,
  double cosine, double thickness)
{
  const auto p = static_cast<std::size_t>(part);
  return InPlaneOf(moments[k], moments[p], thickness) || OneSheet(moments[k], moments[p], cosine, thickness) ||
    !ShortSeamBetween(points, graph, partOf, static_cast<int>(k), part, parts[k], parts[p]);
}

/// A part's spread in its plane: the root mean square of its points along its main axis and across it.
Eigen::Vector2d InPlaneSpread(const PartMoments& m)
{
  const Eigen::Vector3d l =
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m.scatter / m.count, Eigen::EigenvaluesOnly).eigenvalues();
  return { std::sqrt(std::max(0.0, l[2])), std::sqrt(std::max(0.0, l[1])) };
}

/// The plant's typical leaf part's spread in its plane (InPlaneSpread): the medians, along and across, over the flat
/// parts (off their plane by under `thickness`) of at least `small` points; zero when there is none.
Eigen::Vector2d TypicalSpread(
  const std::vector<std::vector<int>>& parts, const std::vector<PartMoments>& moments, double small, double thickness)
{
  std::vector<double> along, across;
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    double spread = 0.0;
    if (static_cast<double>(parts[k].size()) < small || parts[k].empty())
      continue;
    moments[k].Normal(spread);
    if (spread >= thickness)
      continue;
    const Eigen::Vector2d s = InPlaneSpread(moments[k]);
    along.push_back(s[0]);
    across.push_back(s[1]);
  }
  if (along.empty())
    return Eigen::Vector2d::Zero();
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  return { median(along), median(across) };
}

/// A part with few points may still be a whole leaf: seen at a grazing angle, a leaf's points are fewer, not its
/// size. Flat (off its plane by under `thickness`) and spread in its plane over at least LeafSpreadFraction of the
/// plant's typical part (`typical`, TypicalSpread) along and across, it is no tip or rim cut off by a crease (those
/// are small in extent or narrow).
bool SpreadLikeALeaf(const PartMoments& m, const Eigen::Vector2d& typical, double thickness)
{
  double spread = 0.0;
  m.Normal(spread);
  const Eigen::Vector2d s = InPlaneSpread(m);
  return typical[0] > 0.0 && spread < thickness && s[0] >= LeafSpreadFraction * typical[0] &&
    s[1] >= LeafSpreadFraction * typical[1];
}

/// Pieces of one leaf join it. A leaf part touching other leaf parts over the link graph joins the one it shares the
/// most links with, smallest part first (so a chain of pieces gathers into its leaf), in two passes:
///  - parts much smaller than the plant's typical leaf (under `fraction` of the median part of at least
///    MinimumLeafPoints points: a tip or rim cut off by a fold or crease) join the part they touch most among those
///    they are a piece of (PieceOf). One that touches parts but is a piece of none is a leaf seen small beside
///    another (its base hidden or in another part): it joins nothing and gets no instance (its points stay leaf,
///    LeafId -1), since alone it is mostly a fragment of a leaf that the instances do not match;
///  - then larger parts join only a touching part that continues the same sheet (OneSheet): a leaf cut in two by a
///    crease, a vein, a line of missing points or a turn of the normals, whose halves are each as large as a leaf,
///    unless their seam says two leaves (ShortSeamBetween: two leaves 12-23 degrees apart, cut at their seam, are
///    one sheet within NormalAngle and were joined again).
/// Parts touching no other part (a leaf seen in parts behind another) stay apart. The small parts that are a piece
/// of none are moved to `setAside` (SetAsideJoinAcrossGaps may still join them to their leaf across a gap).
void JoinPieces(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, double fraction,
  int minimumLeafPoints, double cosine, double thickness, std::vector<std::vector<int>>& parts,
  std::vector<std::vector<int>>& setAside)
{
  std::vector<std::size_t> sizes;
  for (const std::vector<int>& ids : parts)
    if (ids.size() >= static_cast<std::size_t>(minimumLeafPoints))
      sizes.push_back(ids.size());
  if (sizes.empty())
    return;
  std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2), sizes.end());
  const double small = fraction * static_cast<double>(sizes[sizes.size() / 2]);
  std::size_t n = 0;
  for (const std::vector<int>& ids : parts)
    for (int j : ids)
      n = std::max(n, static_cast<std::size_t>(j) + 1);
  std::vector<int> partOf(n, -1);
  std::vector<PartMoments> moments(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    for (int j : parts[k])
      partOf[static_cast<std::size_t>(j)] = static_cast<int>(k);
    moments[k] = PartMoments::Of(points, parts[k]);
  }
  std::vector<std::size_t> order(parts.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = k;
  std::stable_sort(
    order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return parts[a].size() < parts[b].size(); });
  const Eigen::Vector2d typical = TypicalSpread(parts, moments, small, thickness);
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k : order)
    {
      if (parts[k].empty() || (pass == 0) != (static_cast<double>(parts[k].size()) < small))
        continue;
      std::map<int, int> links; // per neighbouring part: the links to it
      for (int j : parts[k])
        for (std::size_t e = graph.offsets[static_cast<std::size_t>(j)];
             e < graph.offsets[static_cast<std::size_t>(j) + 1]; ++e)
        {
          const auto q = static_cast<std::size_t>(graph.neighbours[e]);
          if (q < n && partOf[q] >= 0 && partOf[q] != static_cast<int>(k))
            ++links[partOf[q]];
        }
      int best = -1; // the most links; ties to the lowest part (deterministic)
      for (const auto& [part, count] : links)
        if ((best < 0 || count > links[best]) &&
          (pass == 0 ? PieceOf(points, graph, partOf, parts, moments, k, part, cosine, thickness)
                     : OneSheet(moments[k], moments[static_cast<std::size_t>(part)], cosine, thickness) &&
                !ShortSeamBetween(points, graph, partOf, static_cast<int>(k), part, parts[k],
                  parts[static_cast<std::size_t>(part)], false)))
          best = part;
      if (best < 0 && pass == 0 && !links.empty() && !SpreadLikeALeaf(moments[k], typical, thickness))
      { // a small leaf beside others: no instance
        for (int j : parts[k])
          partOf[static_cast<std::size_t>(j)] = -1;
        setAside.push_back(std::move(parts[k]));
        parts[k].clear();
      }
      if (best < 0)
        continue;
      std::vector<int>& into = parts[static_cast<std::size_t>(best)];
      for (int j : parts[k])
        partOf[static_cast<std::size_t>(j)] = best;
      into.insert(into.end(), parts[k].begin(), parts[k].end());
      std::sort(into.begin(), into.end());
      moments[static_cast<std::size_t>(best)] = moments[static_cast<std::size_t>(best)].Merged(moments[k]);
      parts[k].clear();
    }
  parts.erase(
    std::remove_if(parts.begin(), parts.end(), [](const std::vector<int>& x) { return x.empty(); }), parts.end());
}

/// Pieces of one leaf seen apart (JoinAcrossGaps) are at most this many features' radii r apart: the reach at which
/// a region's contacts with the wood count as one base (SplitAtBases).
constexpr double GapRadii = 4.0;
/// ... and lie in one plane: their planes within half of NormalAngle of each other (the features' normals are good
/// to about 10 degrees) and the points of both off their common plane by under a quarter of r (r is at least 12
/// times the range noise).
constexpr double GapAngleFraction = 0.5;
constexpr double GapThickness = 0.25;
/// Pieces farther apart than GapRadii r may span this many r more than a leaf: a piece carries the points its
/// region took in at a contact (a twig's surface at the leaf's base, a neighbour's margin), which lie up to the
/// features' radius r beyond the leaf's own end. On the stored scans of the accuracy benchmark a whole leaf's span
/// is 0.96-1.01 of LeafLength on the plants of one leaf size, and the pieces of one leaf that did not join spanned
/// 1.02-1.04 of it, 0.05 beyond the leaf's own points (25 twig points at one base, 2 of a neighbour at another).
constexpr double GapContactRadii = 1.0;

/// The smallest distance between a point of one part and one of another when under `reach`, else infinity, for
/// parts that do not change while they are asked: the larger part of a pair is indexed in a grid of side `reach`, each
/// part's grid built the first time it is needed and kept (a big leaf is paired with every row and piece near it, and
/// indexing it again for each pair cost more than the searches).
class PartGaps
{
public:
  PartGaps(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& parts, double reach)
    : Points(points)
    , Parts(parts)
    , Reach(reach)
    , Grids(parts.size())
  {
  }

  double Between(std::size_t a, std::size_t b)
  {
    const std::size_t query = this->Parts[a].size() < this->Parts[b].size() ? a : b;
    const std::size_t indexed = query == a ? b : a;
    if (!this->Grids[indexed])
    {
      std::vector<Eigen::Vector3d> cloud;
      cloud.reserve(this->Parts[indexed].size());
      for (int j : this->Parts[indexed])
        cloud.push_back(this->Points[static_cast<std::size_t>(j)]);
      this->Grids[indexed] = std::make_unique<PointGrid>(cloud, this->Reach);
    }
    const PointGrid& grid = *this->Grids[indexed];
    double best = std::numeric_limits<double>::infinity();
    for (int j : this->Parts[query])
    {
      const auto nearest = grid.Nearest(this->Points[static_cast<std::size_t>(j)], 1, -1, std::min(best, this->Reach));
      if (!nearest.empty())
        best = std::min(best, std::sqrt(nearest[0].first));
    }
    return best;
  }

private:
  const std::vector<Eigen::Vector3d>& Points;
  const std::vector<std::vector<int>>& Parts;
  double Reach;
  std::vector<std::unique_ptr<PointGrid>> Grids;
};

/// The extent of points[ids] along the main axis of their moments `m` (the largest spread).
double SpanAlong(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const PartMoments& m)
{
  return ExtentAlong(
    points, ids, m.mean, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m.scatter / m.count).eigenvectors().col(2));
}

/// The pieces of one leaf together span no more than a leaf: this quantile of the spans of the flat parts (off
/// their plane by under `thickness`; a flat part is one leaf or a piece of one, two leaves grown into one part are
/// not flat), the longest leaves but a few, plus `thickness` (a quarter of r: at least a spacing and three times the
/// range noise, which move a span's two ends).
constexpr double LeafSpanQuantile = 0.9;
/// The longest leaf on a plant, over its leaf length (the quantile above): pieces of one leaf never span more, even
/// on a plant of leaves of several sizes; two whole leaves in one plane that had joined there spanned 1.6-1.9 leaf
/// lengths on the simulated tree.
constexpr double NearSpanFactor = 1.25;

/// The extent of parts a and b together along the main axis of their merged moments `both`.
double JointSpan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& parts, std::size_t a,
  std::size_t b, const PartMoments& both)
{
  std::vector<int> ids = parts[a];
  ids.insert(ids.end(), parts[b].begin(), parts[b].end());
  return SpanAlong(points, ids, both);
}

/// A leaf's length on this plant: LeafSpanQuantile of the spans of the flat parts among `big` (off their plane by
/// under `thickness`); 0 when none is flat.
double LeafLength(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& parts,
  const std::vector<std::size_t>& big, const std::vector<PartMoments>& moments, double thickness)
{
  std::vector<double> spans;
  for (std::size_t k : big)
  {
    double spread = 0.0;
    moments[k].Normal(spread);
    if (spread < thickness)
      spans.push_back(SpanAlong(points, parts[k], moments[k]));
  }
  if (spans.empty())
    return 0.0;
  const auto at = static_cast<std::ptrdiff_t>(LeafSpanQuantile * static_cast<double>(spans.size() - 1));
  std::nth_element(spans.begin(), spans.begin() + at, spans.end());
  return spans[static_cast<std::size_t>(at)];
}

/// The longest a part of one leaf can be, from the plant's LeafLength `length` (0 when no part is flat: then no
/// bound, infinity): NearSpanFactor times the length plus `thickness`.
double LongestLeafSpan(double length, double thickness)
{
  return length > 0.0 ? NearSpanFactor * (length + thickness) : std::numeric_limits<double>::infinity();
}

/// LongestLeafSpan over the parts of at least `minimumLeafPoints`; 0 when no part is flat (no bound).
double LongestLeaf(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& parts,
  int minimumLeafPoints, double thickness)
{
  std::vector<std::size_t> big;
  std::vector<PartMoments> moments(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].size() >= static_cast<std::size_t>(minimumLeafPoints))
    {
      big.push_back(k);
      moments[k] = PartMoments::Of(points, parts[k]);
    }
  const double length = LeafLength(points, parts, big, moments, thickness);
  return length > 0.0 ? LongestLeafSpan(length, thickness) : 0.0;
}

/// The leaf points cut off from every region (IsolatedPiecesByTheirSurroundings: their whole component of the link
/// graph has under JudgedRegionPoints points), one part per component, appended to `parts`: a leaf seen edge on in
/// scattered points or short rows, which GatherRows may join to the rest of its leaf.
void IsolatedLeafPieces(const LinkGraph& graph, const std::vector<int>& region, const std::vector<int>& organ,
  std::vector<std::vector<int>>& parts)
{
  const std::size_t n = region.size();
  std::vector<char> seen(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (seen[i] || region[i] >= 0 || organ[i] != OrganLeaf)
      continue;
    std::vector<int> piece;
    LinkComponent(
      graph, i, [&](std::size_t j) { return region[j] < 0 && organ[j] == OrganLeaf; }, seen, piece);
    std::sort(piece.begin(), piece.end());
    parts.push_back(std::move(piece));
  }
}

/// Whether a part gets no leaf instance: under `minimumLeafPoints` points, or made only of flat strips (narrower than
/// 2r or a long strip) and points cut off from every region (region -1): no leaf shape to fit. Such points join a
/// leaf when they are its rows (GatherRows); alone they stay leaf without LeafId.
bool NoLeafShape(const std::vector<int>& region, const std::vector<RegionVerdict>& verdicts,
  const std::vector<int>& ids, int minimumLeafPoints)
{
  return ids.size() < static_cast<std::size_t>(minimumLeafPoints) || std::all_of(ids.begin(), ids.end(), [&](int j) {
    const int r = region[static_cast<std::size_t>(j)];
    return r < 0 || verdicts[static_cast<std::size_t>(r)].flatStrip;
  });
}

/// Leaf parts joined pairwise (union-find): a joined pair's root is its lower index, which takes the other's points
/// (kept sorted); the other is left empty, for the caller to drop once every join is done.
struct PartRoots
{
  DisjointSets<std::size_t> sets;

  explicit PartRoots(std::size_t n)
    : sets(n)
  {
  }

  std::size_t Find(std::size_t k) { return this->sets.Find(k); }

  /// Joins the parts of roots a and b; returns (the root kept, the root emptied).
  std::pair<std::size_t, std::size_t> Join(std::size_t a, std::size_t b, std::vector<std::vector<int>>& parts)
  {
    const std::size_t into = std::min(a, b), from = std::max(a, b);
    this->sets.JoinRoots(into, from);
    parts[into].insert(parts[into].end(), parts[from].begin(), parts[from].end());
    std::sort(parts[into].begin(), parts[into].end());
    parts[from].clear();
    return { into, from };
  }
};

/// The plane of a group of rows (moments `m`, the sum `evidence` of its points' SurfaceEvidence) and the spread of
/// its points off it (root mean square): the best plane of the moments, unless the points lie on a line (their
/// spread across its main axis under `thickness`: one row, or two points), which every plane through the line fits.
/// Then it is the plane through the line that the features agree with most: the row directions measured around the
/// points (a point of the next row seen from this one, the line crossing the rows, spans the leaf's plane with them).
Eigen::Vector3d PlaneOfRows(const PartMoments& m, const Eigen::Matrix3d& evidence, double thickness, double& spread)
{
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m.scatter / m.count);
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
  if (std::sqrt(l[1]) >= thickness)
  {
    spread = std::sqrt(l[0]);
    return solver.eigenvectors().col(0);
  }
  const Eigen::Vector3d line = solver.eigenvectors().col(2);
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - line * line.transpose();
  const Eigen::Vector3d n =
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(across * evidence * across).eigenvectors().col(2);
  spread = std::sqrt(std::max(0.0, n.dot(m.scatter * n) / m.count));
  return n;
}

/// Rows of a leaf seen at a grazing angle: the scan's rows on it lie farther apart than the links, so each row grows
/// into its own region (a strip one row wide: leaf, no instance) or is cut off from every region, and the leaf's
/// instance holds only the piece seen densely, or the leaf none. The features, whose radius r spans several rows, see
/// one surface: their normals are the leaf's. Parts with no leaf shape (NoLeafShape) join a part within 2r (the
/// features' outer neighbourhood) when the two lie in one plane that the features of both agree with (mean squared
/// cosine of the normals to it, or of the sine of a row's direction where the neighbourhood is a line and has no
/// normal, SurfaceEvidence, at least `cosine` squared: two parallel rows, or two segments that meet, always lie in
/// some plane; the features tell whether it is the leaf's; PlaneOfRows), the points of both off it by under
/// `thickness`, and together
/// they span no more than a leaf (LeafLength, as in JoinAcrossGaps). Nearest first, each join checked again on the
/// parts already joined; rows join rows or one leaf part, never two leaf parts through rows between them. Rows that
/// reach no leaf part are judged afterwards as a leaf seen only in rows (LeavesSeenInRows).
void GatherRows(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const std::vector<int>& region,
  const std::vector<RegionVerdict>& verdicts, const SegmentationParameters& p, double cosine, double thickness,
  std::vector<std::vector<int>>& parts)
{
  const double reach = 2.0 * f.radius;
  std::vector<std::size_t> rows, big;
  std::vector<char> whole(parts.size(), 0); // a part with a leaf's shape (or one that has joined such a part)
  std::vector<PartMoments> moments(parts.size());
  std::vector<Eigen::Matrix3d> normals(parts.size(), Eigen::Matrix3d::Zero()); // sums of SurfaceEvidence
  std::vector<double> measured(parts.size(), 0.0);                             // the points measured
  std::vector<Eigen::Vector3d> low(parts.size()), high(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    if (parts[k].empty())
      continue;
    moments[k] = PartMoments::Of(points, parts[k]);
    whole[k] = !NoLeafShape(region, verdicts, parts[k], p.minimumLeafPoints);
    (whole[k] ? big : rows).push_back(k);
    low[k] = high[k] = points[static_cast<std::size_t>(parts[k].front())];
    for (int j : parts[k])
    {
      double weight = 0.0;
      normals[k] += SurfaceEvidence(f, static_cast<std::size_t>(j), weight);
      measured[k] += weight;
      low[k] = low[k].cwiseMin(points[static_cast<std::size_t>(j)]);
      high[k] = high[k].cwiseMax(points[static_cast<std::size_t>(j)]);
    }
  }
  const double leafLength = LeafLength(points, parts, big, moments, thickness) + thickness;
  const auto together = [&](std::size_t a, std::size_t b) {
    const PartMoments m = moments[a].Merged(moments[b]);
    double spread = 0.0;
    const Eigen::Vector3d n = PlaneOfRows(m, normals[a] + normals[b], thickness, spread);
    const double count = measured[a] + measured[b];
    if (spread >= thickness || count == 0.0 || n.dot((normals[a] + normals[b]) * n) < cosine * cosine * count)
      return false;
    return JointSpan(points, parts, a, b, m) <= leafLength;
  };
  std::vector<std::size_t> order = rows; // swept along x: the pairs whose boxes come within reach
  order.insert(order.end(), big.begin(), big.end());
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return low[a].x() < low[b].x(); });
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs; // (gap, a, b): a row and a row or a leaf
  PartGaps gaps(points, parts, reach);
  for (std::size_t x = 0; x < order.size(); ++x)
    for (std::size_t y = x + 1; y < order.size() && low[order[y]].x() <= high[order[x]].x() + reach; ++y)
    {
      const std::size_t a = order[x], b = order[y];
      if ((whole[a] && whole[b]) || (low[a].array() - reach > high[b].array()).any() ||
        (low[b].array() - reach > high[a].array()).any())
        continue;
      if (const double gap = gaps.Between(a, b); gap < reach && together(a, b))
        pairs.emplace_back(gap, a, b);
    }
  std::sort(pairs.begin(), pairs.end());
  PartRoots roots(parts.size());
  for (const auto& [gap, a, b] : pairs)
  {
    const std::size_t ra = roots.Find(a), rb = roots.Find(b);
    // rows join each other or one leaf; two leaves never join through rows between them
    if (ra == rb || (whole[ra] && whole[rb]) || !together(ra, rb))
      continue;
    const auto [into, from] = roots.Join(ra, rb, parts);
    whole[into] = whole[into] || whole[from];
    moments[into] = moments[into].Merged(moments[from]);
    normals[into] += normals[from];
    measured[into] += measured[from];
  }
  parts.erase(
    std::remove_if(parts.begin(), parts.end(), [](const std::vector<int>& x) { return x.empty(); }), parts.end());
}

/// A leaf part may carry a few points of what it touches, grown into it at a contact (a neighbouring blade's margin or
/// its twig's side, off its plane by up to several r): the plane test of two pieces across a gap may leave out up to
/// this share of each part's points, those off the part's own plane by r or more (CoreMoments).
constexpr double ForeignShare = 0.05;

/// The moments of the points of a part (`ids`, moments `all`) within `apart` of its plane, the plane refitted to them
/// twice: its own sheet without the few points of a neighbour it carries. `all` when more than ForeignShare of its
/// points lie that far off (the part is no flat sheet: it keeps its spread).
PartMoments CoreMoments(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const PartMoments& all, double apart)
{
  PartMoments m = all;
  std::vector<int> kept;
  for (int round = 0; round < 2; ++round)
  {
    double spread = 0.0;
    const Eigen::Vector3d n = m.Normal(spread);
    kept.clear();
    for (int j : ids)
      if (std::abs((points[static_cast<std::size_t>(j)] - m.mean).dot(n)) < apart)
        kept.push_back(j);
    if (kept.size() < 3 ||
      static_cast<double>(ids.size() - kept.size()) > ForeignShare * static_cast<double>(ids.size()))
      return all;
    m = PartMoments::Of(points, kept);
  }
  return m;
}

/// Pieces of one leaf that do not touch: a leaf seen in pieces behind another leaf or a branch, cut by a line of
/// missing points wider than the links. Two leaf parts (each of at least MinimumLeafPoints points) join when they
/// lie in one plane (planes within GapAngleFraction NormalAngle, both off their common plane by under GapThickness
/// r) and come within GapRadii r of each other, or, farther apart, together span no more than a leaf (LeafLength, plus
/// GapContactRadii r for the points a piece took in at a contact): the shadow that cuts a leaf is as wide as the leaf
/// or twig in front, whatever the spacing and the noise. Pairs join nearest first (those farther than GapRadii r by
/// their joint span), each join checked again on the parts already joined, so a chain of pieces cannot drift from one
/// leaf plane to the next nor grow past a leaf's length.
/// On the simulated shrub and tree (12 scans), of the instance pairs within 4r, 158 pairs of pieces of one leaf pass
/// the plane test and no pair of two leaves does: leaves that lie side by side are tilted against each other or
/// offset off one plane. Farther apart, on the tree from two positions at 0.1 % noise, 16 pairs of pieces of one
/// leaf lie in one plane 4.3 to 12.4 r apart spanning 0.79-1.33 together (the leaves' own spans: up to 1.35), and
/// 11 pairs of two leaves in one plane span 1.54 or more. Pairs within GapRadii r span no more than the longest
/// leaf either (NearSpanFactor times the leaf length): two whole leaves in one plane, touching or a few spacings
/// apart (opposite leaves of one node, or a leaf and the next one along its twig), joined there and spanned 2.2-2.5
/// on the tree from four positions at 1 % noise. `withoutForeign`: each part's plane is measured without the few
/// points of a neighbour it may carry (CoreMoments).
void JoinAcrossGaps(const std::vector<Eigen::Vector3d>& points, double radius, double cosine, int minimumLeafPoints,
  std::vector<std::vector<int>>& parts, bool withoutForeign = false)
{
  const double reach = GapRadii * radius, thickness = GapThickness * radius;
  std::vector<std::size_t> big;
  std::vector<PartMoments> moments(parts.size());
  std::vector<PartMoments> core(parts.size()); // the moments the plane test uses
  std::vector<Eigen::Vector3d> low(parts.size()), high(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    if (parts[k].size() < static_cast<std::size_t>(minimumLeafPoints))
      continue;
    big.push_back(k);
    moments[k] = PartMoments::Of(points, parts[k]);
    core[k] = withoutForeign ? CoreMoments(points, parts[k], moments[k], radius) : moments[k];
    low[k] = high[k] = points[static_cast<std::size_t>(parts[k].front())];
    for (int j : parts[k])
    {
      low[k] = low[k].cwiseMin(points[static_cast<std::size_t>(j)]);
      high[k] = high[k].cwiseMax(points[static_cast<std::size_t>(j)]);
    }
  }
  const double length = LeafLength(points, parts, big, moments, thickness);
  const double leafLength = length + thickness + GapContactRadii * radius;
  const double nearLength = LongestLeafSpan(length, thickness);
  const double search = std::max(reach, leafLength);
  const auto jointSpan = [&](std::size_t a, std::size_t b) {
    return JointSpan(points, parts, a, b, moments[a].Merged(moments[b]));
  };
  // (0 near / 1 far, gap or joint span, a, b), a < b
  std::vector<std::tuple<int, double, std::size_t, std::size_t>> pairs;
  PartGaps gaps(points, parts, reach);
  for (std::size_t x = 0; x < big.size(); ++x)
    for (std::size_t y = x + 1; y < big.size(); ++y)
    {
      const std::size_t a = big[x], b = big[y];
      if ((low[a].array() - search > high[b].array()).any() || (low[b].array() - search > high[a].array()).any() ||
        !OneSheet(core[a], core[b], cosine, thickness))
        continue;
      const double gap = gaps.Between(a, b);
      if (gap < reach)
      {
        if (jointSpan(a, b) <= nearLength)
          pairs.emplace_back(0, gap, a, b);
      }
      else if (const double span = jointSpan(a, b); span <= leafLength)
        pairs.emplace_back(1, span, a, b);
    }
  std::sort(pairs.begin(), pairs.end());
  PartRoots roots(parts.size());
  for (const auto& [far, gap, a, b] : pairs)
  {
    const std::size_t ra = roots.Find(a), rb = roots.Find(b);
    if (ra == rb || !OneSheet(core[ra], core[rb], cosine, thickness) ||
      jointSpan(ra, rb) > (far == 1 ? leafLength : nearLength))
      continue;
    const auto [into, from] = roots.Join(ra, rb, parts);
    moments[into] = moments[into].Merged(moments[from]);
    core[into] = core[into].Merged(core[from]);
  }
  parts.erase(
    std::remove_if(parts.begin(), parts.end(), [](const std::vector<int>& x) { return x.empty(); }), parts.end());
}

/// JoinAcrossGaps over `parts` and the small parts JoinPieces set aside (a small leaf beside others, a piece of none
/// of the parts it touches): one that joins a part across a gap is a piece of that part's leaf, cut off from it by a
/// crease or a contact with another leaf and linked to that other leaf only, or not at all; the others stay out of
/// every part (leaf, no LeafId), as do set-aside parts joined only to each other. `setAside` is emptied.
void SetAsideJoinAcrossGaps(const std::vector<Eigen::Vector3d>& points, double radius, double cosine,
  int minimumLeafPoints, std::vector<std::vector<int>>& parts, std::vector<std::vector<int>>& setAside)
{
  if (setAside.empty())
  {
    JoinAcrossGaps(points, radius, cosine, minimumLeafPoints, parts);
    return;
  }
  std::vector<char> aside(points.size(), 0);
  for (std::vector<int>& ids : setAside)
  {
    for (int j : ids)
      aside[static_cast<std::size_t>(j)] = 1;
    parts.push_back(std::move(ids));
  }
  setAside.clear();
  JoinAcrossGaps(points, radius, cosine, minimumLeafPoints, parts);
  parts.erase(std::remove_if(parts.begin(), parts.end(),
                [&](const std::vector<int>& ids) {
                  return std::all_of(ids.begin(), ids.end(), [&](int j) { return aside[static_cast<std::size_t>(j)]; });
                }),
    parts.end());
}

/// Whether the row group `ids` (moments `m`) is as wide across its rows as a leaf region must be (2r, the features'
/// neighbourhood) and the features agree with its plane (SurfaceEvidence: mean at least `cosine` squared):
/// narrower, or with normals across its plane, it is a twig's facets or a strip of wood seen as leaf.
bool RowsAsWideAsALeaf(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const std::vector<int>& ids,
  const PartMoments& m, double cosine)
{
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m.scatter / m.count);
  const Eigen::Vector3d n = solver.eigenvectors().col(0), across = solver.eigenvectors().col(1);
  double low = std::numeric_limits<double>::infinity(), high = -low, agree = 0.0, count = 0.0;
  for (int j : ids)
  {
    low = std::min(low, (points[static_cast<std::size_t>(j)] - m.mean).dot(across));
    high = std::max(high, (points[static_cast<std::size_t>(j)] - m.mean).dot(across));
    double weight = 0.0;
    agree += n.dot(SurfaceEvidence(f, static_cast<std::size_t>(j), weight) * n);
    count += weight;
  }
  return high - low >= 2.0 * f.radius && count > 0.0 && agree >= cosine * cosine * count;
}

/// A group's rows are not asked to lie at one spacing. The rows' spacing on a leaf is the scanner's step over the
/// sine of the angle it meets the leaf at, which turns across a leaf; where two positions see a part of the leaf
/// their rows interleave there and not beyond; and single points cut off between rows count as rows. On the 18
/// simulated scans, the groups refused only for the median gap on the two sides of the widest differing by over 1.5
/// times were 11 whole leaves and 2 pieces. Two leaves end to end, which that test was for, cannot lie in one group
/// as large as a leaf: GatherRows joins no more than a leaf's length, and a narrower band fails the width test.
/// The group's outline closes: the outermost row at an end is at most this fraction of the longest row's length, as
/// a leaf's rows shorten towards its ends (an ellipse's outermost of four rows: 0.68 of the longest); half a leaf
/// cut across its rows keeps a full row at the cut, and closes at its other end.
constexpr double RowEndFraction = 0.7;

/// The rows of a group (its points `ids` joined from the pieces `pieceOf` names: strips one row wide, cut-off
/// pieces) along the direction `along` in its plane (normal `n`): per row its position across the rows and its
/// extent along them, sorted across. Pieces whose positions across lie within `merge` (half a link: rows closer than
/// the links are one region) are one row.
std::vector<std::array<double, 3>> RowsAcross(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
  const std::vector<int>& pieceOf, const Eigen::Vector3d& centre, const Eigen::Vector3d& along,
  const Eigen::Vector3d& n, double merge)
{
  const Eigen::Vector3d across = n.cross(along).normalized();
  std::map<int, std::array<double, 4>> pieces; // piece -> (sum across, count, low along, high along)
  for (int j : ids)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - centre;
    const double a = d.dot(along);
    auto [it, fresh] = pieces.try_emplace(pieceOf[static_cast<std::size_t>(j)], std::array<double, 4>{ 0, 0, a, a });
    it->second[0] += d.dot(across);
    it->second[1] += 1.0;
    it->second[2] = std::min(it->second[2], a);
    it->second[3] = std::max(it->second[3], a);
  }
  std::vector<std::array<double, 3>> byAcross; // (across, low, high)
  for (const auto& [piece, q] : pieces)
    byAcross.push_back({ q[0] / q[1], q[2], q[3] });
  std::sort(byAcross.begin(), byAcross.end());
  std::vector<std::array<double, 3>> rows;
  for (const auto& q : byAcross)
    if (!rows.empty() && q[0] - rows.back()[0] < merge)
    {
      rows.back()[1] = std::min(rows.back()[1], q[1]);
      rows.back()[2] = std::max(rows.back()[2], q[2]);
    }
    else
      rows.push_back(q);
  return rows;
}

/// Whether points whose scatter has the ascending `eigenvalues` are a line by their shape: their second spread under
/// LineSpread of their first.
bool LineShaped(const Eigen::Vector3d& eigenvalues)
{
  return eigenvalues[1] < LineSpread * LineSpread * eigenvalues[2];
}

/// The row directions the features measured at the points of `ids` whose neighbourhood is a line (IsRow), each of
/// weight 1, where the group's own points within r of the point are a line by their own shape too (the second
/// spread under LineSpread of the first, as a part's axis must be): IsRow asks a width under LineSpread r, which three
/// or four points of a row's end or of a leaf's margin closer together than r also have, their main axis any.
std::vector<std::pair<Eigen::Vector3d, double>> RowDirections(
  const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const std::vector<int>& ids)
{
  std::vector<Eigen::Vector3d> own;
  for (int j : ids)
    own.push_back(points[static_cast<std::size_t>(j)]);
  const PointGrid grid(own, f.radius);
  std::vector<std::pair<Eigen::Vector3d, double>> directions;
  std::vector<int> near;
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    const auto i = static_cast<std::size_t>(ids[k]);
    if (!IsRow(f, i))
      continue;
    grid.Within(own[k], f.radius, near);
    if (near.size() < 3)
      continue;
    Eigen::Vector3d mean;
    if (LineShaped(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Scatter(own, near, mean)).eigenvalues()))
      directions.emplace_back(f.direction[i], 1.0);
  }
  return directions;
}

/// The weighted median over `directions` (unit vectors, weights) of their squared cosine to `along`: what most of
/// the rows say. On the simulated trees (from one position at 0.1 % and 1 % noise, two at 1 %), the whole leaves
/// whose row groups the mean of the squared cosines refused had 2-14 directions measured, each from 3-7 points; one
/// to five of them lay 20-90 degrees off the rest, which mostly agreed within ten degrees (RowDirections keeps out
/// most of those).
double MedianSquaredCosine(
  const std::vector<std::pair<Eigen::Vector3d, double>>& directions, const Eigen::Vector3d& along)
{
  std::vector<std::pair<double, double>> byCosine; // (squared cosine, weight)
  double total = 0.0;
  for (const auto& [d, w] : directions)
  {
    byCosine.emplace_back(d.dot(along) * d.dot(along), w);
    total += w;
  }
  std::sort(byCosine.begin(), byCosine.end());
  double below = 0.0;
  for (const auto& [c, w] : byCosine)
    if ((below += w) >= total / 2)
      return c;
  return byCosine.empty() ? 0.0 : byCosine.back().first;
}

/// The rows seen in a group (its points `ids`; `pieceOf` names each point's part before GatherRows) as (direction,
/// weight): the row directions the features measured (RowDirections), or, where under three are, the axes of the
/// parts that are lines by their own shape (each weighted by its points). None: no row is seen in the group.
std::vector<std::pair<Eigen::Vector3d, double>> RowsSeen(const std::vector<Eigen::Vector3d>& points,
  const PointFeatures& f, const std::vector<int>& ids, const std::vector<int>& pieceOf)
{
  std::vector<std::pair<Eigen::Vector3d, double>> directions = RowDirections(points, f, ids);
  if (directions.size() >= 3)
    return directions;
  directions.clear();
  std::map<int, std::vector<int>> pieces;
  for (int j : ids)
    pieces[pieceOf[static_cast<std::size_t>(j)]].push_back(j);
  for (const auto& [piece, members] : pieces)
  {
    if (members.size() < 3)
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, members, mean));
    if (LineShaped(solver.eigenvalues()))
      directions.emplace_back(solver.eigenvectors().col(2), static_cast<double>(members.size()));
  }
  return directions;
}

/// Whether a row group (its points `ids`, moments `m`) is consistent with one leaf seen in rows: spread at least r
/// across its main axis (root mean square: a leaf's width; the pieces such groups held on the simulated trees were
/// narrow strips along their leaf), its rows nearly parallel (the row directions the features measured where a
/// neighbourhood is a line, RowDirections, or the pieces' own axes where under three are: the median of their
/// squared cosines to their main direction at least `cosine` squared, MedianSquaredCosine), at least three of them,
/// shortening towards an end of the group (RowEndFraction), at whatever spacing (see RowEndFraction): both ends, or
/// one only where the leaf is cut across its rows by another leaf's shadow or contact, or half of it is seen.
/// `directions`: the group's RowsSeen.
bool RowsOfOneLeaf(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const std::vector<int>& ids,
  const std::vector<int>& pieceOf, const std::vector<std::pair<Eigen::Vector3d, double>>& directions,
  const PartMoments& m, double cosine, double merge)
{
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> moments(m.scatter / m.count);
  if (moments.eigenvalues()[1] < f.radius * f.radius)
    return false;
  const Eigen::Vector3d n = moments.eigenvectors().col(0);
  const Eigen::Matrix3d inPlane = Eigen::Matrix3d::Identity() - n * n.transpose();
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  double weights = 0.0;
  for (const auto& [d, w] : directions)
  {
    sum += w * d * d.transpose();
    weights += w;
  }
  if (weights == 0.0)
    return false;
  const Eigen::Vector3d along =
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inPlane * sum * inPlane).eigenvectors().col(2);
  if (MedianSquaredCosine(directions, along) < cosine * cosine)
    return false;
  const std::vector<std::array<double, 3>> rows = RowsAcross(points, ids, pieceOf, m.mean, along, n, merge);
  if (rows.size() < 3)
    return false;
  std::vector<double> lengths;
  for (const std::array<double, 3>& row : rows)
    lengths.push_back(row[2] - row[1]);
  const double longest = *std::max_element(lengths.begin(), lengths.end());
  return lengths.front() <= RowEndFraction * longest || lengths.back() <= RowEndFraction * longest;
}

/// A leaf seen only in rows (and cut-off pieces): the scanner meets it at a grazing angle and no part of it has a
/// leaf's shape, so GatherRows' group of its rows reaches no leaf part. Such a group (NoLeafShape, at least
/// `minimumLeafPoints` points) is a leaf instance of its own when it is as wide as a leaf (RowsAsWideAsALeaf), no
/// point of a leaf instance lies within GapRadii r of it, and no leaf point outside it and outside every leaf
/// instance lies within 2r of it in its plane (off it by under `thickness`). Beside another leaf the rows are mostly
/// a piece of a leaf cut by that leaf's shadow or contact (on the 18 simulated scans, 32 of 136 such groups within
/// 4r of a leaf instance held under half of their leaf, 3 of 45 farther away); with more rows of its plane beside it
/// that did not join it, it is part of a leaf whose rest lies in pieces. A group as wide as a leaf whose rows are one
/// leaf's (RowsOfOneLeaf; `pieceOf` names each point's part before GatherRows, its row; `merge` is half a link) is
/// an instance wherever it lies, and so is a group in which no row is seen (RowsSeen gives none: its neighbourhoods
/// are planes and its parts flat strips, narrower than 2r by their variance, no line by their shape), which the
/// rows' tests cannot judge: a leaf seen whole as a narrow sheet far more often than a piece (on the six simulated
/// tree scans, of such groups within 4r of a leaf instance 16 were whole leaves and 3 pieces; test
/// ANarrowLeafSeenWithoutRowsBesideALeafIsAnInstance).
/// Returns, per part of `leaves`, whether it is such a leaf.
std::vector<char> LeavesSeenInRows(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f,
  const std::vector<int>& region, const std::vector<RegionVerdict>& verdicts, const std::vector<int>& organ,
  const std::vector<int>& pieceOf, int minimumLeafPoints, double cosine, double thickness, double merge,
  const std::vector<std::vector<int>>& leaves)
{
  std::vector<char> rows(leaves.size(), 0), inShaped(points.size(), 0);
  std::vector<Eigen::Vector3d> shaped; // the points of the parts with a leaf's shape
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    if (!NoLeafShape(region, verdicts, leaves[k], minimumLeafPoints))
      for (int j : leaves[k])
      {
        shaped.push_back(points[static_cast<std::size_t>(j)]);
        inShaped[static_cast<std::size_t>(j)] = 1;
      }
    else if (leaves[k].size() >= static_cast<std::size_t>(minimumLeafPoints))
      rows[k] = 1;
  }
  std::vector<Eigen::Vector3d> loose; // leaf points in no part with a leaf's shape
  std::vector<int> looseIds;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (organ[i] == OrganLeaf && !inShaped[i])
    {
      loose.push_back(points[i]);
      looseIds.push_back(static_cast<int>(i));
    }
  const double reach = GapRadii * f.radius;
  const std::unique_ptr<PointGrid> grid = shaped.empty() ? nullptr : std::make_unique<PointGrid>(shaped, reach);
  const std::unique_ptr<PointGrid> looseGrid =
    loose.empty() ? nullptr : std::make_unique<PointGrid>(loose, 2.0 * f.radius);
  std::vector<char> mine(points.size(), 0);
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    if (!rows[k])
      continue;
    const PartMoments m = PartMoments::Of(points, leaves[k]);
    if (!RowsAsWideAsALeaf(points, f, leaves[k], m, cosine))
    {
      rows[k] = 0;
      continue;
    }
    const std::vector<std::pair<Eigen::Vector3d, double>> directions = RowsSeen(points, f, leaves[k], pieceOf);
    if (directions.empty() || RowsOfOneLeaf(points, f, leaves[k], pieceOf, directions, m, cosine, merge))
      continue; // no rows seen (a narrow sheet), or its rows are one leaf's: an instance wherever it lies
    rows[k] = !grid || std::none_of(leaves[k].begin(), leaves[k].end(), [&](int j) {
      return !grid->Nearest(points[static_cast<std::size_t>(j)], 1, -1, reach).empty();
    });
    if (!rows[k] || !looseGrid)
      continue;
    // more of its rows beside it (in its plane, within 2r) that did not join: half a leaf, the rest in pieces
    double spread = 0.0;
    const Eigen::Vector3d n = m.Normal(spread);
    for (int j : leaves[k])
      mine[static_cast<std::size_t>(j)] = 1;
    std::vector<int> near;
    for (int j : leaves[k])
    {
      looseGrid->Within(points[static_cast<std::size_t>(j)], 2.0 * f.radius, near);
      if (std::any_of(near.begin(), near.end(), [&](int q) {
            const auto i = static_cast<std::size_t>(looseIds[static_cast<std::size_t>(q)]);
            return !mine[i] && std::abs((points[i] - m.mean).dot(n)) < thickness;
          }))
      {
        rows[k] = 0;
        break;
      }
    }
    for (int j : leaves[k])
      mine[static_cast<std::size_t>(j)] = 0;
  }
  return rows;
}

/// Per part of `leaves`, whether it is made of flat strips only (NoLeafShape, with at least the fewest points of a
/// leaf) and yet spreads over a leaf: flat (off its plane by under r) and over at least LeafSpreadFraction of the
/// plant's typical part with a leaf's shape, along and across (SpreadLikeALeaf). On noisy scans, where the features'
/// radius r widens with the noise, a small leaf or one seen edge on is cut into strips narrower than 2r, each of which
/// is no leaf by its width; together they are one.
std::vector<char> StripsSpreadLikeALeaf(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& region,
  const std::vector<RegionVerdict>& verdicts, const SegmentationParameters& p, double radius,
  const std::vector<std::vector<int>>& leaves)
{
  std::vector<char> strips(leaves.size(), 0);
  std::vector<std::vector<int>> shaped;
  std::vector<PartMoments> moments;
  for (std::size_t k = 0; k < leaves.size(); ++k)
    if (!NoLeafShape(region, verdicts, leaves[k], p.minimumLeafPoints))
    {
      shaped.push_back(leaves[k]);
      moments.push_back(PartMoments::Of(points, leaves[k]));
    }
    else
      strips[k] = leaves[k].size() >= static_cast<std::size_t>(p.minimumLeafPoints);
  const Eigen::Vector2d typical = TypicalSpread(shaped, moments, 0.0, radius);
  for (std::size_t k = 0; k < leaves.size(); ++k)
    strips[k] = strips[k] && SpreadLikeALeaf(PartMoments::Of(points, leaves[k]), typical, radius);
  return strips;
}

/// A leaf part bent off its plane by more than this fraction of r (root mean square) ...
constexpr double WoodSheetBend = 0.25;
/// ... with more than this share of its points within WoodSheetReach r of the wood lies along the wood.
constexpr double WoodSheetShare = 0.6;
constexpr double WoodSheetReach = 2.0;
/// A part with the wood around it (in EnclosedSheetSectors or more of the twelve directions about it in its plane) is
/// the wood's surface when bent off its plane by more than this fraction of r already, and by more than
/// EnclosedSheetNoise times the range noise (a bend within the noise is none: at 1 % noise, where r is 12 times the
/// noise, such wood patches and blades merged at an angle are bent alike, 2.1-2.9 times it).
constexpr double EnclosedSheetBend = 1.0 / 7.0;
constexpr double EnclosedSheetNoise = 3.0;
constexpr int EnclosedSheetSectors = 6;

/// How many of twelve equal sectors around the part (about its mean, in its plane) hold wood beyond its outline:
/// wood points within r of its plane, more than r / 2 and at most WoodSheetReach r from its nearest point.
int SectorsWithWoodAround(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const PartMoments& m,
  const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& wood, const PointGrid& woodGrid, double radius)
{
  std::vector<Eigen::Vector3d> part;
  double extent = 0.0;
  for (int j : ids)
  {
    part.push_back(points[static_cast<std::size_t>(j)]);
    extent = std::max(extent, (part.back() - m.mean).norm());
  }
  const PointGrid partGrid(part, radius);
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  std::vector<int> near;
  woodGrid.Within(m.mean, extent + WoodSheetReach * radius, near);
  std::array<char, 12> seen{};
  for (int q : near)
  {
    const Eigen::Vector3d d = wood[static_cast<std::size_t>(q)] - m.mean;
    if (std::abs(d.dot(n)) >= radius || partGrid.Near(wood[static_cast<std::size_t>(q)], 0.5 * radius) >= 0 ||
      partGrid.Near(wood[static_cast<std::size_t>(q)], WoodSheetReach * radius) < 0)
      continue;
    const double turn = std::atan2(d.dot(v), d.dot(u)) + Pi; // [0, 2 pi]
    seen[std::min<std::size_t>(11, static_cast<std::size_t>(turn / (2.0 * Pi) * 12.0))] = 1;
  }
  return static_cast<int>(std::count(seen.begin(), seen.end(), 1));
}

/// Whether the leaf part `ids` is the wood's surface grown into a leaf-shaped sheet (a twig's facets, a branch's
/// flank): lying along the wood (over WoodSheetShare of its points within WoodSheetReach r of it) and bent off its
/// plane by more than WoodSheetBend r, or by more than EnclosedSheetBend r where the wood surrounds it in its plane
/// (an arc of a thin branch's bark with the branch around it). A blade is flat to the features and meets its twig at
/// its base only: on the six simulated tree scans none of the 1,672 instances matching a leaf is both over r / 4 off
/// its plane and along the wood (nine tenths lie under 0.18 r off their plane; of those over r / 4 off it, at most
/// 0.54 lies within 2r of the wood), and 31 of the 59 instances of wood points are. On the five tree scans with the
/// lowest scores, the wood instances left lie on branches 0.8-1.7 r thick, bent by 0.10-0.27 r, with wood in 6-11
/// sectors for 9 of 12; no instance matching a leaf along the wood with wood in 6 sectors is bent by over 0.09 r at
/// 0.1 % noise.
bool WoodSurfaceSheet(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
  const std::vector<Eigen::Vector3d>& wood, const PointGrid& woodGrid, double radius, double noise)
{
  const PartMoments m = PartMoments::Of(points, ids);
  double spread = 0.0;
  const Eigen::Vector3d n = m.Normal(spread);
  const double enclosedBend = std::max(EnclosedSheetBend * radius, EnclosedSheetNoise * noise);
  if (spread <= std::min(enclosedBend, WoodSheetBend * radius))
    return false;
  const auto close = std::count_if(ids.begin(), ids.end(),
    [&](int j) { return woodGrid.Near(points[static_cast<std::size_t>(j)], WoodSheetReach * radius) >= 0; });
  if (static_cast<double>(close) <= WoodSheetShare * static_cast<double>(ids.size()))
    return false;
  return spread > WoodSheetBend * radius ||
    (spread > enclosedBend && SectorsWithWoodAround(points, ids, m, n, wood, woodGrid, radius) >= EnclosedSheetSectors);
}

/// Each kept part (`kept`) takes its contact points (ContactPointsOfParts): a contact piece is a region judged wood
/// whose points became leaf, so a part of its own may hold them already (a region curved across, judged wood, whose
/// points ContactPiecesAreLeaves made leaf): they leave that part, so that no point is in two parts.
void AddContactPoints(const std::vector<std::vector<int>>& contactPoints, const std::vector<char>& kept, std::size_t n,
  std::vector<std::vector<int>>& parts)
{
  std::vector<int> partOf(n, -1);
  for (std::size_t k = 0; k < parts.size(); ++k)
    for (int j : parts[k])
      partOf[static_cast<std::size_t>(j)] = static_cast<int>(k);
  std::vector<char> left(parts.size(), 0);
  for (std::size_t li = 0; li < parts.size(); ++li)
    if (kept[li])
      for (int j : contactPoints[li])
      {
        int& holder = partOf[static_cast<std::size_t>(j)];
        if (holder == static_cast<int>(li))
          continue;
        if (holder >= 0)
          left[static_cast<std::size_t>(holder)] = 1;
        holder = static_cast<int>(li);
        parts[li].push_back(j);
      }
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (left[k])
      parts[k].erase(std::remove_if(parts[k].begin(), parts[k].end(),
                       [&](int j) { return partOf[static_cast<std::size_t>(j)] != static_cast<int>(k); }),
        parts[k].end());
}

/// The leaf instances: leaf regions of at least MinimumLeafPoints points, numbered by their lowest point index.
void MakeLeaves(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  const std::vector<int>& region, const std::vector<RegionVerdict>& verdicts, double spacing, double radius,
  const SegmentationParameters& p, const ParallelFor& parallel, const std::vector<std::pair<int, int>>& contacts,
  PlantLabels& labels)
{
  const std::size_t n = points.size();
  const double gapCosine = std::cos(GapAngleFraction * p.normalAngle * Pi / 180.0);
  std::vector<std::vector<int>> members;
  std::vector<int> instance(n, -1), leafOfRegion;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (labels.organ[i] != OrganLeaf || region[i] < 0)
      continue;
    const auto r = static_cast<std::size_t>(region[i]);
    if (r >= leafOfRegion.size())
      leafOfRegion.resize(r + 1, -1);
    if (leafOfRegion[r] < 0)
    {
      leafOfRegion[r] = static_cast<int>(members.size());
      members.emplace_back();
    }
    members[static_cast<std::size_t>(leafOfRegion[r])].push_back(static_cast<int>(i));
  }
  std::vector<int> hops, source;
  DistanceFromWood(graph, labels.organ, hops, source);
  std::vector<int> segment = WoodSegments(graph, labels.organ, region);
  std::vector<Eigen::Vector3d> wood;
  std::vector<int> woodIds;
  for (std::size_t i = 0; i < n; ++i)
    if (labels.organ[i] == OrganWood)
    {
      wood.push_back(points[i]);
      woodIds.push_back(static_cast<int>(i));
    }
  const PointGrid woodGrid(wood, PointGrid::CellFor(wood, 4.0));
  std::vector<std::vector<int>> leaves;
  std::vector<int> owner(n, -1);
  for (const std::vector<int>& ids : members)
    for (std::vector<int>& part : SplitAtBases(points, graph, ids, hops, 4.0 * radius, owner))
      leaves.push_back(std::move(part));
  std::vector<std::vector<int>> setAside; // small leaves beside others (JoinPieces), unless joined across a gap
  JoinPieces(
    points, graph, PieceFraction, p.minimumLeafPoints, std::cos(p.normalAngle * Pi / 180.0), radius, leaves, setAside);
  IsolatedLeafPieces(graph, region, labels.organ, leaves);
  std::vector<int> pieceOf(n, -1); // the part each leaf point was in before the rows gather: its row
  for (std::size_t k = 0; k < leaves.size(); ++k)
    for (int j : leaves[k])
      pieceOf[static_cast<std::size_t>(j)] = static_cast<int>(k);
  GatherRows(points, f, region, verdicts, p, gapCosine, GapThickness * radius, leaves);
  SetAsideJoinAcrossGaps(points, radius, gapCosine, p.minimumLeafPoints, leaves, setAside);
  // a side of a cut needs only a leaf's fewest points: the seam, not its size, tells a crease from a contact, and a
  // small side is judged again by the joins (a piece joins its leaf; a small leaf beside another gets no instance)
  // two normal groups over half of NormalAngle apart (the features' normals are good to about 10 degrees) are looked
  // at: leaves touching at 12-23 degrees were left merged at the full NormalAngle; a part longer than the longest
  // leaf is several leaves, cut whatever its seam
  if (CutAtShortSeams(points, f, graph, gapCosine, static_cast<std::size_t>(p.minimumLeafPoints),
        LongestLeaf(points, leaves, p.minimumLeafPoints, GapThickness * radius), parallel, leaves) > 0)
  {
    // a cut side may be a piece of a third leaf whose rest lies in another part: the joins again
    JoinPieces(points, graph, PieceFraction, p.minimumLeafPoints, std::cos(p.normalAngle * Pi / 180.0), radius, leaves,
      setAside);
    SetAsideJoinAcrossGaps(points, radius, gapCosine, p.minimumLeafPoints, leaves, setAside);
  }
  // last, pieces whose planes agree once the few points of a neighbour one of them carries are left out: after the
  // cuts and the pieces' joins, which judge a part's size against the plant's median part
  JoinAcrossGaps(points, radius, gapCosine, p.minimumLeafPoints, leaves, true);
  std::sort(leaves.begin(), leaves.end());
  const std::vector<char> seenInRows = LeavesSeenInRows(points, f, region, verdicts, labels.organ, pieceOf,
    p.minimumLeafPoints, gapCosine, GapThickness * radius, 0.5 * p.linkScale * spacing, leaves);
  // only where the noise widened the features' radius past FeatureScale spacings: there strips narrower than 2r are
  // cut out of small leaves and leaves seen edge on
  const std::vector<char> spreadLikeALeaf = radius > p.featureScale * spacing * (1.0 + 1e-9)
    ? StripsSpreadLikeALeaf(points, region, verdicts, p, radius, leaves)
    : std::vector<char>(leaves.size(), 0);
  std::vector<std::vector<int>> contactPoints = ContactPointsOfParts(leaves, region, contacts);
  std::vector<char> kept(leaves.size(), 0);
  for (std::size_t li = 0; li < leaves.size(); ++li)
    // a part made only of flat strips (narrower than 2r or a long strip) and cut-off points has no leaf shape to
    // fit: leaf, no LeafId, unless it is a leaf seen only in rows, or its strips spread over a leaf; nor the wood's
    // surface seen as a sheet
    kept[li] =
      (seenInRows[li] || spreadLikeALeaf[li] || !NoLeafShape(region, verdicts, leaves[li], p.minimumLeafPoints)) &&
      (wood.empty() || !WoodSurfaceSheet(points, leaves[li], wood, woodGrid, radius, f.noise));
  for (std::size_t li = 0; li < leaves.size(); ++li)
    if (kept[li] && CurvedAcross(points, leaves[li], radius, f.noise)) // a twig's side cut out of a leaf's region
    {
      kept[li] = 0;
      for (int j : leaves[li])
        labels.organ[static_cast<std::size_t>(j)] = OrganWood;
    }
  AddContactPoints(contactPoints, kept, n, leaves);
  PlaneMoves planeMoves;
  planeMoves.cell = 2.0 * radius;
  planeMoves.borderMargin = PlaneMargin * spacing;
  planeMoves.margin = std::max(planeMoves.borderMargin, PlaneNoiseMargin * f.noise);
  LeafPointsOntoTheirPlane(points, graph, labels.organ, planeMoves, kept, parallel, leaves);
  // a contact piece may be the twig itself, lying between two leaves
  TwigsAlongLeafEdges(points, wood, woodGrid, kept, radius, spacing, parallel, leaves, labels.organ, labels.confidence);
  for (std::size_t li = 0; li < leaves.size(); ++li)
  {
    std::vector<int>& ids = leaves[li];
    if (!kept[li] || ids.empty())
      continue;
    SegmentedLeaf leaf;
    leaf.leafId = static_cast<int>(labels.leaves.size());
    leaf.points = static_cast<long long>(ids.size());
    leaf.area = PlaneArea(points, ids, 2.0 * spacing);
    int base = ids.front();
    for (int j : ids)
    {
      leaf.centre += points[static_cast<std::size_t>(j)];
      if (hops[static_cast<std::size_t>(j)] < hops[static_cast<std::size_t>(base)])
        base = j;
      labels.leaf[static_cast<std::size_t>(j)] = leaf.leafId;
    }
    leaf.centre /= static_cast<double>(ids.size());
    int woodPoint = source[static_cast<std::size_t>(base)];
    if (woodPoint < 0 && !wood.empty()) // cut off from the wood: the wood point nearest the centre
    {
      const auto nearest = woodGrid.Nearest(leaf.centre, 1);
      woodPoint = nearest.empty() ? -1 : woodIds[static_cast<std::size_t>(nearest[0].second)];
    }
    leaf.base = points[static_cast<std::size_t>(base)];
    if (woodPoint >= 0)
    {
      leaf.branch = segment[static_cast<std::size_t>(woodPoint)];
      leaf.baseGap = (points[static_cast<std::size_t>(woodPoint)] - leaf.base).norm();
    }
    labels.leaves.push_back(leaf);
  }
  labels.woodSegment = std::move(segment);
}
/// A flat surface is no plant: a board, a wall, the ground alone, scanned in lines (closer along a line than
/// across, so that at the features' scale the lines look like twigs and the strips between them like leaves). ""
/// or the reason: the points' spread off their best plane (the square root of the covariance's smallest eigenvalue)
/// below half the features' radius, where the features cannot tell a twig from a strip of the surface.
std::string RefuseFlat(const std::vector<Eigen::Vector3d>& points, double radius)
{
  std::vector<int> all(points.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<int>(i);
  Eigen::Vector3d mean;
  const Eigen::Matrix3d covariance = Scatter(points, all, mean) / static_cast<double>(points.size());
  const double thickness =
    std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues()[0]));
  if (thickness >= 0.5 * radius)
    return {};
  return "the " + std::to_string(points.size()) + " points lie on one plane (their spread off it, " +
    std::to_string(thickness) + ", is below half the features' radius, " + std::to_string(radius) +
    "): a flat surface, not a plant; a cloud of one flat leaf goes to LeafFitFilter directly";
}
} // namespace

std::size_t FlatPiecesAwayFromWood(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, double radius,
  double noise, std::vector<int>& organ, std::vector<double>& confidence)
{
  const std::size_t n = organ.size();
  std::vector<char> seen(n, 0);
  std::vector<int> piece;
  std::vector<std::vector<int>> flat;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (seen[i] || organ[i] != OrganWood)
      continue;
    LinkComponent(
      graph, i, [](std::size_t) { return true; }, seen, piece);
    if (piece.size() < JudgedRegionPoints ||
      std::any_of(piece.begin(), piece.end(), [&](int j) { return organ[static_cast<std::size_t>(j)] != OrganWood; }))
      continue;
    Eigen::Vector3d mean;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, piece, mean));
    const Eigen::Vector3d spread = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    if (spread[0] < FlatPieceThickness * spread[1] && !CurvedAcross(points, piece, radius, noise))
      flat.push_back(piece);
  }
  if (flat.empty())
    return 0;
  // the wood points alone, in a grid (a tenth to a fifth of the cloud)
  std::vector<Eigen::Vector3d> wood;
  std::vector<std::size_t> woodIndex;
  for (std::size_t i = 0; i < n; ++i)
    if (organ[i] == OrganWood)
    {
      wood.push_back(points[i]);
      woodIndex.push_back(i);
    }
  const PointGrid grid(wood, radius);
  std::vector<int> owner(n, -1), near;
  std::size_t count = 0;
  for (std::size_t k = 0; k < flat.size(); ++k)
  {
    for (int j : flat[k])
      owner[static_cast<std::size_t>(j)] = static_cast<int>(k);
    bool away = true;
    for (std::size_t a = 0; a < flat[k].size() && away; ++a)
    {
      grid.Within(points[static_cast<std::size_t>(flat[k][a])], radius, near);
      away = std::all_of(near.begin(), near.end(),
        [&](int q) { return owner[woodIndex[static_cast<std::size_t>(q)]] == static_cast<int>(k); });
    }
    if (!away)
      continue;
    for (int j : flat[k])
    {
      organ[static_cast<std::size_t>(j)] = OrganLeaf;
      confidence[static_cast<std::size_t>(j)] = 0.25;
    }
    count += flat[k].size();
  }
  return count;
}

/// A noisy flat piece (NoisyFlatPiecesAwayFromWood) lies this many features' radii r or more from all other wood ...
constexpr double NoisyPieceApart = 3.0;
/// ... is no longer than this many widths (its largest principal spread over the middle one) ...
constexpr double NoisyPieceElongation = 4.0;
/// ... and spreads off its plane by under this many of the range noise measured (NoiseLevel: the lower quartile of
/// the plane-fit residuals, about 0.6 of the range noise's standard deviation on the benchmark's scans).
constexpr double NoisyPieceThickness = 2.5;

std::size_t NoisyFlatPiecesAwayFromWood(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  double radius, double noise, std::vector<int>& organ, std::vector<double>& confidence)
{
  const double apart = NoisyPieceApart * radius;
  const std::size_t n = organ.size();
  std::vector<unsigned char> wood(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    wood[i] = organ[i] == OrganWood ? 1 : 0;
  std::vector<char> seen(n, 0);
  std::vector<int> piece;
  std::vector<std::vector<int>> candidates;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (seen[i] || !wood[i])
      continue;
    LinkComponent(
      graph, i, [&](std::size_t j) { return wood[j] != 0; }, seen, piece);
    if (piece.size() < JudgedRegionPoints)
      continue;
    const Eigen::Vector3d spread = PartMoments::Of(points, piece).Spreads();
    if (spread[2] < NoisyPieceElongation * spread[1] && spread[0] < NoisyPieceThickness * noise)
      candidates.push_back(piece);
  }
  if (candidates.empty())
    return 0;
  // judged all at once, against the wood as it stands
  const PointGrid grid(points, apart);
  std::vector<const std::vector<int>*> away;
  for (const std::vector<int>& ids : candidates)
    if (ApartFromOtherWood(points, grid, ids, apart, wood))
      away.push_back(&ids);
  std::size_t count = 0;
  for (const std::vector<int>* ids : away)
  {
    for (int j : *ids)
    {
      organ[static_cast<std::size_t>(j)] = OrganLeaf;
      confidence[static_cast<std::size_t>(j)] = 0.25;
    }
    count += ids->size();
  }
  return count;
}

std::string SegmentPlant(const std::vector<Eigen::Vector3d>& points, const SegmentationParameters& p,
  const ParallelFor& parallel, PlantLabels& labels)
{
  const std::size_t n = points.size();
  if (n < static_cast<std::size_t>(MinimumPlantPoints))
    return "the cloud has " + std::to_string(n) + " points; a plant needs at least " +
      std::to_string(MinimumPlantPoints);
  // the grid and the sampled searches threaded: the same spacing on any number of threads
  const double spacing = MedianSpacing(points, PointGrid(points, PointGrid::CellFor(points, 4.0), parallel), parallel);
  if (!(spacing > 0.0))
    return "the points all coincide: no spacing to derive the neighbourhoods from";
  PointFeatures f;
  LinkGraph graph;
  ComputeFeatures(points, spacing, p, parallel, f, graph);
  std::vector<int> region;
  int count = GrowRegions(f, graph, p, parallel, region);
  std::vector<RegionVerdict> verdicts = JudgeRegions(points, f, region, count, p, true);
  if (std::any_of(verdicts.begin(), verdicts.end(), [](const RegionVerdict& v) { return v.mixed; }))
  {
    count = SplitMixedRegions(f, graph, p, verdicts, region, count);
    verdicts = JudgeRegions(points, f, region, count, p, false);
  }
  JoinFoldedStrips(points, f, graph, p, verdicts, region);
  FlatStripsAreLeaves(points, graph, f.radius, verdicts, region);
  std::vector<char> judged;
  SpreadRegions(points, f, graph, verdicts, region, judged);
  labels.organ.assign(n, OrganWood);
  labels.leaf.assign(n, -1);
  labels.confidence.assign(n, 0.5);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (region[i] < 0)
      continue; // linear, or cut off from every judged region: wood
    const RegionVerdict& v = verdicts[static_cast<std::size_t>(region[i])];
    labels.organ[i] = v.leaf ? OrganLeaf : OrganWood;
    labels.confidence[i] = judged[i] ? v.confidence : 0.5 * v.confidence;
  }
  LoneFlatStripsAreLeaves(points, f, judged, verdicts, region, labels.organ);
  CoplanarFlatStripsAreLeaves(points, f, spacing, p, judged, verdicts, region, labels.organ);
  StripsAmongLeavesAreLeaves(points, f, graph, judged, spacing, verdicts, region, labels.organ);
  ThickWoodKeepsItsSurface(points, f, verdicts, region, p, std::max(ThickWoodBand * f.noise, spacing), labels.organ);
  AbsorbWoodFragments(graph, verdicts, p, region, labels.organ);
  const std::vector<std::pair<int, int>> contacts =
    ContactPiecesAreLeaves(points, graph, f.radius, verdicts, region, labels.organ);
  for (const auto& contact : contacts)
    labels.confidence[static_cast<std::size_t>(contact.first)] = 0.5; // judged wood, made leaf by its surroundings
  IsolatedPiecesByTheirSurroundings(points, graph, f.radius, labels.organ, labels.confidence);
  FlatPiecesAwayFromWood(points, graph, f.radius, f.noise, labels.organ, labels.confidence);
  NoisyFlatPiecesAwayFromWood(points, graph, f.radius, f.noise, labels.organ, labels.confidence);
  SegmentedPlant& plant = labels.plant;
  plant.points = static_cast<long long>(n);
  plant.spacing = spacing;
  for (std::size_t i = 0; i < n; ++i)
    (labels.organ[i] == OrganWood ? plant.woodPoints : plant.leafPoints) += 1;
  if (plant.leafPoints == 0)
    return "no leaf found in " + std::to_string(n) + " points (the cloud is all wood or all thin lines)";
  if (plant.woodPoints == 0)
    return "no wood found in " + std::to_string(n) +
      " points (a cloud of leaves alone: fit them with LeafFitFilter directly)";
  const std::string flat = RefuseFlat(points, f.radius);
  if (!flat.empty())
    return flat;
  MakeLeaves(points, f, graph, region, verdicts, spacing, f.radius, p, parallel, contacts, labels);
  FindPetioles(points, f, graph, spacing, p, parallel, labels);
  // counted again: the leaf instances give twigs along their edges back to the wood, the petioles take thin wood
  plant.woodPoints = plant.leafPoints = 0;
  for (std::size_t i = 0; i < n; ++i)
    (labels.organ[i] == OrganWood      ? plant.woodPoints
        : labels.organ[i] == OrganLeaf ? plant.leafPoints
                                       : plant.petiolePoints) += 1;
  plant.leafCount = static_cast<int>(labels.leaves.size());
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (std::size_t i = 0; i < n; ++i)
  {
    low = std::min(low, points[i][p.upAxis]);
    high = std::max(high, points[i][p.upAxis]);
    plant.unassignedLeafPoints += labels.organ[i] == OrganLeaf && labels.leaf[i] < 0 ? 1 : 0;
  }
  plant.height = high - low;
  return {};
}

} // namespace segmentation
} // namespace plantmorph
