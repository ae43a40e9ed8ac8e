// SPDX-License-Identifier: GPL-3.0-or-later
// CloudStatistics (filters/comparison/core): closed forms on small sets (mean, population std, RMS^2 = mean^2 + std^2,
// numpy-type-7 percentiles), the outlier cut-off, NaN handling, and histograms that count every kept value once.
#include "CloudStatistics.h"

#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <numeric>
#include <thread>
#include <vector>

namespace plantmorph
{
namespace
{
// The two parts of the statistics on two threads at once give the serial result bit for bit, with NaN, infinite,
// outlying and equal distances among them; and the parts are really independent (each alone on its thread). The
// histogram over the statistics' range, its blocks on two threads, equals the serial histogram.
TEST(CloudStatistics, TwoThreadsGiveTheSerialResult)
{
  RandomStream random(39);
  std::vector<double> d(150001); // three of the histogram's blocks
  for (double& x : d)
  {
    x = std::fabs(random.Normal(1.0, 0.5));
  }
  d[7] = std::numeric_limits<double>::quiet_NaN();
  d[70] = std::numeric_limits<double>::infinity();
  std::fill(d.begin() + 100, d.begin() + 200, 0.25);
  const ParallelFor twoThreads = [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::thread other([&]() { body(1, count); });
    body(0, 1);
    other.join();
  };
  for (const double cutOff : { -1.0, 1.5 })
  {
    const DistanceStatistics serial = ComputeDistanceStatistics(d.data(), d.size(), cutOff);
    const DistanceStatistics threaded = ComputeDistanceStatistics(d.data(), d.size(), cutOff, twoThreads);
    EXPECT_EQ(serial.count, threaded.count);
    EXPECT_EQ(serial.outliers, threaded.outliers);
    EXPECT_EQ(serial.invalid, threaded.invalid);
    EXPECT_EQ(serial.invalid, 2u);
    EXPECT_EQ(serial.count + serial.outliers + serial.invalid, d.size());
    const double DistanceStatistics::*values[] = { &DistanceStatistics::minimum, &DistanceStatistics::maximum,
      &DistanceStatistics::mean, &DistanceStatistics::standardDeviation, &DistanceStatistics::rms,
      &DistanceStatistics::p50, &DistanceStatistics::p68, &DistanceStatistics::p75, &DistanceStatistics::p95,
      &DistanceStatistics::p99 };
    for (const auto value : values)
    {
      EXPECT_EQ(serial.*value, threaded.*value);
    }
    // The median against a full sort of the kept values.
    std::vector<double> kept;
    std::copy_if(d.begin(), d.end(), std::back_inserter(kept),
      [&](double x) { return std::isfinite(x) && (cutOff < 0.0 || x <= cutOff); });
    std::sort(kept.begin(), kept.end());
    EXPECT_EQ(threaded.p50, SortedPercentile(kept, 50.0));
    EXPECT_EQ(threaded.minimum, kept.front());
    EXPECT_EQ(threaded.maximum, kept.back());
    const DistanceHistogram histogram = ComputeDistanceHistogram(d.data(), d.size(), 17, cutOff);
    const DistanceHistogram over =
      ComputeDistanceHistogramOver(d.data(), d.size(), 17, cutOff, threaded.minimum, threaded.maximum, twoThreads);
    EXPECT_EQ(histogram.count, over.count);
    EXPECT_EQ(histogram.binStart, over.binStart);
    EXPECT_EQ(histogram.binEnd, over.binEnd);
    EXPECT_EQ(std::accumulate(over.count.begin(), over.count.end(), std::size_t(0)), threaded.count);
  }
}

TEST(CloudStatistics, ClosedFormsOnOneToTen)
{
  std::vector<double> d(10);
  std::iota(d.begin(), d.end(), 1.0); // 1..10
  const DistanceStatistics s = ComputeDistanceStatistics(d.data(), d.size());
  EXPECT_EQ(s.count, 10u);
  EXPECT_EQ(s.outliers, 0u);
  EXPECT_EQ(s.minimum, 1.0);
  EXPECT_EQ(s.maximum, 10.0);
  EXPECT_DOUBLE_EQ(s.mean, 5.5);
  EXPECT_DOUBLE_EQ(s.standardDeviation, std::sqrt(8.25)); // population: (n^2 - 1) / 12
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(38.5));               // (n + 1)(2n + 1) / 6
  // numpy.percentile([1..10], p): 5.5, 7.12, 7.75, 9.55, 9.91
  EXPECT_DOUBLE_EQ(s.p50, 5.5);
  EXPECT_NEAR(s.p68, 7.12, 1e-12);
  EXPECT_DOUBLE_EQ(s.p75, 7.75);
  EXPECT_NEAR(s.p95, 9.55, 1e-12);
  EXPECT_NEAR(s.p99, 9.91, 1e-12);
}

TEST(CloudStatistics, RmsSquaredIsMeanSquaredPlusVarianceOnRandomData)
{
  RandomStream random(1);
  std::vector<double> d(10001);
  for (double& x : d)
  {
    x = std::fabs(random.Normal(0.3, 1.0));
  }
  const DistanceStatistics s = ComputeDistanceStatistics(d.data(), d.size());
  EXPECT_NEAR(s.rms * s.rms, s.mean * s.mean + s.standardDeviation * s.standardDeviation, 1e-12);
  std::vector<double> sorted = d;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(s.p50, sorted[5000]); // odd count: the middle value
  EXPECT_LE(s.p50, s.p68);
  EXPECT_LE(s.p68, s.p75);
  EXPECT_LE(s.p75, s.p95);
  EXPECT_LE(s.p95, s.p99);
  EXPECT_LE(s.p99, s.maximum);
}

TEST(CloudStatistics, PercentilesEqualThoseOfAFullSortForEveryCount)
{
  // The percentiles come from nth_element on the ranks they need; they must be the values a full sort gives, for
  // every small count (ranks that coincide, n = 1, 2) and with many ties.
  RandomStream random(9);
  for (std::size_t n = 1; n <= 300; n += (n < 40 ? 1 : 37))
  {
    for (const bool ties : { false, true })
    {
      std::vector<double> d(n);
      for (double& x : d)
      {
        x = ties ? std::floor(random.Uniform(0.0, 4.0)) : random.Uniform(0.0, 2.0);
      }
      const DistanceStatistics s = ComputeDistanceStatistics(d.data(), d.size());
      std::vector<double> sorted = d;
      std::sort(sorted.begin(), sorted.end());
      ASSERT_EQ(s.minimum, sorted.front()) << n;
      ASSERT_EQ(s.maximum, sorted.back()) << n;
      ASSERT_EQ(s.p50, SortedPercentile(sorted, 50.0)) << n;
      ASSERT_EQ(s.p68, SortedPercentile(sorted, 68.0)) << n;
      ASSERT_EQ(s.p75, SortedPercentile(sorted, 75.0)) << n;
      ASSERT_EQ(s.p95, SortedPercentile(sorted, 95.0)) << n;
      ASSERT_EQ(s.p99, SortedPercentile(sorted, 99.0)) << n;
    }
  }
}

TEST(CloudStatistics, CutOffAndNaN)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> d = { 0.5, 1.0, nan, 7.0, 1.5, 100.0 };
  const DistanceStatistics s = ComputeDistanceStatistics(d.data(), d.size(), 5.0);
  EXPECT_EQ(s.count, 3u);
  EXPECT_EQ(s.outliers, 2u);
  EXPECT_EQ(s.invalid, 1u);
  EXPECT_DOUBLE_EQ(s.mean, 1.0);
  EXPECT_EQ(s.maximum, 1.5);
  const DistanceStatistics all = ComputeDistanceStatistics(d.data(), d.size());
  EXPECT_EQ(all.count, 5u);
  EXPECT_EQ(all.maximum, 100.0);
  const DistanceStatistics none = ComputeDistanceStatistics(d.data(), 0);
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.mean, 0.0);
}

