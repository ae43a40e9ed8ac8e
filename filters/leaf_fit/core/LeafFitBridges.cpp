// SPDX-License-Identifier: GPL-3.0-or-later
// The blade's sparsely sampled parts joined point to point before its outline is traced (LeafFitInternal.h,
// FindSparseParts).
#include "LeafFitInternal.h"
#include "plantmorph/MathConstants.h"
#include "plantmorph/ParallelFor.h"
#include "plantmorph/graph/DisjointSets.h"
#include "plantmorph/statistics/Median.h"

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace fit
{
namespace
{
constexpr int Sectors = 8;
/// Each sector's nearest point: squared distance (infinite: none) and index.
using SectorNeighbours = std::array<std::pair<double, std::size_t>, Sectors>;

/// The nearest point of ts in each sector of 45 degrees about point i, within `reach` (the buckets `rings` about
/// its own must cover it). Ties go to the lower index.
SectorNeighbours Nearest(
  const std::vector<Eigen::Vector2d>& ts, const Buckets& buckets, std::size_t i, int rings, double reach)
{
  SectorNeighbours nearest;
  nearest.fill({ std::numeric_limits<double>::infinity(), i });
  buckets.Near(ts[i], rings, [&](std::size_t k) {
    const Eigen::Vector2d d = ts[k] - ts[i];
    const double d2 = d.squaredNorm();
    if (!(d2 > 0.0) || d2 > reach * reach)
      return;
    // Sectors centred on the axes and diagonals (a lattice's neighbours fall inside, not on their edges).
    const double turn = (std::atan2(d.y(), d.x()) + Pi) / (2.0 * Pi) * Sectors + 0.5;
    auto& sector = nearest[static_cast<int>(std::floor(turn)) % Sectors];
    if (d2 < sector.first || (d2 == sector.first && k < sector.second))
      sector = { d2, k };
  });
  return nearest;
}

/// The point's gap: the distance to the fifth nearest of its sector neighbours (infinite with fewer than five).
double Gap(const SectorNeighbours& nearest)
{
  std::array<double, Sectors> d;
  for (int s = 0; s < Sectors; ++s)
    d[s] = nearest[s].first;
  std::nth_element(d.begin(), d.begin() + 4, d.end());
  return std::sqrt(d[4]);
}

/// Whether the sector neighbours nearer than half the gap all lie in two adjacent sectors and the two opposite
/// them (along a scan line), not over a half plane (a margin, a sinus's side, a hole's edge).
bool NearOnesAlongALine(const SectorNeighbours& nearest, double gap)
{
  unsigned near = 0;
  for (int s = 0; s < Sectors; ++s)
    if (nearest[s].first < 0.25 * gap * gap)
      near |= 1u << s;
  for (int k = 0; k < Sectors; ++k)
  {
    unsigned line = 0;
    for (int s : { k, k + 1, k + 4, k + 5 })
      line |= 1u << (s % Sectors);
    if ((near & ~line) == 0)
      return true;
  }
  return false;
}
} // namespace

SparseParts FindSparseParts(const std::vector<Eigen::Vector2d>& ts, double spacing, const ParallelFor& parallel)
{
  SparseParts parts;
  std::vector<std::pair<std::size_t, std::size_t>>& bridges = parts.bridges;
  if (ts.size() < 3 || !(spacing > 0.0))
    return parts;
  Eigen::Vector2d lo = ts.front(), hi = ts.front();
  for (const auto& p : ts)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double width = 2.0 * spacing, reach = MaxSparseGap * spacing;
  if (!((hi - lo).maxCoeff() / width < 1e5))
    return parts;
  const Buckets buckets(ts, lo, width, hi.x() - lo.x() + width, hi.y() - lo.y() + width);
  auto ringsFor = [&](double distance) { return static_cast<int>(std::ceil(distance / width)); };
  // The blade's usual gap (the median over at most 5000 points): a part is sparse against it, so that a blade
  // sampled evenly at any density (a scanner's lattice wider than the nearest-neighbour spacing, two lattices
  // superimposed) has none.
  const std::size_t stride = std::max<std::size_t>(1, ts.size() / 5000);
  std::vector<double> usual((ts.size() + stride - 1) / stride);
  ForEachIndex(
    parallel, usual.size(),
    [&](std::size_t k) { usual[k] = Gap(Nearest(ts, buckets, k * stride, ringsFor(reach), reach)); }, 64);
  const double sparse = MinSparseGap * std::max(spacing, Median(usual));
  if (!(sparse < reach))
    return parts;
  std::vector<std::array<std::size_t, Sectors>> joined(ts.size());
  std::vector<unsigned char> count(ts.size(), 0);
  std::vector<double> gaps(ts.size(), 0.0);
  ForEachIndex(
    parallel, ts.size(),
    [&](std::size_t i) {
      if (Gap(Nearest(ts, buckets, i, ringsFor(sparse), sparse)) <= sparse)
        return;
      const SectorNeighbours nearest = Nearest(ts, buckets, i, ringsFor(reach), reach);
      const double gap = Gap(nearest);
      if (!(gap <= reach) || !NearOnesAlongALine(nearest, gap))
        return;
      gaps[i] = gap;
      for (const auto& [d2, k] : nearest)
        if (d2 <= 2.25 * gap * gap && d2 > spacing * spacing)
          joined[i][count[i]++] = k;
    },
    256);
  // Only sparse points are joined, to one another: a stray group of points beside the blade (a piece of another
  // leaf) stays apart from it, as the discs leave it.
  for (std::size_t i = 0; i < ts.size(); ++i)
    for (int m = 0; m < count[i]; ++m)
      if (count[joined[i][m]] > 0)
        bridges.emplace_back(std::min(i, joined[i][m]), std::max(i, joined[i][m]));
  std::sort(bridges.begin(), bridges.end());
  bridges.erase(std::unique(bridges.begin(), bridges.end()), bridges.end());
  // A sparse part is MinSparsePoints or more points joined together, at least MinSparseWidth of their gaps across
  // (a band as wide has its minor principal deviation width / sqrt(12)); a smaller or narrower group is a stray one
  // (a piece of a neighbouring leaf, a twig's or stalk's points left with the leaf), which the discs alone leave
  // apart or erode away.
  DisjointSets<std::size_t> groups(ts.size());
  for (const auto& [a, b] : bridges)
    groups.Join(a, b);
  struct Moments
  {
    double n = 0.0, gap = 0.0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d outer = Eigen::Matrix2d::Zero();
  };
  std::vector<Moments> moments(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
    if (count[i] > 0)
    {
      Moments& m = moments[groups.Find(i)];
      const Eigen::Vector2d p = ts[i] - ts.front();
      m.n += 1.0;
      m.gap += gaps[i];
      m.sum += p;
      m.outer += p * p.transpose();
    }
  std::vector<unsigned char> part(ts.size(), 0);
  for (std::size_t i = 0; i < ts.size(); ++i)
  {
    const Moments& m = moments[i];
    if (m.n < static_cast<double>(MinSparsePoints))
      continue;
    const Eigen::Vector2d mean = m.sum / m.n;
    const Eigen::Matrix2d covariance = m.outer / m.n - mean * mean.transpose();
    const double across = std::sqrt(std::max(0.0, 12.0 * covariance.selfadjointView<Eigen::Lower>().eigenvalues()(0)));
    part[i] = across >= MinSparseWidth * m.gap / m.n ? 1 : 0;
  }
  auto apart = [&](std::size_t i) { return part[groups.Find(i)] == 0; };
  bridges.erase(std::remove_if(bridges.begin(), bridges.end(), [&](const auto& bridge) { return apart(bridge.first); }),
    bridges.end());
  for (std::size_t i = 0; i < ts.size(); ++i)
    if (count[i] > 0 && !apart(i))
      parts.reaches.emplace_back(i, SparseMarginShare * gaps[i]);
  return parts;
}

} // namespace fit
} // namespace plantmorph
