// SPDX-License-Identifier: GPL-3.0-or-later
#include "WiltingFrames.h"

#include <algorithm>
#include <cmath>

namespace plantmorph
{

std::vector<double> WiltingFrameTimes(const WiltingParameters& p)
{
  std::vector<double> times;
  if (!ValidateWilting(p).empty())
  {
    return times;
  }
  const int spf = std::max(1, static_cast<int>(std::lround(p.frameInterval / p.newmark.timeStep)));
  const double frame = spf * p.newmark.timeStep;
  const int count = 1 + static_cast<int>(std::floor(p.duration / frame + 1e-9));
  for (int k = 0; k < count; ++k)
  {
    times.push_back(k * spf * p.newmark.timeStep);
  }
  return times;
}

WiltingNodeState InterpolateWiltingFrames(const std::vector<WiltingFrame>& frames, double time, std::size_t nodeCount)
{
  std::size_t lower = 0;
  while (lower + 1 < frames.size() && frames[lower + 1].time <= time)
  {
    ++lower;
  }
  const std::size_t upper = std::min(lower + 1, frames.size() - 1);
  double w = 0.0;
  if (upper != lower && frames[upper].time > frames[lower].time)
  {
    w = std::clamp((time - frames[lower].time) / (frames[upper].time - frames[lower].time), 0.0, 1.0);
  }
  WiltingNodeState state;
  state.q.resize(3 * nodeCount);
  state.v.resize(3 * nodeCount);
  for (std::size_t k = 0; k < state.q.size(); ++k)
  {
    state.q[k] = (1.0 - w) * frames[lower].q[k] + w * frames[upper].q[k];
    state.v[k] = (1.0 - w) * frames[lower].v[k] + w * frames[upper].v[k];
  }
  state.time = (1.0 - w) * frames[lower].time + w * frames[upper].time;
  return state;
}

} // namespace plantmorph
