// SPDX-License-Identifier: GPL-3.0-or-later
// The median of a sample, as the fitters use it for point spacings and robust scales (1.4826 x the median absolute
// deviation). Plain C++17, no VTK.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
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

} // namespace plantmorph
