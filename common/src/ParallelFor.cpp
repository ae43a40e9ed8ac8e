// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/ParallelFor.h>

namespace plantmorph
{

void SerialFor(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body)
{
  if (count > 0)
    body(0, count);
}

} // namespace plantmorph
