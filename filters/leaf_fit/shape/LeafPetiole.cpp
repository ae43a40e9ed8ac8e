// SPDX-License-Identifier: GPL-3.0-or-later
// The petiole of a scanned leaf (LeafShape.h): the thin trail the blade's opening leaves out.
#include "LeafShape.h"
#include "PointGrid.h"

#include <plantmorph/PlaneFit.h>
#include <plantmorph/graph/DisjointSets.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>

namespace plantmorph
{
namespace fit
{
namespace
{
/// One part the opening left out, measured along its trail from the blade.
struct Trail
{
  std::vector<int> ids;         // point ids
  std::vector<double> distance; // graph distance from the blade, per id
  std::vector<int> contact;     // positions in ids of the points touching the blade
  double extent = 0.0;
  bool acrossGap = false; // it touches the blade across a gap (AcrossAGap)
};

/// The sheet's spacing from its density (the nearest-neighbour distance is half of it on randomly placed samples,
/// all of it on a scanner's grid): the median distance r to the 8th neighbour holds 8 points in pi r^2.
double DensitySpacing(const std::vector<Eigen::Vector3d>& points)
{
  const PointGrid grid(points, PointGrid::CellFor(points, 4.0));
  std::vector<double> r8;
  for (std::size_t i = 0; i < points.size(); i += std::max<std::size_t>(1, points.size() / 2000))
  {
    const auto nb = grid.Nearest(points[i], 8, static_cast<int>(i));
    if (nb.size() == 8)
      r8.push_back(std::sqrt(nb.back().first));
  }
  if (r8.empty())
    return 0.0;
  std::nth_element(r8.begin(), r8.begin() + r8.size() / 2, r8.end());
  return r8[r8.size() / 2] * std::sqrt(3.14159265358979323846 / 8.0);
}

/// Whether the points `ids` (a ball's) lie on a stalk seen from more than one side, not on the sheet: they spread
/// along it over the ball's chord and across it over its diameter only (their second principal variance under half
/// their first: a tube of radius rho seen all round gives 1.5 rho^2 / (r^2 - rho^2), half at rho = r / 2), and they
/// are round, not flat (their least variance over a fifth of the second: a half tube, seen from one side, gives
/// 0.19, more of it more; a narrow strip of the sheet, a lobe, 12 sigma^2 / w^2 for range noise sigma, under a fifth
/// while it is wider than 8 sigma). Two scans seeing a stalk from either side sample it as densely as the sheet, and
/// the count alone took it for blade. `round`, when given: whether the points might be a thick stalk's, worth the
/// test in a larger ball (least variance over a tenth of the second: a ball centred on the surface of a stalk of
/// radius 0.7 r holds only an arc of its section, flatter than a fifth; a lobe's strip stays under a tenth while
/// it is wider than 11 sigma).
bool OnAStalk(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, bool* round = nullptr)
{
  if (round)
    *round = false;
  if (ids.size() < 3)
    return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int j : ids)
    mean += points[j];
  mean /= static_cast<double>(ids.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (int j : ids)
    C += (points[j] - mean) * (points[j] - mean).transpose();
  const Eigen::Vector3d variance = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues();
  const bool isRound = variance[0] > 0.2 * variance[1];
  if (round)
    *round = variance[0] > 0.1 * variance[1];
  return variance[1] < 0.5 * variance[2] && isRound;
}

/// Which points the blade's opening covers: a point whose ball of radius `radius` holds at least 70 % of what a
/// ball inside the sheet holds (the 90th percentile of the counts) and does not lie on a stalk (OnAStalk, in its
/// ball or, when its ball's points are rounder than a sheet's (`round`), in a ball twice as large: a stalk more than half the ball's radius
/// thick fills the ball as much across as along) is a centre; every point within `radius` of a centre is blade.
std::vector<unsigned char> Opening(
  const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double radius, const ParallelFor& parallel)
{
  const std::size_t n = points.size();
  const std::vector<int>& ids = grid.SortedIds(); // cell by cell: neighbouring queries share cells (and cache)
  std::vector<int> count(n, 0);
  ForEachIndex(
    parallel, n, [&](std::size_t k) { count[ids[k]] = static_cast<int>(grid.CountWithin(points[ids[k]], radius)); });
  std::vector<int> sorted = count;
  const std::size_t q = static_cast<std::size_t>(0.9 * static_cast<double>(n - 1));
  std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
  const double full = sorted[q];
  std::vector<unsigned char> centre(n, 0);
  ForEachIndex(parallel, n, [&](std::size_t k) {
    const int i = ids[k];
    if (!(count[i] >= 0.7 * full))
      return;
    std::vector<int> near;
    grid.Within(points[i], radius, near);
    bool round = false;
    if (OnAStalk(points, near, &round))
      return;
    // Round but not elongated: a stalk thicker than half the ball's radius fills the ball across as well as along;
    // twice as far out it is elongated again.
    if (round)
    {
      grid.Within(points[i], 2.0 * radius, near);
      if (OnAStalk(points, near))
        return;
    }
    centre[i] = 1;
  });
  // A point is blade when a centre lies within `radius` of it: itself, or the first centre its search meets.
  std::vector<unsigned char> blade(n, 0);
  ForEachIndex(parallel, n, [&](std::size_t k) {
    const int i = ids[k];
    blade[i] = centre[i] || grid.AnyWithin(points[i], radius, centre) ? 1 : 0;
  });
  return blade;
}

/// Graph distances from the trail's contact points along its own points (Dijkstra, neighbours closer than `link`).
void Distances(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, const std::vector<int>& position, double link, Trail& trail)
{
  trail.distance.assign(trail.ids.size(), 1e300);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int k : trail.contact)
  {
    trail.distance[k] = 0.0;
    queue.emplace(0.0, k);
  }
  std::vector<int> near;
  while (!queue.empty())
  {
    const auto [d, k] = queue.top();
    queue.pop();
    if (d > trail.distance[k])
      continue;
    grid.Within(points[trail.ids[k]], link, near);
    for (int j : near)
    {
      const int m = position[j];
      if (blade[j] || m < 0 || trail.ids[m] != j)
        continue;
      const double e = d + (points[j] - points[trail.ids[k]]).norm();
      if (e < trail.distance[m])
      {
        trail.distance[m] = e;
        queue.emplace(e, m);
      }
    }
  }
  trail.extent = *std::max_element(trail.distance.begin(), trail.distance.end());
}

/// A thin part that does not touch the blade may still leave it: a base narrowing gradually into the stalk (an
/// acuminate base) is narrower than the scan's lines are apart over its last stretch, which the scan misses, so the
/// stalk begins a gap away from the blade's lowest samples. A part whose points come within `gap` of the blade's
/// touches it at its points nearest the blade (within a spacing of the nearest).
void AcrossAGap(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, double gap, double spacing, Trail& trail)
{
  std::vector<double> nearest(trail.ids.size(), std::numeric_limits<double>::infinity());
  std::vector<int> near;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
  {
    grid.Within(points[trail.ids[k]], gap, near);
    for (int j : near)
      if (blade[j])
        nearest[k] = std::min(nearest[k], (points[j] - points[trail.ids[k]]).norm());
  }
  const double closest = *std::min_element(nearest.begin(), nearest.end());
  if (!(closest <= gap))
    return;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    if (nearest[k] <= closest + spacing)
      trail.contact.push_back(static_cast<int>(k));
  trail.acrossGap = true;
}

/// The connected thin parts (neighbours closer than `link`) that touch the blade (or leave it across a gap up to
/// `gap`, AcrossAGap; `spacing` the points'), each with its points' graph distances from the blade.
std::vector<Trail> Trails(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, double link, double gap, double spacing)
{
  const int n = static_cast<int>(points.size());
  DisjointSets<int> parts(static_cast<std::size_t>(n));
  std::vector<unsigned char> touches(n, 0);
  std::vector<int> near;
  for (int i = 0; i < n; ++i)
  {
    if (blade[i])
      continue;
    grid.Within(points[i], link, near);
    for (int j : near)
      if (blade[j])
        touches[i] = 1;
      else if (j != i)
        parts.Join(i, j);
  }
  std::vector<int> slot(n, -1);
  std::vector<Trail> trails;
  for (int i = 0; i < n; ++i)
    if (!blade[i])
    {
      const int root = parts.Find(i);
      if (slot[root] < 0)
      {
        slot[root] = static_cast<int>(trails.size());
        trails.emplace_back();
      }
      trails[slot[root]].ids.push_back(i);
    }
  std::vector<Trail> touching;
  std::vector<int> position(n, -1);
  for (Trail& trail : trails)
  {
    for (std::size_t k = 0; k < trail.ids.size(); ++k)
    {
      position[trail.ids[k]] = static_cast<int>(k);
      if (touches[trail.ids[k]])
        trail.contact.push_back(static_cast<int>(k));
    }
    if (trail.contact.empty() && trail.ids.size() >= 5)
      AcrossAGap(points, grid, blade, gap, spacing, trail);
    if (trail.contact.empty())
      continue;
    Distances(points, grid, blade, position, link, trail);
    touching.push_back(std::move(trail));
  }
  return touching;
}

/// The trail in bins of distance from the blade: each bin's centroid, point count (empty bins: count 0) and
/// spread (standard deviation across the trail, along its widest direction).
struct Bins
{
  double width = 1.0;
  std::vector<Eigen::Vector3d> centre;
  std::vector<int> count;
  std::vector<double> spread;

