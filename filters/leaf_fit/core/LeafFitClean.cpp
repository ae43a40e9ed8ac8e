// SPDX-License-Identifier: GPL-3.0-or-later
// FitLeaf's first steps: checking the cloud, removing outliers, and the leaf's frame.
#include "LeafFitInternal.h"
#include "PointGrid.h"

#include <plantmorph/PlaneFit.h>
#include <plantmorph/graph/DisjointSets.h>
#include <plantmorph/statistics/Median.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace plantmorph
{
namespace fit
{
namespace
{
/// Eigenvalues (ascending) and eigenvectors of the points' covariance.
Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> Principal(
  const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d& centroid)
{
  centroid.setZero();
  for (const Eigen::Vector3d& p : points)
    centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points)
    C += (p - centroid) * (p - centroid).transpose();
  C /= static_cast<double>(points.size());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C);
}

/// For each root of `parts` (1 at its index): whether that part, of at least `minPoints` kept points and under 5 % of
/// the largest part, is a piece of the same sheet cut off by a gap: a sheet itself (its smallest principal spread
/// at most a quarter of its largest) no farther from the largest part than its own extent (the diagonal of its
/// bounding box). A lobe that the scanner saw beyond a shadow across its neck (a twig or leaf in front of it) is such
/// a part: a basal lobe of the lobed plant's blade seen from four positions, 137 of its 8298 points, 7 spacings off
/// the blade and 45 across (spread ratio 0.01); dropped, the blade lost the lobe and the slices across it centred
/// the midvein off the true one. A stray clump is thick (0.37 on a soybean scan's clump of 41 points, 16 spacings
/// off its leaf) or lies farther from the blade than its own size.
std::vector<unsigned char> PartsBesideTheBlade(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid,
  const std::vector<unsigned char>& keep, DisjointSets<int>& parts, const std::vector<int>& size, int minPoints)
{
  const int n = static_cast<int>(points.size());
  std::vector<unsigned char> beside(points.size(), 0);
  const int largestRoot = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<unsigned char> inLargest(points.size(), 0);
  std::vector<std::vector<int>> members(points.size());
  for (int i = 0; i < n; ++i)
  {
    if (!keep[i])
      continue;
    const int root = parts.Find(i);
    inLargest[i] = root == largestRoot ? 1 : 0;
    if (root != largestRoot && size[root] >= minPoints && size[root] * 20 < size[largestRoot])
      members[root].push_back(i);
  }
  for (int root = 0; root < n; ++root)
  {
    const std::vector<int>& part = members[root];
    if (part.empty())
      continue;
    std::vector<Eigen::Vector3d> sheet;
    Eigen::Vector3d low = points[part.front()], high = low;
    for (int i : part)
    {
      low = low.cwiseMin(points[i]);
      high = high.cwiseMax(points[i]);
      sheet.push_back(points[i]);
    }
    const Eigen::Vector3d spread = FitPlane(sheet).moments.cwiseMax(0.0);
    if (!(spread[0] <= 0.0625 * spread[2]))
      continue;
    const double extent = (high - low).norm();
    for (int i : part)
      if (grid.AnyWithin(points[i], extent, inLargest))
      {
        beside[root] = 1;
        break;
      }
  }
  return beside;
}
} // namespace

std::string ValidateCloud(const std::vector<Eigen::Vector3d>& points)
{
  std::ostringstream message;
  if (points.size() < static_cast<std::size_t>(MinLeafPoints))
  {
    message << "too few points: " << points.size() << " (a leaf needs at least " << MinLeafPoints << ")";
    return message.str();
  }
  std::size_t bad = 0;
  for (const Eigen::Vector3d& p : points)
    bad += p.allFinite() ? 0 : 1;
  if (bad > 0)
  {
    message << bad << " point(s) with a NaN or infinite coordinate (remove them before fitting)";
    return message.str();
  }
  Eigen::Vector3d centroid;
  const auto eig = Principal(points, centroid);
  const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);
  if (!(l[2] > 0.0) || std::sqrt(l[1] / l[2]) < 1e-3)
    return "the points lie on a line (or a point): no leaf blade to fit";
  if (std::sqrt(l[0] / l[2]) > 0.6)
    return "no leaf shape: the cloud is about as thick as it is long (not a sheet of points)";
  return {};
}

