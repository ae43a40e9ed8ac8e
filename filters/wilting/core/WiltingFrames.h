// SPDX-License-Identifier: GPL-3.0-or-later
// The frames of a wilting run as WiltingSimulator plays them (docs/methods/wilting.md "Time"): the times it
// advertises before anything is simulated, and the state served at any time between two frames. Plain C++17, no VTK.
#pragma once

#include "WiltingSimulation.h"

#include <cstddef>
#include <vector>

namespace plantmorph
{

/// The frame times a run with `parameters` will have, known before it runs: every FrameInterval (rounded to whole
/// TimeSteps, at least one) from 0 to Duration. Empty when ValidateWilting rejects the parameters.
std::vector<double> WiltingFrameTimes(const WiltingParameters& parameters);

/// The nodes' displacements q and velocities v (3 per node) at one time.
struct WiltingNodeState
{
  std::vector<double> q, v;
  double time = 0.0;
};

/// The state at `time`: linear between the two frames around it, the first frame before it, the last after it (a
/// frame's own time gives that frame exactly). `frames` is not empty, each with 3 * nodeCount values in q and v.
WiltingNodeState InterpolateWiltingFrames(const std::vector<WiltingFrame>& frames, double time, std::size_t nodeCount);

} // namespace plantmorph