  /// Whether a bin's spread is measured (it holds two points or more).
  bool Measured(std::size_t k) const { return this->count[k] >= 2; }

  /// The median spread of the measured bins from `first` on.
  double Spread(std::size_t first) const
  {
    std::vector<double> s;
    for (std::size_t k = first; k < this->count.size(); ++k)
      if (this->Measured(k))
        s.push_back(this->spread[k]);
    if (s.empty())
      return 0.0;
    std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
    return s[s.size() / 2];
  }
};

Bins CentreLine(const std::vector<Eigen::Vector3d>& points, const Trail& trail, double width)
{
  Bins b;
  b.width = width;
  const int bins = std::max(1, static_cast<int>(std::ceil(trail.extent / width)));
  std::vector<std::vector<Eigen::Vector3d>> members(bins);
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    members[std::min(bins - 1, static_cast<int>(trail.distance[k] / width))].push_back(points[trail.ids[k]]);
  for (const auto& m : members)
  {
    b.count.push_back(static_cast<int>(m.size()));
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : m)
      mean += p;
    b.centre.push_back(mean / std::max<double>(1.0, static_cast<double>(m.size())));
  }
  // The spread across the trail (perpendicular to the line through the neighbouring bins' centres): along it, a
  // bin's extent is the bin's, not the trail's width.
  b.spread.assign(members.size(), 0.0);
  for (std::size_t k = 0; k < members.size(); ++k)
  {
    if (members[k].size() < 2)
      continue;
    std::size_t before = k, after = k;
    while (before > 0 && (before == k || members[before].empty()))
      --before;
    while (after + 1 < members.size() && (after == k || members[after].empty()))
      ++after;
    Eigen::Vector3d t = b.centre[after] - b.centre[before];
    if (members[before].empty() || members[after].empty() || !(t.norm() > 0.0))
      t = Eigen::Vector3d::Zero();
    else
      t.normalize();
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& p : members[k])
    {
      Eigen::Vector3d r = p - b.centre[k];
      r -= r.dot(t) * t;
      C += r * r.transpose();
    }
    C /= static_cast<double>(members[k].size());
    b.spread[k] = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues()[2]));
  }
  return b;
}

/// The first bin of the stalk: the stalk keeps its width (its bins' spread; the median over the outer half of the
/// trail's bins), while the blade's end the opening left out beside it (a margin, an acute or cuneate base) is
/// wider. From the blade outwards, the first bin no wider than 1.5 times the stalk's spread plus half a spacing.
/// (Counts alone would not do: a stalk scanned from the side thins out along its length.) A blade's end may also be
/// narrower than the stalk: an attenuate base tapering to a point where a thicker stalk leaves it is a trail of the
/// blade's last samples, a point or two across. Two bins or more (3 spacings) from there (or from the next bin, the
/// blade's edge) that are empty or both narrower than the stalk and holding under 0.6 of its bins' median count, one
/// of them at least sampled, are the blade's; the stalk begins after them, where at least 6 spacings of it are left.
std::size_t FirstStalkBin(const Bins& b, double spacing)
{
  const std::size_t n = b.count.size();
  const double stalk = b.Spread(n / 2);
  std::size_t start = 0;
  while (start + 1 < n && (!b.Measured(start) || b.spread[start] > 1.5 * stalk + 0.5 * spacing))
    ++start;
  // The blade's last samples before a thicker stalk: sparser and narrower than the stalk.
  std::vector<int> counts;
  for (std::size_t k = n / 2; k < n; ++k)
    if (b.count[k] > 0)
      counts.push_back(b.count[k]);
  if (counts.empty())
    return start;
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  const double full = counts[counts.size() / 2];
  // The first bin may be the blade's edge, as many points as the stalk's.
  const auto thin = [&](std::size_t k) { return b.count[k] == 0 || (b.count[k] < 0.6 * full && b.spread[k] < stalk); };
  std::size_t k = thin(start) ? start : start + 1;
  const std::size_t first = k;
  bool sampled = false; // a gap alone (a line scan's) is not the blade's
  for (; k < n && thin(k); ++k)
    sampled = sampled || b.count[k] > 0;
  if (sampled && k >= first + 2 && k < n && static_cast<double>(n - k) * b.width >= 6.0 * spacing)
    return k;
  return start;
}

/// The stalk's end at the blade. Near the blade the left-out part may still hold the blade's last samples (a
/// rounded end the ball did not quite reach): they lie farther from the stalk's axis than its own points do (its
/// half-width: the 80th percentile of the distances to the axis of the points of its next bins), and not on its far
/// side or flank (OnFarSide); those, and every point nearer the blade than the farthest of them, go back to the blade.
struct StalkAxis
{
  bool valid = false;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), towardsBlade = Eigen::Vector3d::Zero();
  double half = 0.0; ///< the stalk's half-width about the axis
  double gap = 0.0;  ///< the largest gap between the stalk's own samples along the axis (a line scan's lines)
  /// From the line through the bins' centroids to the stalk's own axis (zero when its cross-section draws no arc).
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  /// The line through the points of the stalk's first 20 bins (their centroid, their principal direction towards
  /// the blade): two centroids 6 spacings apart give a direction that a bin's wandering centroid tilts by up to 15
  /// degrees, a line through every point of 30 spacings of stalk by a tenth of that.
  bool fitted = false;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::Zero();
  Eigen::Vector3d lineOffset = Eigen::Vector3d::Zero(); ///< from that line to the stalk's axis
  /// The points' RMS scatter about the parabola that gave `lineOffset`, over the section's half-extent (AxisOffset).
  double arcScatter = 0.0;
  /// The scan's noise is as large as the stalk is thick (NoisyStalk): a slice the noise alone widens does not end
  /// the walk towards the blade (FollowStalkToBlade), and the section's arc is not read (no offsets).
  bool noisy = false;
};

