// SPDX-License-Identifier: GPL-3.0-or-later
#include "CloudComparisonExchange.h"

#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphWholeInput.h"

#include "vtkCommunicator.h"
#include "vtkDataObjectTypes.h"
#include "vtkMultiProcessController.h"
#include "vtkPointSet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace cloudmpi
{
namespace
{
/// A buffer's data, never null (MPI implementations may reject null buffers even of length 0).
template <typename T>
T* Data(std::vector<T>& v)
{
  static thread_local T dummy{};
  return v.empty() ? &dummy : v.data();
}

/// Every rank's `width` values, in rank order (the same vector on every rank).
std::vector<double> GatherAll(vtkMultiProcessController* controller, const double* mine, int width)
{
  std::vector<double> all(static_cast<std::size_t>(controller->GetNumberOfProcesses() * width));
  controller->AllGather(mine, all.data(), width);
  return all;
}

/// The kept distances of this rank as order keys, sorted, and their counts and sums.
struct LocalPart
{
  std::vector<std::uint64_t> keys;
  unsigned long long counts[3] = { 0, 0, 0 }; // kept, outliers, invalid
  double minimum = std::numeric_limits<double>::infinity();
  double maximum = -std::numeric_limits<double>::infinity();
  CompensatedSum sum;
};

LocalPart Local(const double* distances, std::size_t count, double maximumDistance)
{
  LocalPart part;
  part.keys.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    const double d = distances[i];
    if (!std::isfinite(d))
    {
      ++part.counts[2];
    }
    else if (maximumDistance >= 0.0 && d > maximumDistance)
    {
      ++part.counts[1];
    }
    else
    {
      part.keys.push_back(OrderKey(d));
      part.sum.Add(d);
      part.minimum = std::min(part.minimum, d);
      part.maximum = std::max(part.maximum, d);
    }
  }
  part.counts[0] = part.keys.size();
  return part;
}

/// The order statistics `ranks` (0-based, among all ranks' kept distances): for each, the smallest key with at least
/// rank + 1 kept distances at or below it. Each round splits every open key interval [lo, hi] at 255 candidates and
/// counts (one AllReduce for all targets) the distances at or below each, every rank on its own sorted keys; the
/// interval shrinks 256-fold, so at most 9 rounds (few synchronisations: each costs a scheduling delay on a loaded
/// machine and a latency on a cluster).
std::vector<double> OrderStatistics(vtkMultiProcessController* controller, const std::vector<std::uint64_t>& keys,
  const std::vector<unsigned long long>& ranks, double minimum, double maximum)
{
  constexpr std::size_t candidates = 255;
  const std::size_t n = ranks.size();
  std::vector<std::uint64_t> lo(n, OrderKey(minimum)), hi(n, OrderKey(maximum)), at(n * candidates);
  std::vector<unsigned long long> below(n * candidates), total(n * candidates);
  for (int round = 0; round < 12; ++round) // 256-fold per round: 2^64 keys in 8 rounds
  {
    bool open = false;
    for (std::size_t t = 0; t < n; ++t)
    {
      open = open || lo[t] < hi[t];
      const std::uint64_t width = hi[t] - lo[t];
      const std::uint64_t step = width / (candidates + 1) + 1;
      for (std::size_t j = 0; j < candidates; ++j)
      {
        const std::uint64_t offset = step * (j + 1) - 1; // no overflow: step * 256 <= width + 256
        at[t * candidates + j] = offset >= width ? hi[t] : lo[t] + offset;
        below[t * candidates + j] = static_cast<unsigned long long>(
          std::upper_bound(keys.begin(), keys.end(), at[t * candidates + j]) - keys.begin());
      }
    }
    if (!open) // the same on every rank: lo and hi move alike everywhere
    {
      break;
    }
    controller->AllReduce(below.data(), total.data(), static_cast<vtkIdType>(below.size()), vtkCommunicator::SUM_OP);
    for (std::size_t t = 0; t < n; ++t)
    {
      if (lo[t] >= hi[t])
      {
        continue;
      }
      // The first candidate with enough at or below it bounds the target from above; the one before, from below.
      std::size_t j = 0;
      while (j < candidates && total[t * candidates + j] < ranks[t] + 1)
      {
        ++j;
      }
      const std::uint64_t newLo = j > 0 ? at[t * candidates + j - 1] + 1 : lo[t];
      hi[t] = j < candidates ? at[t * candidates + j] : hi[t];
      lo[t] = newLo;
    }
  }
  std::vector<double> values(n);
  for (std::size_t t = 0; t < n; ++t)
  {
    values[t] = FromOrderKey(lo[t]);
  }
  return values;
}
} // namespace