std::string CleanCloud(const std::vector<Eigen::Vector3d>& points, double outlierSigma,
  std::vector<unsigned char>& keep, double& spacing, const ParallelFor& parallel)
{
  const int n = static_cast<int>(points.size());
  const int k = 8;
  const double cell = PointGrid::CellFor(points, 4.0);
  const PointGrid grid(points, cell, parallel);
  // Neighbours are looked for within 8 cells (about 16 point spacings on the sheet; the search cost grows with the
  // cube of the reach): a point with fewer than k there counts its missing neighbours at that distance, beyond the
  // outlier limit below.
  const double reach = 8.0 * cell;
  std::vector<double> meanDistance(n), nearest(n);
  std::vector<std::pair<double, int>> neighbours(static_cast<std::size_t>(n) * k, { 0.0, -1 });
  const std::vector<int>& ids = grid.SortedIds(); // cell by cell: neighbouring queries share cells (and cache)
  ForEachIndex(parallel, ids.size(), [&](std::size_t at) {
    const int i = ids[at];
    const auto nb = grid.Nearest(points[i], k, i, reach);
    double sum = (k - static_cast<double>(nb.size())) * reach;
    for (std::size_t j = 0; j < nb.size(); ++j)
    {
      sum += std::sqrt(nb[j].first);
      neighbours[static_cast<std::size_t>(i) * k + j] = { std::sqrt(nb[j].first), nb[j].second };
    }
    meanDistance[i] = sum / k;
    nearest[i] = nb.empty() ? reach : std::sqrt(nb.front().first);
  });
  // Statistical outlier removal, robust: a point is dropped when its mean neighbour distance is beyond the median
  // by OutlierSigma robust deviations AND five times the median. Points on the margin have about 1.4 times the
  // median, and at a sharp tip, whose neighbours all lie in a narrow wedge, up to sqrt(pi / half-angle) times it:
  // they must stay, or the outline shrinks. Points off the surface closer than that go in the surface's robust fit.
  const double median = Median(meanDistance, 0.0);
  const double sigma = RobustScale(meanDistance, median, 0.0);
  const double limit = std::min(std::max(median + outlierSigma * sigma, 5.0 * median), 0.9 * reach);
  keep.assign(n, 0);
  for (int i = 0; i < n; ++i)
    keep[i] = meanDistance[i] <= limit ? 1 : 0;
  // Connected parts of the graph of k nearest neighbours closer than three median distances: keep the largest and
  // every part of at least 5 % of it (a scan with a gap across it is still one leaf).
  DisjointSets<int> parts(static_cast<std::size_t>(n));
  const double radius = 3.0 * median;
  for (int i = 0; i < n; ++i)
  {
    if (!keep[i])
      continue;
    for (int j = 0; j < k; ++j)
    {
      const auto& nb = neighbours[static_cast<std::size_t>(i) * k + j];
      if (nb.second >= 0 && keep[nb.second] && nb.first <= radius)
        parts.Join(i, nb.second);
    }
  }
  // On a line scan a point's k nearest neighbours all lie on its own line: the lines are joined where points lie
  // within twice the spacing across them (CrossSpacing), or a line beyond a wider gap is dropped as a stray part.
  const double across = 2.0 * CrossSpacing(points, grid, parallel);
  if (across > radius)
  {
    std::vector<int> near;
    for (int i = 0; i < n; ++i)
      if (keep[i])
      {
        grid.Within(points[i], across, near);
        for (int j : near)
          if (keep[j])
            parts.Join(i, j);
      }
  }
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i)
    if (keep[i])
      ++size[parts.Find(i)];
  const int largest = *std::max_element(size.begin(), size.end());
  const std::vector<unsigned char> besideBlade = PartsBesideTheBlade(points, grid, keep, parts, size, 2 * k);
  std::vector<double> kept;
  for (int i = 0; i < n; ++i)
  {
    if (keep[i] && size[parts.Find(i)] * 20 < largest && !besideBlade[parts.Find(i)])
      keep[i] = 0;
    if (keep[i])
      kept.push_back(nearest[i]);
  }
  if (kept.size() < static_cast<std::size_t>(MinLeafPoints))
  {
    std::ostringstream message;
    message << "too few points after outlier removal: " << kept.size() << " of " << n << " (a leaf needs at least "
            << MinLeafPoints << ")";
    return message.str();
  }
  spacing = Median(kept, 0.0);
  if (!(spacing > 0.0))
    return "the points are duplicates of each other (zero spacing)";
  return {};
}

