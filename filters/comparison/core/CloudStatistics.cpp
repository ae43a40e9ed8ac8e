// SPDX-License-Identifier: GPL-3.0-or-later
#include "CloudStatistics.h"

#include <plantmorph/memory/CloudArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace plantmorph
{

namespace
{
bool Kept(double d, double maximumDistance)
{
  return std::isfinite(d) && (maximumDistance < 0.0 || d <= maximumDistance);
}
} // namespace

//------------------------------------------------------------------------------
double SortedPercentile(const std::vector<double>& sorted, double p)
{
  if (sorted.empty())
  {
    return 0.0;
  }
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(rank));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = rank - static_cast<double>(below);
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

//------------------------------------------------------------------------------
DistanceStatistics ComputeDistanceStatistics(
  const double* distances, std::size_t count, double maximumDistance, const ParallelFor& tasks)
{
  // Two independent parts, each writing its own members of s (all zero when nothing is kept): the sums and
  // extremes over the kept distances in input order (part 0), and the counts and percentiles (part 1, on the kept
  // distances gathered, which it reorders).
  DistanceStatistics s;
  const auto sums = [&]() {
    // Two passes for the mean and the deviation (no cancellation), in a fixed order (deterministic).
    // Compensated sums: within about one rounding of the exact sums, so that per-rank partial sums (MPI) added in
    // rank order give the same statistics to ~1e-16 relative, whatever the split.
    CompensatedSum sum;
    std::size_t kept = 0;
    double minimum = std::numeric_limits<double>::infinity();
    double maximum = -minimum;
    for (std::size_t i = 0; i < count; ++i)
    {
      const double d = distances[i];
      if (Kept(d, maximumDistance))
      {
        sum.Add(d);
        ++kept;
        minimum = std::min(minimum, d);
        maximum = std::max(maximum, d);
      }
    }
    if (kept == 0)
    {
      return;
    }
    const double n = static_cast<double>(kept);
    const double mean = sum.Value() / n;
    CompensatedSum squares;
    CompensatedSum deviations;
    for (std::size_t i = 0; i < count; ++i)
    {
      const double d = distances[i];
      if (Kept(d, maximumDistance))
      {
        squares.Add(d * d);
        deviations.Add((d - mean) * (d - mean));
      }
    }
    s.mean = mean;
    s.standardDeviation = std::sqrt(deviations.Value() / n);
    s.rms = std::sqrt(squares.Value() / n);
    s.minimum = minimum;
    s.maximum = maximum;
  };
  const auto percentiles = [&]() {
    // On transparent huge pages from 4 MiB (CloudArray): 10^6 distances gathered into fresh 4 KiB pages took 2 k
    // page faults on the first update, in this part alone while the other waits.
    CloudArray<double> order;
    order.reserve(count);
    for (std::size_t i = 0; i < count; ++i)
    {
      const double d = distances[i];
      if (!std::isfinite(d))
      {
        ++s.invalid;
      }
      else if (!Kept(d, maximumDistance))
      {
        ++s.outliers;
      }
      else
      {
        order.push_back(d);
      }
    }
    s.count = order.size();
    if (order.empty())
    {
      return;
    }
    // The percentiles need only the order statistics at their two ranks: place those by nth_element, each on the
    // part above the previous one (O(n) each instead of a full O(n log n) sort; the values are the same).
    double* targets[5] = { &s.p50, &s.p68, &s.p75, &s.p95, &s.p99 };
    // Ranks are asked in non-decreasing order; order[placed - 1] is the last one placed, nothing before it is
    // larger, and a rank below `placed` is always one placed before (its position is never touched again).
    std::size_t placed = 0;
    const auto orderStatistic = [&](std::size_t rank) {
      if (rank >= placed)
      {
        std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(placed),
          order.begin() + static_cast<std::ptrdiff_t>(rank), order.end());
        placed = rank + 1;
      }
      return order[rank];
    };
    std::size_t ranks[2 * kPercentiles];
    double fractions[kPercentiles];
    PercentileRanks(order.size(), ranks, fractions);
    for (std::size_t i = 0; i < kPercentiles; ++i)
    {
      const double low = orderStatistic(ranks[2 * i]);
      const double high = orderStatistic(ranks[2 * i + 1]);
      *targets[i] = low + fractions[i] * (high - low);
    }
  };
  tasks(2, [&](std::size_t begin, std::size_t end) {
    for (std::size_t part = begin; part < end; ++part)
    {
      if (part == 0)
      {
        sums();
      }
      else
      {
        percentiles();
      }
    }
  });
  return s;
}

