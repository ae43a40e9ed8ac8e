// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointGrid.h"

#include <plantmorph/statistics/Median.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>
#include <utility>

namespace plantmorph
{

PointGrid::PointGrid(const std::vector<Eigen::Vector3d>& points, double cell, const ParallelFor& parallel)
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
  const Key lastKey = this->KeyOf(this->Extent[0] - 1, this->Extent[1] - 1, this->Extent[2] - 1);
  int keyBits = 0;
  while (keyBits < 63 && (Key{ 1 } << keyBits) <= lastKey)
    ++keyBits;
  if (keyBits <= 32)
  {
    // Key above, index below: the radix sort on the key's bits gives the (key, index) order in linear time.
    std::vector<std::uint64_t> packed(points.size());
    ForEachIndex(parallel, points.size(), [&](std::size_t i) {
      const Eigen::Vector3i c = this->CellOf(points[i]);
      packed[i] = static_cast<std::uint64_t>(this->KeyOf(c[0], c[1], c[2])) << 32 | i;
    });
    SortKeysInParallel(parallel, packed, 32, 32 + keyBits);
    ForEachIndex(parallel, points.size(), [&](std::size_t i) {
      keyed[i] = { static_cast<Key>(packed[i] >> 32), static_cast<int>(packed[i] & 0xffffffffu) };
    });
  }
  else
  {
    ForEachIndex(parallel, points.size(), [&](std::size_t i) {
      const Eigen::Vector3i c = this->CellOf(points[i]);
      keyed[i] = { this->KeyOf(c[0], c[1], c[2]), static_cast<int>(i) };
    });
    // (key, id) pairs are all different: any sort gives the one order.
    SortInParallel(parallel, keyed, std::less<std::pair<Key, int>>());
  }
  this->Order.resize(keyed.size());
  this->Sorted.resize(keyed.size());
  ForEachIndex(parallel, keyed.size(), [&](std::size_t i) {
    this->Order[i] = keyed[i].second;
    this->Sorted[i] = points[keyed[i].second];
  });
  std::size_t cells = 0;
  for (std::size_t i = 0; i < keyed.size(); ++i)
    cells += i == 0 || keyed[i].first != keyed[i - 1].first ? 1 : 0;
  // A table of at least twice as many slots as cells (a power of two), filled by linear probing.
  int bits = 4;
  while ((std::size_t{ 1 } << bits) < 2 * cells)
    ++bits;
  this->SlotShift = 64 - bits;
  this->SlotMask = (std::uint64_t{ 1 } << bits) - 1;
  this->SlotKey.assign(std::size_t{ 1 } << bits, -1);
  this->SlotRange.assign(std::size_t{ 1 } << bits, { 0, 0 });
  for (std::size_t i = 0; i < keyed.size();)
  {
    std::size_t end = i + 1;
    while (end < keyed.size() && keyed[end].first == keyed[i].first)
      ++end;
    std::uint64_t slot = (static_cast<std::uint64_t>(keyed[i].first) * 0x9E3779B97F4A7C15ull) >> this->SlotShift;
    while (this->SlotKey[slot] != -1)
      slot = (slot + 1) & this->SlotMask;
    this->SlotKey[slot] = keyed[i].first;
    this->SlotRange[slot] = { static_cast<int>(i), static_cast<int>(end) };
    i = end;
  }
  const double budget = 64.0 * static_cast<double>(keyed.size()) + 65536.0;
  for (;; ++this->BlockShift)
  {
    for (int a = 0; a < 3; ++a)
      this->Blocks[a] = ((this->Extent[a] - 1) >> this->BlockShift) + 1;
    if (static_cast<double>(this->Blocks[0]) * this->Blocks[1] * this->Blocks[2] <= budget)
      break;
  }
  this->Occupied.assign((static_cast<std::size_t>(this->Blocks[0]) * this->Blocks[1] * this->Blocks[2] + 63) / 64, 0);
  for (const Eigen::Vector3d& p : this->Sorted)
  {
    const Eigen::Vector3i c = this->CellOf(p);
    const std::size_t b = this->BlockOf(c[0], c[1], c[2]);
    this->Occupied[b >> 6] |= std::uint64_t{ 1 } << (b & 63);
  }
}

std::size_t PointGrid::BlockOf(int i, int j, int k) const
{
  return (static_cast<std::size_t>(i >> this->BlockShift) * this->Blocks[1] + (j >> this->BlockShift)) *
    this->Blocks[2] +
    (k >> this->BlockShift);
}

