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
  std::sort(kept.begin(), kept.end());
  s.minimum = kept.front();
  s.maximum = kept.back();
  s.p50 = SortedPercentile(kept, 50.0);
  s.p68 = SortedPercentile(kept, 68.0);
  s.p75 = SortedPercentile(kept, 75.0);
  s.p95 = SortedPercentile(kept, 95.0);
  s.p99 = SortedPercentile(kept, 99.0);
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