//------------------------------------------------------------------------------
vtkMultiProcessController* Parallel()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPointSet> Replicate(vtkMultiProcessController* controller, vtkPointSet* piece)
{
  vtkSmartPointer<vtkPointSet> whole = GatherOnFirstRank(piece);
  if (!controller)
  {
    return whole;
  }
  int type = whole && whole->GetNumberOfPoints() > 0 ? whole->GetDataObjectType() : -1;
  controller->Broadcast(&type, 1, 0);
  if (type < 0)
  {
    return nullptr;
  }
  if (controller->GetLocalProcessId() != 0)
  {
    whole.TakeReference(vtkPointSet::SafeDownCast(vtkDataObjectTypes::NewDataObject(type)));
  }
  controller->Broadcast(whole, 0);
  return whole;
}

//------------------------------------------------------------------------------
PointLayout Layout(vtkMultiProcessController* controller, std::uint64_t count)
{
  PointLayout layout;
  layout.total = count;
  layout.count = count;
  if (!controller)
  {
    return layout;
  }
  const int ranks = controller->GetNumberOfProcesses();
  const int me = controller->GetLocalProcessId();
  const unsigned long long mine = count;
  std::vector<unsigned long long> all(static_cast<std::size_t>(ranks));
  controller->AllGather(&mine, all.data(), 1);
  layout.total = 0;
  for (int q = 0; q < ranks; ++q)
  {
    layout.first += q < me ? all[static_cast<std::size_t>(q)] : 0;
    layout.total += all[static_cast<std::size_t>(q)];
  }
  return layout;
}

//------------------------------------------------------------------------------
std::vector<double> Landmarks(
  vtkMultiProcessController* controller, const PointLayout& layout, const double* xyz, std::size_t limit)
{
  const std::uint64_t stride =
    std::max<std::uint64_t>(1, (layout.total + limit - 1) / std::max<std::uint64_t>(limit, 1));
  // This rank's points have global indices [first, first + count): the first multiple of the stride among them.
  std::vector<double> mine;
  for (std::uint64_t i = (stride - layout.first % stride) % stride; i < layout.count; i += stride)
  {
    mine.insert(mine.end(), xyz + 3 * i, xyz + 3 * i + 3);
  }
  if (!controller)
  {
    return mine;
  }
  const std::size_t ranks = static_cast<std::size_t>(controller->GetNumberOfProcesses());
  const double length = static_cast<double>(mine.size());
  const std::vector<double> lengths = GatherAll(controller, &length, 1);
  std::vector<vtkIdType> counts(ranks), offsets(ranks, 0);
  for (std::size_t q = 0; q < ranks; ++q)
  {
    counts[q] = static_cast<vtkIdType>(lengths[q]);
    offsets[q] = q ? offsets[q - 1] + counts[q - 1] : 0;
  }
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  controller->AllGatherV(Data(mine), Data(all), static_cast<vtkIdType>(mine.size()), counts.data(), offsets.data());
  return all;
}

//------------------------------------------------------------------------------
namespace
{
/// Collective: the ranks' compensated partial sums added in rank order.
CompensatedSum SumOverRanks(vtkMultiProcessController* controller, const CompensatedSum& mine)
{
  const double sums[2] = { mine.Sum, mine.Compensation };
  const std::vector<double> allSums = GatherAll(controller, sums, 2);
  CompensatedSum sum;
  for (std::size_t q = 0; q < allSums.size(); q += 2)
  {
    sum.Add(CompensatedSum{ allSums[q], allSums[q + 1] });
  }
  return sum;
}

/// Collective: the standard deviation and RMS of the counted distances of every rank (s.count, s.mean known).
void Spread(vtkMultiProcessController* controller, const double* distances, std::size_t count, double maximumDistance,
  DistanceStatistics& s)
{
  CompensatedSum squares, deviations;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double d = distances[i];
    if (std::isfinite(d) && (maximumDistance < 0.0 || d <= maximumDistance))
    {
      squares.Add(d * d);
      deviations.Add((d - s.mean) * (d - s.mean));
    }
  }
  const double n = static_cast<double>(s.count);
  s.standardDeviation = std::sqrt(SumOverRanks(controller, deviations).Value() / n);
  s.rms = std::sqrt(SumOverRanks(controller, squares).Value() / n);
}