/// The scan's noise, as the blade's points' scatter about their plane beside the junction, over the stalk's
/// half-width, from which a walk along the stalk may have stopped at a noisy point rather than at the blade: on the
/// accuracy benchmark's scans at 1 % range noise 0.47-0.83 where it stopped short, on the shipped sugar-beet scans
/// 0.18-0.32 (their walks stop where the lamina begins along the petiole, which is the junction). At that noise a
/// stalk's cross-section draws no arc the noise has not bent (NoArcInTheNoise).
constexpr double MinNoiseForAhead = 0.4;

/// A stalk's cross-section whose points scatter about their parabola by at least this share of its half-extent
/// (AxisOffset's R) is more noise than arc: on the accuracy benchmark's stalks 0.26-0.41 at 0.3 % range noise (the
/// arc bent the right way on 58 of 60), 0.41-0.51 at 1 % where the arc was bent the wrong way.
constexpr double MaxArcScatter = 0.4;

/// A stalk is noisy when the scan's range noise (SheetNoise) is at least this share of its half-width: on the
/// accuracy benchmark's scans 0.37-0.85 at 1 % range noise (the stalk's radius), 0.20-0.63 at 0.3 % (the highest
/// where the walk's half-width is narrowed among a cordate base's lobes) and 0.07-0.23 at 0.1 %. Range noise moves
/// each point along its beam by about its size: at that share a stalk's points scatter beyond its width (its
/// half-width, the 80th percentile of its points' distances from its axis, and 0.75 spacings) here and there (at
/// 1 % noise 43 of the benchmark's 66 walks towards the blade ended at a slice one point made wide, 26 of them more
/// than 2 spacings out on the stalk, up to 9.5), and its section's arc bends either way.
constexpr double NoisyStalk = 0.4;

/// The scan's range noise: the median, over up to 1,000 of the blade's points, of the RMS offset of the blade's
/// points within `radius` (the opening's ball) from their plane. Within a ball of 4 spacings a curled blade's
/// sagitta is a hundredth of a spacing or less, so the offsets are the noise's (unlike the blade's scatter over 12
/// spacings beside a junction, which a blade curving beside its base raises to 0.8 of a stalk's half-width at 0.3 %
/// noise). Zero when no ball holds 20 of the blade's points.
double SheetNoise(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, double radius)
{
  const std::size_t count = static_cast<std::size_t>(std::count(blade.begin(), blade.end(), 1));
  const std::size_t stride = std::max<std::size_t>(1, count / 1000);
  std::vector<double> rms;
  std::vector<int> near;
  std::vector<Eigen::Vector3d> ball;
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (!blade[i] || k++ % stride != 0)
      continue;
    grid.Within(points[i], radius, near);
    ball.clear();
    for (int j : near)
      if (blade[j])
        ball.push_back(points[j]);
    if (ball.size() >= 20)
      rms.push_back(std::sqrt(FitPlane(ball).moments[0] / static_cast<double>(ball.size())));
  }
  if (rms.empty())
    return 0.0;
  std::nth_element(rms.begin(), rms.begin() + rms.size() / 2, rms.end());
  return rms[rms.size() / 2];
}

/// The largest gap between consecutive values of `along` (sorted here).
double LargestGap(std::vector<double>& along)
{
  std::sort(along.begin(), along.end());
  double gap = 0.0;
  for (std::size_t k = 1; k < along.size(); ++k)
    gap = std::max(gap, along[k] - along[k - 1]);
  return gap;
}

/// A scanner sees one side of a stalk: its points' centroids lie on that side, up to its radius off its axis
/// towards the scanner, so the line through them meets the blade's plane that offset over the tangent of the stalk's
/// angle to the blade out on the stalk. The stalk's cross-section (`lateral`: each point's offset from its bin's
/// centroid, perpendicular to `u`) gives the offset to the axis: across it (its widest direction) the seen side
/// spans the stalk's diameter whatever the view (the radius: half its 2-98 % extent); in depth, a parabola through
/// the section gives the crest (the depth in the middle), and the ends bend back towards the axis, which lies a
/// radius behind the crest. Zero when the radius is more than twice the section's half-width about the centroids'
/// line plus a spacing (not a stalk's section) or the axis would lie more than a radius from that line. `scatter`,
/// when given: the points' RMS offset in depth from the parabola, over R.
Eigen::Vector3d AxisOffset(const std::vector<Eigen::Vector3d>& lateral, const Eigen::Vector3d& u, double half,
  double spacing, bool arc = false, double* scatter = nullptr)
{
  if (lateral.size() < 10)
    return Eigen::Vector3d::Zero();
  const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  std::vector<Eigen::Vector2d> flat;
  for (const auto& r : lateral)
    flat.emplace_back(r.dot(e1), r.dot(e2));
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& q : flat)
    mean += q;
  mean /= static_cast<double>(flat.size());
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (const auto& q : flat)
    C += (q - mean) * (q - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
  const Eigen::Vector2d ed = eig.eigenvectors().col(0), ea = eig.eigenvectors().col(1);
  std::vector<double> across;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d B = Eigen::Vector2d::Zero();
  for (const auto& q : flat)
  {
    const double x = (q - mean).dot(ea), y = (q - mean).dot(ed);
    across.push_back(x);
    const Eigen::Vector2d f(1.0, x * x);
    A += f * f.transpose();
    B += f * y;
  }
  const Eigen::Vector2d c = A.ldlt().solve(B);
  std::sort(across.begin(), across.end());
  const std::size_t lo = static_cast<std::size_t>(0.02 * static_cast<double>(across.size() - 1));
  const std::size_t hi = static_cast<std::size_t>(0.98 * static_cast<double>(across.size() - 1));
  const double R = 0.5 * (across[hi] - across[lo]);
  // A flat section (a strip seen from one side, a ribbon) bends by its noise alone: the parabola's sagitta over the
  // section (an arc of the front half of a circle bends by about R) must reach a quarter of the radius, or the
  // section's own centre line is the axis.
  if (arc && !(std::abs(c.y()) * R * R >= 0.25 * R))
    return Eigen::Vector3d::Zero();
  if (scatter)
  {
    double squares = 0.0;
    for (const auto& q : flat)
    {
      const double x = (q - mean).dot(ea), y = (q - mean).dot(ed);
      squares += (y - c.x() - c.y() * x * x) * (y - c.x() - c.y() * x * x);
    }
    *scatter = std::sqrt(squares / static_cast<double>(flat.size())) / R;
  }
  const double depth = c.x() + (c.y() > 0.0 ? R : -R);
  const Eigen::Vector2d centre = mean + 0.5 * (across[hi] + across[lo]) * ea + depth * ed;
  if (!c.allFinite() || !(R > 0.0 && R <= 2.0 * half + spacing) || !(centre.norm() <= R))
    return Eigen::Vector3d::Zero();
  return centre.x() * e1 + centre.y() * e2;
}

/// The line through `section` (the stalk's points): their centroid and principal direction, pointing along `u`.
/// Not fitted when they are fewer than 10 or not elongated (their spread along the line at most 3 times across it).
void FitStalkLine(const std::vector<Eigen::Vector3d>& section, const std::vector<Eigen::Vector3d>& across,
  const Eigen::Vector3d& u, double spacing, StalkAxis& axis)
{
  if (section.size() < 10)
    return;
  const FittedPlane fit = FitPlane(section);
  if (!(fit.moments[2] > 9.0 * fit.moments[1]))
    return;
  axis.fitted = true;
  axis.centroid = fit.centroid;
  axis.direction = fit.major.dot(u) < 0.0 ? Eigen::Vector3d(-fit.major) : fit.major;
  const Eigen::Vector3d offset = AxisOffset(across, u, axis.half, spacing, true, &axis.arcScatter);
  axis.lineOffset = offset - offset.dot(axis.direction) * axis.direction;
}

