// SPDX-License-Identifier: GPL-3.0-or-later
#include "ScannerView.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{

void RangeEquations::Add(const Eigen::Vector3d& point, double range)
{
  if (!point.allFinite() || !std::isfinite(range) || !(range > 0.0))
    return;
  const Eigen::Vector4d row(-2.0 * point.x(), -2.0 * point.y(), -2.0 * point.z(), 1.0);
  this->normal.noalias() += row * row.transpose();
  this->right += row * (range * range - point.squaredNorm());
  this->count += 1.0;
  this->rangeSum += range;
}

std::vector<double> RangeEquations::Values() const
{
  std::vector<double> values(this->normal.data(), this->normal.data() + 16);
  values.insert(values.end(), this->right.data(), this->right.data() + 4);
  values.push_back(this->count);
  values.push_back(this->rangeSum);
  return values;
}

void RangeEquations::Add(const double* values)
{
  for (int k = 0; k < 16; ++k)
    this->normal.data()[k] += values[k];
  for (int k = 0; k < 4; ++k)
    this->right[k] += values[16 + k];
  this->count += values[20];
  this->rangeSum += values[21];
}

std::optional<Eigen::Vector3d> ScannerPosition(const RangeEquations& equations)
{
  if (equations.count < 4.0 || !equations.normal.allFinite() || !equations.right.allFinite())
    return std::nullopt;
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(equations.normal);
  if (lu.rank() < 4)
    return std::nullopt;
  const Eigen::Vector4d solution = lu.solve(equations.right);
  const Eigen::Vector3d position = solution.head<3>();
  if (!position.allFinite())
    return std::nullopt;
  // The fourth unknown is |s|^2: a scan whose ranges are distances from one place gives it back.
  const double meanRange = equations.rangeSum / equations.count;
  if (std::abs(solution[3] - position.squaredNorm()) > MaxRangeResidual * meanRange * meanRange + 1e-12)
    return std::nullopt;
  return position;
}

DirectionCells::DirectionCells(const Eigen::Vector3d& up, double cell)
{
  if (!(cell > 0.0) || !std::isfinite(cell) || !(up.norm() > 0.0))
    return;
  this->Up = up.normalized();
  const Eigen::Vector3d other =
    std::abs(this->Up.x()) < 0.9 ? Eigen::Vector3d::UnitX().eval() : Eigen::Vector3d::UnitY().eval();
  this->East = (other - other.dot(this->Up) * this->Up).normalized();
  this->North = this->Up.cross(this->East);
  this->Cell = std::max(cell, 1e-7); // a ring count that fits the key
}

void DirectionCells::RingAndAngle(const Eigen::Vector3d& d, long long& ring, double& angle) const
{
  const double elevation = std::asin(std::clamp(d.dot(this->Up), -1.0, 1.0)); // [-pi/2, pi/2]
  ring = static_cast<long long>(std::floor((elevation + 0.5 * M_PI) / this->Cell));
  angle = std::atan2(d.dot(this->North), d.dot(this->East)) + M_PI; // [0, 2 pi]
}

long long DirectionCells::CellsInRing(long long ring) const
{
  const double elevation = (static_cast<double>(ring) + 0.5) * this->Cell - 0.5 * M_PI;
  return std::max(1LL, static_cast<long long>(std::ceil(2.0 * M_PI * std::cos(elevation) / this->Cell)));
}

std::int64_t DirectionCells::Key(const Eigen::Vector3d& d) const
{
  long long ring = 0;
  double angle = 0.0;
  this->RingAndAngle(d, ring, angle);
  const long long n = this->CellsInRing(ring);
  const long long at = static_cast<long long>(std::floor(angle / (2.0 * M_PI) * static_cast<double>(n))) % n;
  return static_cast<std::int64_t>(ring) * (1LL << 32) + at;
}

std::vector<std::int64_t> DirectionCells::Around(const Eigen::Vector3d& d) const
{
  long long ring = 0;
  double angle = 0.0;
  this->RingAndAngle(d, ring, angle);
  std::vector<std::int64_t> keys;
  keys.reserve(9);
  for (long long r = ring - 1; r <= ring + 1; ++r)
  {
    if (r < 0 || static_cast<double>(r) * this->Cell > M_PI)
      continue;
    const long long n = this->CellsInRing(r);
    const long long at = static_cast<long long>(std::floor(angle / (2.0 * M_PI) * static_cast<double>(n)));
    for (long long a = at - 1; a <= at + 1; ++a)
      keys.push_back(static_cast<std::int64_t>(r) * (1LL << 32) + ((a % n) + n) % n);
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

std::vector<CellRange> DepthMap::CellRanges(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::int64_t>& leaves) const
{
  std::vector<CellRange> cells;
  cells.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::Vector3d d = points[i] - this->position;
    const double range = d.norm();
    if (range > 0.0 && std::isfinite(range))
      cells.push_back({ this->cells.Key(d / range), range, i < leaves.size() ? leaves[i] : -1 });
  }
  return cells;
}

void DepthMap::Merge(std::vector<CellRange> points)
{
  std::sort(points.begin(), points.end());
  this->keys.clear();
  this->nearest.clear();
  this->otherNearest.clear();
  this->nearestLeaf.clear();
  const double none = std::numeric_limits<double>::infinity();
  for (const CellRange& p : points)
    if (this->keys.empty() || this->keys.back() != p.key) // sorted: the first of a key is its nearest
    {
      this->keys.push_back(p.key);
      this->nearest.push_back(p.range);
      this->nearestLeaf.push_back(p.leaf);
      this->otherNearest.push_back(none);
    }
    else if (this->otherNearest.back() == none && (p.leaf != this->nearestLeaf.back() || p.leaf < 0))
      this->otherNearest.back() = p.range;
}

double DepthMap::NearestAround(const Eigen::Vector3d& point, std::int64_t own) const
{
  double least = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d d = point - this->position;
  const double range = d.norm();
  if (!(range > 0.0) || !this->cells.Valid())
    return least;
  for (const std::int64_t key : this->cells.Around(d / range))
  {
    const auto it = std::lower_bound(this->keys.begin(), this->keys.end(), key);
    if (it == this->keys.end() || *it != key)
      continue;
    const auto at = static_cast<std::size_t>(it - this->keys.begin());
    const bool mine = own >= 0 && this->nearestLeaf[at] == own;
    least = std::min(least, mine ? this->otherNearest[at] : this->nearest[at]);
  }
  return least;
}

Eigen::Vector3d BladeCentre(const LeafFitResult& fit)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : fit.points)
    centre += p / static_cast<double>(fit.points.size());
  return centre;
}

