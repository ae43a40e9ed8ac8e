// SPDX-License-Identifier: GPL-3.0-or-later
// FitLeaf's outline as the points draw it (LeafFitInternal.h, TraceContour): lobes, sinuses and a cordate base.
#include "LeafFitInternal.h"
#include "PointGrid.h"
#include "plantmorph/MathConstants.h"
#include "plantmorph/statistics/Median.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace plantmorph
{
namespace fit
{
namespace
{
/// Squared Euclidean distance transform along one line (Felzenszwalb and Huttenlocher): f in, d out.
void DistanceLine(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v, std::vector<double>& z)
{
  const int n = static_cast<int>(f.size());
  int k = 0;
  v[0] = 0;
  z[0] = -1e300;
  z[1] = 1e300;
  for (int q = 1; q < n; ++q)
  {
    double s = 0.0;
    while (true)
    {
      s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
      if (s > z[k] || k == 0)
        break;
      --k;
    }
    if (s <= z[k])
    {
      v[0] = q;
      z[0] = -1e300;
      z[1] = 1e300;
      k = 0;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = 1e300;
  }
  k = 0;
  for (int q = 0; q < n; ++q)
  {
    while (z[k + 1] < q)
      ++k;
    d[q] = (double(q) - v[k]) * (double(q) - v[k]) + f[v[k]];
  }
}

/// Distance (in cells) from every cell to the nearest cell where `target` is 1; grid nx x ny, index i + nx * j. The
/// rows, then the columns, are transformed through `parallel`, each line on its own (the same result on any threads).
std::vector<double> DistanceTo(const std::vector<unsigned char>& target, int nx, int ny, const ParallelFor& parallel)
{
  const double far = 1e20;
  std::vector<double> g(target.size());
  ForEachIndex(parallel, target.size(), [&](std::size_t c) { g[c] = target[c] ? 0.0 : far; });
  // Lines of `length` cells, cell k of line `line` at line * across + k * along; `root` takes the square root.
  auto lines = [&](int count, int length, std::size_t across, std::size_t along, bool root) {
    parallel(static_cast<std::size_t>(count), [&](std::size_t first, std::size_t last) {
      std::vector<double> f(length), d(length), z(length + 1);
      std::vector<int> v(length);
      for (std::size_t line = first; line < last; ++line)
      {
        for (int k = 0; k < length; ++k)
          f[k] = g[line * across + k * along];
        DistanceLine(f, d, v, z);
        for (int k = 0; k < length; ++k)
          g[line * across + k * along] = root ? std::sqrt(d[k]) : d[k];
      }
    });
  };
  lines(ny, nx, static_cast<std::size_t>(nx), 1, false);
  lines(nx, ny, 1, static_cast<std::size_t>(nx), true);
  return g;
}

/// Marks every 0 cell not reachable from the grid's border through 0 cells as 1 (holes are filled).
void FillHoles(std::vector<unsigned char>& inside, int nx, int ny)
{
  std::vector<unsigned char> outside(inside.size(), 0);
  std::vector<int> stack;
  auto push = [&](int i, int j) {
    const int c = i + nx * j;
    if (i >= 0 && j >= 0 && i < nx && j < ny && !inside[c] && !outside[c])
    {
      outside[c] = 1;
      stack.push_back(c);
    }
  };
  for (int i = 0; i < nx; ++i)
  {
    push(i, 0);
    push(i, ny - 1);
  }
  for (int j = 0; j < ny; ++j)
  {
    push(0, j);
    push(nx - 1, j);
  }
  while (!stack.empty())
  {
    const int c = stack.back();
    stack.pop_back();
    const int i = c % nx, j = c / nx;
    push(i - 1, j);
    push(i + 1, j);
    push(i, j - 1);
    push(i, j + 1);
  }
  for (std::size_t c = 0; c < inside.size(); ++c)
    inside[c] = outside[c] ? 0 : 1;
}

/// The closed loops of the level set F = level by marching squares (node values F, grid nx x ny, node (i, j) at
/// origin + cell (i, j)); each loop counter-clockwise around the region F > level.
std::vector<std::vector<Eigen::Vector2d>> LevelLoops(
  const std::vector<double>& F, int nx, int ny, double level, const Eigen::Vector2d& origin, double cell)
{
  // Edge ids: horizontal edge (i, j)-(i+1, j) is 2 (i + nx j), vertical edge (i, j)-(i, j+1) is 2 (i + nx j) + 1.
  auto crossing = [&](int edge) {
    const int node = edge / 2, i = node % nx, j = node / nx;
    const int other = edge % 2 == 0 ? node + 1 : node + nx;
    const double a = F[node] - level, b = F[other] - level;
    const double f = a / (a - b);
    return Eigen::Vector2d(
      origin.x() + cell * (i + (edge % 2 == 0 ? f : 0.0)), origin.y() + cell * (j + (edge % 2 == 1 ? f : 0.0)));
  };
  std::map<int, int> next; // segment from edge a to edge b, the region F > level on its left
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
    {
      const int n0 = i + nx * j, n1 = n0 + 1, n2 = n0 + 1 + nx, n3 = n0 + nx;
      const int bottom = 2 * n0, right = 2 * n1 + 1, top = 2 * n3, left = 2 * n0 + 1;
      const bool in[4] = { F[n0] > level, F[n1] > level, F[n2] > level, F[n3] > level };
      const int code = in[0] + 2 * in[1] + 4 * in[2] + 8 * in[3];
      // Counter-clockwise corners 0 (i, j), 1 (i+1, j), 2 (i+1, j+1), 3 (i, j+1); edges between corners k and k+1:
      // bottom, right, top, left. A link runs with the inside on its right (reversed below).
      const int edges[4] = { bottom, right, top, left };
      auto link = [&](int from, int to) { next[edges[from]] = edges[to]; };
      switch (code)
      {
        case 1:
          link(3, 0);
          break;
        case 2:
          link(0, 1);
          break;
        case 3:
          link(3, 1);
          break;
        case 4:
          link(1, 2);
          break;
        case 5:
          link(3, 2);
          link(1, 0);
          break; // saddle: the two inside corners kept apart
        case 6:
          link(0, 2);
          break;
        case 7:
          link(3, 2);
          break;
        case 8:
          link(2, 3);
          break;
        case 9:
          link(2, 0);
          break;
        case 10:
          link(0, 3);
          link(2, 1);
          break;
        case 11:
          link(2, 1);
          break;
        case 12:
          link(1, 3);
          break;
        case 13:
          link(1, 0);
          break;
        case 14:
          link(0, 3);
          break;
        default:
          break;
      }
    }
  std::vector<std::vector<Eigen::Vector2d>> loops;
  while (!next.empty())
  {
    const int start = next.begin()->first;
    std::vector<Eigen::Vector2d> loop;
    int edge = start;
    while (true)
    {
      const auto it = next.find(edge);
      if (it == next.end())
        break;
      loop.push_back(crossing(edge));
      edge = it->second;
      next.erase(it);
      if (edge == start)
        break;
    }
    if (loop.size() >= 3)
      loops.emplace_back(loop.rbegin(), loop.rend()); // the links run clockwise around the inside
  }
  return loops;
}

double SignedArea(const std::vector<Eigen::Vector2d>& loop)
{
  double a = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
  {
    const Eigen::Vector2d& p = loop[i];
    const Eigen::Vector2d& q = loop[(i + 1) % loop.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * a;
}

/// Taubin's smoothing (lambda, mu): removes the marching squares' steps without shrinking the loop.
void SmoothLoop(std::vector<Eigen::Vector2d>& loop, int iterations)
{
  const std::size_t n = loop.size();
  std::vector<Eigen::Vector2d> moved(n);
  for (int k = 0; k < 2 * iterations; ++k)
  {
    const double factor = k % 2 == 0 ? 0.5 : -0.53;
    for (std::size_t i = 0; i < n; ++i)
      moved[i] = loop[i] + factor * (0.5 * (loop[(i + n - 1) % n] + loop[(i + 1) % n]) - loop[i]);
    loop.swap(moved);
  }
}
/// Which points of a loop are snapped to the smooth margin (1): all but the runs off the band (from a spacing
/// outside the smooth margin to `band` inside it, `depth` the distance inwards) that reach max(4 spacings, twice
/// the band) away somewhere. `features`: whether such a run (or no point on the band) was found.
std::vector<unsigned char> SnapFlags(const std::vector<double>& depth, double spacing, double band, bool& features)
{
  const std::size_t n = depth.size();
  std::vector<unsigned char> snapped(n, 1);
  auto off = [&](std::size_t i) { return !(depth[i] > -spacing && depth[i] < band); };
  std::size_t first = 0; // a point on the band to start the runs from
  while (first < n && off(first))
    ++first;
  if (first == n)
  {
    features = true;
    snapped.assign(n, 0);
  }
  else
    for (std::size_t k = 0; k < n;)
    {
      const std::size_t i = (first + k) % n;
      if (!off(i))
      {
        ++k;
        continue;
      }
      std::size_t length = 0;
      double deepest = 0.0;
      while (k + length < n && off((first + k + length) % n))
      {
        const double d = depth[(first + k + length) % n];
        deepest = std::max(deepest, std::isnan(d) ? 1e300 : std::abs(d));
        ++length;
      }
      if (deepest >= std::max(4.0 * spacing, 2.0 * band))
      {
        features = true;
        for (std::size_t j = 0; j < length; ++j)
          snapped[(first + k + j) % n] = 0;
      }
      k += length;
    }
  return snapped;
}
/// The midvein's ends on a counter-clockwise loop: the crossings of t = 0 (s, index of the edge's first point) that
/// bound the longest piece of t = 0 inside the loop (between crossings 0-1, 2-3, ... in s order): the apex and the
/// base (a cordate blade's basal sinus, or its lowest point). A cordate blade's lobes overlapping below the sinus, or
/// a tooth hooked over the apex, make shorter pieces. Two pieces less than 2 spacings apart are one: the loop's
/// flank grazing t = 0 beside a narrow base (the midvein fitted a little off the base's point) is no sinus (a notch
/// counts from 4 spacings deep). False when the loop does not cross t = 0 in pairs.
bool MidveinEnds(const std::vector<Eigen::Vector2d>& loop, double spacing, std::pair<double, std::size_t>& base,
  std::pair<double, std::size_t>& apex)
{
  const std::size_t n = loop.size();
  std::vector<std::pair<double, std::size_t>> crossings;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector2d& p = loop[i];
    const Eigen::Vector2d& q = loop[(i + 1) % n];
    if ((p.x() > 0.0) != (q.x() > 0.0))
      crossings.push_back({ p.y() + (q.y() - p.y()) * p.x() / (p.x() - q.x()), i });
  }
  if (crossings.size() < 2 || crossings.size() % 2 != 0)
    return false;
  std::sort(crossings.begin(), crossings.end());
  std::vector<std::pair<double, std::size_t>> ends{ crossings[0] };
  for (std::size_t k = 1; k + 1 < crossings.size(); k += 2)
    if (crossings[k + 1].first - crossings[k].first >= 2.0 * spacing)
    {
      ends.push_back(crossings[k]);
      ends.push_back(crossings[k + 1]);
    }
  ends.push_back(crossings.back());
  std::size_t longest = 0;
  for (std::size_t k = 2; k + 1 < ends.size(); k += 2)
    if (ends[k + 1].first - ends[k].first > ends[longest + 1].first - ends[longest].first)
      longest = k;
  base = ends[longest];
  apex = ends[longest + 1];
  return true;
}

/// The bottom of a basal sinus, a notch in the outline on the midvein whose loop crosses t = 0 at `crossing`. The closing's discs (radius r, 2.5 spacings) round a narrow notch's bottom off, so the loop crosses
/// the midvein beyond it, by about r (1 / sin of the walls' angle to the midvein - 1) and the gap to the margin
/// (about 2.8 spacings at the cucumber's sinus, whose walls leave it 31 degrees off the midvein). The points reach
/// into the notch: its bottom is where they close across the midvein, the deepest place where a point on each side
/// of t = 0 lie within 2 steps of each other along s and no farther apart across it than 2.5 steps (the step: the
/// points' mean spacing inside the blade beyond the notch, at least the spacing; a gap the closing bridges), the
/// pair's depth that of its upper point; below the bottom the notch's walls are farther apart. Looked for from the
/// crossing to a notch's depth `shallow` and r beyond it; the crossing when no pair closes there or fewer than 8
/// points lie inside.
double NotchBottom(const std::vector<Eigen::Vector2d>& ts, double crossing, double shallow, double spacing)
{
  // The points' mean spacing inside the blade beyond the notch's reach (a strip 5 spacings wide along the midvein,
  // 10 long): one pass's lines give the spacing, two passes' interleaved lines and random samples a larger one.
  const double reach = shallow + 2.5 * spacing, strip = 2.5 * spacing;
  std::size_t inside = 0;
  for (const auto& p : ts)
  {
    const double depth = p.y() - crossing;
    inside += depth >= reach && depth < reach + 4.0 * strip && std::abs(p.x()) < strip ? 1 : 0;
  }
  if (inside < 8)
    return crossing;
  const double step = std::max(spacing, std::sqrt(8.0 * strip * strip / static_cast<double>(inside)));
  const double across = 2.5 * step;
  std::vector<Eigen::Vector2d> band; // (t, depth inwards from the crossing) near t = 0 above the crossing
  for (const auto& p : ts)
  {
    const double depth = p.y() - crossing;
    if (depth > -step && depth < reach && std::abs(p.x()) < across)
      band.push_back({ p.x(), depth });
  }
  double bottom = std::numeric_limits<double>::infinity();
  for (const auto& a : band)
    for (const auto& b : band)
      if (a.x() < 0.0 && b.x() >= 0.0 && std::abs(a.y() - b.y()) < 2.0 * step && b.x() - a.x() <= across)
        bottom = std::min(bottom, std::max(a.y(), b.y()));
  return std::isfinite(bottom) ? crossing + std::max(bottom, 0.0) : crossing;
}

/// How far the loop rises above its apex crossing `apex` (s, index of the edge's first point on the
/// counter-clockwise loop): from the crossing along the loop to the right and to the left, the highest s reached
/// before the loop falls `fall` below the crossing or crosses t = 0; the lower of the two sides' heights.
double ApexNotchRise(const std::vector<Eigen::Vector2d>& loop, const std::pair<double, std::size_t>& apex, double fall)
{
  const std::size_t n = loop.size();
  double lowest = std::numeric_limits<double>::infinity();
  for (int side = 0; side < 2; ++side)
  {
    const bool right = side == 0;
    std::size_t i = right ? apex.second : (apex.second + 1) % n;
    double highest = apex.first;
    for (std::size_t k = 0; k < n / 2; ++k)
    {
      const Eigen::Vector2d& p = loop[i];
      if ((p.x() > 0.0) != right || p.y() < apex.first - fall)
        break;
      highest = std::max(highest, p.y());
      i = right ? (i + n - 1) % n : (i + 1) % n;
    }
    lowest = std::min(lowest, highest - apex.first);
  }
  return lowest;
}

/// The midvein's apex end where the loop crosses t = 0 at `apex` and the apex is no tip. Where the loop rises on
/// both sides of the crossing to two lobes (each above it by more than MinNotchDepth of the blade's extent and 2
/// spacings: a notch), the notch's bottom is where the points close across the midvein (NotchBottom mirrored along
/// s), moved out by `gap`, the distance from the outermost points to the margin by which the loop is grown; never
/// beyond the crossing. The loop's crossing itself follows the one or two points that the scan's range noise throws
/// into the notch (a scanner's beams are not square to the blade, so noise along them moves points along s), and the
/// closing's discs join them to the blade: up to a spacing beyond the bottom (the ginkgo from two positions); a pair
/// on either side of the midvein is the blade's. Elsewhere (the loop falls away on a side: a tip whose end lies off
/// the midvein, below the smooth margins' tip) the crossing.
double ApexEnd(const std::vector<Eigen::Vector2d>& loop, const std::vector<Eigen::Vector2d>& ts,
  const std::pair<double, std::size_t>& apex, double extent, double shallow, double spacing, double gap)
{
  if (!(ApexNotchRise(loop, apex, shallow) > std::max(MinNotchDepth * extent, 2.0 * spacing)))
    return apex.first;
  std::vector<Eigen::Vector2d> mirrored(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
    mirrored[i] = { ts[i].x(), -ts[i].y() };
  const double bottom = -NotchBottom(mirrored, -apex.first, shallow, spacing);
  return bottom < apex.first ? std::min(apex.first, bottom + gap) : apex.first;
}

/// Whether the blade's points between the loop's crossing of the midvein at `crossing` and a petiole's junction above
/// it (where the stalk's axis meets the blade's plane) are, near the midvein, the stalk's: the stalk's first
/// spacings, seen in the blade's plane below a sinus (within the opening's ball of the blade, so counted as blade),
/// close the points across the midvein below the sinus's bottom. They lie within the stalk's width of t = 0
/// (`halfWidth` plus a spacing) from the crossing up to the first point farther out (up to 3 spacings more: the
/// blade at the sinus's bottom, or lobes overlapping), which lies within 4 spacings (the ball's radius) of the
/// junction.
bool OnlyTheStalkBelowJunction(
  const std::vector<Eigen::Vector2d>& ts, double crossing, double junction, double halfWidth, double spacing)
{
  const double narrow = halfWidth + spacing, look = narrow + 3.0 * spacing;
  double wideAt = junction;
  for (const auto& p : ts)
    if (p.y() > crossing && p.y() < junction && std::abs(p.x()) >= narrow && std::abs(p.x()) < look)
      wideAt = std::min(wideAt, p.y());
  if (junction - wideAt > 4.0 * spacing)
    return false;
  return std::any_of(ts.begin(), ts.end(),
    [&](const Eigen::Vector2d& p) { return p.y() > crossing && p.y() < wideAt && std::abs(p.x()) < narrow; });
}

/// The midvein's base at a sinus, where the loop crosses t = 0 at `crossing`: a petiole's junction above that
/// crossing, by less than a notch's depth (`shallow`), is the bottom, where the stalk meets the blade; so is a
/// junction where the stalk's axis meets the blade's plane farther above it when only the stalk lies across the
/// midvein in between (OnlyTheStalkBelowJunction); else where the points close across the midvein (NotchBottom).
double SinusBottom(
  const std::vector<Eigen::Vector2d>& ts, const Outline& outline, double crossing, double shallow, double spacing)
{
  if (outline.junction > crossing && outline.junction < crossing + shallow)
    return outline.junction;
  if (outline.junctionMeetsPlane && outline.junction > crossing &&
    OnlyTheStalkBelowJunction(ts, crossing, outline.junction, outline.stalkHalfWidth, spacing))
    return outline.junction;
  return NotchBottom(ts, crossing, shallow, spacing);
}

/// Whether the blade's points run on along the midvein from the loop's crossing at `crossing` down to a petiole's
/// junction below it (a cusp or cuneate base narrower than the closing's discs, which the loop does not follow):
/// points within 2 spacings of t = 0 with no gap along s wider than 3 spacings from the junction to the crossing.
/// Not where the blade reaches on below the junction on both sides of the midvein (points more than 2 spacings
/// out and 3 spacings below it): those are the lobes beside a sinus whose bottom is the junction. The closing
/// rounds a sinus's bottom off above it, so its crossing lies a spacing or so above a junction placed at the
/// bottom, and with no room for a gap between them the run was found there too: the curled cucumber from two
/// positions at 0.1 % noise lost both basal lobes (Area -6.8 %).
bool BaseRunsToJunction(const std::vector<Eigen::Vector2d>& ts, double junction, double crossing, double spacing)
{
  if (!(junction < crossing))
    return false;
  bool lobeRight = false, lobeLeft = false;
  std::vector<double> along;
  for (const auto& p : ts)
    if (p.y() < junction - 3.0 * spacing)
    {
      lobeRight = lobeRight || p.x() > 2.0 * spacing;
      lobeLeft = lobeLeft || p.x() < -2.0 * spacing;
    }
    else if (p.y() > junction - spacing && p.y() < crossing && std::abs(p.x()) < 4.0 * spacing)
    {
      if (std::abs(p.x()) >= 2.0 * spacing)
        return false; // wider than a strip along the midvein (lobes overlapping below a sinus)
      along.push_back(p.y());
    }
  if (lobeRight && lobeLeft)
    return false;
  along.push_back(junction);
  along.push_back(crossing);
  std::sort(along.begin(), along.end());
  for (std::size_t k = 1; k < along.size(); ++k)
    if (along[k] - along[k - 1] > 3.0 * spacing)
      return false;
  return true;
}

/// Whether the blade ends in a drawn-out (acuminate) tip a point or two across along the midvein, from `from` on:
/// at least 4 points beyond `from`, all within `r` of t = 0 (at most the closing's discs' radius: a rounded or acute
/// apex is wider there; a notch's lobes lie farther out), leaving no gap along s wider than 2 r (random samples
/// along a tip a fraction of a spacing across lie up to 4 spacings apart; a stray point beyond the apex leaves a
/// wider gap). `end`: its last sample and the mean gap between its last samples (up to 10): the tip's samples lie
/// one behind the other and do not thin out as a blade's area does, so the tip extrapolated from the highest
/// samples by the area's growth (the smooth margins' s1) lay up to 4 spacings beyond it.
bool DrawnOutApex(const std::vector<Eigen::Vector2d>& ts, double from, double r, double& end)
{
  std::vector<double> along;
  for (const auto& p : ts)
    if (p.y() > from)
    {
      if (!(std::abs(p.x()) < r))
        return false;
      along.push_back(p.y());
    }
  if (along.size() < 4)
    return false;
  along.push_back(from);
  std::sort(along.begin(), along.end());
  for (std::size_t k = 1; k < along.size(); ++k)
    if (along[k] - along[k - 1] > 2.0 * r)
      return false;
  const std::size_t gaps = std::min<std::size_t>(10, along.size() - 2);
  end = along.back() + (along.back() - along[along.size() - 1 - gaps]) / static_cast<double>(gaps);
  return true;
}

/// How far across (t) the blade's samples within a spacing of its lowest (along s) spread.
double LowestSamplesSpan(const std::vector<Eigen::Vector2d>& ts, double spacing)
{
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& p : ts)
    lowest = std::min(lowest, p.y());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : ts)
    if (p.y() < lowest + spacing)
    {
      lo = std::min(lo, p.x());
      hi = std::max(hi, p.x());
    }
  return hi > lo ? hi - lo : 0.0;
}

/// The midvein's base end `baseS` where the loop crosses t = 0 at `crossing`; true when it is a tip. Within
/// `shallow` of the smooth margins' tip s0, that tip, but no more than a spacing past a petiole's junction where
/// the stalk's axis meets the blade's plane: a scanner sees the stalk's top, which lies within a radius of the
/// blade's plane for 1 / sin(angle) radii back along the midvein, so the blade's lowest samples are partly the
/// stalk's, they do not thin out like a free tip's, and the tip extrapolated from them lies out on the stalk (the
/// junction itself is placed to about a radius either way: it bounds the tip, it does not replace it). Where that tip
/// lies inside the blade from the junction and the blade's samples within a spacing of its lowest spread across
/// wider than the stalk (its width and a spacing), the base is the junction: a blade that wide does not narrow to a
/// free tip between its lowest line and the stalk, and a scanner's lines hold their samples at one s, so they do not
/// thin out like a free tip's and the tip extrapolated from them lies short of where the blade meets the stalk. A
/// base narrower than the closing's discs (a cusp) that runs on along the midvein below the crossing down to a
/// petiole's junction, where the stalk's axis meets the blade's plane, is a tip at that junction. Else a sinus
/// (SinusBottom).
bool BaseEnd(const std::vector<Eigen::Vector2d>& ts, const Outline& outline, double crossing, double shallow,
  double spacing, double& baseS)
{
  if (std::abs(crossing - outline.roundS0) < shallow)
  {
    const double bound = outline.junction - spacing;
    baseS = outline.junctionMeetsPlane && bound > outline.s0 ? bound : outline.s0;
    if (outline.junction < baseS &&
      (outline.junctionAcrossGap || LowestSamplesSpan(ts, spacing) > 2.0 * outline.stalkHalfWidth + spacing))
      baseS = outline.junction;
    return true;
  }
  if ((outline.junctionMeetsPlane && BaseRunsToJunction(ts, outline.junction, crossing, spacing)) ||
    (outline.junctionAcrossGap && outline.junction < crossing))
  {
    baseS = outline.junction;
    return true;
  }
  baseS = SinusBottom(ts, outline, crossing, shallow, spacing);
  return false;
}

/// The loop's perimeter.
double Perimeter(const std::vector<Eigen::Vector2d>& loop)
{
  double length = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    length += (loop[(i + 1) % loop.size()] - loop[i]).norm();
  return length;
}

/// The side of the area a point stands for: the square root of the loop's area over the points' count (the same
/// for a lattice and for random points of the same density).
double PointSide(const std::vector<Eigen::Vector2d>& loop, std::size_t count)
{
  return std::sqrt(std::max(SignedArea(loop), 0.0) / static_cast<double>(std::max<std::size_t>(count, 1)));
}

/// The gap between the closing's boundary (level r of F, through the outermost points) and the margin, from the
/// points' count: the level r - gap whose loop (`outer`) encloses `target`, the area the points sample. Each point
/// stands for 1 / density of the blade at its place, plus the holes the loop bridges (cells deeper than the
/// kernel's reach farther than 2 `scale` from every point). The scales come from the density as well as from the
/// spacing: `side`, the side of the area a point stands for (the loop's area over the count), is the same for a
/// lattice and for random points of the same density, where the nearest-neighbour spacing of random points is about
/// half of it and their gaps about twice a lattice's in spacings; `scale` is the larger of side and spacing (a line
/// scan's spacing, half the distance between its lines, can exceed its side).
/// The density is a Gaussian kernel's sum (sigma the larger of side and 2 spacings, cut at 4 sigma) taken at places a
/// sigma apart at least 2 sigma inside the points' region (F >= r + 2 sigma), each sum divided by the share of the
/// kernel that lies on the blade (a half plane's, the margin taken half a point's side beyond the loop, then at the gap
/// found: at least 0.977 at that depth), not at the points: a sum at a point holds the point itself (1 / (2 pi
/// sigma^2)), which a lattice's sum needs (its sum is the kernel's integral times the density wherever it is taken, at
/// a point or between: sigma is at least the distance between a line scan's lines) and random points' does not (their
/// sum at a point is that plus the point; 15 % of the density at sigma 2 spacings, and holes counted where random
/// points leave gaps of 2 spacings: the lobed blade sampled at random came out 9 % short). A count inside a region
/// whose edge follows a scanner's lines would not do: that edge lies on a line or between two all along (3 % from one
/// edge to the next on a line scan of the pin oak). Places nearer the loop than 2 sigma are left out: there the
/// kernel's share depends on where the margin lies, and a loop drawn through the outermost points has more points just
/// inside it than a line at the same place would (random points came out 1 % small with places up to the loop, a
/// lattice 0.5 % large). Places only 4 sigma deep and more, as before, read too high a density on a plant scanned from
/// several sides, whose margins the neighbouring leaves hide from some of the views: on the shrub's blades from four
/// positions the density within 2 % of the length of the margin was up to 12 % under the blade's mean and 4 sigma deep
/// 4 % over it, and the blades came out 1-4 % small.
/// A point takes the mean density of the tiles of 4 scales around its own (the window, 3 tiles wide at least, widened
/// until it holds 20 of the points inside the loop): a scan's density varies smoothly, with the range, the view's angle
/// to the blade and where one pass's field ends; a window of 8 spacings and 50 points reached farther inside and read a
/// margin rolled away from the scanner as dense as the blade (the curled pin oak obliquely, -1.05 % against -0.82 %).
/// The window never shrinks to a tile's own: a tile whose own count stopped the widening would set its density from its
/// own points, and the tiles holding more points than their share would count them at a smaller area each (-1.3 % on
/// random points). Unlike a gap measured against the smooth margins this follows any margin (lobes, sinuses) and any
/// spread of the points (one pass or several, a lattice or random). NaN (and `target` NaN) when fewer than 50 points
/// lie 4 sigma deep.
template <typename Outer>
double CountedGap(const std::vector<Eigen::Vector2d>& ts, const std::vector<double>& F,
  const std::vector<double>& toPoint, int nx, int ny, const Eigen::Vector2d& origin, double cell, double r,
  double spacing, const std::vector<Eigen::Vector2d>& loop, const Outer& outer, double& target)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  target = nan;
  auto index = [&](const Eigen::Vector2d& p) {
    const int i = std::clamp(static_cast<int>(std::lround((p.x() - origin.x()) / cell)), 0, nx - 1);
    const int j = std::clamp(static_cast<int>(std::lround((p.y() - origin.y()) / cell)), 0, ny - 1);
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j;
  };
  // The side of the area a point stands for, which means the same whatever the points' pattern.
  const double side = PointSide(loop, ts.size());
  if (!(side > 0.0))
    return nan;
  const double scale = std::max(side, spacing);
  const double sigma = std::max(side, 2.0 * spacing), reach = 4.0 * sigma;
  // The points by buckets a sigma wide, for the kernel's sums.
  const Buckets buckets(ts, origin, sigma, nx * cell, ny * cell);
  const double norm = 2.0 * Pi * sigma * sigma * (1.0 - std::exp(-8.0));
  auto kernel = [&](const Eigen::Vector2d& p) {
    double sum = 0.0;
    buckets.Near(p, 4, [&](std::size_t k) {
      const double d2 = (ts[k] - p).squaredNorm();
      if (d2 < reach * reach)
        sum += std::exp(-0.5 * d2 / (sigma * sigma));
    });
    return sum / norm;
  };
  const double tile = 4.0 * scale;
  const int tx = static_cast<int>(nx * cell / tile) + 1, ty = static_cast<int>(ny * cell / tile) + 1;
  auto tileOf = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2i(std::clamp(static_cast<int>((p.x() - origin.x()) / tile), 0, tx - 1),
      std::clamp(static_cast<int>((p.y() - origin.y()) / tile), 0, ty - 1));
  };
  std::vector<double> tileSum(static_cast<std::size_t>(tx) * ty, 0.0), tileCount(tileSum.size(), 0.0),
    tileProbes(tileSum.size(), 0.0);
  double deepCount = 0.0;
  for (const auto& p : ts)
    if (F[index(p)] >= r)
    {
      const Eigen::Vector2i k = tileOf(p);
      tileCount[k.x() + tx * k.y()] += 1.0;
      deepCount += F[index(p)] >= r + reach ? 1.0 : 0.0;
    }
  if (deepCount < 50.0)
    return nan;
  // A hole: a cell farther than 2 scales from every point (random points leave such an empty disc with
  // probability e^(-4 pi), a lattice none).
  const double hole = 2.0 * scale;
  // The kernel's sums at places a sigma apart inside the loop through the outermost points (holes left out), by
  // tiles (they do not depend on where the margin lies), and each place's tile and depth below that loop.
  struct Place
  {
    std::size_t tile;
    double depth;
  };
  std::vector<Place> places;
  const int stride = std::max(1, static_cast<int>(std::lround(sigma / cell)));
  for (int j = 0; j < ny; j += stride)
    for (int i = 0; i < nx; i += stride)
    {
      const std::size_t c = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j;
      if (!(F[c] >= r + 2.0 * sigma) || toPoint[c] * cell > hole)
        continue;
      const Eigen::Vector2d at = origin + cell * Eigen::Vector2d(i, j);
      const Eigen::Vector2i k = tileOf(at);
      places.push_back({ static_cast<std::size_t>(k.x() + tx * k.y()), F[c] - r });
      tileSum[places.back().tile] += kernel(at);
    }
  double holes = 0.0;
  for (std::size_t c = 0; c < F.size(); ++c)
    if (F[c] >= r + reach && toPoint[c] * cell > hole)
      holes += cell * cell;
  // The area the points sample with the margin `gap` beyond the loop: a place's kernel reaches past the margin, so
  // its sum is divided by the share of the kernel inside (a half plane's, the margin straight within a few sigma),
  // summed by tiles as the kernel's sums are.
  auto counted = [&](double gap) {
    std::fill(tileProbes.begin(), tileProbes.end(), 0.0);
    for (const Place& place : places)
      tileProbes[place.tile] += 0.5 * std::erfc(-(place.depth + gap) / (std::sqrt(2.0) * sigma));
    // The area one point stands for in each tile (NaN: not yet computed).
    std::vector<double> perPoint(tileSum.size(), nan);
    auto share = [&](const Eigen::Vector2i& k) {
      double& a = perPoint[k.x() + tx * k.y()];
      double n = 0.0, probes = 0.0, sum = 0.0;
      for (int w = 1; std::isnan(a) && w <= std::max(tx, ty) && (n < 20.0 || !(sum > 0.0)); ++w)
      {
        n = probes = sum = 0.0;
        for (int j = std::max(0, k.y() - w); j <= std::min(ty - 1, k.y() + w); ++j)
          for (int i = std::max(0, k.x() - w); i <= std::min(tx - 1, k.x() + w); ++i)
          {
            n += tileCount[i + tx * j];
            probes += tileProbes[i + tx * j];
            sum += tileSum[i + tx * j];
          }
      }
      if (std::isnan(a))
        a = sum > 0.0 ? probes / sum : 0.0;
      return a;
    };
    double area = holes;
    for (const auto& p : ts)
      area += share(tileOf(p));
    return area > 0.0 ? area : nan;
  };
  // The loop's area grows by about its perimeter times the gap: two secant steps with the area counted for a margin
  // half a point's side beyond the loop, then two more with it counted for the gap found.
  double margin = 0.5 * side, gap = 0.0;
  std::vector<Eigen::Vector2d> at = loop;
  for (int round = 0; round < 2; ++round)
  {
    target = counted(margin);
    if (!(target > 0.0))
      return nan;
    for (int step = 0; step < 2; ++step)
    {
      const double perimeter = Perimeter(at);
      if (!(perimeter > 0.0))
        return nan;
      gap = std::clamp(gap + (target - SignedArea(at)) / perimeter, -r, r);
      at = outer(r - gap);
      if (at.empty())
        return nan;
    }
    margin = gap;
  }
  return gap;
}

/// The smooth margins sampled densely (2000 steps along s), to measure a loop's points against.
struct SmoothSides
{
  const Outline& outline;
  std::vector<Eigen::Vector2d> right, left;
  explicit SmoothSides(const Outline& given)
    : outline(given)
  {
    const int samples = 2000;
    for (int k = 0; k <= samples; ++k)
    {
      const double y = outline.s0 + (outline.s1 - outline.s0) * k / samples;
      right.push_back({ outline.Right(y), y });
      left.push_back({ outline.Left(y), y });
    }
  }
  /// The distance from p inwards to the smooth margin of its side (negative outside it) and that margin's nearest
  /// point.
  double Inwards(const Eigen::Vector2d& p, Eigen::Vector2d& nearest) const
  {
    const std::vector<Eigen::Vector2d>& margin = p.x() > 0.0 ? right : left;
    double best = 1e300;
    for (const auto& q : margin)
      if ((q - p).squaredNorm() < best)
      {
        best = (q - p).squaredNorm();
        nearest = q;
      }
    const double xi = (p.y() - outline.s0) / (outline.s1 - outline.s0);
    const bool inside =
      xi > 0.0 && xi < 1.0 && std::abs(p.x()) < (p.x() > 0.0 ? outline.Right(p.y()) : -outline.Left(p.y()));
    return inside ? std::sqrt(best) : -std::sqrt(best);
  }
};

/// The area the contour encloses (its right side up from the base, its left side back down).
double ContourArea(const Contour& contour)
{
  std::vector<Eigen::Vector2d> polygon(contour.right.begin(), contour.right.end());
  polygon.insert(polygon.end(), contour.left.rbegin(), contour.left.rend());
  return std::abs(SignedArea(polygon));
}

/// TraceContour's contour from its loop (counter-clockwise, in (t, s)): from the base's crossing of t = 0 to the
/// apex's on either side, snapped to the smooth margins where it follows them (`snap`, `band`), the smooth margins'
/// tips near a tip. Empty when the loop describes no blade; sets outline.base and outline.apex otherwise.
Contour ContourFromLoop(const std::vector<Eigen::Vector2d>& loop, const std::vector<Eigen::Vector2d>& ts,
  double spacing, double gap, double band, bool snap, const SmoothSides& sides, Outline& outline)
{
  // The midvein's ends: crossings of t = 0 by the loop (MidveinEnds).
  const std::size_t n = loop.size();
  std::pair<double, std::size_t> base, apex;
  Contour contour;
  if (!MidveinEnds(loop, spacing, base, apex))
    return contour;
  // The midvein spans most of the blade's extent: a piece shorter than half of it is not a midvein this outline
  // describes (the smooth margins are taken).
  const double extent = outline.s1 - outline.s0;
  if (!(apex.first - base.first > 0.5 * extent))
    return contour;
  // A tip (not a notch) extends beyond the last points by more than the gap, and the loop rounds it off: near a
  // tip (within 6 spacings) the smooth margins, whose tips are extrapolated from the last points (TipBeyond), are
  // taken instead. A notch or sinus counts only when deeper than MinNotchDepth of the blade's extent (and 4
  // spacings): shallower ones are the tip's own margin, unless the loop rises on both sides of the apex's crossing
  // to two lobes (ApexIsTip: the ginkgo's notch, 3 spacings deep on a line scan, below an s1 the noise moves).
  const double shallow = std::max(4.0 * spacing, MinNotchDepth * extent);
  double baseS = outline.s0;
  const bool baseTip = BaseEnd(ts, outline, base.first, shallow, spacing, baseS);
  // A drawn-out tip (DrawnOutApex) ends a mean gap beyond its last sample, wherever the loop crosses the midvein
  // (it does not follow a run of points one across). Where the loop's crossing is a tip already, only a run one
  // point across (within a spacing of t = 0) is one: an acute apex's samples thin out as its area does.
  double drawnEnd = 0.0;
  const bool nearTip = ApexIsTip(loop, apex, outline.s1, extent, spacing);
  const bool drawnOut = DrawnOutApex(ts, apex.first - 5.0 * spacing, (nearTip ? 1.0 : 2.5) * spacing, drawnEnd);
  const bool apexTip = drawnOut || nearTip;
  const double apexS = drawnOut ? std::min(outline.s1, drawnEnd)
                                : (apexTip ? outline.s1 : ApexEnd(loop, ts, apex, extent, shallow, spacing, gap));
  // (A shallow notch's walls are left out with the tip: the cut reaches 2 spacings below its bottom.)
  const double baseCut = baseTip ? baseS + std::max(6.0 * spacing, base.first - baseS + 2.0 * spacing) : -1e300;
  const double apexCut =
    apexTip ? outline.s1 - std::max(6.0 * spacing, outline.s1 - apex.first + 2.0 * spacing) : 1e300;
  // The loop from the base to the apex on the right (t > 0, counter-clockwise) and on the left (clockwise).
  // Where the loop runs along the smooth margin, the smooth margin: it is the better estimate of a margin the points
  // reach (its stations know their own density). The loop is kept where it departs from it by a real feature: a run
  // of the loop's points off the band (from a spacing outside the smooth margin to `band` inside it) that reaches
  // 4 spacings (twice the band) away somewhere (a sinus, a notch, a lobe the smooth margins do not follow); shallower runs are the
  // ragged edge of a real scan's points and are snapped too.
  std::vector<Eigen::Vector2d> nearest(n);
  std::vector<double> depth(n);
  for (std::size_t i = 0; i < n; ++i)
    depth[i] = sides.Inwards(loop[i], nearest[i]);
  std::vector<unsigned char> snapped = SnapFlags(depth, spacing, band, contour.features);
  if (!snap)
    snapped.assign(n, 0);
  // Snapped points go up the smooth margin from base to apex (nearest points may fall back where the loop turns
  // sharply: those are left out, or the margin would cross itself).
  auto walk = [&](std::size_t from, std::size_t to, bool forward) {
    std::vector<Eigen::Vector2d> path;
    std::size_t i = forward ? (from + 1) % n : from;
    const std::size_t stop = forward ? (to + 1) % n : to;
    double highest = -1e300;
    while (i != stop)
    {
      if (loop[i].y() > baseCut && loop[i].y() < apexCut && !(snapped[i] && nearest[i].y() <= highest))
      {
        path.push_back(snapped[i] ? nearest[i] : loop[i]);
        if (snapped[i])
          highest = nearest[i].y();
      }
      i = forward ? (i + 1) % n : (i + n - 1) % n;
    }
    return path;
  };
  auto smooth = [&](std::vector<Eigen::Vector2d>& side, bool right, double from, double to) {
    const int steps = std::max(2, static_cast<int>(std::ceil(std::abs(to - from) / (0.25 * spacing))));
    for (int k = 1; k < steps; ++k)
    {
      // A base below the smooth margins' tip (down to a stalk's junction across a gap) is reached in a straight
      // line from where they have width: along t = 0 the two sides would meet and the outline would fold.
      const double y = from + (to - from) * k / steps;
      if (y > outline.s0)
        side.push_back({ right ? outline.Right(y) : outline.Left(y), y });
    }
  };
  for (int side = 0; side < 2; ++side)
  {
    std::vector<Eigen::Vector2d>& path = side == 0 ? contour.right : contour.left;
    path.push_back({ 0.0, baseS });
    if (baseTip)
      smooth(path, side == 0, baseS, baseCut);
    for (const auto& p : walk(base.second, apex.second, side == 0))
      path.push_back(p);
    if (apexTip)
      smooth(path, side == 0, apexCut, apexS);
    path.push_back({ 0.0, apexS });
  }
  // Both sides must keep to their side of t = 0 (a loop that crosses it elsewhere between the two ends is not
  // a blade this outline describes). A point less than half a spacing across (a flank grazing t = 0 beside a narrow
  // base, MidveinEnds) is put on t = 0.
  for (int side = 0; side < 2; ++side)
  {
    std::vector<Eigen::Vector2d>& path = side == 0 ? contour.right : contour.left;
    const double sign = side == 0 ? 1.0 : -1.0;
    for (std::size_t i = 1; i + 1 < path.size(); ++i)
    {
      if (sign * path[i].x() < -0.5 * spacing)
        return Contour();
      path[i].x() = sign * std::max(sign * path[i].x(), 0.0);
    }
  }
  outline.base = baseS;
  outline.apex = apexS;
  return contour;
}

/// The smooth margins kept within a spacing of `loop` (the region the points draw), for a blade whose loop gives no
/// contour (its crossings of t = 0 do not bound one midvein, or a side crosses t = 0: a strip of points along the
/// midrib beside t = 0 below a bare base, the sugar beet of 30 August's): each margin at s goes no farther out than
/// the loop's outermost point at s and a spacing, and no farther in than t = 0. Where the loop does not reach (the
/// tips beyond the last points) the smooth margins are kept. Empty when the loop is.
Contour ClippedMargins(const std::vector<Eigen::Vector2d>& loop, const Outline& outline, double spacing)
{
  Contour contour;
  if (loop.size() < 3 || !(outline.s1 > outline.s0))
    return contour;
  const int steps = std::max(2, static_cast<int>(std::ceil((outline.s1 - outline.s0) / (0.25 * spacing))));
  contour.right.push_back({ 0.0, outline.s0 });
  contour.left.push_back({ 0.0, outline.s0 });
  for (int k = 1; k < steps; ++k)
  {
    const double s = outline.s0 + (outline.s1 - outline.s0) * k / steps;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < loop.size(); ++i)
    {
      const Eigen::Vector2d& p = loop[i];
      const Eigen::Vector2d& q = loop[(i + 1) % loop.size()];
      if ((p.y() > s) != (q.y() > s))
      {
        const double t = p.x() + (q.x() - p.x()) * (s - p.y()) / (q.y() - p.y());
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
    }
    const bool reached = hi >= lo;
    contour.right.push_back({ reached ? std::clamp(hi + spacing, 0.0, outline.Right(s)) : outline.Right(s), s });
    contour.left.push_back({ reached ? std::clamp(lo - spacing, outline.Left(s), 0.0) : outline.Left(s), s });
  }
  contour.right.push_back({ 0.0, outline.s1 });
  contour.left.push_back({ 0.0, outline.s1 });
  return contour;
}
} // namespace

bool ApexIsTip(const std::vector<Eigen::Vector2d>& loop, const std::pair<double, std::size_t>& apex, double s1,
  double extent, double spacing)
{
  const double shallow = std::max(4.0 * spacing, MinNotchDepth * extent);
  if (!(std::abs(apex.first - s1) < shallow))
    return false;
  return !(ApexNotchRise(loop, apex, shallow) > std::max(MinNotchDepth * extent, 2.0 * spacing));
}

double ApexTrail(const std::vector<Eigen::Vector2d>& ts, double spacing)
{
  if (ts.empty() || !(spacing > 0.0))
    return 0.0;
  std::vector<Eigen::Vector2d> top(ts);
  std::sort(top.begin(), top.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.y() > b.y(); });
  // Down from the highest sample, slice by slice a spacing thick: the trail goes on while each slice's samples lie
  // within 1.5 spacings of one another across (a point or two) and no gap along it is wider than 8 spacings.
  const double highest = top.front().y();
  double end = highest, lo = top.front().x(), hi = lo, sliceTop = highest;
  for (const auto& p : top)
  {
    if (sliceTop - p.y() > spacing)
    {
      if (end - p.y() > 8.0 * spacing)
        break;
      sliceTop = p.y();
      lo = hi = p.x();
    }
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
    if (!(hi - lo < 1.5 * spacing))
      break;
    end = p.y();
  }
  return highest - end;
}