/// Whether a point `r` from the centroids' line (along `u`), beyond the stalk's width from it, is still the stalk's:
/// that line lies on the seen side, up to a radius off the axis (`offset`, from AxisOffset), and the stalk's far side
/// (seen from a second scanner position, or its inside through a cut end) and its flanks lie farther than the seen
/// side's width from it. Such a point lies within that width (`narrow`) of the stalk's own axis, less a quarter of
/// the offset (the offset's own uncertainty, from a parabola through a few points: a blade's point beside the stalk
/// is not taken for it). Less half the offset, a dense scan's flank points (a stalk 2.5 spacings thick seen from two
/// sides, down to its axis) lay beyond it, as the spacing's share of `narrow` is small there, and ended the walk
/// towards the blade 4 radii out on the stalk.
bool OnFarSide(const Eigen::Vector3d& offset, const Eigen::Vector3d& u, const Eigen::Vector3d& r, double narrow)
{
  if (!(offset.norm() > 0.0))
    return false;
  const Eigen::Vector3d fromAxis = r - offset;
  return (fromAxis - fromAxis.dot(u) * u).norm() <= narrow - 0.25 * offset.norm();
}

StalkAxis JunctionEnd(const std::vector<Eigen::Vector3d>& points, const Trail& trail, const Bins& b, std::size_t start,
  double spacing, Petiole& petiole)
{
  std::size_t k1 = start + 1;
  while (k1 < b.count.size() && b.count[k1] == 0)
    ++k1;
  const std::size_t k2 = std::min(b.count.size() - 1, k1 + 4);
  const double from = start * b.width, near = from + 2.0 * b.width;
  if (k1 >= b.count.size() || k2 <= k1 || b.count[k2] == 0 || !((b.centre[k1] - b.centre[k2]).norm() > 0.0))
  {
    // Too short to have an axis: the mean of the stalk's points nearest the blade.
    std::size_t n = 0;
    for (std::size_t k = 0; k < trail.ids.size(); ++k)
      if (petiole.member[trail.ids[k]] && trail.distance[k] < from + b.width)
      {
        petiole.junction += points[trail.ids[k]];
        ++n;
      }
    petiole.junction /= static_cast<double>(std::max<std::size_t>(1, n));
    return {};
  }
  const Eigen::Vector3d origin = b.centre[k1], u = (b.centre[k1] - b.centre[k2]).normalized(); // towards the blade
  auto lateral = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d r = p - origin;
    return (r - r.dot(u) * u).norm();
  };
  std::vector<double> own, along;
  std::vector<Eigen::Vector3d> across;  // the stalk's cross-section: its first 20 bins about their centroids
  std::vector<Eigen::Vector3d> section; // those points themselves
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
  {
    const std::size_t bin = std::min(b.count.size() - 1, static_cast<std::size_t>(trail.distance[k] / b.width));
    if (bin >= k1 && bin < k1 + 20)
    {
      const Eigen::Vector3d r = points[trail.ids[k]] - b.centre[bin];
      across.push_back(r - r.dot(u) * u);
      section.push_back(points[trail.ids[k]]);
    }
    if (trail.distance[k] >= from + b.width && trail.distance[k] < from + 6.0 * b.width)
    {
      own.push_back(lateral(points[trail.ids[k]]));
      along.push_back((points[trail.ids[k]] - origin).dot(u));
    }
  }
  double half = 0.0;
  if (!own.empty())
  {
    const std::size_t q = static_cast<std::size_t>(0.8 * static_cast<double>(own.size() - 1));
    std::nth_element(own.begin(), own.begin() + q, own.end());
    half = own[q];
  }
  // The blade reaches as far from it as its farthest sample wider than the stalk (not the stalk's far side or
  // flank, OnFarSide): everything nearer is blade.
  const Eigen::Vector3d offset = AxisOffset(across, u, half, spacing);
  double cut = -1.0;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
  {
    const Eigen::Vector3d& p = points[trail.ids[k]];
    if (petiole.member[trail.ids[k]] && trail.distance[k] < near && lateral(p) > half + spacing &&
      !OnFarSide(offset, u, p - origin, half + spacing))
      cut = std::max(cut, trail.distance[k]);
  }
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    if (trail.distance[k] < near && trail.distance[k] <= cut)
      petiole.member[trail.ids[k]] = 0;
  // The junction: the stalk's points nearest the blade (within half a bin of the nearest), averaged.
  double nearest = 1e300;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    if (petiole.member[trail.ids[k]])
      nearest = std::min(nearest, trail.distance[k]);
  std::size_t count = 0;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    if (petiole.member[trail.ids[k]] && trail.distance[k] <= nearest + 0.5 * b.width)
    {
      petiole.junction += points[trail.ids[k]];
      ++count;
    }
  petiole.junction /= static_cast<double>(std::max<std::size_t>(1, count));
  StalkAxis axis{ !own.empty(), origin, u, half, LargestGap(along), offset };
  FitStalkLine(section, across, u, spacing, axis);
  return axis;
}