namespace
{
/// The blade point nearest q.
Eigen::Vector3d Nearest(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& q)
{
  std::size_t best = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if ((points[i] - q).squaredNorm() < (points[best] - q).squaredNorm())
      best = i;
  return points[best];
}

/// The length in slices of a terminal lobe at the end of the slice widths `width` (the high end when `high`), or 0:
/// a narrow end (under 0.35 of the widest slice) for two to six slices, after which the blade widens by more than
/// 0.4 of the widest within two slices (10 % of the length), where the lateral lobes begin beyond the sinuses beside
/// it, or, on a shallowly lobed blade, narrows again by more than 0.05 of the widest and then widens beyond the lobe
/// within the next six slices (the sinuses between the terminal lobe and the first lateral lobes). A base widens steadily from
/// a wedge (a fan, a cuneate base), or is a sinus (wide), or is where the lobes meet, narrow for fewer slices than the
/// terminal lobe (the lateral lobes reach back beside it).
int TerminalLobe(const std::vector<double>& width, double widest, bool high)
{
  const int n = static_cast<int>(width.size());
  const auto at = [&](int k) { return width[high ? n - 1 - k : k] / widest; };
  int run = 0;
  while (run < 7 && at(run) < 0.35)
    ++run;
  if (run < 2 || run >= 7)
    return 0;
  if (at(run + 1) - at(run - 1) > 0.4)
    return run;
  // A sinus: the width falls from the lobe's widest by over 0.05 of the widest, then widens beyond it.
  double lobe = at(run - 1), dip = 1e300;
  for (int k = run; k < std::min(n, run + 6); ++k)
  {
    if (dip > 1.0 && at(k) < lobe - 0.05)
      dip = at(k);
    else if (dip > 1.0)
      lobe = std::max(lobe, at(k));
    else if (at(k) > lobe)
      return run;
    else
      dip = std::min(dip, at(k));
  }
  return 0;
}

/// The centroid of the area the points cover, not of the points: each point weighted by the area it stands for in
/// the plane normal to `normal` (where the blade's symmetry is sought), the squared distance to its 8th nearest
/// neighbour there; `centroid` when they all coincide. A scanner seeing the blade obliquely samples its near side
/// more densely than its far side, which pulls the points' centroid across the blade, and a mirror line along the
/// midvein through that point leaves the midvein's mirror images off the blade.
Eigen::Vector3d AreaCentroid(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
  const Eigen::Vector3d& centroid, const ParallelFor& parallel)
{
  std::vector<Eigen::Vector3d> flat(points.size());
  ForEachIndex(parallel, points.size(), [&](std::size_t i) { flat[i] = points[i] - points[i].dot(normal) * normal; });
  const PointGrid grid(flat, PointGrid::CellFor(flat, 4.0), parallel);
  // The weights searched on the threads, summed in index order (the sum is the serial one, bit for bit).
  std::vector<double> weights(points.size());
  ForEachIndex(parallel, points.size(), [&](std::size_t i) {
    const auto nearest = grid.Nearest(flat[i], 8, static_cast<int>(i));
    weights[i] = nearest.empty() ? 0.0 : nearest.back().first;
  });
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    sum += weights[i] * points[i];
    weight += weights[i];
  }
  return weight > 0.0 ? Eigen::Vector3d(sum / weight) : centroid;
}

