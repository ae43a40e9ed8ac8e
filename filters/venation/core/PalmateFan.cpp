// SPDX-License-Identifier: GPL-3.0-or-later
#include "PalmateFan.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace
{
double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() * b.y() - a.y() * b.x();
}

/// The outer boundary loop seen from the base: points from the base vertex round the loop, with d and phi.
struct View
{
  std::vector<Eigen::Vector2d> points;
  std::vector<double> distance, angle, axial;
};

View Look(
  const VenationBlade& blade, const BladeLocator& locator, const Eigen::Vector2d& base, const Eigen::Vector2d& axis)
{
  View view;
  if (locator.BoundaryLoops().empty())
    return view;
  const std::vector<int>& loop = locator.BoundaryLoops().front();
  std::size_t start = 0;
  for (std::size_t i = 1; i < loop.size(); ++i)
  {
    if ((blade.points[loop[i]] - base).norm() < (blade.points[loop[start]] - base).norm())
      start = i;
  }
  for (std::size_t k = 0; k < loop.size(); ++k)
  {
    const Eigen::Vector2d x = blade.points[loop[(start + k) % loop.size()]];
    const Eigen::Vector2d r = x - base;
    view.points.push_back(x);
    view.distance.push_back(r.norm());
    view.axial.push_back(r.dot(axis));
    view.angle.push_back(std::atan2(Cross(axis, r), r.dot(axis)));
  }
  return view;
}

/// Loop indices of the lobe tips: local maxima of the distance with at least `prominence` whose lobe (the margin
/// between its two sinuses, closed by their chord) has an area of at least `area`.
std::vector<std::size_t> LobeTips(const View& view, double prominence, double area)
{
  const std::vector<double>& d = view.distance;
  const std::size_t n = d.size();
  std::vector<std::size_t> tips;
  for (std::size_t i = 1; i < n; ++i)
  {
    const double previous = d[i - 1], next = i + 1 < n ? d[i + 1] : d[0];
    if (!(d[i] > previous && d[i] >= next))
      continue;
    // The lowest point on each side before the walk meets a higher point or returns to the base (d = 0 there); of
    // two equally high maxima (the two teeth beside a serrate lobe's tip) the walk to the left stops at the other,
    // so only the first of them is a lobe.
    double left = d[i], right = d[i];
    std::size_t from = i, to = i;
    for (std::size_t j = i; j-- > 0 && d[j] < d[i];)
    {
      if (d[j] < left)
      {
        left = d[j];
        from = j;
      }
    }
    for (std::size_t j = i + 1; j <= n && (j == n ? 0.0 : d[j]) <= d[i]; ++j)
    {
      if ((j == n ? 0.0 : d[j]) < right)
      {
        right = j == n ? 0.0 : d[j];
        to = j;
      }
    }
    if (d[i] - std::max(left, right) < prominence)
      continue;
    // The lobe's area (shoelace over the margin from one sinus to the other; the base closes a walk that reached it).
    double twice = 0.0;
    for (std::size_t j = from; j < to; ++j)
      twice += Cross(view.points[j], view.points[(j + 1) % n]);
    twice += Cross(view.points[to % n], view.points[from]);
    if (0.5 * std::abs(twice) >= area)
      tips.push_back(i);
  }
  return tips;
}

/// Where the ray from `base` at angle `phi` leaves the blade's outer loop: for the first time (beyond `near`) when
/// that is at least 0.8 of the way to the last time (a serration's notch: the straight vein from the base stays
/// on the blade, so every primary may be straight and leave the base at its own angle), else for the last time; the
/// boundary vertex nearest in angle (among those at least `near` from the base) when the ray meets nothing.
Eigen::Vector2d RayEnd(
  const View& view, const Eigen::Vector2d& base, const Eigen::Vector2d& axis, double phi, double near)
{
  const Eigen::Vector2d left(-axis.y(), axis.x());
  const Eigen::Vector2d direction = std::cos(phi) * axis + std::sin(phi) * left;
  const std::size_t n = view.points.size();
  double farthest = -1.0, first = std::numeric_limits<double>::max();
  for (std::size_t i = 1; i + 1 < n; ++i) // the two edges at the base vertex are left out
  {
    const Eigen::Vector2d a = view.points[i], b = view.points[i + 1];
    const Eigen::Vector2d e = b - a;
    const double denominator = Cross(direction, e);
    if (std::abs(denominator) < 1e-300)
      continue;
    const double t = Cross(a - base, e) / denominator;
    const double s = Cross(a - base, direction) / denominator;
    if (t > near && s >= 0.0 && s <= 1.0)
    {
      farthest = std::max(farthest, t);
      first = std::min(first, t);
    }
  }
  if (farthest > 0.0)
    return base + (first >= 0.8 * farthest ? first : farthest) * direction;
  std::size_t best = 0;
  double gap = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (view.distance[i] >= near && std::abs(view.angle[i] - phi) < gap)
    {
      gap = std::abs(view.angle[i] - phi);
      best = i;
    }
  }
  return view.points[best];
}