/// Where the line through `centre` along the unit vector `u` (the stalk's axis) meets the plane of the points within
/// `radius` of `centre` that are not the petiole's and lie farther than `narrow` from the line: the distance along
/// `u`, or none when they are fewer than `least`, are not a sheet (their thickness well below their extent, not the
/// stalk's surroundings in 3-D), or the line lies within 15 degrees of their plane (in or near the plane, it would
/// meet it anywhere). `near`: the points within `radius`. `plane`, when given: the plane's unit normal and the
/// points' standard deviation about it.
std::optional<double> AxisMeetsPlane(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const Eigen::Vector3d& centre, const Eigen::Vector3d& u, double radius, double narrow, std::size_t least,
  const Petiole& petiole, std::vector<int>& near, std::pair<Eigen::Vector3d, double>* plane = nullptr)
{
  std::vector<int> around;
  grid.Within(centre, radius, near);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int j : near)
  {
    const Eigen::Vector3d r = points[j] - centre;
    if (!petiole.member[j] && (r - r.dot(u) * u).norm() > narrow)
    {
      around.push_back(j);
      mean += points[j];
    }
  }
  if (around.size() < least)
    return std::nullopt;
  mean /= static_cast<double>(around.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (int j : around)
    C += (points[j] - mean) * (points[j] - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  const Eigen::Vector3d n = eig.eigenvectors().col(0);
  if (!(eig.eigenvalues()[0] < 0.1 * eig.eigenvalues()[1]) ||
    std::abs(u.dot(n)) < std::sin(15.0 * 3.14159265358979323846 / 180.0))
    return std::nullopt;
  if (plane)
    *plane = { n, std::sqrt(std::max(eig.eigenvalues()[0], 0.0) / static_cast<double>(around.size())) };
  return (mean - centre).dot(n) / u.dot(n);
}

/// Where the stalk's axis, from `position` on, meets the blade: the plane of the points around `position` off the
/// axis (the blade's end, or the basal lobes around a sinus). Below a cordate base those reach the axis before
/// the stalk meets the blade, which lies on in the lobes' plane. Only a stalk leaving that plane at 15 degrees or
/// more is followed there (in or near the plane, the line would meet it anywhere); the stalk's points on the way
/// join the petiole.
void MeetBlade(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double spacing, const StalkAxis& axis,
  const Eigen::Vector3d& position, Petiole& petiole)
{
  const Eigen::Vector3d& u = axis.towardsBlade;
  const double narrow = axis.half + 0.75 * spacing, reach = axis.half + 6.0 * spacing;
  std::vector<int> near;
  const std::optional<double> meets = AxisMeetsPlane(points, grid, position, u, reach, narrow, 10, petiole, near);
  if (!meets)
    return;
  const double lambda = *meets;
  if (!(lambda > 0.0 && lambda < reach))
    return;
  for (int j : near)
  {
    const Eigen::Vector3d r = points[j] - position;
    const double along = r.dot(u);
    if (along >= 0.0 && along <= lambda && (r - along * u).norm() <= narrow)
      petiole.member[j] = 1;
  }
  petiole.junction = position + lambda * u;
  petiole.meetsPlane = true;
}

/// The stalk run through the gaps between its lines to a slice wider than it (from `position`, one spacing along
/// `u`) ends at the slice's near side, on the line of its last points (`last`). The slice's points within the stalk's
/// width of the axis (`slice`) are its top, seen by the line that crosses it where it meets the blade: they join the
/// petiole (left with the blade, they were its lowest samples, and the base's tip extrapolated from them lay out on
/// the stalk).
void EndInWideSlice(const std::vector<int>& slice, const Eigen::Vector3d& position, const Eigen::Vector3d& u,
  const Eigen::Vector3d& last, Petiole& petiole)
{
  for (int j : slice)
    petiole.member[j] = 1;
  const Eigen::Vector3d r = last - position;
  petiole.junction = position + (r - r.dot(u) * u);
}

/// The points of the slice one spacing thick (along the stalk's axis, `axis.towardsBlade`) centred on `centre` that lie
/// within the stalk's half-width and 2 spacings of the axis: those within its width (its half-width and 0.75
/// spacings; `slice`) and its far side or flanks beyond that width (OnFarSide; `farSide`). True when any other point
/// lies beyond that width (the slice is wider than the stalk). `near`: scratch.
bool SortSlice(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const StalkAxis& axis,
  const Eigen::Vector3d& centre, double spacing, std::vector<int>& near, std::vector<int>& slice,
  std::vector<int>& farSide)
{
  const Eigen::Vector3d& u = axis.towardsBlade;
  const double narrow = axis.half + 0.75 * spacing, look = axis.half + 2.0 * spacing;
  grid.Within(centre, std::hypot(look, 0.5 * spacing), near);
  slice.clear();
  farSide.clear();
  bool wide = false;
  for (int j : near)
  {
    const Eigen::Vector3d r = points[j] - centre;
    const double along = r.dot(u), lateral = (r - along * u).norm();
    if (std::abs(along) > 0.5 * spacing || lateral > look)
      continue;
    if (lateral > narrow && OnFarSide(axis.offset, u, r, narrow))
      farSide.push_back(j); // the stalk's, but not where its seen side's slice is centred
    else if (lateral > narrow)
      wide = true;
    else
      slice.push_back(j);
  }
  return wide;
}

/// The opening's ball covers the stalk's first few spacings beside the blade (and, below a cordate base, the stalk
/// between the basal lobes): from the junction found so far, the stalk is followed along its axis towards the blade in
/// slices one spacing thick while each slice's points within 2 spacings of the axis all lie within the stalk's width,
/// centred on the axis (the blade, a lobe, the blade's end, reaches further from the axis); those points join the
/// petiole and the junction moves to the last such slice. A gap ends the stalk too (beyond it, on the axis, lies the
/// end of a wedge-shaped blade), but only one wider than the gaps between the stalk's own samples along its axis: a
/// line scan crosses a stalk in lines that may lie more than a slice apart, and an empty slice between two of them is
/// still the stalk (the walk stopped there, up to 5 spacings short of the blade, whose ball covered the rest). A slice
/// wider than the stalk right after such empty slices ends the stalk at that slice's near side: the stalk ran on
/// through the gap (the junction left at the last slice with points lay 2.2 radii out on the benchmark's flat
/// watermelon seen from above), and that slice's points within the stalk's width are its top (EndInWideSlice). The
/// stalk's far side and flanks are not wider than it (OnFarSide): they join the petiole with their slice, which is
/// judged centred on the axis without them (they lie off the seen side's centre line). On a noisy stalk
/// (StalkAxis::noisy) a slice that the points beyond the stalk's width make wide does not end the walk when the next
/// slice holds points and none beyond that width: the blade is a sheet, wider than the stalk in every slice from the
/// junction on, while the noise throws a stalk's point beyond its width here and there (at 1 % range noise the walk
/// stopped on such a slice up to 9.5 spacings out on the benchmark's stalks).
void FollowStalkToBlade(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double spacing,
  const StalkAxis& axis, Petiole& petiole)
{
  if (!axis.valid)
    return;
  const Eigen::Vector3d& u = axis.towardsBlade;
  Eigen::Vector3d position = petiole.junction;
  std::vector<int> near, slice, farSide, nextSlice, nextFarSide;
  const int skippable = static_cast<int>(std::floor(axis.gap / spacing)); // empty slices a stalk's gap spans
  int empty = 0;
  for (int step = 0; step < 10000; ++step)
  {
    const Eigen::Vector3d centre = position + 0.5 * spacing * u;
    bool wide = SortSlice(points, grid, axis, centre, spacing, near, slice, farSide);
    if (wide && axis.noisy && empty == 0 &&
      !SortSlice(points, grid, axis, centre + spacing * u, spacing, near, nextSlice, nextFarSide) && !nextSlice.empty())
      wide = false; // the noise's: the next slice is the stalk's alone
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int j : slice)
      mean += points[j];
    if (!wide && slice.empty() && empty < skippable)
    {
      ++empty; // between two of the stalk's lines: the junction stays at the last slice with points
      position += spacing * u;
      continue;
    }
    if (wide || slice.empty())
    {
      const Eigen::Vector3d last = petiole.junction;
      MeetBlade(points, grid, spacing, axis, position - empty * spacing * u, petiole);
      // Wider than the stalk right after empty slices taken as the gaps between its lines: the stalk runs through
      // them to this slice, so the junction is at its near side (on the line of the stalk's last points), not back
      // at the last slice with points (up to `skippable` spacings out on the stalk).
      if (wide && empty > 0 && !petiole.meetsPlane)
        EndInWideSlice(slice, position, u, last, petiole);
      break;
    }
    empty = 0;
    // A stalk's slice is centred on its axis; the blade's end beyond the junction leaves it at the stalk's angle to
    // the blade (the end of a wedge-shaped base is as narrow as the stalk).
    mean /= static_cast<double>(slice.size());
    const Eigen::Vector3d r = mean - centre;
    if ((r - r.dot(u) * u).norm() > spacing)
      break;
    for (int j : slice)
      petiole.member[j] = 1;
    for (int j : farSide)
      petiole.member[j] = 1;
    petiole.junction = mean;
    position += spacing * u;
  }
}

/// A junction the walk left where the stalk's seen side meets the blade (no plane of lobes met around the walk's
/// end) moves to where the stalk's own axis (the line through `q`, on the centroids' line, moved by the offset of
/// AxisOffset) meets the blade's plane (the points within `radius` farther than `narrow` from it), when that lies
/// ahead of it, within `radius`. BackToPlane calls it only where no fitted axis is read (ToFittedAxis: a section
/// that does not bend like a tube's, or no plane met on that axis): the centroids' line wanders with its two
/// centroids.
void ToStalkAxis(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const StalkAxis& axis,
  const Eigen::Vector3d& q, double radius, double narrow, Petiole& petiole)
{
  if (!(axis.offset.norm() > 0.0) || petiole.meetsPlane)
    return;
  std::vector<int> near;
  const std::optional<double> meets =
    AxisMeetsPlane(points, grid, q + axis.offset, axis.towardsBlade, radius, narrow, 20, petiole, near);
  if (!meets || !(*meets > 0.0 && *meets < radius))
    return;
  petiole.junction = q + axis.offset + *meets * axis.towardsBlade;
  petiole.meetsPlane = true;
}

