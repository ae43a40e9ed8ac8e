// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointGrid.h"

#include <algorithm>
#include <cmath>

namespace plantmorph
{

PointGrid::PointGrid(const std::vector<Eigen::Vector3d>& points, double cell)
  : Cell(cell)
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(0.0), hi = lo;
  if (!points.empty())
  {
    lo = hi = points.front();
    for (const Eigen::Vector3d& p : points)
    {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  this->Origin = lo;
  // Keep the cell count bounded (a few stray far points must not make a huge grid index overflow).
  const double span = (hi - lo).maxCoeff();
  if (!(this->Cell > 0.0) || span / this->Cell > 1.0e6)
    this->Cell = std::max(span / 1.0e6, 1e-300);
  for (int a = 0; a < 3; ++a)
    this->Extent[a] = static_cast<int>(std::floor((hi[a] - lo[a]) / this->Cell)) + 1;
  std::vector<std::pair<Key, int>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::Vector3i c = this->CellOf(points[i]);
    keyed[i] = { this->KeyOf(c[0], c[1], c[2]), static_cast<int>(i) };
  }
  std::sort(keyed.begin(), keyed.end());
  this->Order.resize(keyed.size());
  this->Sorted.resize(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i)
  {
    this->Order[i] = keyed[i].second;
    this->Sorted[i] = points[keyed[i].second];
    auto it = this->Ranges.find(keyed[i].first);
    if (it == this->Ranges.end())
      this->Ranges.emplace(keyed[i].first, std::make_pair(static_cast<int>(i), static_cast<int>(i + 1)));
    else
      it->second.second = static_cast<int>(i + 1);
  }
}

PointGrid::Key PointGrid::KeyOf(std::int64_t i, std::int64_t j, std::int64_t k) const
{
  return (i * (static_cast<std::int64_t>(this->Extent[1]) + 2) + j) * (static_cast<std::int64_t>(this->Extent[2]) + 2) +
    k;
}

Eigen::Vector3i PointGrid::CellOf(const Eigen::Vector3d& p) const
{
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<int>(std::floor((p[a] - this->Origin[a]) / this->Cell)), 0, this->Extent[a] - 1);
  return c;
}

std::vector<std::pair<double, int>> PointGrid::Nearest(const Eigen::Vector3d& q, int k, int skip, double reach) const
{
  std::vector<std::pair<double, int>> best;
  if (k <= 0 || this->Sorted.empty())
    return best;
  const Eigen::Vector3i c = this->CellOf(q);
  // q may lie outside the grid (its cell clamped): the shells' reach then starts that far behind.
  double outside = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double lo = this->Origin[a] + c[a] * this->Cell, hi = lo + this->Cell;
    const double d = std::max({ lo - q[a], q[a] - hi, 0.0 });
    outside += d * d;
  }
  outside = std::sqrt(outside);
  const int maxRing = this->Extent.maxCoeff() + 1;
  for (int r = 0; r <= maxRing; ++r)
  {
    // Visit the shell of cells at Chebyshev distance r from c.
    for (int i = c[0] - r; i <= c[0] + r; ++i)
    {
      if (i < 0 || i >= this->Extent[0])
        continue;
      for (int j = c[1] - r; j <= c[1] + r; ++j)
      {
        if (j < 0 || j >= this->Extent[1])
          continue;
        const bool faceIJ = i == c[0] - r || i == c[0] + r || j == c[1] - r || j == c[1] + r;
        for (int l = c[2] - r; l <= c[2] + r; l += (faceIJ ? 1 : std::max(1, 2 * r)))
        {
          if (l < 0 || l >= this->Extent[2])
            continue;
          auto it = this->Ranges.find(this->KeyOf(i, j, l));
          if (it == this->Ranges.end())
            continue;
          for (int o = it->second.first; o < it->second.second; ++o)
          {
            const int id = this->Order[o];
            if (id == skip)
              continue;
            const double d2 = (this->Sorted[o] - q).squaredNorm();
            if (d2 > reach * reach)
              continue;
            if (static_cast<int>(best.size()) < k)
            {
              best.emplace_back(d2, id);
              std::push_heap(best.begin(), best.end());
            }
            else if (std::make_pair(d2, id) < best.front())
            {
              std::pop_heap(best.begin(), best.end());
              best.back() = { d2, id };
              std::push_heap(best.begin(), best.end());
            }
          }
        }
      }
    }
    // Every point not yet visited is farther than r cells (minus q's offset within its cell).
    const double covered = r * this->Cell - outside;
    if (covered >= reach)
      break;
    if (static_cast<int>(best.size()) == k && covered > 0.0 && best.front().first <= covered * covered)
      break;
  }
  std::sort_heap(best.begin(), best.end());
  return best;
}

void PointGrid::Within(const Eigen::Vector3d& q, double radius, std::vector<int>& out) const
{
  out.clear();
  const Eigen::Vector3i lo = this->CellOf(q - Eigen::Vector3d::Constant(radius));
  const Eigen::Vector3i hi = this->CellOf(q + Eigen::Vector3d::Constant(radius));
  const double r2 = radius * radius;
  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int l = lo[2]; l <= hi[2]; ++l)
      {
        auto it = this->Ranges.find(this->KeyOf(i, j, l));
        if (it == this->Ranges.end())
          continue;
        for (int o = it->second.first; o < it->second.second; ++o)
          if ((this->Sorted[o] - q).squaredNorm() <= r2)
            out.push_back(this->Order[o]);
      }
}

double PointGrid::CellFor(const std::vector<Eigen::Vector3d>& points, double perCell)
{
  if (points.empty())
    return 1.0;
  Eigen::Vector3d lo = points.front(), hi = lo;
  for (const Eigen::Vector3d& p : points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Eigen::Vector3d e = hi - lo;
  std::sort(e.data(), e.data() + 3);
  const double area = std::max(e[2] * e[1], e[2] * e[2] * 1e-6);
  const double cell = std::sqrt(area * perCell / static_cast<double>(points.size()));
  return cell > 0.0 ? cell : 1.0;
}

} // namespace plantmorph