/// The widths across `X` of 20 slices of the points along `Y` (taken about `centre`), from the lowest along Y to the
/// highest; `lo` and `hi` the points' extent along Y (0 included). The base and apex rules read the blade's shape
/// from them. All zero when the points have no extent along Y.
std::vector<double> SliceWidths(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centre,
  const Eigen::Vector3d& Y, const Eigen::Vector3d& X, double& lo, double& hi)
{
  const int slices = 20;
  std::vector<double> along(points.size()), across(points.size());
  lo = 0.0;
  hi = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    along[i] = (points[i] - centre).dot(Y);
    across[i] = (points[i] - centre).dot(X);
    lo = std::min(lo, along[i]);
    hi = std::max(hi, along[i]);
  }
  std::vector<double> width(slices, 0.0);
  if (!(hi > lo))
    return width;
  std::vector<double> minA(slices, 1e300), maxA(slices, -1e300);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const int k = std::clamp(static_cast<int>((along[i] - lo) / (hi - lo) * slices), 0, slices - 1);
    minA[k] = std::min(minA[k], across[i]);
    maxA[k] = std::max(maxA[k], across[i]);
  }
  for (int k = 0; k < slices; ++k)
    width[k] = maxA[k] >= minA[k] ? maxA[k] - minA[k] : 0.0;
  return width;
}

/// Whether the slices' first end (or with `last` their last end) is narrow: its two end slices narrower than 0.06
/// and 0.1 of the widest (an acute apex of a broad leaf widens faster than that).
bool NarrowEnd(const std::vector<double>& width, double widest, bool last)
{
  const std::size_t n = width.size();
  return last ? width[n - 1] < 0.06 * widest && width[n - 2] < 0.1 * widest
              : width[0] < 0.06 * widest && width[1] < 0.1 * widest;
}

/// Whether a blade's one narrow end is its base (else its apex), from the widths of its slices counted from that
/// end (`width`, 20 slices of the blade's `length`; `widest` the largest). A stalk keeps its width along its length:
/// the two end slices within 1.5 point spacings or half the wider's width of each other, and the third slice too (a
/// stalk over two slices long) or over three times the second's width (the blade's base beyond a shorter one): a
/// drawn-out tip a point or two across in its last slices widens steadily, about twice over each slice (the
/// acuminate preset's 0.015, 0.04, 0.085 of the widest), which a coarse scan cannot tell from a stalk's width by
/// the first two alone, unless the other end is square (below: an attenuate base narrows beyond its stalk as a
/// parabola, as a tip does, opposite a notched apex). A fan (the blade wider than
/// long, as a ginkgo's) narrows to its base. A blade ending square at the other end (its last slice at least 0.6 of
/// the widest: a truncate or notched apex) has its apex there. Else the narrow end's sides decide: drawn out
/// (acuminate), curving in so that its width a tenth of the length from the end is under 0.35 of its width at a
/// fifth (straight sides give 0.5, sides as a parabola 0.25), it is a tip, as drip tips are; straight or bulging (a
/// cuneate wedge), a base. `byWidth`, when given: true when the base was read from the end's constant width alone
/// (a stalk's, or a drawn-out tip's first slices widened by noise or a coarse scan), the other end not square.
bool NarrowEndIsBase(
  const std::vector<double>& width, double widest, double length, double spacing, bool* byWidth = nullptr)
{
  const std::size_t n = width.size();
  if (byWidth)
    *byWidth = false;
  auto same = [&](double a, double b) { return std::abs(b - a) <= std::max(1.5 * spacing, 0.5 * std::max(a, b)); };
  if (same(width[0], width[1]))
  {
    std::size_t k = 2;
    while (k + 3 < n && same(width[0], width[k]))
      ++k;
    const bool stalk = !(k + 3 < n && width[k + 1] < 0.35 * width[k + 3]), square = width[n - 1] >= 0.6 * widest;
    if (byWidth)
      *byWidth = stalk && !square;
    return stalk || square;
  }
  if (widest >= length || width[n - 1] >= 0.6 * widest)
    return true;
  return !(width[1] < 0.35 * width[3]);
}