/// Where the stalk's own axis meets the blade's plane: the line fitted through the stalk's points (FitStalkLine),
/// moved onto the axis by AxisOffset (only a section that bends like a tube's: a flat strip's centre line is its
/// axis). The junction moves there, back towards the stalk's far end (the cusp the walk ran into) or ahead (the seen
/// side met the plane first, not on a plane of lobes); within 2 spacings behind it stays (the plane's and the axis's
/// scatter). False when there is no such axis or no plane within 12 spacings.
bool ToFittedAxis(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double spacing,
  const StalkAxis& axis, Petiole& petiole)
{
  if (!axis.fitted || !(axis.lineOffset.norm() > 0.0))
    return false;
  const Eigen::Vector3d& w = axis.direction;
  const Eigen::Vector3d a = axis.centroid + axis.lineOffset;
  const Eigen::Vector3d q = a + (petiole.junction - a).dot(w) * w;
  const double narrow = axis.half + 0.75 * spacing, radius = 12.0 * spacing;
  std::vector<int> near;
  const std::optional<double> meets = AxisMeetsPlane(points, grid, q, w, radius, narrow, 20, petiole, near);
  if (!meets || !(std::abs(*meets) < radius))
    return false;
  const double lambda = *meets;
  if (lambda > -2.0 * spacing && (lambda <= 0.0 || petiole.meetsPlane))
    return true;
  if (lambda < 0.0)
    for (std::size_t j = 0; j < points.size(); ++j)
      if (petiole.member[j] && (points[j] - q).dot(w) > lambda)
        petiole.member[j] = 0;
  petiole.junction = q + lambda * w;
  petiole.meetsPlane = true;
  return true;
}

/// A stalk that leaves the blade's plane ends where its axis meets that plane. On a blade whose base narrows to a
/// cusp (a cuneate base, the ginkgo's) the cusp is as narrow as the stalk and lies on in line with it, so the trail
/// and the walk along it run on into the blade; the cusp lies in the blade's plane, the stalk below or above it.
/// The blade's plane: its points (not the stalk's, farther from the axis than the stalk's width) within 12 spacings
/// of the junction. When the centroids' line meets it more than 2 spacings behind the junction (towards the stalk's
/// far end), the junction moves back there and the points beyond it go back to the blade. That line lies on the
/// stalk's seen side and its direction, through two bins' centroids, tilts with their wandering (two passes seeing
/// two sides: 14 degrees from the blade's plane for a stalk at 30), so when it meets the plane behind the junction
/// or not at all, the fitted axis decides (ToFittedAxis) where it can; and so it does when the line meets the plane
/// at or ahead of the junction: there the centroids' line moved by the seen side's offset (ToStalkAxis, only where
/// no fitted axis is read) put the junction up to 2 % of the length inside the blade (its direction 5 degrees too
/// shallow and 6 to the side, the offset taken from a line that passes nearer the axis than the seen side does).
void BackToPlane(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double spacing,
  const StalkAxis& axis, Petiole& petiole)
{
  if (!axis.valid)
    return;
  const Eigen::Vector3d& u = axis.towardsBlade;
  const Eigen::Vector3d q = axis.origin + (petiole.junction - axis.origin).dot(u) * u;
  const double narrow = axis.half + 0.75 * spacing, radius = 12.0 * spacing;
  std::vector<int> near;
  const std::optional<double> meets = AxisMeetsPlane(points, grid, q, u, radius, narrow, 20, petiole, near);
  const bool behind = meets && *meets > -radius && *meets < -2.0 * spacing; // met behind the junction
  if ((!meets || behind) && ToFittedAxis(points, grid, spacing, axis, petiole))
    return;
  if (!meets)
    return;
  const double lambda = *meets;
  if (!(lambda < -2.0 * spacing && lambda > -radius))
  {
    if (!ToFittedAxis(points, grid, spacing, axis, petiole))
      ToStalkAxis(points, grid, axis, q, radius, narrow, petiole);
    return;
  }
  for (std::size_t j = 0; j < points.size(); ++j)
    if (petiole.member[j] && (points[j] - q).dot(u) > lambda)
      petiole.member[j] = 0;
  petiole.junction = q + lambda * u;
  petiole.meetsPlane = true;
}

/// A stalk seen through range noise about as large as its radius: where the noise moves each point along its beam,
/// a section's extreme points across the stalk are those the noise moved outwards, and on a beam seen obliquely
/// (two scanner positions either side of the stalk) outwards is also towards the scanner, so the section's ends
/// rise and the parabola through it bends the wrong way: the axis put a radius in front of the seen side, not
/// behind it (on the accuracy benchmark's stalks at 1 % noise from two positions, every arc that passed AxisOffset's
/// test bent so). The line then stays on the seen points' centroid, within a radius of the axis on its right side,
/// when both the blade's scatter about its plane within 12 spacings of the junction is at least MinNoiseForAhead of
/// the stalk's half-width and the section's own scatter about its parabola at least MaxArcScatter of its
/// half-extent (either alone is met by sections bent the right way at 0.3 % noise: a blade curving beside its base,
/// a section seen sparsely).
void NoArcInTheNoise(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, double spacing, const Petiole& petiole, StalkAxis& axis)
{
  if (!(axis.lineOffset.norm() > 0.0) || axis.arcScatter < MaxArcScatter)
    return;
  std::vector<int> near;
  grid.Within(petiole.junction, 12.0 * spacing, near);
  std::vector<Eigen::Vector3d> around;
  for (int j : near)
    if (blade[j] && !petiole.member[j])
      around.push_back(points[j]);
  if (around.size() < 20)
    return;
  const FittedPlane plane = FitPlane(around);
  if (std::sqrt(plane.moments[0] / static_cast<double>(around.size())) >= MinNoiseForAhead * axis.half)
    axis.lineOffset = Eigen::Vector3d::Zero();
}

/// A stalk seen through range noise at least NoisyStalk of its half-width (`noise`, SheetNoise) is noisy, and its
/// section's arc is not read: the offsets from the lines through its seen side's points to its axis (AxisOffset's
/// parabolas, JunctionEnd's and FitStalkLine's) are dropped, and those lines are taken as they are, within a radius
/// of the axis on its right side. Their parabolas bend either way at that noise; the walk run on to the blade
/// (FollowStalkToBlade) then had the junction moved 7 spacings into the blade along one of them (ToStalkAxis, the
/// benchmark's curled cordate blade seen obliquely at 1 % range noise) and 3 spacings back out on the stalk along
/// another (ToFittedAxis, the flat watermelon seen from above).
void NoOffsetInTheNoise(double noise, StalkAxis& axis)
{
  if (!axis.valid || noise < NoisyStalk * axis.half)
    return;
  axis.noisy = true;
  axis.offset = Eigen::Vector3d::Zero();
  axis.lineOffset = Eigen::Vector3d::Zero();
}

