// SPDX-License-Identifier: GPL-3.0-or-later
#include "CloudStatistics.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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
void CompensatedSum::Add(double value)
{
  const double total = this->Sum + value;
  this->Compensation +=
    std::fabs(this->Sum) >= std::fabs(value) ? (this->Sum - total) + value : (value - total) + this->Sum;
  this->Sum = total;
}

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
DistanceStatistics ComputeDistanceStatistics(const double* distances, std::size_t count, double maximumDistance)
{
  DistanceStatistics s;
  std::vector<double> kept;
  kept.reserve(count);
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
      kept.push_back(d);
    }
  }
  s.count = kept.size();
  if (kept.empty())
  {
    return s;
  }
  // Two passes for the mean and the deviation (no cancellation), in a fixed order (deterministic).
  // Compensated sums: within about one rounding of the exact sums, so that per-rank partial sums (MPI) added in
  // rank order give the same statistics to ~1e-16 relative, whatever the split.
  CompensatedSum sum;
  for (double d : kept)
  {
    sum.Add(d);
  }
  const double n = static_cast<double>(kept.size());
  s.mean = sum.Value() / n;
  CompensatedSum squares;
  CompensatedSum deviations;
  for (double d : kept)
  {
    squares.Add(d * d);
    deviations.Add((d - s.mean) * (d - s.mean));
  }
  s.standardDeviation = std::sqrt(deviations.Value() / n);
  s.rms = std::sqrt(squares.Value() / n);
  s.minimum = *std::min_element(kept.begin(), kept.end());
  s.maximum = *std::max_element(kept.begin(), kept.end());
  // The percentiles need only the order statistics at their two ranks: place those by nth_element, each on the
  // part above the previous one (O(n) each instead of a full O(n log n) sort; the values are the same).
  double* targets[5] = { &s.p50, &s.p68, &s.p75, &s.p95, &s.p99 };
  // Ranks are asked in non-decreasing order; kept[placed - 1] is the last one placed, nothing before it is larger,
  // and a rank below `placed` is always one placed before (its position is never touched again).
  std::size_t placed = 0;
  const auto orderStatistic = [&](std::size_t rank) {
    if (rank >= placed)
    {
      std::nth_element(kept.begin() + static_cast<std::ptrdiff_t>(placed),
        kept.begin() + static_cast<std::ptrdiff_t>(rank), kept.end());
      placed = rank + 1;
    }
    return kept[rank];
  };
  std::size_t ranks[2 * kPercentiles];
  double fractions[kPercentiles];
  PercentileRanks(kept.size(), ranks, fractions);
  for (std::size_t i = 0; i < kPercentiles; ++i)
  {
    const double low = orderStatistic(ranks[2 * i]);
    const double high = orderStatistic(ranks[2 * i + 1]);
    *targets[i] = low + fractions[i] * (high - low);
  }
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
DistanceHistogram ComputeDistanceHistogramOver(
  const double* distances, std::size_t count, std::size_t bins, double maximumDistance, double lo, double hi)
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
  for (std::size_t i = 0; i < count; ++i)
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
    ++h.count[b];
  }
  return h;
}

} // namespace plantmorph
