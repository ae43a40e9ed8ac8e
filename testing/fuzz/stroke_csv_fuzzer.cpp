// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: ParseStrokeCsv (sources/tree/core/StrokeFiles.cpp) on arbitrary bytes. It must return, and either
// give an error with no strokes or strokes of finite points, none of them empty.
#include "StrokeFiles.h"
#include "StrokeFuzzChecks.h"

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
  CheckStrokeOrigins(strokes, origins);
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