/// A stalk whose walk stopped short of the blade (on a noisy scan its points scatter wider than its width, and the
/// walk stops at the first slice that looks wider), with no plane met around its junction (the blade lies beyond
/// the 12 spacings around it, so the points there are the stalk's and a few of the blade's, no sheet): the plane of
/// the points around the axis 12 spacings ahead (the stalk's fitted line where there is one; without the points
/// within twice the stalk's width of it; beside a rounded base those are half a disc, too short across for a sheet
/// at that noise, and then 24 spacings ahead) is looked for, and where the axis meets it, 2 to 24 spacings ahead, the
/// junction moves, when the blade's scatter about that plane is at least MinNoiseForAhead of the stalk's
/// half-width. The stalk's points on the way join the petiole. The plane is fitted again in the ball about the foot
/// of the first ball's centre on it: that centre lies on the axis, which rises past the blade at the stalk's angle,
/// up to most of the ball's radius off the blade 24 spacings ahead, and a ball reaching the blade only with its rim
/// holds the top of the blade's noise band (on the elliptic blade with a noisy strip for a stalk, its walk run on to
/// 1 % of the length from the base: 107 points whose mean lay a noise's width above the blade, met 2.5 % of the
/// length inside the blade, PetioleLength +10 %; fitted again through 698 points: +4 %, the base 0.1 % of the length
/// from the truth).
void AheadToPlane(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, double spacing,
  const StalkAxis& axis, Petiole& petiole)
{
  if (!axis.valid || petiole.meetsPlane)
    return;
  const bool fitted = axis.fitted && axis.direction.dot(axis.towardsBlade) > 0.0;
  const Eigen::Vector3d w = fitted ? axis.direction : axis.towardsBlade;
  const Eigen::Vector3d a = fitted ? Eigen::Vector3d(axis.centroid + axis.lineOffset) : axis.origin;
  const Eigen::Vector3d q = a + (petiole.junction - a).dot(w) * w;
  const double narrow = axis.half + 0.75 * spacing, radius = 12.0 * spacing;
  std::vector<int> near;
  std::pair<Eigen::Vector3d, double> plane;
  double lambda = std::numeric_limits<double>::quiet_NaN(); // no plane met: nothing moves
  for (const double ahead : { radius, 2.0 * radius })
    if (const auto meets =
          AxisMeetsPlane(points, grid, q + ahead * w, w, radius, 2.0 * narrow, 20, petiole, near, &plane))
    {
      lambda = ahead + *meets;
      // Fitted again in the ball about the foot of that centre on the plane, which holds the blade's noise band
      // whole (the first ball, centred on the axis where it rises past the blade, held only the band's top).
      const Eigen::Vector3d centre = q + ahead * w;
      const Eigen::Vector3d foot = centre - (centre - (q + lambda * w)).dot(plane.first) * plane.first;
      std::pair<Eigen::Vector3d, double> again;
      if (const auto there = AxisMeetsPlane(points, grid, foot, w, radius, 2.0 * narrow, 20, petiole, near, &again))
      {
        lambda = *there + (foot - q).dot(again.first) / w.dot(again.first);
        plane = again;
      }
      break;
    }
  if (!(lambda > 2.0 * spacing && lambda < 2.0 * radius) || plane.second < MinNoiseForAhead * axis.half)
    return;

  // The stalk's points on the way: within its width of the axis and off the blade's plane on the stalk's side by
  // more than twice the blade's scatter about it (beside the junction, the blade's own points, a cordate base's
  // lobes around the stalk, lie within its width of the axis too).
  const Eigen::Vector3d junction = q + lambda * w;
  const Eigen::Vector3d below = plane.first.dot(w) > 0.0 ? Eigen::Vector3d(-plane.first) : plane.first;
  grid.Within(q + 0.5 * lambda * w, 0.5 * lambda + narrow, near);
  for (int j : near)
  {
    const Eigen::Vector3d r = points[j] - q;
    const double along = r.dot(w);
    if (along >= 0.0 && along <= lambda && (r - along * w).norm() <= narrow &&
      (points[j] - junction).dot(below) > 2.0 * plane.second)
      petiole.member[j] = 1;
  }
  petiole.junction = junction;
  petiole.meetsPlane = true;
}

/// A stalk seen in pieces: a line scan leaves gaps along a stalk wider than the trail's link where something shadows
/// it or its lines cross it at a grazing angle, and the pieces beyond are left out of the trail (or dropped by the
/// cleaning as strays), so the stalk ends short. From the trail's far end the line through its last 20 spacings
/// (their centroid and principal direction, away from the blade) is followed: the nearest point ahead (or less than a
/// spacing behind the end: a line's other samples) that is not the blade's, lies within the stalk's width of the
/// line (its half-width plus 0.75 spacings) and no more than 12 spacings past the end joins the stalk, and the end
/// moves to it; a piece with points beside the line beyond that width (within 2 spacings more) or of the blade is no
/// stalk, and the walk stops. Returns the new far end, or none.
std::optional<Eigen::Vector3d> JoinStalkPieces(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& blade, const Trail& trail, double spacing, double half, Petiole& petiole)
{
  std::vector<Eigen::Vector3d> last;
  for (std::size_t k = 0; k < trail.ids.size(); ++k)
    if (petiole.member[trail.ids[k]] && trail.distance[k] >= trail.extent - 20.0 * spacing)
      last.push_back(points[trail.ids[k]]);
  if (last.size() < 5)
    return std::nullopt;
  const FittedPlane fit = FitPlane(last);
  if (!(fit.moments[2] > 9.0 * fit.moments[1]))
    return std::nullopt;
  const std::size_t far =
    static_cast<std::size_t>(std::max_element(trail.distance.begin(), trail.distance.end()) - trail.distance.begin());
  Eigen::Vector3d end = points[trail.ids[far]];
  const Eigen::Vector3d w = (end - fit.centroid).dot(fit.major) < 0.0 ? Eigen::Vector3d(-fit.major) : fit.major;
  const double narrow = half + 0.75 * spacing, look = half + 2.0 * spacing, reach = 12.0 * spacing;
  std::optional<Eigen::Vector3d> joined;
  std::vector<int> near;
  for (int guard = 0; guard < 100000; ++guard)
  {
    const double at = (end - fit.centroid).dot(w);
    grid.Within(end + 0.5 * reach * w, std::hypot(0.5 * reach, look), near);
    int next = -1;
    double nextAlong = 1e300;
    for (int j : near)
    {
      const Eigen::Vector3d r = points[j] - fit.centroid;
      const double along = r.dot(w), lateral = (r - along * w).norm();
      if (petiole.member[j] || along <= at - spacing || along > at + reach || lateral > narrow || blade[j])
        continue;
      if (along < nextAlong)
      {
        next = j;
        nextAlong = along;
      }
    }
    if (next < 0)
      break;
    // The piece beside that point: none of its points off the line beyond the stalk's width.
    grid.Within(points[next], 4.0 * spacing, near);
    for (int j : near)
    {
      const Eigen::Vector3d r = points[j] - fit.centroid;
      const double along = r.dot(w), lateral = (r - along * w).norm();
      if (along > at && (blade[j] || (lateral > narrow && lateral <= look)))
        return joined;
    }
    petiole.member[next] = 1;
    if (nextAlong > at)
    {
      end = points[next];
      joined = end;
    }
  }
  return joined;
}