//------------------------------------------------------------------------------
void PercentileRanks(std::size_t kept, std::size_t ranks[2 * kPercentiles], double fractions[kPercentiles])
{
  const double last = static_cast<double>(kept ? kept - 1 : 0);
  for (std::size_t i = 0; i < kPercentiles; ++i)
  {
    const double rank = kPercentileValues[i] / 100.0 * last;
    const std::size_t below = static_cast<std::size_t>(std::floor(rank));
    ranks[2 * i] = below;
    ranks[2 * i + 1] = std::min(below + 1, kept ? kept - 1 : 0);
    fractions[i] = rank - static_cast<double>(below);
  }
}

//------------------------------------------------------------------------------
std::uint64_t OrderKey(double value)
{
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return (bits >> 63) ? ~bits : bits | (std::uint64_t(1) << 63);
}

double FromOrderKey(std::uint64_t key)
{
  const std::uint64_t bits = (key >> 63) ? key & ~(std::uint64_t(1) << 63) : ~key;
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

//------------------------------------------------------------------------------
DistanceHistogram ComputeDistanceHistogram(
  const double* distances, std::size_t count, std::size_t bins, double maximumDistance)
{
  DistanceHistogram h;
  if (bins == 0)
  {
    return h;
  }
  double lo = 0.0;
  double hi = 0.0;
  bool any = false;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double d = distances[i];
    if (Kept(d, maximumDistance))
    {
      lo = any ? std::min(lo, d) : d;
      hi = any ? std::max(hi, d) : d;
      any = true;
    }
  }
  if (!any)
  {
    return h;
  }
  return ComputeDistanceHistogramOver(distances, count, bins, maximumDistance, lo, hi);
}

//------------------------------------------------------------------------------
DistanceHistogram ComputeDistanceHistogramOver(const double* distances, std::size_t count, std::size_t bins,
  double maximumDistance, double lo, double hi, const ParallelFor& parallelFor)
{
  DistanceHistogram h;
  if (bins == 0)
  {
    return h;
  }
  const double width = (hi - lo) / static_cast<double>(bins);
  h.binStart.resize(bins);
  h.binEnd.resize(bins);
  h.binCenter.resize(bins);
  h.count.assign(bins, 0);
  for (std::size_t b = 0; b < bins; ++b)
  {
    h.binStart[b] = lo + width * static_cast<double>(b);
    h.binEnd[b] = b + 1 == bins ? hi : lo + width * static_cast<double>(b + 1);
    h.binCenter[b] = 0.5 * (h.binStart[b] + h.binEnd[b]);
  }
  // Counted in fixed blocks of the distances, each into its own counts, added after: exact, whatever the threads.
  constexpr std::size_t Block = std::size_t(1) << 16;
  const std::size_t blocks = (count + Block - 1) / Block;
  std::vector<std::size_t> counts(blocks * bins, 0);
  ForEachIndex(
    parallelFor, blocks,
    [&](std::size_t block) {
      std::size_t* own = counts.data() + block * bins;
      for (std::size_t i = block * Block; i < std::min(count, (block + 1) * Block); ++i)
      {
        const double d = distances[i];
        if (!Kept(d, maximumDistance) || d < lo || d > hi)
        {
          continue;
        }
        std::size_t b = 0;
        if (width > 0.0)
        {
          b = std::min(bins - 1, static_cast<std::size_t>((d - lo) / width));
        }
        ++own[b];
      }
    },
    1);
  for (std::size_t block = 0; block < blocks; ++block)
  {
    for (std::size_t b = 0; b < bins; ++b)
    {
      h.count[b] += counts[block * bins + b];
    }
  }
  return h;
}

} // namespace plantmorph