/// Without a base or apex given or found: true when the base is at the +Y end of the axis Y (through the centre,
/// X across it): an end that is a terminal lobe (a palmately or pinnately lobed blade's; the longer one) is the apex;
/// else one narrow end decides as NarrowEndIsBase says (a stalk or a wedge is the base, a drawn-out tip the apex);
/// else a blade widest at one end (a fan) has its apex there; else
/// the base is the end nearer the widest cross-section (ovate leaves are wider towards the base). `guess`: the
/// answer is a guess, as BaseGuess says why: none of these rules tells the ends apart (the blade's width is centred
/// along the axis, as on an elliptic blade, the same at both ends), or only the wider half did, which is the base of
/// an ovate blade and the apex of an obovate one (paper 002's Fig. 2 blade, a deltoid poplar's turned round).
/// `stalkWidth`: the base was put at the one narrow end for its end slices' constant width alone, as a stalk's (the
/// other end not square), which a drawn-out tip seen through noise or sparse points can have too.
bool BaseAtPlusY(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centroid, const Eigen::Vector3d& Y,
  const Eigen::Vector3d& X, double spacing, BaseGuess& guess, bool& stalkWidth)
{
  guess = BaseGuess::None;
  stalkWidth = false;
  // Widths of 20 slices; the narrow-end tests look at the end slices, the ovate test at the widest slice.
  double lo = 0.0, hi = 0.0;
  const std::vector<double> width = SliceWidths(points, centroid, Y, X, lo, hi);
  const int slices = static_cast<int>(width.size());
  const double widest = *std::max_element(width.begin(), width.end());
  // The longer terminal lobe is the apex (a curled or obliquely seen palmate base can look like a short one).
  const int lobeLow = TerminalLobe(width, widest, false), lobeHigh = TerminalLobe(width, widest, true);
  if (lobeLow != lobeHigh)
    return lobeLow > lobeHigh;
  // One narrow end tells the ends apart by its shape and the other end's.
  const bool narrowLow = NarrowEnd(width, widest, false), narrowHigh = NarrowEnd(width, widest, true);
  if (narrowLow != narrowHigh)
  {
    std::vector<double> fromNarrow = width;
    if (narrowHigh)
      std::reverse(fromNarrow.begin(), fromNarrow.end());
    return NarrowEndIsBase(fromNarrow, widest, hi - lo, spacing, &stalkWidth) == narrowHigh;
  }
  // A blade widest at one end (the last 15 % of its length: a fan, a truncate or notched apex) has its apex there and
  // narrows to its base.
  const int widestSlice = static_cast<int>(std::max_element(width.begin(), width.end()) - width.begin());
  if (widestSlice >= slices - 3)
    return false;
  if (widestSlice <= 2)
    return true;
  // Width-weighted centre of the slices, relative to the middle.
  double sum = 0.0, moment = 0.0;
  for (int k = 0; k < slices; ++k)
  {
    sum += width[k];
    moment += width[k] * (k + 0.5 - 0.5 * slices);
  }
  // The width-weighted centre's offset from the middle, in units of length: the slices' widths are each uncertain
  // by about a point spacing (their extreme points), so an offset within 2 spacings tells no end from the other
  // (0.1-0.3 % of the length on the elliptic blade's scans, 8-10 % on the cucumber's). Nor does an offset within
  // 2.5 % of the length: obovate blades are as common as ovate ones, and one whose area lies that near its middle
  // (paper 002's Fig. 1, 5 and 6 blades: 1.0-1.8 %, their base the narrower end) is as often one as the other; the
  // ovate blades here lie 3.6-9.4 % off.
  // Beyond that the wider half is the base of an ovate blade, the apex of an obovate one: the outline alone cannot
  // say which, so the answer is still a guess (the ovate one).
  const double offset = sum > 0.0 ? std::abs(moment / sum) * (hi - lo) / slices : 0.0;
  guess = !(sum > 0.0) || offset < std::max(2.0 * spacing, 0.025 * (hi - lo)) ? BaseGuess::SameAtBothEnds
                                                                              : BaseGuess::WiderHalf;
  return sum > 0.0 && moment > 0.0;
}
} // namespace

