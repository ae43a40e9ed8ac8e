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

#include <cstddef>
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

/// Statistics of `count` distances; maximumDistance < 0 means no cut-off. All zero when nothing is kept.
DistanceStatistics ComputeDistanceStatistics(const double* distances, std::size_t count, double maximumDistance = -1.0);

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

} // namespace plantmorph