const std::pair<int, int>* PointGrid::Range(int i, int j, int k) const
{
  const std::size_t b = this->BlockOf(i, j, k);
  if (!(this->Occupied[b >> 6] >> (b & 63) & 1))
    return nullptr;
  const Key key = this->KeyOf(i, j, k);
  std::uint64_t slot = (static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull) >> this->SlotShift;
  for (;; slot = (slot + 1) & this->SlotMask)
  {
    const Key at = this->SlotKey[slot];
    if (at == key)
      return &this->SlotRange[slot];
    if (at == -1)
      return nullptr;
  }
}

template <typename Visit>
void PointGrid::ForCellsAround(const Eigen::Vector3d& q, double radius, Visit&& visit) const
{
  if (this->Sorted.empty())
    return;
  const Eigen::Vector3i lo = this->CellOf(q - Eigen::Vector3d::Constant(radius));
  const Eigen::Vector3i hi = this->CellOf(q + Eigen::Vector3d::Constant(radius));
  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int l = lo[2]; l <= hi[2]; ++l)
        if (const std::pair<int, int>* range = this->Range(i, j, l))
          for (int o = range->first; o < range->second; ++o)
            if (!visit(o))
              return;
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
  best.reserve(static_cast<std::size_t>(std::min(k, 64)));
  const Eigen::Vector3i c = this->CellOf(q);
  // q may lie outside the grid (its cell clamped): the shells' reach then starts that far behind. Inside its cell,
  // q is `inner` from the cell's nearest wall: every point beyond shell r is farther than r cells plus that.
  double outside = 0.0, inner = this->Cell;
  for (int a = 0; a < 3; ++a)
  {
    const double lo = this->Origin[a] + c[a] * this->Cell, hi = lo + this->Cell;
    const double d = std::max({ lo - q[a], q[a] - hi, 0.0 });
    outside += d * d;
    inner = std::min({ inner, std::max(q[a] - lo, 0.0), std::max(hi - q[a], 0.0) });
  }
  outside = std::sqrt(outside);
  // Every point lies in the grid's box, and `outside` is q's distance from it: a query farther than its reach finds
  // nothing (without this, a far stray walked every ring of cells out to the grid, the cube of its distance).
  if (outside > reach)
    return best;
  if (outside > 0.0)
    inner = 0.0;
  const double reach2 = reach * reach;
  // The squared distance from q to cell (i, j, l)'s box: a cell farther than the k-th best (or the reach) is skipped.
  auto boxDistance2 = [&](int i, int j, int l) {
    const int cell[3] = { i, j, l };
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double lo = this->Origin[a] + cell[a] * this->Cell;
      const double d = std::max({ lo - q[a], q[a] - lo - this->Cell, 0.0 });
      d2 += d * d;
    }
    return d2;
  };
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
          // The box test first: it is a few operations, the cell's lookup a hashed memory access.
          if (r > 0)
          {
            const double box = boxDistance2(i, j, l);
            if (box > reach2 || (static_cast<int>(best.size()) == k && box > best.back().first))
              continue;
          }
          const std::pair<int, int>* range = this->Range(i, j, l);
          if (!range)
            continue;
          for (int o = range->first; o < range->second; ++o)
          {
            const int id = this->Order[o];
            if (id == skip)
              continue;
            const double d2 = (this->Sorted[o] - q).squaredNorm();
            if (d2 > reach2)
              continue;
            // `best` ascending by (distance, id): a new one moves in from the back, past those it beats.
            const std::pair<double, int> candidate(d2, id);
            if (static_cast<int>(best.size()) < k)
              best.push_back(candidate);
            else if (candidate < best.back())
              best.back() = candidate;
            else
              continue;
            for (std::size_t m = best.size() - 1; m > 0 && best[m] < best[m - 1]; --m)
              std::swap(best[m], best[m - 1]);
          }
        }
      }
    }
    // Every point not yet visited is farther than r cells (minus q's offset within its cell).
    const double covered = r * this->Cell + inner - outside;
    if (covered >= reach)
      break;
    if (static_cast<int>(best.size()) == k && covered > 0.0 && best.back().first <= covered * covered)
      break;
  }
  return best;
}

int PointGrid::Near(const Eigen::Vector3d& q, double reach) const
{
  if (this->Sorted.empty())
    return -1;
  const Eigen::Vector3i c = this->CellOf(q);
  if (const std::pair<int, int>* range = this->Range(c[0], c[1], c[2]))
  {
    double best = reach * reach;
    int id = -1;
    for (int o = range->first; o < range->second; ++o)
    {
      const double d2 = (this->Sorted[o] - q).squaredNorm();
      if (d2 < best || (id < 0 && d2 <= best))
      {
        best = d2;
        id = this->Order[o];
      }
    }
    if (id >= 0)
      return id;
  }
  const auto nearest = this->Nearest(q, 1, -1, reach);
  return nearest.empty() ? -1 : nearest.front().second;
}