TEST(CloudStatistics, HistogramCountsEveryKeptValueOnce)
{
  RandomStream random(2);
  std::vector<double> d(5000);
  for (double& x : d)
  {
    x = random.Uniform(0.0, 3.0);
  }
  d[17] = 10.0; // an outlier under the cut-off below
  for (std::size_t bins : { 1u, 7u, 64u })
  {
    const DistanceHistogram h = ComputeDistanceHistogram(d.data(), d.size(), bins, 5.0);
    ASSERT_EQ(h.count.size(), bins);
    EXPECT_EQ(std::accumulate(h.count.begin(), h.count.end(), std::size_t{ 0 }), 4999u);
    EXPECT_LE(h.binEnd.back(), 3.0);
    for (std::size_t b = 0; b + 1 < bins; ++b)
    {
      EXPECT_DOUBLE_EQ(h.binEnd[b], h.binStart[b + 1]);
    }
    // Brute-force count of one bin.
    const std::size_t b = bins / 2;
    std::size_t expected = 0;
    for (double x : d)
    {
      if (x <= 5.0 && x >= h.binStart[b] && (x < h.binEnd[b] || (b + 1 == bins && x <= h.binEnd[b])))
      {
        ++expected;
      }
    }
    EXPECT_EQ(h.count[b], expected);
  }
  const std::vector<double> same(10, 2.0);
  const DistanceHistogram flat = ComputeDistanceHistogram(same.data(), same.size(), 4);
  EXPECT_EQ(flat.count[0], 10u);
  EXPECT_TRUE(ComputeDistanceHistogram(same.data(), same.size(), 4, 1.0).count.empty());
}

