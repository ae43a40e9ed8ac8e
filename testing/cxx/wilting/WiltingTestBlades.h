// SPDX-License-Identifier: GPL-3.0-or-later
// Flat grid blades for the wilting unit tests: one builder, the Region rule given by the test.
#pragma once

#include "WiltingSimulation.h"

#include <functional>

namespace plantmorph
{

/// A flat blade [-w/2, w/2] x [0, l] in z = 0, triangulated on an nx x ny grid (two triangles per cell), with LeafUV
/// (u, v) = (i / nx - 0.5, j / ny) and the Region that `region(i, j)` gives grid point (i, j).
inline WiltingInput GridBlade(double w, double l, int nx, int ny, const std::function<int(int, int)>& region)
{
  WiltingInput in;
  for (int j = 0; j <= ny; ++j)
  {
    for (int i = 0; i <= nx; ++i)
    {
      const double u = static_cast<double>(i) / nx - 0.5;
      const double v = static_cast<double>(j) / ny;
      in.points.emplace_back(u * w, v * l, 0.0);
      in.leafUV.emplace_back(u, v);
      in.regions.push_back(region(i, j));
    }
  }
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const int a = j * (nx + 1) + i;
      in.triangles.push_back({ a, a + 1, a + nx + 2 });
      in.triangles.push_back({ a, a + nx + 2, a + nx + 1 });
    }
  }
  return in;
}

} // namespace plantmorph
