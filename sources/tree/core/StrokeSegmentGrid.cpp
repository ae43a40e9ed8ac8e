// SPDX-License-Identifier: GPL-3.0-or-later
#include "StrokeSegmentGrid.h"

#include "TreeStrokes.h" // PointSegmentDistance

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{

namespace
{
constexpr double kDomain = 1073741824.0; // 2^30 cells either way
/// Cells' worth of rounding allowed for in cell coordinates (below 2^30, a double's rounding is under 1e-6 cells).
constexpr double kSlack = 1e-4;

/// Calls visit(major, minor) for the cells crossed by (ua, va)-(ub, vb) in cell units (u the major axis), with a
/// margin of kSlack cells each way (rounding); stops (returning false) after `most` cells.
template <typename Visit>
bool Rasterize(double ua, double va, double ub, double vb, std::size_t most, Visit&& visit)
{
  if (ub < ua)
  {
    std::swap(ua, ub);
    std::swap(va, vb);
  }
  std::size_t count = 0;
  const auto first = static_cast<std::int64_t>(std::floor(ua - kSlack));
  const auto last = static_cast<std::int64_t>(std::floor(ub + kSlack));
  for (std::int64_t m = first; m <= last; ++m)
  {
    const double m0 = std::clamp(static_cast<double>(m) - kSlack, ua, ub);
    const double m1 = std::clamp(static_cast<double>(m + 1) + kSlack, ua, ub);
    double v0 = va, v1 = vb;
    if (ub > ua)
    {
      v0 = va + (m0 - ua) * (vb - va) / (ub - ua);
      v1 = va + (m1 - ua) * (vb - va) / (ub - ua);
    }
    const auto low = static_cast<std::int64_t>(std::floor(std::min(v0, v1) - kSlack));
    const auto high = static_cast<std::int64_t>(std::floor(std::max(v0, v1) + kSlack));
    for (std::int64_t n = low; n <= high; ++n)
    {
      if (++count > most)
      {
        return false;
      }
      visit(m, n);
    }
  }
  return true;
}
} // namespace

StrokeSegmentGrid::StrokeSegmentGrid(const std::vector<Eigen::Vector2d>& points, std::size_t expectedSegments)
{
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& p : points)
  {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  if (points.empty())
  {
    return;
  }
  const Eigen::Vector2d extent = high - low;
  const double count = static_cast<double>(std::max<std::size_t>(1, expectedSegments));
  // About one segment's area per cell; never so small that the extent spans more cells than segments.
  double size = std::max(std::sqrt(extent.x() * extent.y() / count), extent.maxCoeff() / count);
  if (!(size > 0.0) || !std::isfinite(size))
  {
    size = std::isfinite(extent.maxCoeff()) && extent.maxCoeff() > 0.0 ? extent.maxCoeff() : 1.0;
  }
  this->Origin = low;
  this->Size = size;
}

bool StrokeSegmentGrid::Cell(const Eigen::Vector2d& p, std::int64_t& ix, std::int64_t& iy) const
{
  const double u = (p.x() - this->Origin.x()) / this->Size, v = (p.y() - this->Origin.y()) / this->Size;
  if (!(std::abs(u) < kDomain && std::abs(v) < kDomain))
  {
    return false;
  }
  ix = static_cast<std::int64_t>(std::floor(u));
  iy = static_cast<std::int64_t>(std::floor(v));
  return true;
}

std::uint64_t StrokeSegmentGrid::Key(std::int64_t ix, std::int64_t iy)
{
  return (static_cast<std::uint64_t>(ix) << 32) ^ (static_cast<std::uint64_t>(iy) & 0xffffffffull);
}

void StrokeSegmentGrid::Add(std::size_t branch, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const auto id = static_cast<std::uint32_t>(this->Entries.size());
  this->Entries.push_back({ branch, a, b, true });
  this->Stamp.push_back(0);
  if (this->ByBranch.size() <= branch)
  {
    this->ByBranch.resize(branch + 1);
  }
  this->ByBranch[branch].push_back(id);
  std::int64_t ax, ay, bx, by;
  const double s = this->Size;
  const double ua = (a.x() - this->Origin.x()) / s, va = (a.y() - this->Origin.y()) / s;
  const double ub = (b.x() - this->Origin.x()) / s, vb = (b.y() - this->Origin.y()) / s;
  const bool steep = std::abs(vb - va) > std::abs(ub - ua);
  const auto noop = [](std::int64_t, std::int64_t) {};
  if (!this->Cell(a, ax, ay) || !this->Cell(b, bx, by) ||
    !(steep ? Rasterize(va, ua, vb, ub, kMaxCellsPerSegment, noop)
            : Rasterize(ua, va, ub, vb, kMaxCellsPerSegment, noop)))
  {
    this->Everywhere.push_back(id);
    return;
  }
  const auto put = [&](std::int64_t m, std::int64_t n) {
    const std::int64_t ix = steep ? n : m, iy = steep ? m : n;
    this->Cells[Key(ix, iy)].push_back(id);
    const bool empty = this->High[0] < this->Low[0];
    this->Low[0] = empty ? ix : std::min(this->Low[0], ix);
    this->High[0] = empty ? ix : std::max(this->High[0], ix);
    this->Low[1] = empty ? iy : std::min(this->Low[1], iy);
    this->High[1] = empty ? iy : std::max(this->High[1], iy);
  };
  if (steep)
  {
    Rasterize(va, ua, vb, ub, kMaxCellsPerSegment, put);
  }
  else
  {
    Rasterize(ua, va, ub, vb, kMaxCellsPerSegment, put);
  }
}

void StrokeSegmentGrid::Split(
  std::size_t branch, const Eigen::Vector2d& a, const Eigen::Vector2d& c, const Eigen::Vector2d& b)
{
  if (branch < this->ByBranch.size())
  {
    for (std::uint32_t id : this->ByBranch[branch])
    {
      Entry& e = this->Entries[id];
      if (e.alive && e.a == a && e.b == b)
      {
        e.alive = false;
        break;
      }
    }
  }
  this->Add(branch, a, c);
  this->Add(branch, c, b);
}

void StrokeSegmentGrid::Visit(std::uint32_t id, const Eigen::Vector2d& p, double margin, double& nearest)
{
  if (this->Stamp[id] == this->Query)
  {
    return;
  }
  this->Stamp[id] = this->Query;
  const Entry& e = this->Entries[id];
  if (!e.alive)
  {
    return;
  }
  double mu = 0.0;
  const double d = PointSegmentDistance(p, e.a, e.b, mu);
  nearest = std::min(nearest, d);
  if (d <= nearest + margin)
  {
    this->Found.emplace_back(d, e.branch);
  }
}

bool StrokeSegmentGrid::Nearest(
  const Eigen::Vector2d& p, double margin, double& nearest, std::vector<std::size_t>& branches)
{
  if (++this->Query == 0) // the stamps wrapped: start them again
  {
    std::fill(this->Stamp.begin(), this->Stamp.end(), 0);
    this->Query = 1;
  }
  this->Found.clear();
  branches.clear();
  nearest = std::numeric_limits<double>::infinity();
  for (std::uint32_t id : this->Everywhere)
  {
    this->Visit(id, p, margin, nearest);
  }
  std::int64_t cx = 0, cy = 0;
  if (!this->Cell(p, cx, cy))
  {
    return false;
  }
  const std::size_t most = 4 * this->Entries.size() + 4096;
  std::size_t visited = 0;
  if (this->High[0] >= this->Low[0])
  {
    const std::int64_t outside =
      std::max({ std::int64_t(0), this->Low[0] - cx, cx - this->High[0], this->Low[1] - cy, cy - this->High[1] });
    for (std::int64_t r = outside;; ++r)
    {
      // A segment in no cell of rings 0 .. r - 1 crosses only cells r or more from p's: it is at least r - 1 cells
      // from p (less the rounding).
      if ((static_cast<double>(r - 1) - 2.0 * kSlack) * this->Size > nearest + margin)
      {
        break;
      }
      const std::int64_t y0 = std::max(cy - r, this->Low[1]), y1 = std::min(cy + r, this->High[1]);
      for (std::int64_t iy = y0; iy <= y1; ++iy)
      {
        const bool edge = iy == cy - r || iy == cy + r;
        const std::int64_t step = edge || r == 0 ? 1 : 2 * r;
        const std::int64_t x0 = edge ? std::max(cx - r, this->Low[0]) : cx - r;
        const std::int64_t x1 = edge ? std::min(cx + r, this->High[0]) : cx + r;
        for (std::int64_t ix = x0; ix <= x1; ix += step)
        {
          if (ix < this->Low[0] || ix > this->High[0])
          {
            continue;
          }
          if (++visited > most)
          {
            return false;
          }
          const auto cell = this->Cells.find(Key(ix, iy));
          if (cell != this->Cells.end())
          {
            for (std::uint32_t id : cell->second)
            {
              this->Visit(id, p, margin, nearest);
            }
          }
        }
      }
      if (cx - r <= this->Low[0] && cx + r >= this->High[0] && cy - r <= this->Low[1] && cy + r >= this->High[1])
      {
        break; // the ring holds every occupied cell
      }
    }
  }
  if (!std::isfinite(nearest))
  {
    return false;
  }
  for (const auto& [d, branch] : this->Found)
  {
    if (d <= nearest + margin)
    {
      branches.push_back(branch);
    }
  }
  std::sort(branches.begin(), branches.end());
  branches.erase(std::unique(branches.begin(), branches.end()), branches.end());
  return true;
}

} // namespace plantmorph