/// The points' number variance over its mean, in discs of radius `radius` wholly inside the points' region
/// (F >= r + radius), their centres on a grid about 0.7 radius apart (at most about 8000 of them); `windows` the
/// discs counted. A lattice's (or several superimposed lattices') counts vary only where a disc's rim cuts its cells:
/// a small ratio; random points' counts are Poisson: about 1. -1 with fewer than 2 discs.
double NumberVarianceRatio(const std::vector<Eigen::Vector2d>& ts, const std::vector<double>& F, int nx, int ny,
  const Eigen::Vector2d& origin, double cell, double r, double radius, int& windows)
{
  windows = 0;
  const Buckets buckets(ts, origin, radius, nx * cell, ny * cell);
  const double most = std::sqrt(static_cast<double>(nx) * ny / 8000.0);
  const int stride = std::max(1, static_cast<int>(std::ceil(std::max(0.7 * radius / cell, most))));
  double sum = 0.0, sum2 = 0.0;
  for (int j = 0; j < ny; j += stride)
    for (int i = 0; i < nx; i += stride)
    {
      if (!(F[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j] >= r + radius))
        continue;
      const Eigen::Vector2d at = origin + cell * Eigen::Vector2d(i, j);
      double n = 0.0;
      buckets.Near(at, 1, [&](std::size_t k) { n += (ts[k] - at).squaredNorm() < radius * radius ? 1.0 : 0.0; });
      sum += n;
      sum2 += n * n;
      ++windows;
    }
  if (windows < 2 || !(sum > 0.0))
    return -1.0;
  const double mean = sum / windows;
  return std::max(sum2 / windows - mean * mean, 0.0) / mean;
}