TEST(CloudStatistics, CompensatedSumsOfPartsEqualTheWhole)
{
  // Ill-conditioned: plain summation loses the small terms entirely.
  CompensatedSum sum;
  for (double v : { 1e16, 1.0, -1e16, 1.0, 3.0 })
  {
    sum.Add(v);
  }
  EXPECT_EQ(sum.Value(), 5.0);
  // Random distances split into 1..7 parts (as MPI ranks hold them), the parts' sums added in order: the whole's
  // sum to 1e-15 relative (the bound the filter's 1e-12 rests on).
  RandomStream random(5);
  std::vector<double> values(100000);
  for (double& v : values)
  {
    v = random.Uniform(0.0, 1.0) * std::pow(10.0, random.Uniform(-6.0, 3.0));
  }
  CompensatedSum whole;
  for (double v : values)
  {
    whole.Add(v);
  }
  for (std::size_t parts = 1; parts <= 7; ++parts)
  {
    CompensatedSum total;
    for (std::size_t q = 0; q < parts; ++q)
    {
      CompensatedSum part;
      for (std::size_t i = q * values.size() / parts; i < (q + 1) * values.size() / parts; ++i)
      {
        part.Add(values[i]);
      }
      total.Add(part);
    }
    EXPECT_NEAR(total.Value(), whole.Value(), 1e-15 * whole.Value()) << parts << " parts";
  }
}

TEST(CloudStatistics, OrderKeysOrderLikeTheValuesAndInvert)
{
  RandomStream random(9);
  std::vector<double> values = { 0.0, -0.0, 1.0, -1.0, 1e-310, -1e-310, 1e308, -1e308, 0.5, 2.0 };
  for (int i = 0; i < 1000; ++i)
  {
    values.push_back(random.Uniform(-1.0, 1.0) * std::pow(10.0, random.Uniform(-300.0, 300.0)));
  }
  for (double a : values)
  {
    EXPECT_EQ(std::signbit(FromOrderKey(OrderKey(a))), std::signbit(a));
    EXPECT_EQ(FromOrderKey(OrderKey(a)), a);
    for (double b : { 0.0, 1.0, -1.0, 1e-300, values[50] })
    {
      if (a < b)
      {
        EXPECT_LT(OrderKey(a), OrderKey(b)) << a << " " << b;
      }
      else if (a > b)
      {
        EXPECT_GT(OrderKey(a), OrderKey(b)) << a << " " << b;
      }
    }
  }
}

TEST(CloudStatistics, PercentileRanksAndTheHistogramOverARangeAgreeWithTheWholeFunctions)
{
  RandomStream random(13);
  std::vector<double> values(1001);
  for (double& v : values)
  {
    v = random.Uniform(0.0, 4.0);
  }
  const DistanceStatistics s = ComputeDistanceStatistics(values.data(), values.size());
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  std::size_t ranks[2 * kPercentiles];
  double fractions[kPercentiles];
  PercentileRanks(sorted.size(), ranks, fractions);
  const double expected[kPercentiles] = { s.p50, s.p68, s.p75, s.p95, s.p99 };
  for (std::size_t i = 0; i < kPercentiles; ++i)
  {
    const double low = sorted[ranks[2 * i]], high = sorted[ranks[2 * i + 1]];
    EXPECT_EQ(low + fractions[i] * (high - low), expected[i]);
    EXPECT_EQ(SortedPercentile(sorted, kPercentileValues[i]), expected[i]);
  }
  const DistanceHistogram whole = ComputeDistanceHistogram(values.data(), values.size(), 13);
  const DistanceHistogram over =
    ComputeDistanceHistogramOver(values.data(), values.size(), 13, -1.0, s.minimum, s.maximum);
  EXPECT_EQ(whole.count, over.count);
  EXPECT_EQ(whole.binStart, over.binStart);
  EXPECT_EQ(whole.binEnd, over.binEnd);
  // Split in two parts histogrammed over the whole range: the counts add up to the whole's.
  const DistanceHistogram first = ComputeDistanceHistogramOver(values.data(), 400, 13, -1.0, s.minimum, s.maximum);
  const DistanceHistogram second =
    ComputeDistanceHistogramOver(values.data() + 400, values.size() - 400, 13, -1.0, s.minimum, s.maximum);
  for (std::size_t b = 0; b < 13; ++b)
  {
    EXPECT_EQ(first.count[b] + second.count[b], whole.count[b]);
  }
}

} // namespace
} // namespace plantmorph
