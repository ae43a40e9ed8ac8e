#include "CloudStatistics.h"

#include <algorithm>
#include <cmath>

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
  double sum = 0.0;
  for (double d : kept)
  {
    sum += d;
  }
  const double n = static_cast<double>(kept.size());
  s.mean = sum / n;
  double squares = 0.0;
  double deviations = 0.0;
  for (double d : kept)
  {
    squares += d * d;
    deviations += (d - s.mean) * (d - s.mean);
  }
  s.standardDeviation = std::sqrt(deviations / n);
  s.rms = std::sqrt(squares / n);
  s.minimum = *std::min_element(kept.begin(), kept.end());
  s.maximum = *std::max_element(kept.begin(), kept.end());
  // The percentiles need only the order statistics at their two ranks: place those by nth_element, each on the
  // part above the previous one (O(n) each instead of a full O(n log n) sort; the values are the same).
  const double percents[5] = { 50.0, 68.0, 75.0, 95.0, 99.0 };
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
  const double last = static_cast<double>(kept.size() - 1);
  for (int i = 0; i < 5; ++i)
  {
    const double rank = percents[i] / 100.0 * last;
    const std::size_t below = static_cast<std::size_t>(std::floor(rank));
    const std::size_t above = std::min(below + 1, kept.size() - 1);
    const double fraction = rank - static_cast<double>(below);
    const double low = orderStatistic(below);
    const double high = orderStatistic(above);
    *targets[i] = low + fraction * (high - low);
  }
  return s;
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
    if (!Kept(d, maximumDistance))
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