void PointGrid::Within(const Eigen::Vector3d& q, double radius, std::vector<int>& out) const
{
  out.clear();
  const double r2 = radius * radius;
  this->ForCellsAround(q, radius, [&](int o) {
    if ((this->Sorted[o] - q).squaredNorm() <= r2)
      out.push_back(this->Order[o]);
    return true;
  });
}

std::size_t PointGrid::CountWithin(const Eigen::Vector3d& q, double radius) const
{
  std::size_t count = 0;
  const double r2 = radius * radius;
  this->ForCellsAround(q, radius, [&](int o) {
    count += (this->Sorted[o] - q).squaredNorm() <= r2 ? 1 : 0;
    return true;
  });
  return count;
}

bool PointGrid::AnyWithin(const Eigen::Vector3d& q, double radius, const std::vector<unsigned char>& flag) const
{
  bool found = false;
  const double r2 = radius * radius;
  this->ForCellsAround(q, radius, [&](int o) {
    found = flag[this->Order[o]] && (this->Sorted[o] - q).squaredNorm() <= r2;
    return !found;
  });
  return found;
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

namespace
{
std::uint64_t Mix(std::uint64_t x)
{
  // splitmix64's finaliser: every input bit moves every output bit.
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
} // namespace

std::vector<int> SampleIds(const std::vector<Eigen::Vector3d>& points, std::size_t target)
{
  std::vector<int> ids;
  if (points.size() <= target)
  {
    ids.resize(points.size());
    std::iota(ids.begin(), ids.end(), 0);
    return ids;
  }
  // 2^64 times the fraction kept (below 1).
  const auto limit = static_cast<std::uint64_t>(
    static_cast<double>(target) / static_cast<double>(points.size()) * 18446744073709551616.0);
  ids.reserve(target + target / 8);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    std::uint64_t h = 0;
    for (int a = 0; a < 3; ++a)
    {
      const double x = points[i][a] + 0.0; // -0 and +0 alike
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = Mix(h ^ bits);
    }
    if (h < limit)
      ids.push_back(static_cast<int>(i));
  }
  return ids;
}

double MedianSpacing(const std::vector<Eigen::Vector3d>& points)
{
  if (points.size() < 2)
    return 0.0;
  return MedianSpacing(points, PointGrid(points, PointGrid::CellFor(points, 4.0)));
}

double MedianSpacing(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const ParallelFor& parallel)
{
  if (points.size() < 2)
    return 0.0;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 20000);
  // One slot per sampled point (-1: none found), read in order: the same list on any number of threads.
  std::vector<double> found((points.size() + step - 1) / step, -1.0);
  ForEachIndex(
    parallel, found.size(),
    [&](std::size_t k) {
      const std::size_t i = k * step;
      const auto nearest = grid.Nearest(points[i], 1, static_cast<int>(i));
      if (!nearest.empty() && nearest[0].first > 0.0)
        found[k] = std::sqrt(nearest[0].first);
    },
    256);
  std::vector<double> distances;
  for (double d : found)
    if (d >= 0.0)
      distances.push_back(d);
  return Median(std::move(distances), 0.0);
}

double CrossSpacing(const std::vector<Eigen::Vector3d>& points)
{
  if (points.size() < 3)
    return 0.0;
  return CrossSpacing(points, PointGrid(points, PointGrid::CellFor(points, 4.0)));
}

double CrossSpacing(const std::vector<Eigen::Vector3d>& points, const PointGrid& grid, const ParallelFor& parallel)
{
  if (points.size() < 3)
    return 0.0;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 5000);
  std::vector<double> found((points.size() + stride - 1) / stride, -1.0);
  ForEachIndex(
    parallel, found.size(),
    [&](std::size_t k) {
      const std::size_t i = k * stride;
      // 48 neighbours reach the next line of a line scan whose points are up to about 20 times closer along a line.
      const auto nb = grid.Nearest(points[i], 48, static_cast<int>(i));
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      for (const auto& [d2, j] : nb)
      {
        const Eigen::Vector3d d = points[j] - points[i];
        if (!(d2 > 0.0))
          continue;
        if (u.isZero())
          u = d.normalized();
        else if (std::abs(u.dot(d.normalized())) < 0.5)
        {
          found[k] = std::sqrt(d2);
          break;
        }
      }
    },
    64);
  std::vector<double> across;
  for (double d : found)
    if (d >= 0.0)
      across.push_back(d);
  return Median(std::move(across), 0.0);
}

} // namespace plantmorph
