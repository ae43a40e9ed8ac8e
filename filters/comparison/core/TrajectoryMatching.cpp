// SPDX-License-Identifier: GPL-3.0-or-later
#include "TrajectoryMatching.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{

namespace
{
double Distance(const double* a, const double* b)
{
  const double dx = a[0] - b[0];
  const double dy = a[1] - b[1];
  const double dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

void Summarise(TrajectoryMatch& match, const double* measured, std::size_t n, const double* simulated)
{
  match.distance.resize(n);
  match.delta.resize(3 * n);
  double sum = 0.0;
  match.maxDistance = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* s = simulated + 3 * match.simulatedIndex[i];
    const double* p = measured + 3 * i;
    for (int k = 0; k < 3; ++k)
    {
      match.delta[3 * i + k] = s[k] - p[k];
    }
    match.distance[i] = Distance(s, p);
    sum += match.distance[i];
    match.maxDistance = std::max(match.maxDistance, match.distance[i]);
  }
  match.meanDistance = sum / static_cast<double>(n);
  const double* sFirst = simulated + 3 * match.simulatedIndex.front();
  const double* sLast = simulated + 3 * match.simulatedIndex.back();
  const double* mFirst = measured;
  const double* mLast = measured + 3 * (n - 1);
  const double measuredDirection[3] = { mLast[0] - mFirst[0], mLast[1] - mFirst[1], mLast[2] - mFirst[2] };
  const double simulatedDirection[3] = { sLast[0] - sFirst[0], sLast[1] - sFirst[1], sLast[2] - sFirst[2] };
  match.directionAngle = AngleBetween(measuredDirection, simulatedDirection);
}
} // namespace

//------------------------------------------------------------------------------
double AngleBetween(const double a[3], const double b[3])
{
  const double cross[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
  const double sine = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
  const double cosine = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double na = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double nb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (na == 0.0 || nb == 0.0)
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::atan2(sine, cosine) * 180.0 / 3.14159265358979323846;
}

//------------------------------------------------------------------------------
TrajectoryComparison CompareTrajectories(
  const double* measured, std::size_t n, const double* simulated, std::size_t m, std::size_t maximumMonotonePairs)
{
  TrajectoryComparison result;
  // A direction (last minus first sample) needs two samples: one gives no angle, only a NaN.
  if (n < 2 || m < 2)
  {
    const bool measuredShort = n < 2;
    result.error = std::string(measuredShort ? "the measured" : "the simulated") + " trajectory has " +
      std::to_string(measuredShort ? n : m) +
      " sample(s); a comparison needs at least 2 (its direction is the last "
      "minus the first sample)";
    return result;
  }
  for (std::size_t i = 0; i < 3 * n; ++i)
  {
    if (!std::isfinite(measured[i]))
    {
      result.error = "the measured trajectory has a non-finite coordinate (sample " + std::to_string(i / 3) + ")";
      return result;
    }
  }
  for (std::size_t j = 0; j < 3 * m; ++j)
  {
    if (!std::isfinite(simulated[j]))
    {
      result.error = "the simulated trajectory has a non-finite coordinate (sample " + std::to_string(j / 3) + ")";
      return result;
    }
  }

  // Closest sample.
  result.closest.simulatedIndex.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < m; ++j)
    {
      const double d = Distance(measured + 3 * i, simulated + 3 * j);
      if (d < best)
      {
        best = d;
        result.closest.simulatedIndex[i] = j;
      }
    }
  }
  Summarise(result.closest, measured, n, simulated);

  // Time-monotone: cost[i][j] = d(i, j) + min_{k < j} cost[i-1][k]; sample i can only use j in [i, m - n + i].
  if (m >= n && static_cast<double>(n) * static_cast<double>(m) <= static_cast<double>(maximumMonotonePairs))
  {
    result.hasMonotone = true;
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> cost(n * m, inf);
    std::vector<std::size_t> from(n * m, 0); // argmin k of the previous row
    for (std::size_t j = 0; j + n <= m; ++j)
    {
      cost[j] = Distance(measured, simulated + 3 * j);
    }
    for (std::size_t i = 1; i < n; ++i)
    {
      double bestPrevious = inf;
      std::size_t bestK = 0;
      for (std::size_t j = i; j + n <= m + i; ++j)
      {
        const double previous = cost[(i - 1) * m + (j - 1)];
        if (previous < bestPrevious)
        {
          bestPrevious = previous;
          bestK = j - 1;
        }
        cost[i * m + j] = bestPrevious + Distance(measured + 3 * i, simulated + 3 * j);
        from[i * m + j] = bestK;
      }
    }
    std::size_t j = n - 1;
    for (std::size_t k = n - 1; k < m; ++k)
    {
      if (cost[(n - 1) * m + k] < cost[(n - 1) * m + j])
      {
        j = k;
      }
    }
    result.monotone.simulatedIndex.resize(n);
    for (std::size_t i = n; i-- > 0;)
    {
      result.monotone.simulatedIndex[i] = j;
      if (i > 0)
      {
        j = from[i * m + j];
      }
    }
    Summarise(result.monotone, measured, n, simulated);
  }
  return result;
}

} // namespace plantmorph