namespace
{
/// The distance (in cells) to the nearest point's cell or the nearest cell of a segment that joins the points of a
/// sparsely sampled part, less (near such a part's points) the margin's reach beyond them (FindSparseParts), so
/// that discs of radius r about the cells at distance 0 reach that much farther there.
std::vector<double> SparseDistance(std::vector<unsigned char> hit, int nx, int ny, const Eigen::Vector2d& origin,
  double cell, double r, const std::vector<Eigen::Vector2d>& ts, const SparseParts& parts, const ParallelFor& parallel)
{
  auto index = [&](const Eigen::Vector2d& at) {
    const int i = std::clamp(static_cast<int>(std::lround(at.x())), 0, nx - 1);
    const int j = std::clamp(static_cast<int>(std::lround(at.y())), 0, ny - 1);
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j;
  };
  for (const auto& [a, b] : parts.bridges)
  {
    const Eigen::Vector2d from = (ts[a] - origin) / cell, step = (ts[b] - ts[a]) / cell;
    const int steps = static_cast<int>(std::ceil(2.0 * step.norm())) + 1;
    for (int k = 0; k <= steps; ++k)
      hit[index(from + step * (static_cast<double>(k) / steps))] = 1;
  }
  std::vector<double> distance = DistanceTo(hit, nx, ny, parallel);
  for (const auto& [k, reach] : parts.reaches)
  {
    const Eigen::Vector2d at = (ts[k] - origin) / cell;
    const int extent = static_cast<int>(std::ceil((r + reach) / cell));
    const int i0 = static_cast<int>(std::lround(at.x())), j0 = static_cast<int>(std::lround(at.y()));
    for (int j = std::max(0, j0 - extent); j <= std::min(ny - 1, j0 + extent); ++j)
      for (int i = std::max(0, i0 - extent); i <= std::min(nx - 1, i0 + extent); ++i)
      {
        double& d = distance[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j];
        d = std::min(d, std::max(0.0, (Eigen::Vector2d(i, j) - at).norm() - reach / cell));
      }
  }
  return distance;
}
/// The closing's distance inside (0 outside; in the grid's units) of the discs of radius r about the cells at
/// `distance` 0 (in cells), its holes filled.
std::vector<double> Closed(
  const std::vector<double>& distance, int nx, int ny, double cell, double r, const ParallelFor& parallel)
{
  std::vector<unsigned char> inside(distance.size()), outside(distance.size());
  ForEachIndex(parallel, distance.size(), [&](std::size_t c) { inside[c] = distance[c] * cell <= r ? 1 : 0; });
  FillHoles(inside, nx, ny);
  ForEachIndex(parallel, distance.size(), [&](std::size_t c) { outside[c] = inside[c] ? 0 : 1; });
  std::vector<double> inwards = DistanceTo(outside, nx, ny, parallel);
  ForEachIndex(parallel, inwards.size(), [&](std::size_t c) { inwards[c] *= cell; });
  return inwards;
}
} // namespace