bool StalkIsTheBladesTip(const std::vector<Eigen::Vector3d>& points, const Petiole& petiole, double spacing)
{
  if (!petiole.found || points.size() < 20)
    return false;
  Eigen::Vector3d centroid;
  const Eigen::Vector3d normal = Principal(points, centroid).eigenvectors().col(0);
  Eigen::Vector3d Y = petiole.junction - centroid;
  Y -= Y.dot(normal) * normal;
  if (!(Y.norm() > spacing))
    return false;
  Y.normalize();
  // Widths of the slices, counted from the stalk's end (+Y).
  double lo = 0.0, hi = 0.0;
  std::vector<double> width = SliceWidths(points, centroid, Y, normal.cross(Y), lo, hi);
  if (!(hi > lo) || petiole.length >= 0.15 * (hi - lo))
    return false;
  std::reverse(width.begin(), width.end());
  const double widest = *std::max_element(width.begin(), width.end());
  return NarrowEnd(width, widest, false) && !NarrowEndIsBase(width, widest, hi - lo, spacing);
}

Frame LeafFrame(const std::vector<Eigen::Vector3d>& points, const LeafFitParameters& options, double spacing,
  const Petiole& petiole, int& baseFrom, BaseGuess& guess, bool& stalkWidth, const ParallelFor& parallel)
{
  Eigen::Vector3d centroid;
  const auto eig = Principal(points, centroid);
  Frame frame;
  frame.origin = centroid;
  const Eigen::Vector3d normal = eig.eigenvectors().col(0), principal = eig.eigenvectors().col(2);
  // The base: given, or the petiole's junction; the apex side: given. The axis: to the apex, or the blade's axis of
  // symmetry through what is known (never the principal axes alone: a fan is wider than long).
  std::optional<Eigen::Vector3d> base, apex;
  baseFrom = BaseFromShape;
  guess = BaseGuess::None;
  stalkWidth = false;
  if (options.basePoint)
  {
    base = Nearest(points, *options.basePoint);
    baseFrom = BaseFromPoint;
  }
  else if (petiole.found)
  {
    base = petiole.junction;
    baseFrom = BaseFromPetiole;
  }
  if (options.apexPoint)
    apex = Nearest(points, *options.apexPoint);
  Eigen::Vector3d Y;
  if (base && apex && (*apex - *base).norm() > spacing)
    Y = (*apex - *base).normalized();
  else if (base)
    Y = SymmetryAxis(points, *base, normal, centroid - *base, spacing, parallel);
  else if (apex)
    Y = -SymmetryAxis(points, *apex, normal, centroid - *apex, spacing, parallel);
  else
  {
    const Eigen::Vector3d middle = points.size() > 8 ? AreaCentroid(points, normal, centroid, parallel) : centroid;
    Y = SymmetryAxis(points, middle, normal, principal, spacing, parallel);
    if (BaseAtPlusY(points, middle, Y, normal.cross(Y).normalized(), spacing, guess, stalkWidth))
      Y = -Y;
    if (guess != BaseGuess::None)
      baseFrom = BaseFromGuess;
  }
  Eigen::Vector3d Z = normal - normal.dot(Y) * Y;
  Z.normalize();
  if (Z.dot(options.up) < 0.0)
    Z = -Z;
  const Eigen::Vector3d X = Y.cross(Z).normalized();
  frame.axes.col(0) = X;
  frame.axes.col(1) = Y.normalized();
  frame.axes.col(2) = X.cross(Y).normalized();
  return frame;
}

} // namespace fit
} // namespace plantmorph