/// True when the trail is a stalk: at least 6 spacings of stalk bins, thin (their spread at most 2.5 spacings, what
/// a strip the ball cannot fit in has, or a tenth of the blade's width: a stalk scanned from the side is sparser
/// than the blade, so wider in spacings; a sparsely sampled patch of blade is wider still), and not narrowing like
/// a wedge (a tip, a tooth): the first third of those bins (that hold enough points to measure) at most 1.6 times
/// as wide as the last third, or, on a stalk of 15 spacings or more (whose first part may taper: a winged petiole),
/// the middle third at most 1.25 times as wide as the last.
bool IsStalk(const Bins& bins, double spacing, double bladeWidth)
{
  const std::size_t start = FirstStalkBin(bins, spacing), n = bins.count.size();
  if (static_cast<double>(n - start) * bins.width < 6.0 * spacing ||
    bins.Spread(start) > std::max(2.5 * spacing, 0.1 * bladeWidth))
    return false;
  std::vector<double> measured;
  for (std::size_t k = start; k < n; ++k)
    if (bins.Measured(k))
      measured.push_back(bins.spread[k]);
  const std::size_t third = measured.size() / 3;
  if (third == 0)
    return false;
  const double inner = std::accumulate(measured.begin(), measured.begin() + third, 0.0) / third;
  const double middle = std::accumulate(measured.begin() + third, measured.end() - third, 0.0) /
    static_cast<double>(measured.size() - 2 * third);
  const double outer = std::accumulate(measured.end() - third, measured.end(), 0.0) / third;
  if (inner <= 1.6 * outer + 0.25 * spacing)
    return true;
  // A long stalk whose first part tapers (a winged petiole) keeps its width from its middle on.
  const double length = static_cast<double>(n - start) * bins.width;
  return length >= 15.0 * spacing && middle <= 1.4 * outer + 0.1 * spacing;
}
} // namespace

Petiole FindPetiole(const std::vector<Eigen::Vector3d>& points, double spacing, const ParallelFor& parallel,
  const std::vector<Eigen::Vector3d>& loose)
{
  Petiole petiole;
  petiole.member.assign(points.size(), 0);
  petiole.looseMember.assign(loose.size(), 0);
  if (points.size() < 20 || !(spacing > 0.0))
    return petiole;
  spacing = std::max(spacing, DensitySpacing(points));
  // The ball: 4 spacings (about 50 points inside the sheet; a trail up to 4 points wide holds at most 60 % of that,
  // a margin half of it).
  const double radius = 4.0 * spacing, link = 4.0 * spacing;
  const PointGrid grid(points, radius);
  const std::vector<unsigned char> blade = Opening(points, grid, radius, parallel);
  const std::size_t bladeCount = static_cast<std::size_t>(std::count(blade.begin(), blade.end(), 1));
  petiole.sheetShare = static_cast<double>(bladeCount) / static_cast<double>(points.size());
  // Too little blade the ball fits in (a narrow leaf, or a scan whose lines lie far apart over much of the blade,
  // as at a grazing angle): thin parts cannot be told from sparse blade (a line of a grazing scan crossing the blade
  // near its tip was taken for a stalk, the blade cut there, Length -26 %).
  if (petiole.sheetShare < MinSheetShareForPetiole)
    return petiole;
  // The blade's width: four standard deviations across it (an ellipse's width).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i)
    if (blade[i])
      mean += points[i];
  mean /= static_cast<double>(bladeCount);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i)
    if (blade[i])
      C += (points[i] - mean) * (points[i] - mean).transpose();
  const double bladeWidth =
    4.0 * std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C / bladeCount).eigenvalues()[1]));
  // A stalk leaving the blade across the unseen end of its base lies up to 20 spacings from the blade's samples (12
  // to 16 on an acuminate base scanned at about 10^4 points); a stray piece that far out is still tested as a stalk.
  const double gap = 20.0 * spacing;
  const std::vector<Trail> trails = Trails(points, grid, blade, link, gap, spacing);
  const Trail* best = nullptr;
  Bins bestBins;
  for (const Trail& trail : trails)
  {
    if (trail.extent < 5.0 * spacing || trail.ids.size() < 5)
      continue;
    Bins bins = CentreLine(points, trail, 1.5 * spacing);
    if (IsStalk(bins, spacing, bladeWidth) && (!best || trail.extent > best->extent))
    {
      best = &trail;
      bestBins = std::move(bins);
    }
  }
  if (!best)
    return petiole;
  // The stalk proper, from its junction with the blade (bins before it are the blade's narrow end).
  const std::size_t start = FirstStalkBin(bestBins, spacing);
  const double from = start * bestBins.width;
  if (best->extent - from < 5.0 * spacing)
    return petiole;
  petiole.found = true;
  petiole.acrossGap = best->acrossGap;
  for (std::size_t k = 0; k < best->ids.size(); ++k)
    if (best->distance[k] >= from)
      petiole.member[best->ids[k]] = 1;
  StalkAxis axis = JunctionEnd(points, *best, bestBins, start, spacing, petiole);
  NoArcInTheNoise(points, grid, blade, spacing, petiole, axis);
  NoOffsetInTheNoise(SheetNoise(points, grid, blade, radius), axis);
  FollowStalkToBlade(points, grid, spacing, axis, petiole);
  BackToPlane(points, grid, spacing, axis, petiole);
  AheadToPlane(points, grid, spacing, axis, petiole);
  // The centre line: the junction, the centroids of the stalk's bins after the first that lie beyond the junction
  // along the stalk's axis (a junction moved back to the blade's plane leaves bins of the cusp behind it), and its
  // farthest point. A bin's centroid lies on the side of the stalk its few points were seen from, which changes
  // from bin to bin (a line scan crosses the stalk in lines; two scans see two sides): it wanders across the stalk
  // by up to its half-width, and a line through every bin zigzags, longer than the stalk. Centroids are kept at
  // least two stalk widths (4 half-widths) apart along the trail.
  const std::size_t far =
    static_cast<std::size_t>(std::max_element(best->distance.begin(), best->distance.end()) - best->distance.begin());
  const double halfWidth = axis.valid ? axis.half : 2.0 * bestBins.Spread(start);
  const double step = std::max(bestBins.width, 4.0 * halfWidth);
  double last = from;
  petiole.line.push_back(petiole.junction);
  for (std::size_t k = start + 1; k < bestBins.centre.size(); ++k)
  {
    const double at = (static_cast<double>(k) + 0.5) * bestBins.width;
    if (bestBins.count[k] > 0 && at >= last + step &&
      !(axis.valid && (bestBins.centre[k] - petiole.junction).dot(axis.towardsBlade) > 0.0))
    {
      petiole.line.push_back(bestBins.centre[k]);
      last = at;
    }
  }
  const double half = axis.valid ? axis.half : halfWidth;
  petiole.halfWidth = half;
  std::optional<Eigen::Vector3d> beyond;
  if (loose.empty())
    beyond = JoinStalkPieces(points, grid, blade, *best, spacing, half, petiole);
  else
  {
    // The cleaning's strays may be the stalk's far pieces: they are looked at with the rest.
    std::vector<Eigen::Vector3d> all = points;
    all.insert(all.end(), loose.begin(), loose.end());
    std::vector<unsigned char> allBlade = blade;
    allBlade.resize(all.size(), 0);
    Petiole joined;
    joined.member = petiole.member;
    joined.member.resize(all.size(), 0);
    beyond = JoinStalkPieces(all, PointGrid(all, radius), allBlade, *best, spacing, half, joined);
    std::copy(joined.member.begin(), joined.member.begin() + points.size(), petiole.member.begin());
    petiole.looseMember.assign(joined.member.begin() + points.size(), joined.member.end());
  }
  petiole.line.push_back(points[best->ids[far]]);
  if (beyond)
    petiole.line.push_back(*beyond);
  for (std::size_t k = 1; k < petiole.line.size(); ++k)
    petiole.length += (petiole.line[k] - petiole.line[k - 1]).norm();
  return petiole;
}

} // namespace fit
} // namespace plantmorph