namespace
{
/// A probe past a margin vertex: the vertex (an id into the blade's points) and where the probe lies.
struct Probe
{
  int vertex = 0;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
};

/// The probes past one margin polyline (ids into the blade's points, base to apex): MarginProbeSpacings spacings out
/// from each inner vertex, in the tangent plane, away from the blade's `centre` (one side for the whole margin).
std::vector<Probe> MarginProbes(
  const LeafFitResult& fit, const std::vector<int>& margin, const Eigen::Vector3d& centre, double spacing)
{
  std::vector<Probe> probes;
  std::vector<Eigen::Vector3d> outward;
  int away = 0;
  for (std::size_t i = 1; i + 1 < margin.size(); ++i)
  {
    const Eigen::Vector3d tangent = fit.points[margin[i + 1]] - fit.points[margin[i - 1]];
    Eigen::Vector3d out = tangent.cross(fit.normals[margin[i]]);
    if (!(out.norm() > 0.0))
      continue;
    out.normalize();
    away += out.dot(fit.points[margin[i]] - centre) >= 0.0 ? 1 : -1;
    probes.push_back({ margin[i], fit.points[margin[i]] });
    outward.push_back(out);
  }
  const double step = (away >= 0 ? 1.0 : -1.0) * MarginProbeSpacings * spacing;
  for (std::size_t k = 0; k < probes.size(); ++k)
    probes[k].at += step * outward[k];
  return probes;
}

/// Probes seen and hidden in one window of the margin.
struct Window
{
  int probes = 0, hidden = 0;
  void Add(bool blocked)
  {
    ++this->probes;
    this->hidden += blocked ? 1 : 0;
  }
  bool Seen() const { return this->probes > 0 && this->hidden <= MaxHiddenOfSeenWindow * this->probes; }
};

/// Where along the midvein (the flat layout's y) the blade's margin `margin` lies farthest from it (|x|).
double WidestAt(const LeafFitResult& fit, const std::vector<int>& margin)
{
  double widest = -1.0, at = 0.0;
  for (const int v : margin)
    if (std::abs(fit.flat[v].x()) > widest)
    {
      widest = std::abs(fit.flat[v].x());
      at = fit.flat[v].y();
    }
  return at;
}
} // namespace

MarginView ViewOfMargin(
  const LeafFitResult& fit, double spacing, const std::vector<const DepthMap*>& sawIt, std::int64_t own)
{
  MarginView view;
  if (sawIt.empty() || !(spacing > 0.0) || fit.normals.size() != fit.points.size())
    return view;
  // The extents need the blade laid flat (FitLeaf gives it): the windows are along its midvein.
  const bool laidFlat = fit.flat.size() == fit.points.size() && !fit.midvein.empty();
  const double base = laidFlat ? fit.flat[fit.midvein.front()].y() : 0.0;
  const double apex = laidFlat ? fit.flat[fit.midvein.back()].y() : 0.0;
  const double window = ExtentWindowShare * std::abs(apex - base);
  std::size_t probes = 0, hidden = 0;
  Window baseEnd, apexEnd, sides[2];
  const Eigen::Vector3d centre = BladeCentre(fit);
  const std::vector<int>* margins[2] = { &fit.leftMargin, &fit.rightMargin };
  for (int side = 0; side < 2; ++side)
  {
    const double widest = laidFlat ? WidestAt(fit, *margins[side]) : 0.0;
    for (const Probe& probe : MarginProbes(fit, *margins[side], centre, spacing))
    {
      const bool blocked = std::all_of(sawIt.begin(), sawIt.end(), [&](const DepthMap* map) {
        return map->NearestAround(probe.at, own) < (probe.at - map->position).norm() - BlockerSpacings * spacing;
      });
      ++probes;
      hidden += blocked ? 1 : 0;
      if (!laidFlat)
        continue;
      const double y = fit.flat[probe.vertex].y();
      if (std::abs(y - base) <= window)
        baseEnd.Add(blocked);
      if (std::abs(y - apex) <= window)
        apexEnd.Add(blocked);
      if (std::abs(y - widest) <= window)
        sides[side].Add(blocked);
    }
  }
  if (probes == 0)
    return view;
  view.hidden = static_cast<double>(hidden) / static_cast<double>(probes);
  if (laidFlat)
    view.extentsSeen =
      (baseEnd.Seen() && apexEnd.Seen() ? LengthSeen : 0) + (sides[0].Seen() && sides[1].Seen() ? WidthSeen : 0);
  return view;
}

double HiddenMargin(
  const LeafFitResult& fit, double spacing, const std::vector<const DepthMap*>& sawIt, std::int64_t own)
{
  return ViewOfMargin(fit, spacing, sawIt, own).hidden;
}

} // namespace plantmorph
