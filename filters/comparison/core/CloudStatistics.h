// SPDX-License-Identifier: GPL-3.0-or-later
// Statistics and histograms of point-to-reference distances (docs/methods/comparison.md).
// Plain C++17, no VTK.
//
// Choices where no paper decides (docs/methods/comparison.md says why):
// - The standard deviation is the population one (divide by n, not n - 1): the cloud is all the measured points,
//   not a sample of them. RMS is sqrt(mean of d^2), so RMS^2 = mean^2 + std^2.
// - Percentiles interpolate linearly between order statistics at rank p/100 * (n - 1) (numpy's default, Hyndman
//   and Fan's type 7): the 50th percentile of an even count is the mean of the two middle values.
// - An outlier cut-off (maximumDistance >= 0) drops distances above it from every statistic and the histogram; they
//   are counted in `outliers`. NaN distances are never counted (they are reported in `invalid`).
// - The histogram's bins split [min, max] of the kept distances into equal widths, the last bin closed on the right
//   (as ParaView's Histogram filter does); all values equal gives one range of zero width and every value in bin 0.
#pragma once

#include <plantmorph/ParallelFor.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace plantmorph
{

struct DistanceStatistics
{
  std::size_t count = 0;    ///< distances kept (finite, not above the cut-off)
  std::size_t outliers = 0; ///< distances above the cut-off
  std::size_t invalid = 0;  ///< NaN or infinite distances
  double minimum = 0.0;
  double maximum = 0.0; ///< also the one-sided Hausdorff distance of the kept points
  double mean = 0.0;
  double standardDeviation = 0.0; ///< population standard deviation
  double rms = 0.0;
  double p50 = 0.0;
  double p68 = 0.0;
  double p75 = 0.0;
  double p95 = 0.0;
  double p99 = 0.0;
};

/// Neumaier's compensated summation: Value() is the sum of the added values to about one rounding (the error does
/// not grow with their number), so sums of parts (MPI ranks' pieces) added in a fixed order equal the whole one's.
struct CompensatedSum
{
  double Sum = 0.0;
  double Compensation = 0.0;
  void Add(double value) // inline: the statistics call it three times a distance
  {
    const double total = this->Sum + value;
    this->Compensation +=
      std::fabs(this->Sum) >= std::fabs(value) ? (this->Sum - total) + value : (value - total) + this->Sum;
    this->Sum = total;
  }
  /// Adds another part's sum (its sum, then its compensation).
  void Add(const CompensatedSum& part)
  {
    this->Add(part.Sum);
    this->Add(part.Compensation);
  }
  double Value() const { return this->Sum + this->Compensation; }
};

/// The percentiles of DistanceStatistics: p50, p68, p75, p95, p99.
constexpr std::size_t kPercentiles = 5;
constexpr double kPercentileValues[kPercentiles] = { 50.0, 68.0, 75.0, 95.0, 99.0 };

/// The order statistics (0-based ranks among `kept` sorted values) each percentile interpolates between, ranks[2i]
/// and ranks[2i + 1], and the fraction of the way from the first to the second: p_i = low + fraction (high - low).
void PercentileRanks(std::size_t kept, std::size_t ranks[2 * kPercentiles], double fractions[kPercentiles]);

/// A 64-bit key of a double that orders like the value (a < b gives OrderKey(a) < OrderKey(b); -0 is below +0), and
/// its inverse: a distributed selection (MPI) searches keys.
std::uint64_t OrderKey(double value);
double FromOrderKey(std::uint64_t key);

/// Statistics of `count` distances; maximumDistance < 0 means no cut-off. All zero when nothing is kept. `tasks`
/// runs its two independent parts (the sums, extremes, mean and spread; the percentiles), indices 0 and 1, possibly
/// at once (a ParallelFor that gives each index its own range); the results are the same either way.
DistanceStatistics ComputeDistanceStatistics(
  const double* distances, std::size_t count, double maximumDistance = -1.0, const ParallelFor& tasks = SerialFor);

/// The p-th percentile (0 <= p <= 100) of already sorted values, linear interpolation at rank p/100 (n - 1).
double SortedPercentile(const std::vector<double>& sorted, double p);

struct DistanceHistogram
{
  std::vector<double> binStart; ///< left edge of each bin
  std::vector<double> binEnd;   ///< right edge
  std::vector<double> binCenter;
  std::vector<std::size_t> count;
};

/// Histogram of the kept distances (same rule as ComputeDistanceStatistics) in `bins` equal bins over [min, max].
/// bins must be >= 1. Empty vectors when nothing is kept.
DistanceHistogram ComputeDistanceHistogram(
  const double* distances, std::size_t count, std::size_t bins, double maximumDistance = -1.0);

/// The same over a given range [lo, hi] (lo <= hi: the kept distances' minimum and maximum, over all MPI ranks);
/// kept distances outside it are not counted. The counting runs on `parallelFor` (the same counts either way).
DistanceHistogram ComputeDistanceHistogramOver(const double* distances, std::size_t count, std::size_t bins,
  double maximumDistance, double lo, double hi, const ParallelFor& parallelFor = SerialFor);

} // namespace plantmorph
