// SPDX-License-Identifier: GPL-3.0-or-later
// The median of a sample, as the fitters use it for point spacings, and the robust scale made of it (1.4826 x the
// median absolute deviation). Plain C++17, no VTK.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace plantmorph
{

/// The median of the values (for an even count the upper of the two middle ones), placed by std::nth_element on
/// the copy it takes; `ifEmpty` when there are none.
inline double Median(std::vector<double> values, double ifEmpty = std::numeric_limits<double>::quiet_NaN())
{
  if (values.empty())
    return ifEmpty;
  const std::size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle), values.end());
  return values[middle];
}

/// The normal distribution's standard deviation over its median absolute deviation, 1 / Phi^-1(3/4) = 1.4826: the
/// median absolute deviation times it estimates the deviation of a normal sample.
constexpr double MadToDeviation = 1.4826;

/// A robust scale of the values about `centre`: MadToDeviation x the median (as Median takes it) of their absolute
/// deviations from it. With `centre` 0 the values are residuals (their sign does not matter); `ifEmpty` when there
/// are none.
inline double RobustScale(
  const std::vector<double>& values, double centre = 0.0, double ifEmpty = std::numeric_limits<double>::quiet_NaN())
{
  if (values.empty())
    return ifEmpty;
  std::vector<double> deviation(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    deviation[i] = std::abs(values[i] - centre);
  return MadToDeviation * Median(std::move(deviation));
}

} // namespace plantmorph
