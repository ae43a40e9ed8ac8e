// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: ParseStrokeCsv (sources/tree/core/StrokeFiles.cpp) on arbitrary bytes. It must return, and either
// give an error with no strokes or strokes of finite points, none of them empty.
#include "StrokeFiles.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  std::vector<std::string> origins; // where each stroke comes from: one per stroke, none on error
  const std::string error = plantmorph::ParseStrokeCsv(text, strokes, &origins);
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
  if (!error.empty() && !strokes.empty())
  {
    std::abort();
  }
  for (const auto& stroke : strokes)
  {
    if (stroke.empty())
    {
      std::abort();
    }
    for (const auto& p : stroke)
    {
      if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
      {
        std::abort();
      }
    }
  }
  return 0;
}