/// Collective: the percentiles, their order statistics selected exactly over all ranks (`keys`: this rank's).
void Percentiles(vtkMultiProcessController* controller, std::vector<std::uint64_t>& keys, DistanceStatistics& s)
{
  std::size_t ranks[2 * kPercentiles];
  double fractions[kPercentiles];
  PercentileRanks(s.count, ranks, fractions);
  plantmorph::SortKeysInParallel(plantmorph::SMPFor(), keys, 0, 64); // linear, threaded
  const std::vector<double> values = OrderStatistics(
    controller, keys, std::vector<unsigned long long>(ranks, ranks + 2 * kPercentiles), s.minimum, s.maximum);
  double* targets[kPercentiles] = { &s.p50, &s.p68, &s.p75, &s.p95, &s.p99 };
  for (std::size_t i = 0; i < kPercentiles; ++i)
  {
    const double low = values[2 * i];
    const double high = values[2 * i + 1];
    *targets[i] = low + fractions[i] * (high - low);
  }
}
} // namespace

//------------------------------------------------------------------------------
DistanceStatistics Statistics(vtkMultiProcessController* controller, const double* distances, std::size_t count,
  double maximumDistance, const ParallelFor& tasks)
{
  if (!controller)
  {
    return ComputeDistanceStatistics(distances, count, maximumDistance, tasks);
  }
  LocalPart part = Local(distances, count, maximumDistance);
  DistanceStatistics s;
  unsigned long long counts[3] = { 0, 0, 0 };
  controller->AllReduce(part.counts, counts, 3, vtkCommunicator::SUM_OP);
  s.count = static_cast<std::size_t>(counts[0]);
  s.outliers = static_cast<std::size_t>(counts[1]);
  s.invalid = static_cast<std::size_t>(counts[2]);
  if (s.count == 0)
  {
    return s;
  }
  controller->AllReduce(&part.minimum, &s.minimum, 1, vtkCommunicator::MIN_OP);
  controller->AllReduce(&part.maximum, &s.maximum, 1, vtkCommunicator::MAX_OP);
  s.mean = SumOverRanks(controller, part.sum).Value() / static_cast<double>(s.count);
  Spread(controller, distances, count, maximumDistance, s);
  Percentiles(controller, part.keys, s);
  return s;
}

//------------------------------------------------------------------------------
DistanceHistogram Histogram(vtkMultiProcessController* controller, const double* distances, std::size_t count,
  std::size_t bins, double maximumDistance, const DistanceStatistics& whole, const ParallelFor& parallelFor)
{
  if (whole.count == 0 || bins == 0)
  {
    return {};
  }
  // Over the kept distances' range, which the statistics hold (serial: ComputeDistanceHistogram's own range).
  DistanceHistogram h =
    ComputeDistanceHistogramOver(distances, count, bins, maximumDistance, whole.minimum, whole.maximum, parallelFor);
  if (!controller)
  {
    return h;
  }
  std::vector<unsigned long long> mine(h.count.begin(), h.count.end()), total(mine.size());
  controller->AllReduce(Data(mine), Data(total), static_cast<vtkIdType>(mine.size()), vtkCommunicator::SUM_OP);
  std::copy(total.begin(), total.end(), h.count.begin());
  return h;
}

//------------------------------------------------------------------------------
void MinimumOverRanks(vtkMultiProcessController* controller, std::vector<double>& values)
{
  if (!controller)
  {
    return;
  }
  std::vector<double> minimum(values.size());
  controller->AllReduce(Data(values), Data(minimum), static_cast<vtkIdType>(values.size()), vtkCommunicator::MIN_OP);
  values.swap(minimum);
}

} // namespace cloudmpi
} // namespace plantmorph
