// SPDX-License-Identifier: GPL-3.0-or-later
// A ParallelFor that hands a loop's tasks out in reverse order on two threads, so a test can assert that a result
// does not depend on the order or the thread its pieces run in.
#pragma once

#include "plantmorph/ParallelFor.h"

#include <cstddef>
#include <functional>
#include <thread>

namespace plantmorph::testing
{

/// Tasks count-1, ..., 0: the odd ones on a second thread, the even ones on the calling thread.
inline ParallelFor ReversedOnTwoThreads()
{
  return [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::thread other([&] {
      for (std::size_t i = count; i-- > 0;)
        if (i % 2 == 1)
          body(i, i + 1);
    });
    for (std::size_t i = count; i-- > 0;)
      if (i % 2 == 0)
        body(i, i + 1);
    other.join();
  };
}

} // namespace plantmorph::testing