Contour TraceContour(
  const std::vector<Eigen::Vector2d>& ts, double spacing, bool snap, Outline& outline, const ParallelFor& parallel)
{
  Contour contour;
  outline.base = outline.s0;
  outline.apex = outline.s1;
  if (ts.size() < 3 || !(spacing > 0.0))
    return contour;
  Eigen::Vector2d lo = ts.front(), hi = ts.front();
  for (const auto& p : ts)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // The points' region: the union of discs of radius r about the points, its holes filled (bridged), closed
  // (eroded back by r: concave notches wider than about 2 r stay open) and grown by the expected gap between the
  // outermost points and the margin.
  const double r = 2.5 * spacing;
  // The blade's sparsely sampled parts, whose margin reaches farther: the grid leaves room for it.
  const SparseParts parts = FindSparseParts(ts, spacing, parallel);
  double farthest = 0.0;
  for (const auto& reach : parts.reaches)
    farthest = std::max(farthest, reach.second);
  const Eigen::Vector2d span = hi - lo;
  const double cell = std::max(0.5 * spacing, std::sqrt(span.x() * span.y() / 4e6));
  // Whole cells of room, so that the cells lie where they lie without it.
  const int room = static_cast<int>(std::ceil(farthest / cell));
  const Eigen::Vector2d origin = lo - Eigen::Vector2d::Constant(r + (3.0 + room) * cell);
  const int nx = static_cast<int>((span.x() + 2.0 * r) / cell) + 7 + 2 * room;
  const int ny = static_cast<int>((span.y() + 2.0 * r) / cell) + 7 + 2 * room;
  std::vector<unsigned char> hit(static_cast<std::size_t>(nx) * ny, 0);
  for (const auto& p : ts)
  {
    const int i = static_cast<int>(std::lround((p.x() - origin.x()) / cell));
    const int j = static_cast<int>(std::lround((p.y() - origin.y()) / cell));
    hit[std::clamp(i, 0, nx - 1) + nx * std::clamp(j, 0, ny - 1)] = 1;
  }
  std::vector<double> toPoint = DistanceTo(hit, nx, ny, parallel);
  std::vector<double> F = Closed(toPoint, nx, ny, cell, r, parallel);
  // The largest loop at a level (counter-clockwise, smoothed), empty when there is none.
  auto outer = [&](double level) {
    std::vector<std::vector<Eigen::Vector2d>> loops = LevelLoops(F, nx, ny, level, origin, cell);
    if (loops.empty())
      return std::vector<Eigen::Vector2d>();
    std::vector<Eigen::Vector2d> loop = *std::max_element(
      loops.begin(), loops.end(), [](const auto& a, const auto& b) { return SignedArea(a) < SignedArea(b); });
    if (!(SignedArea(loop) > 0.0))
      return std::vector<Eigen::Vector2d>();
    SmoothLoop(loop, 4);
    return loop;
  };
  // The discs about the segments that join the points of sparsely sampled parts too (whose margin reaches farther
  // beyond their points). `pointsOnly`: the points' own closing, on which a regular grid is judged; `added`: the
  // share of the blade's area the sparse parts add to it.
  std::vector<double> pointsOnly;
  double added = 0.0;
  if (!parts.bridges.empty())
  {
    const double before = SignedArea(outer(r));
    pointsOnly = std::move(F);
    F = Closed(SparseDistance(hit, nx, ny, origin, cell, r, ts, parts, parallel), nx, ny, cell, r, parallel);
    added = before > 0.0 ? SignedArea(outer(r)) / before - 1.0 : 1.0;
  }
  // The closing's boundary runs through the outermost points; the margin lies beyond them by a gap that depends on
  // how the points are spread (about a quarter of the spacing on a scanner's regular grid, about one spacing for
  // random points). It is measured against the smooth margins (whose stations estimate it from their own density)
  // where the two agree within two spacings (away from sinuses, which the smooth margins bridge): the median
  // distance, along the smooth margin's normal, from the loop to it.
  std::vector<Eigen::Vector2d> loop = outer(r);
  if (loop.empty())
    return contour;
  const double L = outline.s1 - outline.s0;
  const Outline given = outline;
  const SmoothSides sides(given);
  std::vector<double> gaps;
  std::size_t middle = 0; // the loop's points from 10 to 90 % of the length
  double band = spacing;  // where the loop is taken as running along the smooth margin (inwards of it)
  for (const auto& p : loop)
  {
    Eigen::Vector2d q;
    const double xi = (p.y() - outline.s0) / L, d = sides.Inwards(p, q);
    middle += xi > 0.1 && xi < 0.9 ? 1 : 0;
    if (xi > 0.1 && xi < 0.9 && std::abs(d) < 3.0 * spacing)
      gaps.push_back(d);
  }
  // Where the loop runs along the smooth margins (half of its points from 10 to 90 % of the length within 1.5
  // spacings of the median), the median is the gap; where it does not (lobes, sinuses: the smooth margins follow
  // neither), the gap from the points' count (CountedGap), and the contour, tips and snapping included, is then
  // moved in or out by the loop's level to enclose the counted area.
  bool followed = false, regular = false;
  double gap = 0.0;
  if (gaps.size() >= 10)
  {
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    const double median = gaps[gaps.size() / 2];
    gap = std::clamp(median, 0.0, 3.0 * spacing);
    // How far the loop wanders about the smooth margin (robust deviation): random points leave deeper dents
    // between them than a scanner's regular grid does.
    // Only the loop's points within 1.5 spacings of the median count (a lobed blade's sinuses are no wandering).
    std::vector<double> deviation;
    for (double d : gaps)
      if (std::abs(d - median) < 1.5 * spacing)
        deviation.push_back(std::abs(d - median));
    band = std::clamp(2.5 * MadToDeviation * Median(deviation), spacing, 3.0 * spacing);
    followed = 2 * deviation.size() >= middle;
    // A scanner's regular grid, one pass or several superimposed (MaxGridNumberVariance): its count gives the area,
    // and its outline is kept where it is. The smooth margins' stations put the margin about a quarter of a spacing
    // beyond the count's on a clean scan, farther where range noise spreads the outermost points (an oblique view's
    // noise moves them across the blade), and snapping moved the outline there: the accuracy benchmark's 132 cases
    // -0.83 to +1.46 % in Area at 0.3 % noise, 44 of 132 within 1 % at 1 % noise; by the count -0.83 to +0.35 %, and
    // 96 of 132 (the rest mostly the fitted surface's own bumps). Random points keep the smooth margins and their
    // gap: the count is biased on them. The grid is judged on the points' own discs; a blade whose sparse parts add
    // MinSparseShare of its area or more is no regular grid: the count would give their points the area the dense
    // part's stand for (an ellipse with a flank on a lattice 6 spacings apart came out 24 % short by the count).
    const double side = PointSide(loop, ts.size());
    int windows = 0;
    const double variance =
      NumberVarianceRatio(ts, pointsOnly.empty() ? F : pointsOnly, nx, ny, origin, cell, r, 2.5 * side, windows);
    regular = added < MinSparseShare && followed && windows >= MinGridWindows && variance >= 0.0 &&
      variance <= MaxGridNumberVariance;
  }
  // The contour from the loop at the gap, or (`byCount`) at the level whose contour encloses the counted area.
  // `at`: the level's gap, set to the level the contour was taken at.
  auto attempt = [&](bool byCount, bool snapping, double& at, std::vector<Eigen::Vector2d>& traced, Outline& out) {
    double target = std::numeric_limits<double>::quiet_NaN();
    const double counted =
      byCount ? CountedGap(ts, F, toPoint, nx, ny, origin, cell, r, spacing, traced, outer, target) : target;
    const bool count = std::isfinite(counted);
    if (count)
      at = std::clamp(counted, 0.0, 3.0 * spacing);
    if (at > 0.0)
      traced = outer(r - at);
    if (traced.empty())
      return Contour();
    Contour found = ContourFromLoop(traced, ts, spacing, at, band, snapping, sides, out);
    // The loop's area changes by about its perimeter times a change of level (less where tips or snapped runs
    // replace it: the measured change is used for the second step).
    double slope = Perimeter(traced), level = at;
    const double base = out.base, apex = out.apex;
    for (int step = 0; count && step < 2 && !found.right.empty(); ++step)
    {
      const double area = ContourArea(found), excess = area - target;
      if (std::abs(excess) <= 1e-3 * target || !(slope > 0.0))
        break;
      const double next = std::clamp(level - excess / slope, -3.0 * spacing, 3.0 * spacing);
      const std::vector<Eigen::Vector2d> moved = outer(r - next);
      Outline again = given;
      const Contour matched = moved.empty() || next == level
        ? Contour()
        : ContourFromLoop(moved, ts, spacing, next, band, snapping, sides, again);
      // The move must leave the midvein's ends where they were, within the move and a spacing: a notch between
      // lobes at an end (a palmate blade's base) deepens or fills far faster than the level moves, and the counted
      // area is no measure of where the midvein ends.
      if (matched.right.empty() || std::abs(again.base - base) > std::abs(next - at) + spacing ||
        std::abs(again.apex - apex) > std::abs(next - at) + spacing)
        break;
      slope = (ContourArea(matched) - area) / (next - level);
      level = next;
      found = matched;
      out = again;
    }
    at = level;
    return found;
  };
  // A regular scan's count is kept when its contour leaves the midvein's ends where the smooth margins' gap puts
  // them, within the change of level and a spacing: a narrow wedge's crossing of t = 0 moves far faster than the
  // level (the ginkgo's base into its petiole, read as a sinus 5 % of the length up), and a loop that gives no
  // contour unsnapped (a flank wiggling across t = 0) has none to compare. Otherwise, and on other scans, the
  // smooth margins and their gap (or the count, where the loop does not follow them).
  double level = gap;
  if (regular)
  {
    std::vector<Eigen::Vector2d> counted = loop;
    Outline byCount = given;
    double countLevel = gap;
    const Contour found = attempt(true, false, countLevel, counted, byCount);
    const double moved = std::abs(countLevel - gap) + spacing;
    contour = attempt(false, snap, level, loop, outline);
    if (!found.right.empty() &&
      (contour.right.empty() ||
        (std::abs(byCount.base - outline.base) <= moved && std::abs(byCount.apex - outline.apex) <= moved)))
    {
      contour = found;
      loop = counted;
      outline = byCount;
    }
  }
  else
    contour = attempt(!followed, snap, level, loop, outline);
  // No contour from the loop: the smooth margins, but not beyond the loop (they would spread the blade over
  // ground no point samples: 214 of the sugar beet's triangles, up to 8 spacings from the scan).
  if (contour.right.empty())
    contour = ClippedMargins(loop, given, spacing);
  return contour;
}

} // namespace fit

} // namespace plantmorph
