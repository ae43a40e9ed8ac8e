// SPDX-License-Identifier: GPL-3.0-or-later
// What both stroke-file harnesses check of a parse beside its own format's rules: every stroke has its origin (the
// line or element it came from, none on error), and an error about the last stroke names the file and that origin.
#pragma once

#include "StrokeFiles.h"

#include <cstddef>
#include <cstdlib>
#include <string>
#include <vector>

inline void CheckStrokeOrigins(
  const std::vector<std::vector<Eigen::Vector3d>>& strokes, const std::vector<std::string>& origins)
{
  if (origins.size() != strokes.size())
  {
    std::abort();
  }
  if (!strokes.empty())
  {
    const std::size_t k = strokes.size() - 1;
    const std::string said =
      plantmorph::StrokeFileError("Strokes input, stroke " + std::to_string(k) + ": zero length", "f", origins);
    if (said.find(origins[k]) == std::string::npos || said.rfind("StrokeFile 'f', stroke ", 0) != 0)
    {
      std::abort();
    }
  }
}