struct Primary
{
  double angle = 0.0;
  bool hasTip = false;
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();
};
} // namespace

PalmateFan FindPalmateFan(const VenationBlade& blade, const BladeLocator& locator, const Eigen::Vector2d& base,
  const Eigen::Vector2d& axis, double length, const PalmateFanParameters& settings)
{
  PalmateFan fan;
  const View view = Look(blade, locator, base, axis);
  if (view.points.size() < 3)
    return fan;
  const std::size_t n = view.points.size();
  const double near = 0.05 * length;

  // Lobes, basal lobes, and the angular extent.
  const std::vector<std::size_t> tips =
    LobeTips(view, settings.lobeProminence * length, settings.lobeArea * length * length);
  int basal[2] = { -1, -1 }; // right (phi < 0), left
  double low = 0.0, high = 0.0, lowest = 0.0, highest = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (view.distance[i] >= settings.extentDistance * length)
    {
      low = std::min(low, view.angle[i]);
      high = std::max(high, view.angle[i]);
    }
    if (view.distance[i] >= near)
    {
      lowest = std::min(lowest, view.angle[i]);
      highest = std::max(highest, view.angle[i]);
    }
    if (view.axial[i] < -settings.basalDepth * length)
    {
      const int side = view.angle[i] < 0.0 ? 0 : 1;
      if (basal[side] < 0 || view.axial[i] < view.axial[basal[side]])
        basal[side] = static_cast<int>(i);
    }
  }
  const bool lobed = tips.size() >= 3;
  const bool cordate = basal[0] >= 0 && basal[1] >= 0;

  std::vector<Primary> primaries;
  if (lobed)
  {
    for (std::size_t i : tips)
    {
      primaries.push_back({ view.angle[i], true, view.points[i] });
      fan.lobeTips.push_back(view.points[i]);
    }
  }
  // On a lobed blade the lobes are the prominent maxima alone: a basal lobe is one of them when its sinus is deep
  // enough, and the lowest margin point behind the base is no lobe of its own (on a fitted scan it is a bump of the
  // noisy margin beside the petiole, and a primary there would end a few per cent of the length from the base).
  if (cordate)
  {
    for (int side : { 0, 1 })
      fan.basalTips.push_back(view.points[basal[side]]);
  }
  const int m = std::max(1, settings.primaries);
  if (!lobed && cordate && m >= 2)
  {
    const double right = view.angle[basal[0]], left = view.angle[basal[1]];
    for (int i = 0; i < m; ++i)
    {
      const bool outer = i == 0 || i == m - 1;
      primaries.push_back({ right + (left - right) * i / (m - 1), outer, view.points[basal[i == 0 ? 0 : 1]] });
    }
  }
  else if (!lobed)
  {
    for (int i = 0; i < m; ++i)
      primaries.push_back({ low + (high - low) * (i + 0.25) / (m - 0.5), false, Eigen::Vector2d::Zero() });
  }
  std::stable_sort(
    primaries.begin(), primaries.end(), [](const Primary& a, const Primary& b) { return a.angle < b.angle; });

  // Each primary's share of the angles: half way to its neighbours (the outermost as wide on their outer side).
  const int branches = 1 << std::max(0, settings.levels);
  for (std::size_t i = 0; i < primaries.size(); ++i)
  {
    const Primary& p = primaries[i];
    std::vector<Eigen::Vector2d> ends;
    if (branches == 1)
    {
      ends.push_back(p.hasTip ? p.tip : RayEnd(view, base, axis, p.angle, near));
      fan.ends.push_back(ends);
      continue;
    }
    const double before = i > 0 ? 0.5 * (p.angle - primaries[i - 1].angle) : -1.0;
    const double after = i + 1 < primaries.size() ? 0.5 * (primaries[i + 1].angle - p.angle) : -1.0;
    double from = p.angle - (before >= 0.0 ? before : std::max(after, 0.0));
    double to = p.angle + (after >= 0.0 ? after : std::max(before, 0.0));
    if (primaries.size() == 1)
    {
      from = low;
      to = high;
    }
    from = std::max(from, lowest);
    to = std::min(to, highest);
    for (int k = 0; k < branches; ++k)
      ends.push_back(RayEnd(view, base, axis, from + (to - from) * (k + 0.5) / branches, near));
    fan.ends.push_back(ends);
  }
  return fan;
}

} // namespace plantmorph
